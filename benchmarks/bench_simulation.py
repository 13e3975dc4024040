"""Simulation benchmark: a trot of --duration seconds (default 10) with each loop closure.
Prints the real-time factor, the worst loop gap, and the share of wall time spent writing the
Rerun recording (simulation + post-processing + recording = the whole `simulate` job).
Run with `make bench`."""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from fivebar_drake.analysis import analyze
from fivebar_drake.recording import write_recording
from fivebar_drake.scenario import load_scenario
from fivebar_drake.simulation import simulate
from fivebar_drake.summary import signals, summarize


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--duration", type=float, default=10.0)
    args = parser.parse_args()
    print(f"{args.duration:g} s trot, default scenario; one core")
    print(f"{'closure':>8} {'step (ms)':>9} {'sim wall (s)':>12} {'real-time':>9} "
          f"{'worst gap (mm)':>14} {'rec (s)':>8} {'logging share':>13} {'rrd (MB)':>8}")
    for closure in ("bushing", "ball"):
        scenario = load_scenario(duration_s=args.duration, closure=closure)
        params = scenario.load_params()
        result, setup = simulate(scenario, params, progress=False)
        start = time.perf_counter()
        sig = signals(result, setup, params, scenario)
        post = time.perf_counter() - start
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "run.rrd"
            start = time.perf_counter()
            summary = summarize(sig, scenario, params, setup, result,
                                analyze(params).results["results"]["seed"])
            write_recording(path, sig, setup, params, scenario, result.table["state"], summary)
            rec = time.perf_counter() - start
            size = path.stat().st_size / 1e6
        total = result.wall_s + post + rec
        print(f"{closure:>8} {setup.time_step_s * 1e3:9.4f} {result.wall_s:12.2f} "
              f"{sig.t[-1] / result.wall_s:8.2f}x {np.max(sig.gap) * 1e3:14.4f} "
              f"{rec:8.2f} {rec / total * 100:12.1f}% {size:8.1f}"
              + (f"  stopped early: {result.error}" if result.error else ""))


if __name__ == "__main__":
    main()
