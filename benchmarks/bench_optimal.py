"""Optimal-maneuver benchmark: the vertical jump's ceiling and floor (optimal/vertical_jump.py)
of the default robot on one core, warm (each computed once before timing), the median of
--repeats; the linear program's solve (Drake MathematicalProgram) for the same floor; the
gaits' floors (optimal/gait_floor.py: trot, walk, bound, pronk; uncached: each repeat solves
them); the stand-up's floor (optimal/stand_up.py). Prints a table, then one JSON object:
ceiling_s, floor_s, lp_s, lp_solver, bisection_steps, KIND_floor_s, KIND_programs per gait,
stand_up_floor_s."""

from __future__ import annotations

import argparse
import json
import statistics
import time

from fivebar_drake.gaits import Jump as JumpPath
from fivebar_drake.optimal import gait_floor as gf
from fivebar_drake.optimal import stand_up
from fivebar_drake.optimal import top_speed as ts
from fivebar_drake.optimal import vertical_jump as vj
from fivebar_drake.robots.quadruped.config import load_params, with_path_defaults


def timed(function, repeats: int) -> tuple[float, object]:
    """(median seconds, the last result) of function() over repeats calls."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--speed-repeats", type=int, default=1)
    args = parser.parse_args()
    params, plan = load_params(None), JumpPath()
    standing = -params.gait.y_home_m
    u0, u1 = vj.reach(params)

    def ceiling():
        return vj.push(vj.stroke(params, u0, u1), standing)

    def maneuver():
        return vj.stroke(params, standing - plan.crouch_m, standing + plan.extension_m)

    def floor():
        return vj.torque_floor(maneuver(), standing, plan.height_m)

    steps = 0
    original = vj.push

    def counting(*a, **k):
        nonlocal steps
        steps += 1
        return original(*a, **k)

    ceiling(), floor()                                   # warm: compiled kernels loaded
    ceiling_s, jump = timed(ceiling, args.repeats)
    floor_s, (peak, _) = timed(floor, args.repeats)
    vj.push = counting
    floor()
    vj.push = original
    stroke = maneuver()
    lp_s, (lp_peak, solver) = timed(lambda: vj.box_floor_lp(stroke, standing, plan.height_m),
                                    args.repeats)
    gaits = {kind: timed(lambda kind=kind: gf._solve(with_path_defaults(params, kind),
                                                    gf.foot_path(kind), 0.0, False, False),
                         args.repeats) for kind in gf.KINDS}
    stand_up.stand_up_floor(params)                      # warm
    stand_s, rise = timed(lambda: stand_up.stand_up_floor(params), args.repeats)
    print(f"vertical jump, default robot, {vj.GRID_POINTS} nodes, median of {args.repeats}:")
    print(f"  ceiling (highest jump, {jump.com_rise_from_standing_m * 1e3:.1f} mm): "
          f"{ceiling_s * 1e3:.0f} ms")
    print(f"  floor of the {plan.height_m * 1e3:.0f} mm jump ({peak:.3f} N m, {steps} pushes "
          f"by bisection): {floor_s * 1e3:.0f} ms   (target <= 10 s)")
    print(f"  torque-box floor, Drake linear program ({lp_peak:.3f} N m, {solver}): "
          f"{lp_s * 1e3:.0f} ms")
    for kind, (seconds, floor) in gaits.items():
        print(f"  {kind} floor ({floor.floor_Nm:.3f} N m, {floor.programs} linear programs, "
              f"pitch residual {floor.moment_residual_Nm:.1e} N m): {seconds * 1e3:.0f} ms   "
              f"(target <= 10 s)")
    print(f"  stand-up floor ({rise.floor_Nm:.3f} N m, a 1 mm grid): {stand_s * 1e3:.0f} ms")

    def uncached_top_speed(kind):
        ts._CACHE.clear()
        gf._FLOORS.clear()
        return ts.top_speed(params, kind)

    speeds = {kind: timed(lambda kind=kind: uncached_top_speed(kind), args.speed_repeats)
              for kind in ts.GAITS}
    for kind, (seconds, top) in speeds.items():
        print(f"  {kind} top speed ({top.speed_m_s:.3f} m/s, {top.checks} checks, limited by "
              f"{top.limited_by}): {seconds:.1f} s   (target <= 60 s)")
    print(json.dumps({"ceiling_s": ceiling_s, "floor_s": floor_s, "lp_s": lp_s,
                      "lp_solver": solver, "bisection_steps": steps,
                      **{f"{kind}_floor_s": seconds for kind, (seconds, _) in gaits.items()},
                      **{f"{kind}_programs": f.programs for kind, (_, f) in gaits.items()},
                      "stand_up_floor_s": stand_s,
                      **{f"{kind}_top_speed_s": seconds for kind, (seconds, _) in speeds.items()},
                      **{f"{kind}_top_speed_m_s": t.speed_m_s for kind, (_, t) in speeds.items()},
                      **{f"{kind}_top_speed_checks": t.checks for kind, (_, t) in speeds.items()}}))


if __name__ == "__main__":
    main()
