"""Motor model against hand-computed points; bushing design against the 1-DOF explicit step."""

import dataclasses

import numpy as np
import pytest

from fivebar_drake.bushing import bushing_parameters
from fivebar_drake.footpath import stance_weight
from fivebar_drake.systems import motor_torque


@pytest.fixture()
def motor(params):
    return dataclasses.replace(params.motor, peak_torque_Nm=5.0, no_load_speed_rad_s=4 * np.pi,
                               coulomb_friction_Nm=0.02, viscous_friction_Nm_s=0.002)


@pytest.mark.parametrize("command, speed, applied, clip", [
    (3.0, 0.0, 3.0, ""),                                      # inside the limits, no friction
    (10.0, 0.0, 5.0, "peak"),                                 # stall: peak torque
    (10.0, 2 * np.pi, 2.5 - 0.02 - 0.002 * 2 * np.pi, "line"),  # half no-load speed: half torque
    (-10.0, 2 * np.pi, -5.0 - 0.02 - 0.002 * 2 * np.pi, "peak"),  # braking: full torque
    (4.0, 20.0, 0.0 - 0.02 - 0.04, "line"),                   # beyond no-load speed: nothing
    (-1.0, -1.0, -1.0 + 0.02 + 0.002, ""),                    # friction opposes the motion
])
def test_motor_model_points(motor, command, speed, applied, clip):
    out = motor_torque(motor, command, speed, smoothing_rad_s=1e-9)
    assert out.joint == pytest.approx(applied, abs=1e-12)
    assert out.delivered - out.friction == pytest.approx(out.joint, abs=1e-15)
    assert bool(out.clipped_peak) == (clip == "peak")
    assert bool(out.clipped_line) == (clip == "line")


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


def test_stance_weight_hands_load_over_smoothly(params):
    """0 in swing, 1 in mid-stance, rising and falling smoothly over the transfer time."""
    import dataclasses

    gait = dataclasses.replace(params.gait, duty_factor=0.75, frequency_hz=1.0)
    t = np.linspace(0.0, 1.0, 100001)
    w = stance_weight(gait, "trot", t, 0.0, 0.04)
    assert np.all(w[t < 0.25] == 0.0)                       # swing: u < 1 - beta
    assert np.all(w[(t > 0.29) & (t < 0.96)] == 1.0)        # 40 ms after touchdown .. before lift-off
    assert np.max(np.abs(np.diff(w))) < 1e-3                # continuous at 10 us steps
    assert w[np.searchsorted(t, 0.27)] == pytest.approx(0.5, abs=1e-3)   # halfway up at 20 ms
