"""Run a co-design: the search (search.py: closed-form screening and the optimal-maneuver
floors, predict.py), then level (c), full Drake simulation of the requirements' envelope for the
default design and the finalists on the package's Dask engine (envelope/run.py, a local cluster
or an existing scheduler), then the report (report.py):

    OUT/codesign.journal          the Optuna study (rerunning into OUT resumes it)
    OUT/finalists/default/        the default design's envelope (the base parameters)
    OUT/finalists/trial_N/        each finalist's envelope: envelope.md/json and a folder per
                                  maneuver with its recordings
    OUT/design.md, design.json    the recommended design and why, margins, predicted vs simulated
    OUT/design.toml               the recommended design's parameter file
    OUT/pareto.png                the objectives, predicted and verified

A design is verified only when its simulated envelope has every maneuver (and the duty cycle)
in the accepted verdicts; without finalists nothing is simulated. The finalists are the designs predicted to meet every requirement,
best first (with several objectives, the predicted Pareto front first), one per motor and
gearbox type before a second of the same, `budget.finalists` of them. Each envelope's outcome is
kept in the journal, so a rerun simulates only the finalists that lack one.
"""

from __future__ import annotations

import math
from contextlib import nullcontext
from pathlib import Path

from fivebar_drake.codesign.designs import GEARBOX, MOTOR, design_envelope, design_name
from fivebar_drake.codesign.predict import CHECKS, needs
from fivebar_drake.codesign.report import DEFAULT, CodesignRun, write_report
from fivebar_drake.codesign.search import predictions, ranked, search
from fivebar_drake.codesign.spec import CodesignSpec
from fivebar_drake.envelope.run import run_envelope
from fivebar_drake.sweep.engine import (Progress, check_output_folder, check_scheduler,
                                        check_workers, dask_client)

FINALISTS_DIR = "finalists"
DUTY = "duty cycle"        # its row beside the maneuvers (no maneuver name has a space)


def pareto(spec: CodesignSpec, entries: list[dict]) -> list[dict]:
    """The entries no other entry dominates on the objectives."""
    sign = [1.0 if d == "minimize" else -1.0 for d in spec.directions]

    def key(e):
        return [s * e["objectives"][o] for s, o in zip(sign, spec.objectives)]

    return [e for e in entries if not any(
        all(a <= b for a, b in zip(key(f), key(e))) and key(f) != key(e) for f in entries)]


def finalists(spec: CodesignSpec, entries: list[dict]) -> list[dict]:
    """The designs to simulate (module docstring)."""
    meeting = [e for e in entries if e["meets"]]
    front = ranked(spec, pareto(spec, meeting)) if len(spec.objectives) > 1 else []
    order = front + [e for e in ranked(spec, meeting) if e["name"] not in
                     {f["name"] for f in front}]
    picked, kinds = [], set()
    for e in order:
        kind = (e["design"][MOTOR], e["design"][GEARBOX])
        if kind not in kinds:
            kinds.add(kind)
            picked.append(e)
    picked += [e for e in order if e not in picked]
    return picked[:spec.finalists]


def simulated(report: dict, spec: CodesignSpec) -> dict:
    """An envelope's outcome (envelope.json's dictionary) against the requirements: per
    maneuver, and for the duty cycle (DUTY), its verdict, deciding check, each check's worst
    figure over the motors and legs (torque: safety factor, speed: least margin, thermal:
    current margin; the duty cycle: its hottest winding's current margin) and its margin (the
    figure over what the accepted verdict needs, predict.needs); `passes` when every verdict
    is accepted."""
    need = needs(spec.envelope.maneuvers[0].params, spec.accept)
    keys = {"torque": "sf", "speed": "least_margin", "thermal": "margin"}
    out = {}
    for name, e in report["maneuvers"].items():
        rows = [r for r in (e["motors"] or {}).values() if r["checks"] is not None]
        figures = {c: min(_finite(r["checks"][c][keys[c]]) for r in rows) for c in CHECKS} \
            if rows and len(rows) == len(e["motors"]) else {}
        out[name] = {"verdict": e["verdict"], "deciding_check": e.get("deciding_check"),
                     "figures": figures, "margins": {c: f / need[c] for c, f in figures.items()}}
    duty = report["duty_cycle"]
    if duty is not None:
        margin = min(_finite(m["margin"]) for m in duty["motors"].values())
        out[DUTY] = {"verdict": duty["verdict"], "deciding_check": "thermal",
                     "figures": {"thermal": margin},
                     "margins": {"thermal": margin / need["thermal"]}}
    return {"maneuvers": out, "duty_cycle": duty is not None,
            "passes": all(m["verdict"] in spec.accept for m in out.values())}


def _finite(x) -> float:
    return math.inf if x is None else x


def verify(study, spec: CodesignSpec, key: str, design: dict | None, folder: Path,
           dask) -> dict:
    """The design's simulated envelope (simulated), from the journal if it has it, else run
    into folder on the Dask client and kept in the journal."""
    attr = f"envelope:{key}"
    if attr not in study.user_attrs:
        run = run_envelope(design_envelope(spec.envelope, design), folder, progress=False,
                           client=dask)
        study.set_user_attr(attr, simulated(run.report, spec))
    return study.user_attrs[attr]


def run_codesign(spec: CodesignSpec, out: str | Path, workers: int | None = None,
                 scheduler: str | None = None, progress: bool = True,
                 client=None) -> CodesignRun:
    """Search, verify and report into out (module docstring). client: a Dask client to use
    (and leave open); otherwise one of the scheduler, or of a new local cluster of
    `workers`."""
    out = Path(out)
    check_workers(workers)
    if scheduler:
        check_scheduler(scheduler)
    check_output_folder(out)
    out.mkdir(parents=True, exist_ok=True)
    study = search(spec, out, progress)
    entries = predictions(study)
    chosen = finalists(spec, entries)
    jobs = [(DEFAULT, None)] + [(f"trial_{e['trial']}", e) for e in chosen] if chosen else []
    missing = any(f"envelope:{key}" not in study.user_attrs for key, _ in jobs)
    verified = {}
    bar = Progress(len(jobs), 0, progress, "verify", "envelopes")
    with dask_client(workers, scheduler, client) if missing else nullcontext() as dask:
        for key, entry in jobs:
            verified[key] = verify(study, spec, key, entry and entry["design"],
                                   out / FINALISTS_DIR / key, dask)
            passing = ranked(spec, [e for k, e in jobs[1:] if k in verified and
                                    verified[k]["passes"]])
            bar.note = "best verified: " + (design_name(passing[0]["design"]) if passing
                                            else "none yet")
            bar.add(1, int(not verified[key]["passes"]))
    return write_report(spec, out, entries, chosen, verified)
