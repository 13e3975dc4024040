"""Co-design benchmark (`make bench`): the rate of each level of `fivebar-drake codesign`, per
core (one process), on the packaged demo spec (fivebar_drake/data/codesign_demo.yaml):

- screening: the closed-form trot analysis of many designs of the default leg at once
  (codesign/predict.closed_form: every catalogue motor of the spec at ratios over its range);
- floors: the jump's and the drop's optimal-maneuver floors of a design (predict.floors);
- full simulation: each maneuver of the spec's envelope for the default design, run as an
  envelope's worker runs it (envelope/maneuver.run_maneuver, output files included).

Prints a line per level, then, as its last line, one JSON object: `screening_designs_per_hour
_per_core` (target >= 1e6), `floor_designs_per_hour_per_core`, `simulations_per_hour_per_core`
(target >= 1000) and the figures they come from. `--quick`: a few designs and 0.3 s maneuvers
(a smoke run)."""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from fivebar_drake.codesign.designs import design_of, design_params
from fivebar_drake.codesign.predict import closed_form, floors
from fivebar_drake.codesign.spec import load_codesign_spec
from fivebar_drake.core.footpath import Landing
from fivebar_drake.envelope.maneuver import run_maneuver

SPEC = Path(__file__).resolve().parent.parent / "fivebar_drake" / "data" / "codesign_demo.yaml"
HOUR_S = 3600.0


def designs(spec, count: int) -> list[dict]:
    """count designs: the spec's motors at ratios spread over its gear-ratio range."""
    ratio = next(v for v in spec.vary if v.path == "motor.gear_ratio")
    ratios = np.linspace(ratio.low, ratio.high, max(count // len(spec.motors), 1))
    return [design_of({"motor": m, "motor.gear_ratio": float(r)})
            for m in spec.motors for r in ratios][:count]


def rate(count: int, seconds: float) -> float:
    return count / seconds * HOUR_S


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
                      "simulations_per_hour_per_core": sims, "simulation_wall_s": walls,
                      "quick": args.quick}))


if __name__ == "__main__":
    main()
