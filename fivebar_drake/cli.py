"""Command line: `fivebar-drake analyze [--config FILE] [--out DIR]`."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .kinematics import UnreachableError
from .params import ParameterError, load_params


def _analyze(args) -> int:
    import matplotlib

    matplotlib.use("Agg")  # files only, never a window
    from .analysis import analyze
    from .plots import write_plots
    from .report import write_report

    start = time.perf_counter()
    params = load_params(args.config)
    print(f"parameters: {args.config or 'packaged default'}")
    analysis = analyze(params)
    out = Path(args.out)
    written = write_report(analysis, out) + write_plots(analysis, out)
    for model in ("seed", "full"):
        for motor, m in analysis.results["results"][model].items():
            print(f"  {model:>4} motor {motor}: peak {m['peak_torque_Nm']:.3f} N m, "
                  f"static {m['static_torque_Nm']:.3f} N m, SF {m['safety_factor']:.2f} "
                  f"({m['verdict']}), peak speed {m['peak_speed_rad_s']:.2f} rad/s")
    print(f"wrote {len(written)} files to {out.resolve()} in {time.perf_counter() - start:.1f} s:")
    for path in written:
        print(f"  {path}")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="fivebar-drake", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("analyze", help="the seed's torque analysis over the elliptical gait")
    p.add_argument("--config", help="parameter file (TOML); default: the packaged parameters")
    p.add_argument("--out", default="out/analysis", help="output folder (default: %(default)s)")
    p.set_defaults(run=_analyze)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except (ParameterError, UnreachableError) as err:
        print(f"fivebar-drake: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
