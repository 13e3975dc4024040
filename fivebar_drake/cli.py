"""Command line of fivebar_drake:

  fivebar-drake analyze  [--mechanism NAME] [--gait NAME] [--config FILE]
                         [--set FIELD=VALUE ...] [--out DIR]
  fivebar-drake simulate [--mechanism NAME] [--scenario FILE] [--config FILE]
                         [--set FIELD=VALUE ...] [--gait NAME] [--duration S]
                         [--closure {bushing,bushing_rpy,ball}] [--step-check] [--out DIR]
  fivebar-drake sweep    SPEC.yaml [--out DIR] [--workers N] [--scheduler ADDRESS]
  fivebar-drake envelope [SPEC.yaml] [--out DIR] [--workers N] [--scheduler ADDRESS]
  fivebar-drake codesign SPEC.yaml [--out DIR] [--workers N] [--scheduler ADDRESS]
  fivebar-drake optimal  [--config FILE] [--set FIELD=VALUE ...] [--height M] [--payload KG]
                         [--top-speed GAITS] [--simulate] [--out DIR]
  fivebar-drake compare  RUN_DIR [RUN_DIR ...] [--out FILE]
  fivebar-drake models   [--scenario FILE] [--config FILE] [--out DIR]

(fivebar-drake COMMAND --help lists each option's choices: analyze's 6 foot paths, simulate's
gaits and maneuvers, the closures, the mechanisms.)"""

from __future__ import annotations

import argparse
import contextlib
import signal
import sys
import tempfile
import time
import traceback
from importlib.metadata import version

from fivebar_drake import catalog
from fivebar_drake.core.files import (check_output_file, check_path_name, prepare_output_dir,
                                      release_folders, say)
from fivebar_drake.gaits import PATHS
from fivebar_drake.core import plugins
from fivebar_drake.core.interrupts import SIGNALS, Interrupted, Signals
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.verdicts.rules import ACHIEVED_VERDICTS
from fivebar_drake.robots.quadruped.closure import CLOSURES
from fivebar_drake.simulation.scenario import Scenario


EXIT_CODES = """exit codes:
  0    done
  1    the run failed (stopped early, diverged), has no verdict (too few gait cycles) or
       did not achieve its motion (verdict not_achieved)
  2    bad input: a parameter or scenario file, a command-line value, an output path
  3    internal error (a bug): the message names a log file with the traceback
  130  interrupted by SIGINT (Ctrl-C), 143 by SIGTERM; simulate, envelope and optimal write
       what they have first"""

EXIT_INTERNAL = 3
DEFAULTS = Scenario()
COMMON = {"help", "mechanism", "config", "duration", "out"}   # options every study takes


def _err(text: str) -> None:
    say(f"fivebar-drake: {text}", sys.stderr)


def _study(args):
    """The study of --mechanism and the values of its own options given to this command
    (ParameterError for one it does not take)."""
    import matplotlib

    matplotlib.use("Agg")  # files only, never a window
    study = catalog.study(args.mechanism)
    options = {}
    for action in _commands()[args.command]._actions:
        if action.dest in COMMON:
            continue
        value, flag = getattr(args, action.dest), action.option_strings[0]
        if flag in study.OPTIONS:
            options[action.dest] = value
        elif value is not None:
            takers = [m for m in catalog.mechanisms() if flag in catalog.study(m).OPTIONS]
            raise ParameterError(f"{flag} = {value}: applies to --mechanism "
                                 f"{', '.join(takers)} only, not to {args.mechanism}", flag,
                                 "command line")
    return study, options


def _analyze(args, signals) -> int:
    """The analysis of --mechanism through its study (studies/base.py): every input checked
    before the folder is touched (exit 2), then run, written and reported."""
    study, options = _study(args)
    start = time.perf_counter()
    plan = study.load_analysis(args.config, **options)          # bad input: exit 2 first
    out = _output_dir(args, study.ANALYSIS_FILES)
    return _finish(study.write_analysis(study.analyze(_begin(plan)), out), out, start, signals)


def _simulate(args, signals) -> int:
    """The simulation of --mechanism through its study, as _analyze; a signal stops a run that
    can stop early, and what it simulated is written."""
    study, options = _study(args)
    if not study.SIMULATION_FILES:
        raise ParameterError(f"--mechanism = {args.mechanism}: has no simulation; simulate "
                             f"takes {[m for m in catalog.mechanisms() if catalog.can_simulate(m)]}",
                             "--mechanism", "command line")
    start = time.perf_counter()
    plan = study.load_simulation(args.config, args.duration, **options)
    out = _output_dir(args, study.SIMULATION_FILES)
    record = study.simulate(_begin(plan), progress=True, stop=lambda: signals.name)
    return _finish(study.write_simulation(record, out), out, start, signals)


