"""The actuator (core/motor.py): the envelope against hand-computed points of the voltage and
current limits, the Drake MotorModel against them, the gear ratio's one meaning, the seed's
figures from the default motor-side data, the torque-current table and the plain line."""

import dataclasses
import math

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from fivebar_drake.core.motor import (BldcMotor, LineMotor, MotorModel, build_motor, clip_flags,
                                      with_gear)
from fivebar_drake.core.validation import ParameterError


@pytest.fixture()
def motor():
    """Round numbers: k_t = 0.1 N m/A, R = 1 ohm, phase amplitude V_bus / sqrt(3) = 10 V,
    peak 5 A, N = 10, eta = 0.8: back-EMF 0.1 / 1.5 V s/rad; peak output 10 * 0.8 * 0.1 * 5 =
    4 N m; no-load 10 V / (0.1 / 1.5) = 150 rad/s at the motor, 15 rad/s at the output; corner
    (10 - 1 * 5) / (0.1 / 1.5) = 75 rad/s, 7.5 rad/s at the output."""
    return BldcMotor(torque_constant_Nm_per_A=0.1, winding_resistance_ohm=1.0,
                     bus_voltage_V=10.0 * math.sqrt(3.0), peak_current_A=5.0, gear_ratio=10.0,
                     gear_efficiency=0.8, rotor_inertia_kg_m2=1e-6, coulomb_friction_Nm=0.02,
                     viscous_friction_Nm_s=0.002)


def motor_outputs(motor, command, speed):
    """(applied, delivered) torques of the MotorModel for commands and joint speeds (n,), after
    its first sample."""
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


def test_derived_figures_by_hand(motor):
    assert motor.peak_torque_Nm == pytest.approx(4.0, rel=1e-14)
    assert motor.no_load_speed_rad_s == pytest.approx(15.0, rel=1e-14)
    assert motor.braking_peak_torque_Nm == pytest.approx(10 * 0.1 * 5 / 0.8, rel=1e-14)
    up = motor.torque_limit([0.0, 7.5, 10.0, 15.0, 20.0])
    # at 10 rad/s: i = (10 - 100 / 15) / 1 = 10/3 A -> 10 * 0.8 * 0.1 * 10/3 N m
    np.testing.assert_allclose(up, [4.0, 4.0, 8.0 / 3.0, 0.0, 0.0], atol=1e-13)


@pytest.mark.parametrize("command, speed, applied, clip", [
    (3.0, 0.0, 3.0, ""),                                        # inside the limits
    (10.0, 0.0, 4.0, "peak"),                                   # stall: the peak current
    (10.0, 5.0, 4.0 - 0.02 - 0.01, "peak"),                     # below the corner: still flat
    (10.0, 10.0, 8.0 / 3.0 - 0.02 - 0.02, "line"),              # the voltage limits it
    (-10.0, 10.0, -6.25 - 0.02 - 0.02, "peak"),                 # braking: N tau_m / eta
    (10.0, -10.0, 6.25 + 0.02 + 0.02, "peak"),
    (4.0, 20.0, 0.0 - 0.02 - 0.04, "line"),                     # beyond no-load speed
    (-1.0, -1.0, -1.0 + 0.02 + 0.002, ""),                      # friction opposes the motion
    (1.0, 0.01, 1.0 - 0.02 * 0.2 - 0.002 * 0.01, ""),           # Coulomb ramps in
])
def test_motor_model_points(motor, command, speed, applied, clip):
    out, delivered = motor_outputs(motor, command, speed)
    assert out[0] == pytest.approx(applied, abs=1e-12)
    at_peak, at_line = clip_flags(motor, command, delivered)
    assert bool(at_peak[0]) == (clip == "peak")
    assert bool(at_line[0]) == (clip == "line")


def test_envelope_obeys_the_voltage_equation(motor):
    """Every point of the driving envelope beyond the corner draws the current whose
    R i + (k_t / 1.5) w_m equals the phase voltage V_bus / sqrt(3), and below it the peak
    current: the envelope's own formula checked against the circuit."""
    speed = np.linspace(0.0, 14.9, 150)
    tau = motor.torque_limit(speed)
    i = tau / (motor.gear_ratio * motor.gear_efficiency * motor.torque_constant_Nm_per_A)
    volts = motor.winding_resistance_ohm * i + motor.torque_constant_Nm_per_A / 1.5 * (
        motor.gear_ratio * speed)
    corner = speed > 7.5
    np.testing.assert_allclose(volts[corner], motor.bus_voltage_V / math.sqrt(3), rtol=1e-12)
    np.testing.assert_allclose(i[~corner], motor.peak_current_A, rtol=1e-12)
    assert np.all(volts[~corner] <= motor.bus_voltage_V / math.sqrt(3) * (1 + 1e-12))


