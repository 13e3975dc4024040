"""The actuator (actuators/motor.py): the envelope against hand-computed points of the voltage and
current limits (both quadrants, beyond the no-load speed too), the Drake MotorModel against them
and against the voltage equation on a joint that moves, the gear ratio's one meaning, the seed's
figures from the default motor-side data, the torque-current table and the plain line."""

import dataclasses
import math

import numpy as np
import pytest
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import RevoluteJoint, SpatialInertia, UnitInertia
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource, VectorLogSink

from fivebar_drake.actuators.motor import (BldcMotor, LineMotor, build_motor, clip_flags,
                                      with_gear)
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.simulation.motor_model import MotorModel


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
    model = MotorModel(motor, np.arange(n), n, period_s=1e-3, step_s=1e-3)
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
    # at 10 rad/s: i = (10 - 100 / 15) / 1 = 10/3 A -> 10 * 0.8 * 0.1 * 10/3 N m; at 20 rad/s
    # the back-EMF 200 / 15 V exceeds the 10 V: it drives 10/3 A against the motion, braking
    # -10 * 0.1 * 10/3 / 0.8 N m
    np.testing.assert_allclose(up, [4.0, 4.0, 8.0 / 3.0, 0.0, -1.0 / 0.24], atol=1e-13)


@pytest.mark.parametrize("command, speed, applied, clip", [
    (3.0, 0.0, 3.0, ""),                                        # inside the limits
    (10.0, 0.0, 4.0, "peak"),                                   # stall: the peak current
    (10.0, 5.0, 4.0 - 0.02 - 0.01, "peak"),                     # below the corner: still flat
    (10.0, 10.0, 8.0 / 3.0 - 0.02 - 0.02, "line"),              # the voltage limits it
    (-10.0, 10.0, -6.25 - 0.02 - 0.02, "peak"),                 # braking: N tau_m / eta
    (10.0, -10.0, 6.25 + 0.02 + 0.02, "peak"),
    (4.0, 20.0, -1.0 / 0.24 - 0.02 - 0.04, "line"),             # beyond no-load: it brakes
    (-10.0, 25.0, -10 * 0.1 * (25 / 1.5 - 10) / 0.8 - 0.02 - 0.05, "line"),  # beyond the peak
    (-1.0, -1.0, -1.0 + 0.02 + 0.002, ""),                      # friction opposes the motion
    (1.0, 0.01, 1.0 - 0.02 * 0.2 - 0.002 * 0.01, ""),           # Coulomb ramps in
])
def test_motor_model_points(motor, command, speed, applied, clip):
    out, delivered = motor_outputs(motor, command, speed)
    assert out[0] == pytest.approx(applied, abs=1e-12)
    at_peak, at_line = clip_flags(motor, command, delivered, np.atleast_1d(speed))
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


def by_hand(motor, speed):
    """(upper, lower) output torque at output speeds from the circuit alone (inductance
    neglected, no d-axis current): the q-axis current i with |R i + e| <= V_bus / sqrt(3),
    e = (k_t / 1.5) N w, and |i| <= I_peak where that allows it (else the least |i| the voltage
    forces); output N k_t i x eta where torque and speed have one sign, / eta where not."""
    n, kt, r = motor.gear_ratio, motor.torque_constant_Nm_per_A, motor.winding_resistance_ohm
    v, peak, eta = motor.bus_voltage_V / math.sqrt(3), motor.peak_current_A, motor.gear_efficiency
    upper, lower = [], []
    for w in np.atleast_1d(speed):
        e = kt / 1.5 * n * w
        hi, lo = min((v - e) / r, peak), max((-v - e) / r, -peak)
        if hi < lo:                       # beyond the peak: the forced current, both sides
            hi = lo = (v - e) / r if w > 0 else (-v - e) / r
        torque = [n * kt * i * (eta if i * w >= 0 else 1 / eta) for i in (hi, lo)]
        upper.append(torque[0])
        lower.append(torque[1])
    return np.array(upper), np.array(lower)


def test_envelope_beyond_the_no_load_speed_brakes(motor):
    """Beyond the no-load speed (15 rad/s) the back-EMF exceeds the phase voltage: the current
    the voltage forces brakes, so the interval of achievable torque no longer holds 0 (no
    coasting); beyond (10 V + 1 ohm x 5 A) / (0.1 / 1.5 x 10) = 22.5 rad/s that current
    exceeds the peak current and is all there is. Below the no-load speed 0 lies inside."""
    speed = np.concatenate([np.linspace(-30.0, 30.0, 121), [15.0 + 1e-9, 22.5]])
    up, lo = motor.limits(speed)
    hand_up, hand_lo = by_hand(motor, speed)
    np.testing.assert_allclose(up, hand_up, atol=1e-12)
    np.testing.assert_allclose(lo, hand_lo, atol=1e-12)
    beyond = np.abs(speed) > 15.0
    assert np.all(np.sign(up[beyond]) == -np.sign(speed[beyond]))       # both bounds brake
    assert np.all(np.sign(lo[beyond]) == -np.sign(speed[beyond]))
    assert np.all((lo[~beyond] <= 0.0) & (up[~beyond] >= 0.0))
    # 20 rad/s: e = 40/3 V, at least (40/3 - 10) / 1 A of braking; 30 rad/s: 10 A, beyond 5 A
    assert up[speed == 20.0][0] == pytest.approx(-10 * 0.1 * (10 / 3) / 0.8, rel=1e-12)
    assert up[speed == 30.0][0] == lo[speed == 30.0][0] == pytest.approx(-10 * 0.1 * 10 / 0.8)


