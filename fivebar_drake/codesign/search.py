"""The co-design's search: Optuna's TPE sampler (one or several objectives, the predicted
requirements as its constraints) over the design space, one design per trial judged by the
predictions (predict.py), the study kept in a journal file in the output folder.

Resumable and deterministic: trial k is sampled by a TPE sampler seeded with seed + k from the
trials before it, and its evaluation is deterministic, so a rerun into the same folder goes on
where the journal ends (a trial cut short by Ctrl-C is evaluated again first) and gives the
same trials as an uninterrupted run.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from fivebar_drake.codesign.designs import GEARBOX, MOTOR, design_of
from fivebar_drake.codesign.predict import predict
from fivebar_drake.codesign.spec import CodesignSpec
from fivebar_drake.core.files import say
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.core.progress import Progress

JOURNAL_FILE = "codesign.journal"
STUDY = "codesign"
STARTUP_SHARE = 3            # a third of the trials (at most 10) sample at random first


def journal_records(path: Path) -> list[dict]:
    """The journal's records (one JSON object a line), read before Optuna touches the file: a
    last line cut short (a crash, a full disk) is dropped from the file, and said on stderr; a
    line that is not a record anywhere else is ParameterError naming the journal and the line
    (the file is left as it is)."""
    text = path.read_bytes()
    lines = text.split(b"\n")
    records, good = [], 0
    for number, line in enumerate(lines, 1):
        if not line.strip():
            good += len(line) + 1
            continue
        try:
            record = json.loads(line)
            if not isinstance(record, dict):
                raise ValueError("not a record")
        except ValueError:
            if number >= len(lines) - 1 and not any(x.strip() for x in lines[number:]):
                with path.open("r+b") as f:          # the cut last record: dropped
                    f.truncate(good)
                say(f"warning: {path}: its last line {number} was cut short (a crash or a full "
                    "disk); dropped, the study resumes from the record before it", sys.stderr)
                break
            raise ParameterError(f"line {number} is not a journal record (a stray or damaged "
                                 "line): repair or remove the line, or the file to start "
                                 "over", source=str(path)) from None
        records.append(record)
        good += len(line) + 1
    return records


def open_study(spec: CodesignSpec, out: Path):
    """The study in out's journal (made if new); ParameterError if the journal holds another
    co-design's study (another spec or other files it names), or a damaged line
    (journal_records). A refused run and a resumed one add nothing to the journal."""
    import optuna
    from optuna.storages import JournalStorage
    from optuna.storages.journal import JournalFileBackend

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    path = out / JOURNAL_FILE
    records = journal_records(path) if path.exists() else []
    fingerprint = next((r["user_attr"]["fingerprint"] for r in records
                        if "trial_id" not in r and isinstance(r.get("user_attr"), dict)
                        and "fingerprint" in r["user_attr"]), None)
    if fingerprint is not None and fingerprint != spec.fingerprint():
        raise ParameterError("holds the journal of another co-design (another spec, or a file "
                             "it names has changed): give another folder or remove "
                             f"{JOURNAL_FILE}", source=f"--out {out}")
    storage = JournalStorage(JournalFileBackend(str(path)))
    if any(r.get("study_name") == STUDY for r in records):
        study = optuna.load_study(study_name=STUDY, storage=storage)
    else:
        study = optuna.create_study(study_name=STUDY, storage=storage,
                                    directions=spec.directions)
    if fingerprint is None:
        study.set_user_attr("fingerprint", spec.fingerprint())
    return study


def _sampler(spec: CodesignSpec, number: int):
    """Trial `number`'s sampler (module docstring)."""
    import optuna

    return optuna.samplers.TPESampler(
        seed=spec.seed + number, n_startup_trials=min(10, max(1, spec.trials // STARTUP_SHARE)))


def _suggest(trial, spec: CodesignSpec) -> dict:
    """The trial's sampled values: motor, gearbox (if varied) and the varied parameters."""
    values = {MOTOR: trial.suggest_categorical(MOTOR, list(spec.motors))}
    if spec.gearboxes:
        values[GEARBOX] = trial.suggest_categorical(GEARBOX, list(spec.gearboxes))
    for v in spec.vary:
        values[v.path] = (trial.suggest_categorical(v.path, list(v.values)) if v.values else
                          trial.suggest_int(v.path, v.low, v.high) if v.integer else
                          trial.suggest_float(v.path, v.low, v.high))
    return values


def evaluate(spec: CodesignSpec, values: dict) -> dict:
    """The prediction of a trial's sampled values (predict.predict), or of why no design has
    them (no gearbox spans the ratio)."""
    try:
        design = design_of(values)
    except ParameterError as err:
        return {"design": values, "name": str(values), "error": err.message, "meets": False,
                "margin": 0.0, "short_of": "", "objectives": {}, "maneuvers": {}}
    return predict(spec, [design])[0]


def _tell(study, spec: CodesignSpec, trial, values: dict) -> dict:
    """Evaluate and record a trial: its prediction and constraint as user attributes, its
    objectives as values (failed when it has none)."""
    import optuna

    prediction = evaluate(spec, values)
    trial.set_user_attr("prediction", prediction)
    trial.set_constraint("margin", 1.0 - min(prediction["margin"], 2.0))
    if set(spec.objectives) <= set(prediction["objectives"]):
        study.tell(trial, [prediction["objectives"][o] for o in spec.objectives])
    else:
        study.tell(trial, state=optuna.trial.TrialState.FAIL)
    return prediction


def search(spec: CodesignSpec, out: Path, progress: bool = True):
    """Run the study's missing trials (module docstring); returns the study."""
    import optuna

    study = open_study(spec, out)
    for frozen in study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,)):
        _tell(study, spec, optuna.trial.Trial(study, frozen._trial_id), frozen.params)
    bar = Progress(spec.trials, min(len(study.trials), spec.trials), progress, "co-design",
                   "trials")
    while len(study.trials) < spec.trials:
        study.sampler = _sampler(spec, len(study.trials))
        trial = study.ask()
        prediction = _tell(study, spec, trial, _suggest(trial, spec))
        best = best_predicted(study, spec)
        bar.note = "best predicted: " + (f"{best['name']}, {_objectives_text(best)}"
                                         if best else "none yet")
        bar.add(1, int(bool(prediction["error"])))
    return study


def predictions(study) -> list[dict]:
    """Every finished trial's prediction with its trial number, in trial order."""
    return [{**t.user_attrs["prediction"], "trial": t.number} for t in study.trials
            if "prediction" in t.user_attrs and t.state.is_finished()]


def ranked(spec: CodesignSpec, entries: list[dict]) -> list[dict]:
    """The entries by the first objective, best first (one per design)."""
    sign = 1.0 if spec.directions[0] == "minimize" else -1.0
    seen, out = set(), []
    for e in sorted(entries, key=lambda e: (sign * e["objectives"][spec.objectives[0]],
                                            e["trial"])):
        if e["name"] not in seen:
            seen.add(e["name"])
            out.append(e)
    return out


def best_predicted(study, spec: CodesignSpec) -> dict | None:
    """The best design (first objective) predicted to meet every requirement, or None."""
    meeting = ranked(spec, [p for p in predictions(study) if p["meets"]])
    return meeting[0] if meeting else None


def _objectives_text(entry: dict) -> str:
    return ", ".join(f"{k} {v:.3f}" for k, v in entry["objectives"].items())


def corrected(entry: dict, factors: dict[str, float]) -> float:
    """The entry's least predicted margin with the corrections applied."""
    return min((margin * factors.get(f"{name} {check}", 1.0)
                for name, p in entry["maneuvers"].items()
                for check, margin in p["margins"].items()), default=math.inf)