def _output_dir(args, files):
    """--out (default: the mechanism's folder for this command), cleared of the job's files."""
    return prepare_output_dir(args.out or catalog.default_out(args.mechanism, args.command),
                              "--out", files)


def _begin(plan) -> object:
    """Print the plan's heading; its inputs."""
    for line in plan.heading:
        say(line)
    return plan.inputs


def _finish(written, out, start: float, signals) -> int:
    """Print what the job wrote and says; its exit code (see EXIT_CODES)."""
    for line in written.lines:
        say(line)
    took = f" in {time.perf_counter() - start:.1f} s" if written.timed else ""
    say(f"wrote {len(written.files)} files to {out.resolve()}{took}:")
    for path in written.files:
        say(f"  {path}")
    for line in written.closing:
        say(line)
    for line in written.warnings:
        _err(line)
    if signals.signum:
        _err(written.interrupted or f"interrupted by {signals.name} after the run: its files "
             "are complete")
        return 128 + signals.signum
    if written.failure:
        _err(written.failure)
        return 1
    return 0


def _check_cluster(args) -> None:
    """--workers applies to the local cluster only."""
    if args.workers is not None and (args.workers < 1 or args.scheduler):
        raise ParameterError(f"--workers = {args.workers}: must be >= 1, and applies to the "
                             "local cluster (not with --scheduler)", "--workers", "command line")


def _sweep(args, signals) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from pathlib import Path
    from fivebar_drake.sweep.engine import sweep
    from fivebar_drake.sweep.spec import load_spec

    spec = load_spec(args.spec)
    _check_cluster(args)
    out = Path(args.out or Path("out/sweep") / Path(args.spec).stem)
    start = time.perf_counter()
    try:
        result, summary, written = sweep(spec, out, args.workers, args.scheduler)
    except (KeyboardInterrupt, Interrupted):
        from fivebar_drake.sweep.engine import finished_points

        done, total = finished_points(spec, out)
        _err(f"the finished points are in {out / 'points.csv'} ({done} of {total}); run the same "
             "command again to " + ("compute the rest" if done < total else
                                    "write the plots and sweep.md (every point is done)"))
        raise
    say(f"{summary['points']} design points ({spec.fidelity}), {result.computed} computed now, "
        f"{result.failed} failed; outcomes: " + ", ".join(
            f"{k} {v}" for k, v in sorted(summary["outcomes"].items())))
    best = summary["fastest_passing"]
    say("fastest design where every motor passes: " + ("none" if best is None else
        f"point {best['point']} " + ", ".join(f"{k} = {best[k]}" for k in spec.names)
        + f" ({best['speed_m_s']:.3f} m/s, worst SF {best['worst_safety_factor']:.2f})"))
    say(f"wrote {len(written)} files to {out.resolve()} in {time.perf_counter() - start:.1f} s:")
    for path in written:
        say(f"  {path}")
    return 0


def _envelope(args, signals) -> int:
    """The duty envelope (envelope/run.py): every input checked first (exit 2), the maneuvers
    run on Dask, the envelope written; exit 1 when a maneuver has no verdict or did not achieve
    its motion."""
    import matplotlib

    matplotlib.use("Agg")
    from pathlib import Path
    from fivebar_drake.envelope.report import floor_text
    from fivebar_drake.envelope.run import run_envelope
    from fivebar_drake.envelope.spec import DEFAULT_SPEC, load_envelope_spec

    spec = load_envelope_spec(args.spec)
    _check_cluster(args)
    out = Path(args.out or Path("out/envelope") / Path(args.spec or DEFAULT_SPEC).stem)
    start = time.perf_counter()
    say(f"envelope: {len(spec.maneuvers)} maneuvers of {spec.source}"
        + (f", a duty cycle of {len(spec.duty_cycle)} steps" if spec.duty_cycle else ""))
    try:
        run = run_envelope(spec, out, args.workers, args.scheduler)
    except (KeyboardInterrupt, Interrupted):
        if (out / "envelope.json").exists():
            _err(f"the finished maneuvers' folders and an envelope of them (complete: false) "
                 f"are in {out}")
        raise
    report = run.report
    say(report["answer"])
    for motor, s in report["sized_by"].items():
        if s:
            say(f"motor {motor} is sized by {s['maneuver']} ({s['verdict'].upper()}, "
                f"{s['deciding_check']} check, leg {s['leg']})")
    floor = report["sized_by_floor"]
    if floor:
        say("for any controller: " + floor_text(floor).replace("**", ""))
    duty = report["duty_cycle"]
    say("duty cycle: " + (report["duty_cycle_why_none"] if duty is None else ", ".join(
        f"motor {m} peaks at {v['peak_C']:.1f} °C (leg {v['leg']})"
        for m, v in duty["motors"].items()) + f": {duty['verdict'].upper()}"))
    files = run.files + [p for paths in run.maneuver_files.values() for p in paths]
    say(f"wrote {len(files)} files to {out.resolve()} in {time.perf_counter() - start:.1f} s: "
        + ", ".join(p.name for p in run.files) + " and a folder per maneuver")
    unrated = [n for n, e in report["maneuvers"].items()
               if e["verdict"] not in ACHIEVED_VERDICTS]
    if unrated:
        _err(f"no verdict or not achieved: {', '.join(unrated)} (see {out / 'envelope.md'})")
        return 1
    return 0