def test_issue_figures_at_11_5_from_the_voltage_equation(params):
    """The default motor behind 11.5:1 (issue 28): the least braking the back-EMF forces at
    8.924 rad/s (0.38 N m, where the closed form had left 0.034 N m of braking) and at 13.1 rad/s
    (beyond the peak current: 9.12 N m), from the motor-side data by hand."""
    m = dataclasses.replace(params.motor, gear_ratio=11.5)
    kt, r, v = m.torque_constant_Nm_per_A, m.winding_resistance_ohm, m.bus_voltage_V / math.sqrt(3)
    for w in (8.924, 13.1):
        forced = (kt / 1.5 * 11.5 * w - v) / r                      # A, against the motion
        torque = 11.5 * kt * forced / m.gear_efficiency
        up, lo = m.limits(np.array([w]))
        assert up[0] == pytest.approx(-torque, rel=1e-12)
        assert lo[0] == pytest.approx(-11.5 * kt * max(forced, m.peak_current_A)
                                      / m.gear_efficiency, rel=1e-12)
    assert m.limits(np.array([8.924]))[0][0] == pytest.approx(-0.38, abs=0.005)
    assert forced > m.peak_current_A and torque == pytest.approx(9.12, abs=0.01)


def test_drake_model_saturates_on_the_envelope(motor):
    """The MotorModel on a standing sample (no measured response yet) clips to the circuit's
    limits at the joint speed, in all four quadrants and beyond the no-load speed."""
    speed = np.linspace(-25.0, 25.0, 101)
    frictionless = dataclasses.replace(motor, coulomb_friction_Nm=0.0, viscous_friction_Nm_s=0.0)
    _, up = motor_outputs(frictionless, np.full(speed.size, 50.0), speed)
    _, down = motor_outputs(frictionless, np.full(speed.size, -50.0), speed)
    hand_up, hand_lo = by_hand(motor, speed)
    np.testing.assert_allclose(up, hand_up, atol=1e-12)
    np.testing.assert_allclose(down, hand_lo, atol=1e-12)


def spin(motor, inertia, command, external=0.0, duration=0.04, step=1e-3):
    """A single joint of `inertia` (kg m^2, no gravity) in a discrete plant (unsampled output
    ports, as the quadruped's), driven by a MotorModel at a constant command with a constant
    external torque: (joint speed at the start and at the end of each plant step, rad/s; the
    delivered torque of that step, N m), from the plant's and the model's logs."""
    builder = DiagramBuilder()
    plant = builder.AddSystem(MultibodyPlant(step))
    plant.SetUseSampledOutputPorts(False)
    body = plant.AddRigidBody("arm", SpatialInertia(1.0, np.zeros(3),
                                                    UnitInertia(inertia, inertia, inertia)))
    plant.AddJointActuator("a", plant.AddJoint(RevoluteJoint("j", plant.world_frame(),
                                                             body.body_frame(), [0, 0, 1])))
    plant.mutable_gravity_field().set_gravity_vector([0, 0, 0])
    plant.Finalize()
    model = builder.AddSystem(MotorModel(motor, [1], 2, step, step))
    builder.Connect(builder.AddSystem(ConstantVectorSource([command])).get_output_port(),
                    model.GetInputPort("torque_command"))
    builder.Connect(builder.AddSystem(ConstantVectorSource([external])).get_output_port(),
                    plant.get_applied_generalized_force_input_port())
    builder.Connect(plant.get_state_output_port(), model.GetInputPort("plant_state"))
    builder.Connect(model.GetOutputPort("applied_torque"), plant.get_actuation_input_port())
    states = builder.AddSystem(VectorLogSink(2, publish_period=step))
    record = builder.AddSystem(VectorLogSink(3, publish_period=step))
    builder.Connect(plant.get_state_output_port(), states.get_input_port())
    builder.Connect(model.GetOutputPort("motor_record"), record.get_input_port())
    diagram = builder.Build()
    simulator = Simulator(diagram)
    simulator.AdvanceTo(duration)
    context = simulator.get_context()
    w = states.FindLog(context).data()[1]
    delivered = record.FindLog(context).data()[1]
    return w[:-1], w[1:], delivered[:-1]


def continuous(motor, inertia, command, external, steps):
    """The joint speed (rad/s) at the end of each 1 ms step of the continuous law J w' =
    (the command clamped to the circuit's limits at w, by_hand) - tau_c clamp(w / 0.05) - b w
    + external, in 10 us steps, the command taking effect after the model's first 1 ms sample."""
    speed, out, dt = 0.0, [], 1e-5
    for k in range(steps):
        for _ in range(100):
            up, lo = by_hand(motor, speed)
            torque = min(max(command, lo[0]), up[0]) if k > 0 else 0.0
            speed += dt / inertia * (torque - motor.coulomb_friction_Nm * np.clip(
                speed / 0.05, -1, 1) - motor.viscous_friction_Nm_s * speed + external)
        out.append(speed)
    return np.array(out)


