"""The ball-screw leg's closed forms against independent checks: the round trip FK/IK, finite
differences, virtual work, hand-derived geometry and hand-computed seed numbers."""

import math

import numpy as np
import pytest

from fivebar_drake.mechanisms.ballscrew_leg import (BallScrewLeg, UnreachableError, load_params,
                                                     peak_ratio_q1, squat_statics, stroke_range)

LEVERS = (0.02, 0.05, 0.07)
RNG = np.random.default_rng(1)


def leg(s1=0.05):
    return BallScrewLeg(0.2, 0.2, s1, 0.005)


def random_q(m, n=200):
    """Joint coordinates (q1 rad, q2l m) spread over the screw's range, away from its ends."""
    lo, hi = m.screw_range()
    return np.column_stack([RNG.uniform(-1.0, 1.5, n),
                            RNG.uniform(lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo), n)])


@pytest.mark.parametrize("s1", LEVERS)
def test_forward_inverse_round_trip(s1):
    m = leg(s1)
    q = random_q(m)
    pose = m.forward(q)
    back = m.inverse(pose.f)
    assert np.allclose(back.q, q, atol=1e-10)
    # the seed's foot formula, written out again
    q2 = -np.arccos((0.2**2 + s1**2 - q[:, 1]**2) / (2 * 0.2 * s1))
    x = 0.2 * np.sin(q[:, 0]) + 0.2 * np.sin(q[:, 0] + q2)
    y = -(0.2 * np.cos(q[:, 0]) + 0.2 * np.cos(q[:, 0] + q2))
    assert np.allclose(pose.f, np.column_stack([x, y]), atol=1e-15)


def test_points_sit_where_the_seed_puts_them():
    m = leg(0.05)
    pose = m.forward(random_q(m))
    assert np.allclose(np.linalg.norm(pose.a - pose.o, axis=-1), 0.2)
    assert np.allclose(np.linalg.norm(pose.d - pose.a, axis=-1), 0.05)
    assert np.allclose(np.linalg.norm(pose.d - pose.o, axis=-1), pose.q[:, 1])   # OD = q2l
    u, v = pose.d - pose.a, pose.f - pose.a                                     # D, A, P in line
    assert np.allclose(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], 0.0, atol=1e-15)


def test_unreachable_is_refused():
    m = leg(0.05)
    with pytest.raises(UnreachableError):
        m.forward([0.0, 0.26])
    with pytest.raises(UnreachableError):
        m.inverse([0.0, -0.41])
    assert np.all(np.isnan(m.inverse([0.0, -0.41], strict=False).q))


