"""Co-design benchmark (`make bench`): the rate of each level of `fivebar-drake codesign`, per
core (one process), on the packaged demo spec (fivebar_drake/data/codesign_demo.yaml):

- screening: the closed-form trot analysis of many designs of the default leg at once
  (codesign/predict.closed_form: every catalogue motor of the spec at ratios over its range);
- floors: the jump's and the drop's optimal-maneuver floors of a design (predict.floors);
- gait floors: the walk's, bound's and pronk's floors of a design (predict.gait_floors), which
  every trial of the default spec (fivebar_drake/data/codesign_default.yaml) computes anew (its
  robot's mass changes with its actuators, so the per-process cache does not serve it), and a
  whole trial's prediction on that spec (predict.predict: closed form, floors, gait floors);
- full simulation: each maneuver of the spec's envelope for the default design, run as an
  envelope's worker runs it (envelope/maneuver.run_maneuver, output files included).

Prints a line per level, then, as its last line, one JSON object: `screening_designs_per_hour
_per_core` (target >= 1e6), `floor_designs_per_hour_per_core`,
`gait_floor_designs_per_hour_per_core`, `gait_floor_s_per_design` (per maneuver too),
`trial_s` (a default-spec trial's prediction), `simulations_per_hour_per_core` (target >= 1000)
and the figures they come from. `--quick`: a few designs and 0.3 s maneuvers
(a smoke run)."""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from fivebar_drake.codesign.designs import design_of, design_params
from fivebar_drake.codesign.predict import FLOORED, closed_form, floors, gait_floors, predict
from fivebar_drake.codesign.spec import load_codesign_spec
from fivebar_drake.gaits import Landing
from fivebar_drake.envelope.maneuver import run_maneuver

DATA = Path(__file__).resolve().parent.parent / "fivebar_drake" / "data"
SPEC = DATA / "codesign_demo.yaml"
DEFAULT_SPEC = DATA / "codesign_default.yaml"      # its envelope has the walk, bound and pronk
HOUR_S = 3600.0


def designs(spec, count: int) -> list[dict]:
    """count designs: the spec's motors at ratios spread over its gear-ratio range."""
    ratio = next(v for v in spec.vary if v.path == "motor.gear_ratio")
    ratios = np.linspace(ratio.low, ratio.high, max(count // len(spec.motors), 1))
    return [design_of({"motor": m, "motor.gear_ratio": float(r)})
            for m in spec.motors for r in ratios][:count]


def rate(count: int, seconds: float) -> float:
    return count / seconds * HOUR_S


def gait_figures(designs_: list[dict], trial: dict) -> dict:
    """The gait floors' figures (module docstring): each design's walk, bound and pronk floors
    on the default spec (distinct designs: no cache hit), timed per maneuver; then one whole
    trial's prediction of another design."""
    spec = load_codesign_spec(DEFAULT_SPEC)
    gait = [m for m in spec.envelope.maneuvers if m.scenario.gait.kind in FLOORED]
    walls = {m.name: 0.0 for m in gait}
    for d in designs_:
        for m in gait:
            start = time.perf_counter()
            gait_floors(m, design_params(m.params, d), spec.accept)
            walls[m.name] += time.perf_counter() - start
    per_design = sum(walls.values()) / len(designs_)
    print(f"gait floors: {len(designs_)} designs x {len(gait)} maneuvers in "
          f"{sum(walls.values()):.2f} s, {per_design:.2f} s per design ("
          + ", ".join(f"{k} {v / len(designs_):.2f} s" for k, v in walls.items()) + ")")
    start = time.perf_counter()
    predict(spec, [trial])
    trial_s = time.perf_counter() - start
    print(f"a default-spec trial's prediction: {trial_s:.2f} s")
    return {"gait_floor_designs_per_hour_per_core": rate(1, per_design),
            "gait_floor_s_per_design": per_design, "gait_floors_timed": len(designs_),
            "gait_floor_s_per_maneuver": {k: v / len(designs_) for k, v in walls.items()},
            "trial_s": trial_s}


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="a smoke run: few designs, short "
                        "maneuvers")
    args = parser.parse_args()
    spec = load_codesign_spec(SPEC)
    trot = next(m for m in spec.envelope.maneuvers if m.scenario.gait.kind == "trot")
    many = designs(spec, 50 if args.quick else 20_000)
    params = [design_params(trot.params, d) for d in many]
    closed_form(trot, params[:5], spec.accept)               # compiled kernels loaded
    start = time.perf_counter()
    screened = closed_form(trot, params, spec.accept)
    screen_s = time.perf_counter() - start
    assert not any("error" in s for s in screened)
    print(f"screening: {len(params)} designs in {screen_s:.2f} s, "
          f"{rate(len(params), screen_s):.3g} designs/hour/core")
    landing = [m for m in spec.envelope.maneuvers if isinstance(m.scenario.gait, Landing)]
    few = many[:: max(len(many) // (3 if args.quick else 20), 1)]
    start = time.perf_counter()
    for d in few:
        for m in landing:
            floors(m, design_params(m.params, d), spec.accept)
    floor_s = time.perf_counter() - start
    print(f"floors: {len(few)} designs x {len(landing)} maneuvers in {floor_s:.2f} s, "
          f"{rate(len(few), floor_s):.3g} designs/hour/core")
    gaits = gait_figures(few[:1] if args.quick else few[:4], many[-1])
    maneuvers = [dataclasses.replace(m, scenario=dataclasses.replace(m.scenario, duration_s=0.3))
                 for m in spec.envelope.maneuvers] if args.quick else spec.envelope.maneuvers
    run_maneuver(dataclasses.replace(maneuvers[0], scenario=dataclasses.replace(
        maneuvers[0].scenario, duration_s=0.05)))            # imports and kernels loaded
    walls = {}
    for m in maneuvers:
        start = time.perf_counter()
        run_maneuver(m)
        walls[m.name] = time.perf_counter() - start
        print(f"simulation: {m.name} {m.scenario.duration_s:g} s simulated in "
              f"{walls[m.name]:.2f} s wall")
    sims = rate(len(walls), sum(walls.values()))
    print(f"full simulation: {sims:.3g} maneuvers/hour/core")
    print(json.dumps({"screening_designs_per_hour_per_core": rate(len(params), screen_s),
                      "screened": len(params), "screening_s": screen_s,
                      "floor_designs_per_hour_per_core": rate(len(few), floor_s),
                      **gaits,
                      "simulations_per_hour_per_core": sims, "simulation_wall_s": walls,
                      "quick": args.quick}))


if __name__ == "__main__":
    main()