def test_a_light_joint_reaches_the_no_load_speed_without_overshoot(motor):
    """A leg in the air (5e-4 kg m^2: 8 rad/s per 1 ms step at 4 N m, while the voltage
    limit's time constant J R / (N^2 eta k_t k_e) is 0.94 ms) driven at full command: once its
    response is measured (after the first step with a torque), each step's torque lies within
    the circuit's limits at the step's mean speed, the joint never passes the no-load speed, it
    rises without oscillating, follows the continuous law within 1 rad/s and settles where the
    driving torque meets the friction, by hand: N eta k_t (V - k_e N w) / R = tau_c + b w."""
    start, end, delivered = spin(motor, 5e-4, 50.0)
    up, lo = by_hand(motor, 0.5 * (start + end))
    measured = np.arange(end.size) > np.flatnonzero(delivered)[0]
    assert np.all(delivered[measured] <= up[measured] + 1e-9)
    assert np.all(delivered[measured] >= lo[measured] - 1e-9)
    assert end.max() < 15.0 and np.all(np.diff(end) >= -1e-9)
    np.testing.assert_allclose(end, continuous(motor, 5e-4, 50.0, 0.0, end.size), atol=1.0)
    settle = (10 * 0.8 * 0.1 * 10 / 1.0 - 0.02) / (10 * 0.8 * 0.1 * (0.1 / 1.5) * 10 + 0.002)
    assert end[-1] == pytest.approx(settle, rel=1e-6)


def test_a_loaded_joint_gets_the_envelope_at_its_speed(motor):
    """A heavy joint (0.05 kg m^2) hardly responds within a step: its speed follows the
    continuous law within 0.005 rad/s through the corner to the no-load speed."""
    _, end, _ = spin(motor, 0.05, 50.0, duration=0.3)
    np.testing.assert_allclose(end, continuous(motor, 0.05, 50.0, 0.0, end.size), atol=5e-3)


@pytest.mark.parametrize("inertia", [5e-4, 2e-3])
def test_the_back_emf_brakes_a_joint_driven_beyond_the_no_load_speed(motor, inertia):
    """No command, a constant 3 N m pushing the joint: beyond the no-load speed the back-EMF
    forces braking, and the joint settles where it meets the push (by hand: N k_t (k_e N w -
    V) / (eta R) + tau_c + b w = 3 N m, 18.53 rad/s), following the continuous law, instead of
    spinning up as a coasting motor would (3 N m on 2e-3 kg m^2: 60 rad/s in 40 ms); every
    step from beyond the no-load speed brakes."""
    start, end, delivered = spin(motor, inertia, 0.0, external=3.0, duration=0.1)
    settle = (3.0 - 0.02 + 10 * 0.1 * 10 / 0.8) / (10 * 0.1 * (0.1 / 1.5) * 10 / 0.8 + 0.002)
    assert settle == pytest.approx(18.53, abs=0.01)
    assert end[-1] == pytest.approx(settle, rel=1e-6)
    assert end.max() < settle * 1.05 and np.all(delivered[start > 15.0] < 0)
    reference = continuous(motor, inertia, 0.0, 3.0, end.size)
    assert np.max(np.abs(end - reference)[10:]) < 0.05       # after the first 10 ms


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
    """Driving at 2 N m needs 2.5 A: the back-EMF allows (10 - 2.5) * 15 / 10 = 11.25 rad/s.
    Braking 2 N m takes 2 x 0.8 / 1 = 1.6 A, which the back-EMF may exceed the 10 V by:
    (10 + 1.6) * 15 / 10 = 17.4 rad/s; braking 0.5 N m (0.4 A) only up to 15.6 rad/s, beyond
    which it forces more."""
    margin, outside = motor.speed_margins(np.array([2.0, 2.0, -2.0, 5.0, -0.5, 6.0, 0.0]),
                                          np.array([9.0, 12.0, 12.0, 1.0, 17.0, -1.0, 0.0]))
    assert margin[0] == pytest.approx(11.25 / 9.0, rel=1e-13)
    assert margin[1] == pytest.approx(11.25 / 12.0, rel=1e-13) and outside[1]
    assert margin[2] == pytest.approx(17.4 / 12.0, rel=1e-13) and not outside[2]
    assert math.isnan(margin[3]) and not outside[3]           # beyond the peak: torque's check
    assert margin[4] == pytest.approx(15.6 / 17.0, rel=1e-13) and outside[4]
    assert margin[5] == pytest.approx(14.8 * 15 / 10, rel=1e-13)   # braking 6 N m: 4.8 A
    assert margin[6] == math.inf and not outside[6]


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
    # beyond the no-load speed the line goes on into braking, as a DC motor's does
    np.testing.assert_allclose(line.torque_limit(speed), 5.0 * np.minimum(1 - speed / (4 * np.pi),
                                                                          1), atol=1e-14)
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