def _codesign(args, signals) -> int:
    """The co-design (codesign/run.py): the spec checked first (exit 2), the search and the
    finalists' envelopes on Dask, the design written; exit 1 when no design is verified."""
    import matplotlib

    matplotlib.use("Agg")
    from pathlib import Path
    from fivebar_drake.codesign.run import run_codesign
    from fivebar_drake.codesign.spec import load_codesign_spec

    spec = load_codesign_spec(args.spec)
    _check_cluster(args)
    out = Path(args.out or Path("out/codesign") / Path(args.spec).stem)
    start = time.perf_counter()
    say(f"co-design: {len(spec.motors)} motors, {len(spec.vary)} more variables, "
        f"{spec.trials} trials, {spec.finalists} finalists; requirements: "
        f"{len(spec.envelope.maneuvers)} maneuvers of {spec.envelope.source or args.spec}")
    try:
        run = run_codesign(spec, out, args.workers, args.scheduler)
    except (KeyboardInterrupt, Interrupted):
        _err(f"the finished trials and envelopes are kept in {out}; run the same command "
             "again to resume")
        raise
    say(run.report["answer"])
    say(f"wrote {len(run.files)} files to {out.resolve()} in {time.perf_counter() - start:.1f} "
        "s: " + ", ".join(p.name for p in run.files) + ", the journal and the finalists' "
        "envelopes")
    if run.failure:
        _err(run.failure)
        return 1
    return 0


