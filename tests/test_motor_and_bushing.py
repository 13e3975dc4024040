"""Motor model against hand-computed points; bushing design against the 1-DOF explicit step."""

import dataclasses

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from fivebar_drake.robots.quadruped.closure import bushing_parameters
from fivebar_drake.core.footpath import stance_weight
from fivebar_drake.core.motor import MotorModel, clip_flags


@pytest.fixture()
def motor(params):
    return dataclasses.replace(params.motor, peak_torque_Nm=5.0, no_load_speed_rad_s=4 * np.pi,
                               coulomb_friction_Nm=0.02, viscous_friction_Nm_s=0.002)


def motor_outputs(motor, command, speed):
    """(applied, delivered) torques of the MotorModel Diagram for commands and joint speeds
    (n,), after its first sample."""
    command, speed = np.atleast_1d(command).astype(float), np.atleast_1d(speed).astype(float)
    n = command.size
    model = MotorModel(motor, np.arange(n), n, period_s=1e-3)
    simulator = Simulator(model)
    context = simulator.get_mutable_context()
    model.GetInputPort("torque_command").FixValue(context, command)
    model.GetInputPort("plant_state").FixValue(context, speed)
    simulator.AdvanceTo(0.5e-3)                    # the sample at t = 0 has been taken
    record = model.GetOutputPort("motor_record").Eval(context).reshape(3, n)
    assert np.array_equal(record[0], command)
    assert np.array_equal(model.GetOutputPort("applied_torque").Eval(context), record[2])
    return record[2], record[1]


@pytest.mark.parametrize("command, speed, applied, clip", [
    (3.0, 0.0, 3.0, ""),                                      # inside the limits, no friction
    (10.0, 0.0, 5.0, "peak"),                                 # stall: peak torque
    (10.0, 2 * np.pi, 2.5 - 0.02 - 0.002 * 2 * np.pi, "line"),  # half no-load speed: half torque
    (-10.0, 2 * np.pi, -5.0 - 0.02 - 0.002 * 2 * np.pi, "peak"),  # braking: full torque
    (4.0, 20.0, 0.0 - 0.02 - 0.04, "line"),                   # beyond no-load speed: nothing
    (-1.0, -1.0, -1.0 + 0.02 + 0.002, ""),                    # friction opposes the motion
    (1.0, 0.01, 1.0 - 0.02 * 0.2 - 0.002 * 0.01, ""),         # Coulomb ramps in below 0.05 rad/s
])
def test_motor_model_points(motor, command, speed, applied, clip):
    out, delivered = motor_outputs(motor, command, speed)
    assert out[0] == pytest.approx(applied, abs=1e-12)
    at_peak, at_line = clip_flags(motor, command, delivered)
    assert bool(at_peak[0]) == (clip == "peak")
    assert bool(at_line[0]) == (clip == "line")


def test_motor_model_saturates_on_the_rated_line(motor):
    """A command beyond the peak delivers exactly the torque-speed line of Motor.torque_limit
    (the analysis' formula) at every speed, motoring; braking always gets the peak."""
    speed = np.linspace(-20.0, 20.0, 81)
    frictionless = dataclasses.replace(motor, coulomb_friction_Nm=0.0, viscous_friction_Nm_s=0.0)
    _, up = motor_outputs(frictionless, np.full(speed.size, 50.0), speed)
    _, down = motor_outputs(frictionless, np.full(speed.size, -50.0), speed)
    np.testing.assert_allclose(up, np.where(speed > 0, motor.torque_limit(speed),
                                            motor.peak_torque_Nm), atol=1e-12)
    np.testing.assert_allclose(down, np.where(speed < 0, -motor.torque_limit(speed),
                                              -motor.peak_torque_Nm), atol=1e-12)


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
