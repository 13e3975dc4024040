"""The motor model (Drake C++ primitives) against hand-computed points and the rated line."""

import dataclasses

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

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
