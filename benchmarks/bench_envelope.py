"""Duty-envelope benchmark (`make bench`): the default envelope (fivebar_drake/data/
envelope_default.yaml) on started local clusters of 1 and of 2 process workers (each worker has
run a short maneuver already: its imports and compiled kernels are loaded, as in a long
envelope), through envelope.run.run_envelope, output files included. Prints a line per maneuver,
then, as its last line, one JSON object: per maneuver its `rtf` (simulated over stepping wall
time, from its summary, on 1 worker) and `time_step_s`, and `wall_s_1_worker`,
`wall_s_2_workers`, `parallel_efficiency` (wall on 1 / wall on 2 / 2; target >= 0.8).
`--duration S` shortens every maneuver (a smoke run)."""

from __future__ import annotations

import argparse
import dataclasses
import json
import tempfile
import time
from pathlib import Path

from fivebar_drake.envelope.run import run_envelope
from fivebar_drake.envelope.spec import DEFAULT_SPEC, load_envelope_spec


def shortened(spec, duration_s: float | None):
    """The spec with every maneuver's duration set to duration_s (None: as it is)."""
    if duration_s is None:
        return spec
    return dataclasses.replace(spec, maneuvers=tuple(
        dataclasses.replace(m, scenario=dataclasses.replace(m.scenario, duration_s=duration_s))
        for m in spec.maneuvers))


def envelope_wall(spec, workers: int) -> tuple[float, dict]:
    """(wall time s, envelope.json's dictionary) of the envelope on a started cluster of
    `workers` that has run a 0.05 s maneuver on each worker."""
    from dask.distributed import Client, LocalCluster

    warm = shortened(dataclasses.replace(spec, maneuvers=tuple(
        dataclasses.replace(spec.maneuvers[0], name=f"warm{k}") for k in range(workers)),
        duty_cycle=()), 0.05)
    with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=":0") as cluster, \
            Client(cluster) as client, tempfile.TemporaryDirectory() as tmp:
        run_envelope(warm, Path(tmp) / "warm", progress=False, client=client)
        start = time.perf_counter()
        run = run_envelope(spec, Path(tmp) / "run", progress=False, client=client)
        wall = time.perf_counter() - start
    failed = [n for n, e in run.report["maneuvers"].items() if e["status"] == "failed"]
    assert not failed, f"maneuvers failed: {failed}"
    return wall, run.report


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("spec", nargs="?", default=str(DEFAULT_SPEC), help="envelope spec")
    parser.add_argument("--duration", type=float, help="simulated s of every maneuver")
    args = parser.parse_args()
    spec = shortened(load_envelope_spec(args.spec), args.duration)
    one, report = envelope_wall(spec, 1)
    two, _ = envelope_wall(spec, 2)
    maneuvers = {}
    for name, entry in report["maneuvers"].items():
        maneuvers[name] = {"rtf": entry["timing"]["real_time_factor"],
                           "time_step_s": entry["time_step_s"]}
        print(f"{name}: {entry['duration_s']:g} s simulated at "
              f"{entry['time_step_s'] * 1e3:g} ms, {maneuvers[name]['rtf']:.2f}x real time, "
              f"{entry['verdict']}")
    efficiency = one / two / 2
    print(f"envelope of {len(spec.maneuvers)} maneuvers: 1 worker {one:.1f} s, 2 workers "
          f"{two:.1f} s: parallel efficiency {efficiency:.2f}")
    print(json.dumps({"maneuvers": maneuvers, "wall_s_1_worker": one, "wall_s_2_workers": two,
                      "parallel_efficiency": efficiency}))


if __name__ == "__main__":
    main()