def _optimal(args, signals) -> int:
    """What the legs allow for any controller (optimal/report.py): every input checked
    first (exit 2); exit 1 when the jump asked for is beyond the motors."""
    import matplotlib

    matplotlib.use("Agg")
    from fivebar_drake.core.validation import MAX_MASS_KG, check_number
    from fivebar_drake.optimal.report import OPTIMAL_FILES, beyond, jump_limits, write
    from fivebar_drake.optimal.top_speed import GAITS as SPEED_GAITS
    from fivebar_drake.pipeline import (SIMULATION_FILES, max_jump_scenario, run_simulation,
                                        write_simulation)
    from fivebar_drake.robots.quadruped.config import load_params
    from fivebar_drake.studies.fivebar_leg import with_sets

    params = with_sets(load_params(args.config), args.sets)
    for flag, value, high in (("--height", args.height, 10.0), ("--payload", args.payload,
                                                                 MAX_MASS_KG)):
        if value is not None:
            try:
                check_number(flag, value, 0.0, high, low_open=flag == "--height")
            except ParameterError as err:
                raise err.located("command line") from None
    gaits = speed_gaits(args.top_speed)
    out = prepare_output_dir(args.out or "out/optimal", "--out", OPTIMAL_FILES)
    start = time.perf_counter()
    result, jumps = jump_limits(params, args.height, args.payload or 0.0, gaits)
    files = []
    for stale in (out / "max_jump", *(out / f"top_speed_{kind}{end}" for kind in SPEED_GAITS
                                      for end in ("", "_achieved"))):
        if stale.is_dir():                   # an earlier --simulate's run: never left beside
            for name in SIMULATION_FILES:    # this run's answer (only the names it writes)
                (stale / name).unlink(missing_ok=True)
            with contextlib.suppress(OSError):   # emptied: gone; another file in it: kept
                stale.rmdir()
    try:                    # the simulations; a signal: the answer written first, then 130/143
        if args.simulate and jumps["ceiling"] is None:
            result["max_jump_simulated"] = None
            _err(f"--simulate: no highest jump to simulate ({result['ceiling_why_none']})")
        if args.simulate and jumps["ceiling"] is not None:
            scenario = max_jump_scenario(params, jumps["ceiling"], args.payload or 0.0)
            plan = scenario.gait
            folder = prepare_output_dir(out / "max_jump", "--out", SIMULATION_FILES)
            with signals.gently():
                record = run_simulation(scenario, params, progress=True,
                                        stop=lambda: signals.name)
            summary, files = write_simulation(record, folder)    # an interrupted run's too
            signals.raise_received()
            height = summary["jump"]["height_m"] if summary["jump"] else 0.0
            phases = (summary["any_controller"] or {}).get("phases") or {}
            result["max_jump_simulated"] = {
                "folder": "max_jump", "plan": plan.fields(), "controller": "tracking",
                "height_m": height, "planned_height_m": plan.height_m,
                "share_of_ceiling": height / jumps["ceiling"].body_apex_above_standing_m,
                "verdict": summary["verdict"],
                "achieved": summary["verdict"] in ACHIEVED_VERDICTS,
                "phases": {name: {"floor_Nm": p["floor_Nm"], "asked_Nm": p["asked_Nm"]}
                           for name, p in phases.items()}}
        if args.simulate:
            result["top_speed_simulated"] = {}
            for kind, row in result["top_speed"].items():
                if row["speed_m_s"] == row["speed_m_s"]:
                    tracked, written = _track_top_speed(params, kind, args.payload or 0.0, out,
                                                        signals)
                    result["top_speed_simulated"][kind] = tracked       # kept if interrupted
                    files += written
                    if tracked.get("achieved") is False:           # run, and missed
                        tracked["fastest_achieved"], written = _fastest_achieved(
                            params, row, args.payload or 0.0, out, signals)
                        files += written
    except BaseException:       # Interrupted, or what it became inside compiled code
        if not signals.signum:
            raise
        result["simulation_interrupted"] = signals.name
        write(result, jumps, params, out)
        raise
    files = write(result, jumps, params, out) + files
    say(result["answer"])
    say(f"wrote {len(files)} files to {out.resolve()} in {time.perf_counter() - start:.1f} s:")
    for path in files:
        say(f"  {path}")
    short = beyond(result)
    if short:
        _err(f"beyond the motors for any controller: {short}")
        return 1
    return 0


def _track_top_speed(params, kind: str, payload_kg: float, out, signals) -> tuple[dict, list]:
    """A gait's top speed tracked (pipeline.top_speed_scenario) into out/top_speed_KIND with
    its step check: (its record for optimal.json, the files written)."""
    from fivebar_drake.core.files import prepare_output_dir
    from fivebar_drake.optimal.top_speed import top_speed
    from fivebar_drake.pipeline import (SIMULATION_FILES, run_simulation, run_step_check,
                                        top_speed_scenario, write_simulation)

    found = top_speed(params, kind, payload_kg)                   # cached by jump_limits
    folder = prepare_output_dir(out / f"top_speed_{kind}", "--out", SIMULATION_FILES)
    stop = (lambda: signals.name)
    try:
        with signals.gently():
            record = run_simulation(top_speed_scenario(kind, payload_kg), params,
                                    progress=True, stop=stop)
            half = None if signals.signum else run_step_check(record, progress=True, stop=stop)
    except ParameterError as err:
        return {"folder": folder.name, "why_none": err.message}, []
    summary, files = write_simulation(record, folder, half=half)     # an interrupted run's too
    signals.raise_received()
    asked = max(m["demand_peak_Nm"] for leg in summary["legs"].values() for m in leg.values())
    row = {"folder": folder.name, "speed_m_s": summary["mean_forward_speed_m_s"],
           "share_of_optimum": summary["mean_forward_speed_m_s"] / found.speed_m_s,
           "verdict": summary["verdict"], "achieved": _held(summary),
           "max_tilt_deg": summary["max_tilt_deg"],
           "demand_peak_Nm": asked, "optimum_peak_Nm": max(found.peak_Nm),
           "why_none": "", "fastest_achieved": None}
    return row, files


ACHIEVED_SHARES = (0.95, 0.9, 0.85)   # the fastest achieved: the optimum at these shares of
#                                       its speed first (a plan at the motors' limits leaves the
#                                       feedback nothing),
ACHIEVED_DUTY_STEP = 0.05   # then the top speeds at longer duty factors this far apart


def _held(summary: dict) -> bool:
    """Whether a tracked run did its motion at the plant step and, where it was step-checked,
    at half of it."""
    checked = summary.get("step_check") or {}
    return (summary["verdict"] in ACHIEVED_VERDICTS
            and checked.get("achieved_at_half_step", True))