def test_drake_model_saturates_on_the_envelope(motor):
    speed = np.linspace(-20.0, 20.0, 81)
    frictionless = dataclasses.replace(motor, coulomb_friction_Nm=0.0, viscous_friction_Nm_s=0.0)
    _, up = motor_outputs(frictionless, np.full(speed.size, 50.0), speed)
    _, down = motor_outputs(frictionless, np.full(speed.size, -50.0), speed)
    np.testing.assert_allclose(up, np.where(speed >= 0, motor.torque_limit(speed),
                                            motor.braking_peak_torque_Nm), atol=1e-12)
    np.testing.assert_allclose(down, np.where(speed <= 0, -motor.torque_limit(speed),
                                              -motor.braking_peak_torque_Nm), atol=1e-12)


def test_gear_ratio_has_one_meaning(motor):
    """Motor-side data fixed: output torque x N eta, speeds / N, reflected inertia x N^2."""
    doubled = with_gear(motor, 20.0)
    assert doubled.peak_torque_Nm == pytest.approx(2 * motor.peak_torque_Nm, rel=1e-14)
    assert doubled.no_load_speed_rad_s == pytest.approx(motor.no_load_speed_rad_s / 2, rel=1e-14)
    assert doubled.reflected_inertia_kg_m2 == pytest.approx(4 * motor.reflected_inertia_kg_m2)
    np.testing.assert_allclose(doubled.torque_limit(np.linspace(0, 7.5, 30)),
                               2 * motor.torque_limit(2 * np.linspace(0, 7.5, 30)), rtol=1e-13)


def test_default_motor_gives_the_seeds_figures(params):
    m = params.motor
    assert m.peak_torque_Nm == pytest.approx(5.0, rel=1e-12)
    assert m.no_load_speed_rad_s == pytest.approx(4 * math.pi, rel=1e-12)   # 120 RPM
    assert m.gear_ratio == 8.0


def test_speed_margins(motor):
    """Driving at 2 N m needs 2.5 A: the back-EMF allows (10 - 2.5) * 15 / 10 = 11.25 rad/s."""
    margin, outside = motor.speed_margins(np.array([2.0, 2.0, -2.0, 5.0]),
                                          np.array([9.0, 12.0, 12.0, 1.0]))
    assert margin[0] == pytest.approx(11.25 / 9.0, rel=1e-13)
    assert margin[1] == pytest.approx(11.25 / 12.0, rel=1e-13) and outside[1]
    assert margin[2] == math.inf and not outside[2]           # braking: the speed helps
    assert math.isnan(margin[3]) and not outside[3]           # beyond the peak: torque's check


def test_torque_current_table(motor):
    """A saturating table replaces k_t i: the peak follows the table at the peak current, and
    currents invert it."""
    table = dataclasses.replace(motor, current_table_A=(0.0, 2.0, 6.0),
                                torque_table_Nm=(0.0, 0.2, 0.4))
    assert table.peak_torque_Nm == pytest.approx(10 * 0.8 * (0.2 + 0.2 * 3 / 4), rel=1e-14)
    assert table.currents(np.array([10 * 0.8 * 0.3]), np.array([1.0]))[0] == pytest.approx(4.0)
    with pytest.raises(ParameterError, match="current_table_A"):
        dataclasses.replace(motor, current_table_A=(0.0, 2.0), torque_table_Nm=(0.0, 0.2))


def test_line_motor_is_the_plain_line():
    line = build_motor({"model": "torque_speed_line", "motor_stall_torque_Nm": 0.625,
                        "motor_no_load_speed_rad_s": 32 * math.pi, "gear_ratio": 8.0,
                        "rotor_inertia_kg_m2": 0.0, "coulomb_friction_Nm": 0.0,
                        "viscous_friction_Nm_s": 0.0})
    assert isinstance(line, LineMotor) and line.peak_torque_Nm == pytest.approx(5.0)
    speed = np.array([0.0, np.pi, 2 * np.pi, 4 * np.pi, 5 * np.pi])
    np.testing.assert_allclose(line.torque_limit(speed), 5.0 * np.clip(1 - speed / (4 * np.pi),
                                                                       0, 1), atol=1e-14)
    assert line.limits(np.array([3.0]))[1][0] == pytest.approx(-5.0)    # braking: the stall


@pytest.mark.parametrize("change, field", [
    ({"peak_current_A": 100.0}, "motor.peak_current_A"),          # beyond V / sqrt(3) / R
    ({"gear_efficiency": 1.5}, "motor.gear_efficiency"),
    ({"winding_resistance_ohm": 0.0}, "motor.winding_resistance_ohm"),
    ({"bus_voltage_V": -1.0}, "motor.bus_voltage_V"),
])
def test_bad_actuator_values(motor, change, field):
    with pytest.raises(ParameterError) as err:
        dataclasses.replace(motor, **change)
    assert err.value.field == field


def test_old_line_keys_are_explained():
    with pytest.raises(ParameterError, match="torque_speed_line"):
        build_motor({"peak_torque_Nm": 5.0, "gear_ratio": 8.0})