@pytest.mark.parametrize("s1", LEVERS)
def test_jacobian_against_finite_differences(s1):
    m = leg(s1)
    q = random_q(m, 50)
    jac = m.tool_jacobian(m.forward(q))
    h = 1e-7
    for k in range(2):
        dq = np.zeros(2)
        dq[k] = h
        fd = (m.forward(q + dq).f - m.forward(q - dq).f) / (2 * h)
        assert np.allclose(jac[..., k], fd, rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("eta, driving", [(0.9, True), (0.9, False), (1.0, True)])
def test_screw_relation_by_virtual_work(eta, driving):
    """Driving: motor power x eta = knee power; back-driven: knee power x eta = motor power."""
    m = leg(0.05)
    q2 = -RNG.uniform(0.1, 3.0, 100)
    knee_torque = RNG.uniform(-50.0, 50.0, 100)
    force = m.screw_force(knee_torque, q2)
    knee_speed = RNG.uniform(-5.0, 5.0, 100)
    h = 1e-6                                   # screw speed by finite differences of its length
    screw_speed = (m.screw_from_knee(q2 + h * knee_speed) - m.screw_from_knee(q2 - h * knee_speed)
                   ) / (2 * h)
    assert np.allclose(force * screw_speed, knee_torque * knee_speed, rtol=1e-6, atol=1e-6)
    motor_speed = 2 * np.pi * screw_speed / 0.005
    motor_power = m.screw_motor_torque(force, eta, driving) * motor_speed
    knee_power = knee_torque * knee_speed
    expected = knee_power / eta if driving else knee_power * eta
    assert np.allclose(motor_power, expected, rtol=1e-6, atol=1e-6)


def test_static_torques_balance_the_load_by_virtual_work():
    m = leg(0.05)
    pose = m.forward(random_q(m, 30))
    force = np.array([120.0, 700.0])
    gen = m.static_torques(force, pose)
    dq = RNG.normal(size=(30, 2)) * 1e-7
    df = m.forward(pose.q + dq).f - m.forward(pose.q - dq).f
    # the generalized forces do the work the external force would undo: tau . dq = -F . df
    assert np.allclose(np.sum(gen * 2 * dq, -1), -df @ force, rtol=1e-5, atol=1e-12)


@pytest.mark.parametrize("s1", LEVERS)
def test_ratio_peaks_where_odp_is_square(s1):
    """The peak of the sampled ratio sits (to the sampling) at the hip angle where the right
    angle of triangle OAD is at D, cos(OAD) = s1 / l1, and the plant's angle ODP is 90 deg."""
    p = load_params()
    q1 = np.radians(np.linspace(0.5, 89.5, 17801))
    st = squat_statics(p, s1, q1)
    expected = 0.5 * math.acos(s1 / 0.2)
    assert peak_ratio_q1(p, s1) == pytest.approx(expected, abs=1e-15)
    for ratio in st.ratio.values():
        assert q1[np.argmax(ratio)] == pytest.approx(expected, abs=q1[1] - q1[0])
    # at that angle D, O and P make 90 deg at D (dot product of the two arms)
    pose = leg(s1).points(expected, -2 * expected)
    assert np.dot(pose.o - pose.d, pose.f - pose.d) == pytest.approx(0.0, abs=1e-15)


def test_seed_numbers_by_hand():
    """Knee torque 700 N x l2 sin q1; hip torque 0 (foot below the hip); the peak ratio
    2 pi eta s1 / lead (moment arm s1 at the peak)."""
    p = load_params()
    q1 = np.radians([10.0, 30.0, 60.0])
    st = squat_statics(p, 0.05, q1)
    assert np.allclose(st.knee_Nm, 700 * 0.2 * np.sin(q1))
    assert np.allclose(st.hip_Nm, 0.0, atol=1e-12)
    assert np.allclose(st.geared_motor_Nm, 14 * np.sin(q1))
    # screw force: 700 N x 0.2 sin q1 / (0.2 x 0.05 sin 2q1 / q2l), a pull
    q2l = np.sqrt(0.04 + 0.0025 - 0.02 * np.cos(2 * q1))
    assert np.allclose(st.screw_force_N, -140 * np.sin(q1) * q2l / (0.01 * np.sin(2 * q1)))
    peak = squat_statics(p, 0.05, [peak_ratio_q1(p, 0.05)])
    assert peak.ratio["joint", "forward"][0] == pytest.approx(2 * math.pi * 0.9 * 0.05 / 0.005)
    assert peak.ratio["joint", "back-driven"][0] == pytest.approx(2 * math.pi * 0.05 / 0.0045)
    assert peak.ratio["motor", "forward"][0] == pytest.approx(2 * math.pi * 0.9 * 0.05 / 0.05)


def test_stroke_limits_the_knee():
    """Retracted at the straight leg (q2l = l1 - s1); 60 mm of stroke: for s1 = 0.05 the knee
    bends until q2l = 0.21 m, cos(bend) = (0.04 + 0.0025 - 0.0441) / 0.02."""
    p = load_params()
    r = stroke_range(p, 0.05)
    assert r.screw_m == pytest.approx((0.15, 0.21))
    assert r.bend_rad[1] == pytest.approx(math.acos(-0.08))
    assert stroke_range(p, 0.02).bend_rad[1] == pytest.approx(math.pi)   # 40 mm covers it all
