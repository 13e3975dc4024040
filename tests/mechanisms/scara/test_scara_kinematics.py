"""SCARA kinematics against hand calculations, the seed's own formulas and finite differences."""

import math

import numpy as np
import pytest

from fivebar_drake.mechanisms.scara import OutOfReach, Scara, ScaraArm, load_params, seed_inertia


@pytest.fixture(scope="module")
def scara():
    return Scara(load_params().kinematics)


def random_q(scara, rng, n=500):
    return rng.uniform(scara.lower, scara.upper, (n, 3))


def test_forward_by_hand(scara):
    # stretched along x: (a1 + a2, 0), tool down by q3 from d1 + d2 = 0.45 m
    assert scara.forward([0.0, 0.0, 0.1]).f == pytest.approx([0.85, 0.0, 0.35], abs=1e-15)
    # q1 = 90 deg, q2 = 90 deg: elbow at (0, 0.35), tool 0.5 m further along -x
    assert scara.forward([math.pi / 2, math.pi / 2, 0.0]).f == pytest.approx(
        [-0.5, 0.35, 0.45], abs=1e-15)


def test_seed_ik_formula_at_A(scara):
    # eq. 2.42 with the seed's numbers: q2 = arccos((x^2 + y^2 - 0.3725) / 0.35), q3 = z - 0.45
    x, y, z = 0.25, 0.5, 0.4
    q = scara.inverse([x, y, z], 1).q
    assert q[1] == pytest.approx(math.acos((x * x + y * y - 0.3725) / 0.35), abs=1e-14)
    q1 = math.atan2(0.5 * (y * math.cos(q[1]) - x * math.sin(q[1])) + 0.35 * y,
                    0.5 * (x * math.cos(q[1]) + y * math.sin(q[1])) + 0.35 * x)
    assert q[0] == pytest.approx(q1, abs=1e-14)
    assert q[2] == pytest.approx(0.45 - z, abs=1e-15)       # tool moves down with q3


@pytest.mark.parametrize("elbow", [1, -1])
def test_ik_fk_round_trip_both_elbows(scara, rng, elbow):
    q = random_q(scara, rng)
    q[:, 1] = elbow * np.abs(q[:, 1]).clip(1e-3)             # the elbow under test
    back = scara.inverse(scara.forward(q).f, elbow, strict=False).q
    ok = ~np.isnan(back).any(axis=1)
    assert ok.mean() > 0.9                                   # only q1 past +-165 deg drops out
    assert back[ok] == pytest.approx(q[ok], abs=1e-9)


def test_both_elbows_reach_the_same_point(scara):
    p = np.array([0.25, 0.5, 0.4])
    up, down = scara.inverse(p, 1).q, scara.inverse(p, -1).q
    assert up[1] == pytest.approx(-down[1])
    assert scara.forward(up).f == pytest.approx(p, abs=1e-12)
    assert scara.forward(down).f == pytest.approx(p, abs=1e-12)


def test_out_of_reach_raises(scara):
    with pytest.raises(OutOfReach):
        scara.inverse([0.9, 0.0, 0.3], 1)
    assert np.isnan(scara.inverse([0.9, 0.0, 0.3], 1, strict=False).q).all()


def test_jacobian_against_finite_differences(scara, rng):
    q, h = random_q(scara, rng, 50), 1e-6
    jac = scara.tool_jacobian(q)
    for j in range(3):
        dq = np.zeros(3)
        dq[j] = h
        fd = (scara.forward(q + dq).f - scara.forward(q - dq).f) / (2 * h)
        assert jac[:, :, j] == pytest.approx(fd, abs=1e-8)


def test_jacobian_rate_against_finite_differences(scara, rng):
    q, qd, h = random_q(scara, rng, 50), rng.normal(size=(50, 3)), 1e-6
    fd = (scara.tool_jacobian(q + h * qd) - scara.tool_jacobian(q - h * qd)) / (2 * h)
    assert scara.jacobian_rate(q, qd) == pytest.approx(fd, abs=1e-8)


def test_inverse_path_keeps_the_elbow_and_is_continuous(scara):
    s = np.linspace(0, 2 * np.pi, 400)
    path = np.stack([0.25 + 0.05 * np.sin(s), 0.45 + 0.05 * np.cos(s), np.full_like(s, 0.3)], 1)
    for elbow in (1, -1):
        q = scara.inverse_path(path, elbow)
        assert np.all(np.sign(q[:, 1]) == elbow)
        assert np.abs(np.diff(q, axis=0)).max() < 0.01
        assert scara.forward(q).f == pytest.approx(path, abs=1e-12)


def test_inverse_path_names_the_sample_out_of_limits(scara):
    path = np.array([[0.5, 0.1, 0.3], [-0.84, 0.0, 0.3]])     # behind: q1 near 180 deg
    with pytest.raises(OutOfReach, match="sample 1"):
        scara.inverse_path(path, 1)


def test_cardan_angles(scara):
    # eq. 2.24: alpha = beta = 0, eta = q1 + q2 - pi/2; the rotation about z is q1 + q2
    assert Scara.cardan_angles([0.3, 0.4, 0.1]) == pytest.approx([0, 0, 0.7 - math.pi / 2])


def test_workspace_membership_against_joint_space_sampling(scara, rng):
    q = random_q(scara, rng, 2000)
    assert scara.reachable_xy(scara.forward(q).f[:, :2]).all()
    assert not scara.reachable_xy([[0.86, 0.0], [0.2, 0.0], [0.0, 0.0]]).any()
    # behind the base the arm cannot stretch: q1 = 180 deg is outside +-165 deg
    assert not scara.reachable_xy([[-0.849, 0.0]]).any()


def test_seed_grid_lies_in_the_workspace(scara):
    grid = scara.seed_grid()
    assert len(grid) == 37 * 33          # -165..165 and -147..147 deg in 9 deg steps
    assert scara.reachable_xy(grid).all()


def test_workspace_boundary(scara, rng):
    inner, outer = scara.radial_extent()
    assert outer == pytest.approx(0.85)
    assert inner == pytest.approx(math.sqrt(0.35**2 + 0.5**2 + 2 * 0.35 * 0.5
                                            * math.cos(math.radians(147))))
    pieces = scara.workspace_boundary(800)
    points = np.concatenate(pieces)
    r = np.linalg.norm(points, axis=1)
    assert r.max() == pytest.approx(outer, abs=1e-9) and r.min() == pytest.approx(inner, abs=1e-9)
    # every boundary point has reachable points and unreachable points within 1 mm
    for p in points[rng.integers(0, len(points), 60)]:
        ring = p + 1e-3 * np.stack([np.cos(np.linspace(0, 2 * np.pi, 64)),
                                    np.sin(np.linspace(0, 2 * np.pi, 64))], 1)
        inside = scara.reachable_xy(ring)
        assert inside.any() and not inside.all()


def test_holding_a_pose_takes_the_weight_of_link_3_on_joint_3_only():
    params = load_params()
    arm = ScaraArm(params.kinematics, seed_inertia(params.links))
    pose = arm.inverse([0.25, 0.5, 0.4], arm.modes[1])
    assert arm.tree_positions(pose) == pytest.approx(pose.q) and arm.loop_gaps(pose.q).size == 0
    assert arm.static_torques(arm.inertia, pose) == pytest.approx([0, 0, -4.0 * 9.81])
