"""Command line of fivebar_drake:

  fivebar-drake analyze  [--gait seed_ellipse|trot] [--config FILE] [--out DIR]
  fivebar-drake simulate [--gait trot|seed_ellipse] [--scenario FILE] [--duration S]
                         [--closure bushing|bushing_rpy|ball] [--out DIR]
  fivebar-drake compare  RUN_DIR [RUN_DIR ...] [--out FILE]
  fivebar-drake models   [--scenario FILE] [--out DIR]"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .kinematics import UnreachableError
from .footpath import PATHS
from .config import load_params
from .params import ParameterError
from .plant_model import CLOSURES


def _analyze(args) -> int:
    import matplotlib

    matplotlib.use("Agg")  # files only, never a window
    from .analysis import analyze
    from .plots import write_plots
    from .report import write_report

    start = time.perf_counter()
    params = load_params(args.config)
    print(f"parameters: {args.config or 'packaged default'}")
    analysis = analyze(params, path=args.gait)
    out = Path(args.out)
    written = write_report(analysis, out) + write_plots(analysis, out)
    readings = [(model, motor, m) for model, motors in analysis.results["results"].items()
                for motor, m in motors.items()]
    print(f"foot path: {args.gait}; every reading, the lowest safety factor first:")
    for model, motor, m in sorted(readings, key=lambda r: r[2]["safety_factor"]):
        print(f"  {model:>9} motor {motor}: peak {m['peak_torque_Nm']:.3f} N m, "
              f"static {m['static_torque_Nm']:.3f} N m, SF {m['safety_factor']:.2f} "
              f"({m['verdict'].upper()}), peak speed {m['peak_speed_rad_s']:.2f} rad/s")
    print(f"wrote {len(written)} files to {out.resolve()} in {time.perf_counter() - start:.1f} s:")
    for path in written:
        print(f"  {path}")
    return 0


def _simulate(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from .analysis import analyze
    from .recording import write_recording
    from .scenario import load_scenario
    from .sim_plots import write_sim_plots
    from .simulation import simulate
    from .summary import signals, summarize, write_summary

    scenario = load_scenario(args.scenario, duration_s=args.duration, closure=args.closure,
                             gait=args.gait)
    params = scenario.load_params()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    result, setup = simulate(scenario, params, progress=True)
    sig = signals(result, setup, params, scenario)
    summary = summarize(sig, scenario, params, setup, result,
                        analyze(params).results["results"]["seed"])
    written = write_summary(summary, params, out)
    written += write_sim_plots(sig, setup.legs, params, summary, out)
    written.append(write_recording(out / "run.rrd", sig, setup, params, scenario,
                                   result.table["state"], summary))
    print(f"{summary['gait']} gait, {summary['closure']} closure: {summary['duration_s']:.2f} s "
          f"simulated, {summary['real_time_factor']:.2f}x real time, worst loop gap "
          f"{summary['max_loop_gap_m'] * 1e3:.4f} mm, {summary['cycles_in_window']} whole cycles, "
          f"walking {summary['mean_forward_speed_m_s']:.3f} m/s (gait "
          f"{summary['gait_speed_m_s']:.3f} m/s), largest tilt {summary['max_tilt_deg']:.1f} deg")
    for leg, motors in summary["legs"].items():
        print("  " + leg + ": " + ", ".join(
            f"{m} demand p99 {v['demand_p99_Nm']:.2f} N m (RMS {v['rms_torque_Nm']:.2f}, "
            f"SF {v['safety_factor']:.2f} {v['verdict']})" for m, v in motors.items()))
    print(f"verdict: {summary['verdict'].upper()} (worst motor {summary['worst_motor']})")
    print(summary["answer"])
    print(f"wrote {len(written)} files to {out.resolve()}:")
    for path in written:
        print(f"  {path}")
    print(f"open the recording with: rerun {out / 'run.rrd'}")
    if result.error:
        print(f"fivebar-drake: error: the run stopped early: {result.error}", file=sys.stderr)
        return 1
    if summary["verdict"] == "insufficient":
        print(f"fivebar-drake: error: no verdict: {summary['answer']}", file=sys.stderr)
        return 1
    return 0


def _compare(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from .comparison import write_comparison

    for path in write_comparison(args.runs, Path(args.out)):
        print(f"wrote {path}")
    return 0


def _models(args) -> int:
    from .scenario import load_scenario
    from .sdf_model import write_models
    from .simulation import closure_parameters

    scenario = load_scenario(args.scenario, closure="bushing_rpy")
    params = scenario.load_params()
    _, bushing, _, _ = closure_parameters(scenario, params)
    for path in write_models(params, bushing, Path(args.out)):
        print(f"wrote {path}")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="fivebar-drake", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("analyze", help="the seed's torque analysis over one cycle of a foot path")
    p.add_argument("--gait", choices=PATHS, default="seed_ellipse",
                   help="foot path to analyse (default: %(default)s, the seed's)")
    p.add_argument("--config", help="parameter file (TOML); default: the packaged parameters")
    p.add_argument("--out", default="out/analysis", help="output folder (default: %(default)s)")
    p.set_defaults(run=_analyze)
    s = sub.add_parser("simulate", help="Drake simulation of the trotting quadruped")
    s.add_argument("--scenario", help="scenario file (YAML); default: built-in trot scenario")
    s.add_argument("--duration", type=float, help="simulated time in s (overrides the scenario)")
    s.add_argument("--gait", choices=PATHS,
                   help="foot path (overrides the scenario's, default trot)")
    s.add_argument("--closure", choices=CLOSURES,
                   help="loop closure (overrides the scenario's, default bushing)")
    s.add_argument("--out", default="out/simulation", help="output folder (default: %(default)s)")
    s.set_defaults(run=_simulate)
    c = sub.add_parser("compare", help="simulated runs side by side: what the foot path costs")
    c.add_argument("runs", nargs="+", help="output folders of `simulate` runs")
    c.add_argument("--out", default="out/gait_comparison.md",
                   help="markdown file; a PNG is written beside it (default: %(default)s)")
    c.set_defaults(run=_compare)
    m = sub.add_parser("models", help="write the SDF models generated from the parameters")
    m.add_argument("--scenario", help="scenario file (YAML) for the bushing design")
    m.add_argument("--out", default="sdf", help="output folder (default: %(default)s)")
    m.set_defaults(run=_models)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except (ParameterError, UnreachableError, ValueError) as err:
        print(f"fivebar-drake: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