def _fastest_achieved(params, optimum: dict, payload_kg: float, out,
                      signals) -> tuple[dict, list]:
    """Where a gait's optimum (its TopSpeed.row()) is not achieved when tracked: the optimum's
    own path at each of ACHIEVED_SHARES of its speed (its frequency; the optimum plans the swing
    at the motors' limits, where no feedback fits), then the gait's top speed at each longer duty
    factor (ACHIEVED_DUTY_STEP apart, up to the search's longest: a longer stance asks each foot
    for less force and a duty factor of 0.5 or more has no flight), tracked as the optimum's;
    the first achieved at the plant step and at half of it is written, with its step check, to
    out/top_speed_KIND_achieved: (its record for optimal.json: duty factor, share, planned and
    tracked speed, share of the optimum, verdict; or the plans tried, what each missed and
    whether it was simulated (a plan with no floor is not), files)."""
    import numpy as np

    from fivebar_drake.optimal.top_speed import DUTIES, top_speed
    from fivebar_drake.pipeline import (SIMULATION_FILES, run_simulation, run_step_check,
                                        summarize_run, top_speed_scenario, write_simulation)

    kind, stop, tried = optimum["kind"], (lambda: signals.name), []
    longer = np.arange(optimum["duty_factor"] + ACHIEVED_DUTY_STEP, max(DUTIES[kind]) + 1e-9,
                       ACHIEVED_DUTY_STEP)
    # (the duty factor searched alone, None: the optimum itself; its share)
    plans = ([(None, share) for share in ACHIEVED_SHARES]
             + [(duty, 1.0) for duty in np.round(longer, 3).tolist()])
    for searched, share in plans:
        duty = optimum["duty_factor"] if searched is None else searched
        try:
            with signals.gently():
                record = run_simulation(top_speed_scenario(kind, payload_kg, searched, share),
                                        params, progress=True, stop=stop)
                summary = summarize_run(record)
                half = (run_step_check(record, progress=True, stop=stop)
                        if summary["verdict"] in ACHIEVED_VERDICTS and not signals.signum
                        else None)
        except ParameterError as err:
            tried.append({"duty_factor": duty, "share": share, "missed": err.message,
                          "simulated": False})
            continue
        signals.raise_received()
        if half is not None:
            summary = summarize_run(record, half)
            if _held(summary):
                folder = prepare_output_dir(out / f"top_speed_{kind}_achieved", "--out",
                                            SIMULATION_FILES)
                summary, files = write_simulation(record, folder, half=half)
                planned = share * top_speed(params, kind, payload_kg, duties=(
                    None if searched is None else (searched,))).speed_m_s
                return {"folder": folder.name, "duty_factor": duty, "share": share,
                        "planned_m_s": planned,
                        "speed_m_s": summary["mean_forward_speed_m_s"],
                        "share_of_optimum": (summary["mean_forward_speed_m_s"]
                                             / optimum["speed_m_s"]),
                        "verdict": summary["verdict"], "tried": tried}, files
        tried.append({"duty_factor": duty, "share": share, "missed": summary["answer"],
                      "simulated": True})
    return {"folder": None, "tried": tried}, []


def speed_gaits(text: str | None) -> tuple[str, ...]:
    """The gaits of --top-speed (None: all of them; "none": none), ParameterError naming the
    option and the allowed ones."""
    from fivebar_drake.optimal.top_speed import GAITS

    if text is None:
        return GAITS
    if text.strip() == "none":
        return ()
    names = tuple(n.strip() for n in text.split(","))
    for name in names:
        if name not in GAITS:
            raise ParameterError(f"--top-speed = {text!r}: {name!r} is not one of "
                                 f"{list(GAITS)} (or none)", "", "command line")
    return tuple(dict.fromkeys(names))


def _compare(args, signals) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from fivebar_drake.simulation.comparison import (check_outputs, load_summaries,
                                                     write_comparison)

    check_outputs(args.runs, args.out)            # the outputs and every run read and checked
    load_summaries(args.runs)                     # before the folder is made
    out = check_output_file(args.out, "--out")
    for path in write_comparison(args.runs, out):
        say(f"wrote {path}")
    return 0


def _models(args, signals) -> int:
    from fivebar_drake.simulation.runner import load_run
    from fivebar_drake.robots.quadruped.closure import MODEL_FILES, write_models
    from fivebar_drake.robots.quadruped.mjcf import MJCF_FILE
    from fivebar_drake.simulation.builder import closure_design

    scenario, params = load_run(args.scenario, closure="bushing_rpy", params_file=args.config)
    out = prepare_output_dir(args.out, "--out", (*MODEL_FILES, MJCF_FILE))
    bushing = closure_design(scenario, params).bushing
    for path in write_models(params, bushing, out):
        say(f"wrote {path}")
    return 0


