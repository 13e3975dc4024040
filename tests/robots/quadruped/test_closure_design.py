"""Bushing design against the 1-DOF explicit step."""

import numpy as np
import pytest

from fivebar_drake.robots.quadruped.closure import bushing_parameters


def step_growth(k, d, m, dt, steps=4000):
    """Largest |x| over the last 10 % of steps of the explicit spring-damper step (symplectic
    Euler) started from x = 1, v = 0: decays towards 0 if stable, grows if not."""
    x, v, peak = 1.0, 0.0, 0.0
    for i in range(steps):
        v += dt * (-k * x - d * v) / m
        x += dt * v
        if not np.isfinite(x):
            return np.inf
        if i >= 0.9 * steps:
            peak = max(peak, abs(x))
    return peak


@pytest.mark.parametrize("zeta", [0.1, 0.3, 0.7])
def test_bushing_step_is_stable_and_bound_is_tight(zeta):
    m, force, gap = 0.006, 34.0, 4e-6
    bushing, dt = bushing_parameters(m, force, gap, damping_ratio=zeta, margin=0.8)
    k, d = bushing.stiffness_N_m, bushing.damping_N_s_m
    assert force / k == pytest.approx(gap)
    assert d == pytest.approx(2 * zeta * np.sqrt(k * m))
    assert step_growth(k, d, m, dt) < 1e-2
    _, dt_limit = bushing_parameters(m, force, gap, damping_ratio=zeta, margin=1.0)
    assert step_growth(k, d, m, 1.05 * dt_limit) > 1e3          # just past the bound: diverges


def test_bushing_rejects_bad_input():
    with pytest.raises(ValueError, match=r"target_gap_m = 0.0: must be > 0"):
        bushing_parameters(0.01, 30.0, 0.0)
