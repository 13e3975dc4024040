"""Sweep benchmark (`make bench`): closed-form design points per second on one core (each a whole
gait cycle of N samples with IK and mode tracking, the full model's torques and the verdicts,
through sweep.points.analysis_rows in tasks of engine.ANALYSIS_CHUNK points, as a worker runs them), and the parallel efficiency of a
simulation sweep on a local Dask cluster: the throughput of 2 workers over that of 1 on the same
sweep, divided by 2. Prints a table, then, as its last line, one JSON object:
analysis_points_per_s, analysis_points_per_s_geometry_varied, simulation_parallel_efficiency
(and the wall times)."""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from fivebar_drake.robots.quadruped.config import load_params
from fivebar_drake.sweep.engine import ANALYSIS_CHUNK, run_sweep
from fivebar_drake.sweep.points import analysis_rows
from fivebar_drake.sweep.spec import spec_from_dict

SETTINGS = ("seed_ellipse", "full_trot")    # the spec's defaults: foot path, load model
ANALYSIS = {"sampling": "random", "seed": 1, "vary": {
    "gait.frequency_hz": {"range": [0.5, 3.0]}, "gait.a_m": {"range": [0.03, 0.08]},
    "gait.b_m": {"range": [0.01, 0.04]}, "motor.gear_ratio": {"range": [4.0, 16.0]}}}
GEOMETRY = {"sampling": "grid", "vary": {"leg.ce_m": {"range": [0.135, 0.155], "num": 5},
                                         "gait.frequency_hz": {"range": [0.5, 3.0],
                                                               "num": 2000}}}


def points_per_second(spec_data: dict, samples: int | None) -> tuple[float, int]:
    data = {**spec_data, **({"samples": samples} if samples else {})}
    points = list(enumerate(spec_from_dict(data, Path(".")).points()))
    base = load_params()
    analysis_rows(base, SETTINGS, points[:10])          # compile
    best = 0.0
    for _ in range(3):       # in the tasks of a sweep: ANALYSIS_CHUNK points each
        start = time.perf_counter()
        rows = [row for i in range(0, len(points), ANALYSIS_CHUNK)
                for row in analysis_rows(base, SETTINGS, points[i:i + ANALYSIS_CHUNK])]
        best = max(best, len(points) / (time.perf_counter() - start))
    assert all(r["status"] == "ok" for r in rows), "a benchmark point failed"
    return best, len(points)


def simulation_wall(workers: int, points: int, duration: float) -> float:
    """Wall time of a simulation sweep on a local cluster of `workers` that has started and
    run one short point on each worker already (the workers' imports and compiled caches are
    loaded: a long sweep pays that once)."""
    from dask.distributed import Client, LocalCluster

    spec = spec_from_dict({"fidelity": "simulation", "duration_s": duration, "vary": {
        "gait.frequency_hz": [round(0.9 + 0.05 * i, 3) for i in range(points)]}}, Path("."))
    warm = spec_from_dict({"fidelity": "simulation", "duration_s": 0.05, "vary": {
        "gait.frequency_hz": [1.0 + 0.01 * i for i in range(workers)]}}, Path("."))
    with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=":0") as cluster, \
            Client(cluster) as client, tempfile.TemporaryDirectory() as tmp:
        run_sweep(warm, Path(tmp) / "warm", progress=False, client=client)
        start = time.perf_counter()
        result = run_sweep(spec, Path(tmp) / "run", progress=False, client=client)
        wall = time.perf_counter() - start
    assert result.failed == 0
    return wall


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--points", type=int, default=20_000, help="analysis points")
    parser.add_argument("--sim-points", type=int, default=6, help="simulation points")
    parser.add_argument("--sim-duration", type=float, default=3.0, help="simulated s per point")
    args = parser.parse_args()
    rate, n = points_per_second(ANALYSIS, args.points)
    print(f"analysis: {n} random designs (gait and gear ratio varied), one core: "
          f"{rate:,.0f} points/s (best of 3)")
    geo_rate, geo_n = points_per_second(GEOMETRY, None)
    print(f"analysis: {geo_n} designs over 5 leg geometries, one core: {geo_rate:,.0f} points/s")
    one = simulation_wall(1, args.sim_points, args.sim_duration)
    two = simulation_wall(2, args.sim_points, args.sim_duration)
    efficiency = one / two / 2
    print(f"simulation: {args.sim_points} points of {args.sim_duration:g} s: 1 worker {one:.1f} s, "
          f"2 workers {two:.1f} s: parallel efficiency {efficiency:.2f}")
    print(json.dumps({"analysis_points_per_s": rate,
                      "analysis_points_per_s_geometry_varied": geo_rate,
                      "simulation_parallel_efficiency": efficiency,
                      "simulation_wall_s": {"1_worker": one, "2_workers": two}}))


if __name__ == "__main__":
    main()