def _index(args, signals) -> int:
    from pathlib import Path

    from fivebar_drake.entry.page import INDEX_FILES, write_index

    for path in write_index(args.folder):
        say(f"wrote {path}")
    say(f"open it: {(Path(args.folder) / INDEX_FILES[1]).resolve().as_uri()}")
    return 0


def parser() -> argparse.ArgumentParser:
    """The command line, every option with its choices and default in --help: the choices of
    this package and of the plugins (core/plugins.py), loaded first."""
    plugins.load()
    top = argparse.ArgumentParser(prog="fivebar-drake", description=__doc__, epilog=EXIT_CODES,
                                  formatter_class=argparse.RawDescriptionHelpFormatter)
    top.add_argument("--version", action="version", version=f"%(prog)s "
                     f"{version('fivebar_drake')} (drake {version('drake')})")
    top.add_argument("--no-plugins", action="store_true",
                     help=f"load no plugin (entry points of {plugins.GROUP}); the environment "
                          f"variable {plugins.DISABLE_ENV}=1 does the same")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND")
    config = dict(metavar="FILE", help="parameter file (TOML, the layout of "
                  "fivebar_drake/data/default.toml); default: the packaged parameters")

    def command(name, run, text):
        p = sub.add_parser(name, help=text, description=text, epilog=EXIT_CODES,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        p.set_defaults(run=run)
        return p

    mechanism = dict(choices=catalog.mechanisms(), default=catalog.FIVEBAR,
                     help="the mechanism (default: %(default)s, the quadruped's 5-bar leg)")
    p = command("analyze", _analyze, "the seed's torque analysis over one cycle of a foot path "
                "(5-bar leg), or another mechanism's analysis")
    p.add_argument("--mechanism", **mechanism)
    p.add_argument("--gait", choices=[k for k, path in PATHS.items() if path.periodic],
                   help="foot path to analyse (a periodic one), 5-bar leg only (default: "
                        "seed_ellipse, the seed's)")
    p.add_argument("--config", **{**config, "help": "parameter file (TOML, the layout of the "
                                  "mechanism's file in fivebar_drake/data/: default.toml for the "
                                  "5-bar leg, NAME.toml for another); default: the packaged one"})
    sets = dict(action="append", metavar="FIELD=VALUE", dest="sets",
                help="change a parameter by its dotted path (as a sweep does), e.g. "
                     "motor.gear_ratio=11.5; repeatable, 5-bar quadruped only")
    p.add_argument("--set", **sets)
    p.add_argument("--out", metavar="DIR",
                   help="output folder; a previous analysis's files in it are replaced "
                        "(default: out/analysis for the 5-bar leg, out/NAME for another)")
    s = command("simulate", _simulate, "Drake simulation of the quadruped's gaits and "
                "maneuvers, or of another mechanism")
    s.add_argument("--mechanism", **mechanism)
    s.add_argument("--scenario", metavar="FILE",
                   help="scenario file (YAML, fields of fivebar_drake.simulation.scenario.Scenario, see "
                        "README); default: the built-in scenario")
    s.add_argument("--config", **{**config, "help": config["help"] + "; overrides the "
                                  "scenario's params_file"})
    s.add_argument("--gait", choices=PATHS,
                   help=f"foot path or maneuver (overrides the scenario's; default: "
                        f"{DEFAULTS.gait})")
    s.add_argument("--duration", type=float, metavar="S",
                   help=f"simulated time in s (overrides the scenario's; default: "
                        f"{DEFAULTS.duration_s:g})")
    s.add_argument("--closure", choices=CLOSURES,
                   help=f"loop closure (overrides the scenario's; default: {DEFAULTS.closure})")
    s.add_argument("--set", **sets)
    s.add_argument("--step-check", action="store_const", const=True,
                   help="run again at half the plant step and report the change of each "
                        "motor's demand p99, RMS and safety factor (verdict marginal where it "
                        "reaches a threshold, or the motion is achieved at one step only); "
                        "quadruped only")
    s.add_argument("--contact-check", action="store_const", const=True,
                   help="run again with the foot contact softer and stiffer (stiffness x0.5 "
                        "and x2, its dissipation with it) and report the band of the worst "
                        "safety factor and of every event figure (verdict marginal where the "
                        "contact decides it); about 2x a plain run's time more; quadruped only")
    s.add_argument("--out", metavar="DIR",
                   help="output folder; a previous run's files in it are removed before the "
                        "run starts (default: out/simulation for the quadruped, "
                        "out/simulation/NAME for another mechanism)")
    def on_dask(name, run, text, spec, out, what, **positional):
        """A command on Dask: its spec, --out, --workers and --scheduler (what: what it does on
        a scheduler)."""
        p = command(name, run, text)
        p.add_argument("spec", metavar="SPEC", help=spec, **positional)
        p.add_argument("--out", metavar="DIR", help=out)
        p.add_argument("--workers", type=int, metavar="N", help="process workers of the local "
                       "cluster, one thread each (default: one per core)")
        p.add_argument("--scheduler", metavar="ADDRESS", help=f"{what} this Dask scheduler "
                       "(tcp://HOST:PORT) instead of a local cluster")

    on_dask("sweep", _sweep, "a parameter sweep of the 5-bar quadruped (closed-form analysis or "
            "simulation points) on a local Dask cluster or an existing one",
            "sweep spec (YAML; see README: fidelity, sampling, vary, config, scenario)",
            "output folder: points.csv, plots, sweep.md; rerunning the same sweep into it "
            "computes only the missing points (default: out/sweep/SPEC's name)",
            "send the sweep to")
    on_dask("envelope", _envelope, "the duty envelope of the hip motors: maneuvers simulated on "
            "a local Dask cluster or an existing one; per motor and maneuver the verdict's "
            "checks, what sizes each motor, the operating points over the envelope and a duty "
            "cycle's winding temperature",
            "envelope spec (YAML; see README: maneuvers, duty_cycle, config, scenario, "
            "duration_s); default: the packaged fivebar_drake/data/envelope_default.yaml",
            "output folder: envelope.md, envelope.json, operating_points.png (its points in "
            "operating_points.npz), duty_cycle.png and a folder per maneuver (default: out/envelope/SPEC's name)",
            "run the maneuvers on", nargs="?")
    on_dask("codesign", _codesign, "co-design of motor (from the actuator catalogue), gearbox "
            "and leg parameters against an envelope's maneuvers: a search judged by closed-form "
            "screening and optimal-maneuver floors, the finalists and the default design "
            "verified by full simulation on a local Dask cluster or an existing one",
            "co-design spec (YAML; see README: variables, requirements, objectives, budget)",
            "output folder: design.md, design.json, design.toml, pareto.png, codesign.journal "
            "and the finalists' envelopes; rerunning the same spec into it resumes (default: "
            "out/codesign/SPEC's name)", "run the finalists' maneuvers on")
    o = command("optimal", _optimal, "what the legs and motors allow for any controller: the "
                "highest vertical jump (beside a bound by another method) and the least peak "
                "motor torque of the jump maneuver to a height (5-bar quadruped)")
    o.add_argument("--config", **config)
    o.add_argument("--set", **sets)
    o.add_argument("--height", type=float, metavar="M", help="the jump maneuver's height "
                   "above standing (m; default: the jump maneuver's, 0.06)")
    o.add_argument("--payload", type=float, metavar="KG", help="mass added to the body (kg; "
                   "default 0)")
    o.add_argument("--top-speed", metavar="GAITS", help="the gaits whose top speed is "
                   "searched, comma-separated from trot, bound and pronk, or none (default: all "
                   "three, about 10 to 30 s each)")
    o.add_argument("--simulate", action="store_const", const=True,
                   help="also simulate the highest jump (the jump maneuver planned at the "
                        "ceiling, the tracking controller pushing with the ceiling's torques) "
                        "into DIR/max_jump and report its apex against the ceiling, and each "
                        "top speed (the optimum's gait, the tracking controller following its "
                        "floor, with the step check) into DIR/top_speed_GAIT and report its "
                        "speed against the optimum's; where that is not achieved, the fastest "
                        "plan that is, at the step and at half of it (the optimum's path at "
                        f"{', '.join(f'{s:.0%}' for s in ACHIEVED_SHARES)} of its speed, "
                        "then the top speeds at longer duty factors), into "
                        "DIR/top_speed_GAIT_achieved".replace("%", "%%"))
    o.add_argument("--out", metavar="DIR", help="output folder: optimal.md, optimal.json, "
                   "optimal_jump.png (default: out/optimal)")
    c = command("compare", _compare, "simulated runs side by side: each motor's verdict and torques (what a foot path or a design costs)")
    c.add_argument("runs", nargs="+", metavar="RUN_DIR", help="output folders of `simulate` runs")
    c.add_argument("--out", default="out/gait_comparison.md", metavar="FILE",
                   help="markdown file; a PNG is written beside it (default: %(default)s)")
    m = command("models", _models, "write the SDF models (Drake) and the MJCF model (MuJoCo) "
                "generated from the parameters")
    m.add_argument("--scenario", metavar="FILE", help="scenario file (YAML) for the bushing "
                   "design (target_loop_gap_m) and its params_file")
    m.add_argument("--config", **{**config, "help": config["help"] + "; overrides the "
                                  "scenario's params_file"})
    m.add_argument("--out", default="sdf", metavar="DIR",
                   help="output folder (default: %(default)s)")
    i = command("index", _index, "the entry page of an output folder: the design's answer, the "
                "fix, the spec sheet, the maneuvers, the pictures and a link to every report and "
                "recording (DIR/index.md and DIR/index.html, read from what the other commands "
                "wrote there)")
    i.add_argument("folder", nargs="?", default="out", metavar="DIR",
                   help="the output folder (default: %(default)s, make demo's)")
    return top


def _commands() -> dict[str, argparse.ArgumentParser]:
    """The parser of each subcommand, by name."""
    return next(a for a in parser()._actions
                if isinstance(a, argparse._SubParsersAction)).choices


def options_markdown() -> str:
    """The README's table of every subcommand's options, from the parser: this package's own
    choices (a plugin's kinds left out, so the table holds with plugins installed)."""
    extra = plugins.plugin_names()
    rows = ["| command | option | default | meaning |", "|---|---|---|---|"]
    for name, command in _commands().items():
        for action in command._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            option = ", ".join(action.option_strings) or action.metavar
            if action.choices:
                option += " {" + ",".join(c for c in action.choices if c not in extra) + "}"
            elif action.option_strings and action.metavar:
                option += f" {action.metavar}"
            default = "" if action.default is None else f"`{action.default}`"
            text = action.help.replace("(default: %(default)s)", "").replace(
                "%(default)s", str(action.default)).replace("%%", "%").strip()
            rows.append(f"| {name} | `{option}` | {default} | {text} |")
    return "\n".join(rows)


def _internal_error(err: BaseException, argv) -> int:
    """Write the traceback to a log file and say where it is."""
    fd, log = tempfile.mkstemp(prefix="fivebar-drake-error-", suffix=".log")
    with open(fd, "w", encoding="utf-8") as f:
        f.write(f"fivebar-drake {version('fivebar_drake')}, arguments {argv!r}\n")
        f.write("".join(traceback.format_exception(err)))
    _err(f"internal error (a bug, not your input): {type(err).__name__}: {err}; the traceback "
         f"is in {log}")
    return EXIT_INTERNAL


def main(argv=None) -> int:
    """Run the command line; returns the exit code (see EXIT_CODES)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if "--no-plugins" in argv:                  # before the parser: its choices load plugins
        plugins.disable()
    try:
        args = parser().parse_args(argv)
    except SystemExit as exit_:             # --help, --version, or a usage error (code 2)
        return int(exit_.code or 0)
    except ParameterError as err:           # a plugin that cannot be imported
        _err(f"error: {err}")
        return 2
    signals = Signals(stop_gently=args.command == "simulate")
    try:
        if getattr(args, "out", None) == "":
            raise ParameterError("--out = '': an empty path; give a folder or file name (or "
                                 "leave --out out for the default)", "--out", "command line")
        if getattr(args, "out", None):
            check_path_name(args.out, "--out")
        with signals:
            # the console entry point holds SIGINT and SIGTERM blocked while it loads
            # (__main__.py); they reach the command only now that its handlers are in place,
            # so one sent at any moment of the loading is this command's, never lost
            signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
            code = args.run(args, signals)
        if signals.signum and code == 0:    # the signal's exception swallowed on its way (a
            _err(f"interrupted by {signals.name}: stopped")   # finalizer, a library's
            return 128 + signals.signum                        # callback): never exit 0
        return code
    except ParameterError as err:
        _err(f"error: {err}")
        return 2
    except Interrupted as err:
        _err(f"{err}: stopped")
        return err.exit_code
    except KeyboardInterrupt:
        _err("interrupted: stopped")
        return 130
    except Exception as err:  # noqa: BLE001  (anything else is a bug: logged, never a traceback)
        if signals.signum:                  # raised by the interrupt inside compiled code
            _err(f"interrupted by {signals.name}: stopped")   # (numba's SystemError): the
            return 128 + signals.signum                        # signal's, not a bug
        return _internal_error(err, argv)
    finally:
        release_folders()                   # the output folders this command held

if __name__ == "__main__":
    sys.exit(main())
