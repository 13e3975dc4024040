"""IK + foot Jacobian throughput: vectorised over 10^6 foot targets vs a per-point Python loop
calling the same functions on one target at a time. Prints evaluations per second and the ratio,
both measured in this run. Run with `make bench`."""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")   # one core

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from fivebar_drake.mechanisms.fivebar import foot_jacobian, forward, inverse
from fivebar_drake.robots.quadruped.config import load_params  # noqa: E402


def targets(params, n, rng):
    """n reachable foot targets (m) around the gait ellipse."""
    g = params.gait
    x = rng.uniform(-1.5 * g.a_m, 1.5 * g.a_m, n) + g.x_center_m
    y = rng.uniform(-1.5 * g.b_m, 1.5 * g.b_m, n) + g.y_home_m
    return np.stack([x, y], -1)


def ik_and_jacobian(leg, foot):
    pose = inverse(leg, foot)
    return pose.q, foot_jacobian(leg, pose)


def best_of(repeats, fn):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=1_000_000, help="targets, vectorised")
    parser.add_argument("--loop-n", type=int, default=20_000, help="targets, per-point loop")
    args = parser.parse_args()
    params = load_params()
    rng = np.random.default_rng(0)
    foot = targets(params, args.n, rng)

    t_vec = best_of(3, lambda: ik_and_jacobian(params.leg, foot))
    few = foot[: args.loop_n]
    t_loop = best_of(1, lambda: [ik_and_jacobian(params.leg, f) for f in few])

    q, jac = ik_and_jacobian(params.leg, foot)
    err = np.max(np.abs(forward(params.leg, q).f - foot))
    q_loop, j_loop = ik_and_jacobian(params.leg, few[-1])
    last = args.loop_n - 1
    same = np.array_equal(q_loop, q[last]) and np.array_equal(j_loop, jac[last])

    rate_vec = args.n / t_vec
    rate_loop = args.loop_n / t_loop
    print(f"IK + J_F, knees-out mode, one core (OMP_NUM_THREADS={os.environ['OMP_NUM_THREADS']})")
    print(f"  vectorised : {args.n:>9,d} targets in {t_vec * 1e3:8.1f} ms  "
          f"-> {rate_vec / 1e6:6.2f} M evaluations/s  (best of 3)")
    print(f"  python loop: {args.loop_n:>9,d} targets in {t_loop * 1e3:8.1f} ms  "
          f"-> {rate_loop / 1e3:6.1f} k evaluations/s")
    print(f"  speed-up (vectorised / loop): {rate_vec / rate_loop:,.0f}x")
    print(f"  FK(IK(target)) worst error: {err:.2e} m; loop and vectorised results identical: {same}")
    print(f"  target >= 3 M evaluations/s: {'met' if rate_vec >= 3e6 else 'NOT met'}")


if __name__ == "__main__":
    main()
