"""Closed-form kinematics of the 4-DOF parallel manipulator checked against independent
computations: leg lengths, finite differences, numerical determinants, Grübler by hand."""

import numpy as np
import pytest

from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.parallel4.geometry import (SEED_JOINT_FREEDOMS, SEED_LINKS,
                                                         Geometry, grubler)
from fivebar_drake.mechanisms.parallel4.kinematics import (
    BranchError, UnreachableError, branch_side, det_B_closed_form, det_B_seed, forward, inverse,
    jacobians, seed_B, type2_line_z, velocity_jacobian)
from fivebar_drake.mechanisms.parallel4.statics import in_workspace

G = Geometry(a=0.14, b=0.02, c=0.04, d=0.04, R=0.4, d_min_over_R=0.55, d_max_over_R=1.5)
TILTED = Geometry(a=0.13, b=0.02, c=0.05, d=0.03, R=0.4, d_min_over_R=0.5, d_max_over_R=1.7)


def workspace_poses(g, n=3000, seed=1):
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(-0.3, 0.3, n), rng.uniform(-0.2, 0.2, n),
                             rng.uniform(-0.4, -0.1, n), rng.uniform(-1.3, 1.3, n)])
    return poses[in_workspace(g, poses)]


def leg_ends(g, pose, q):
    """A_i and B_i (n, 4, 3) built from the figure's vectors directly (not from the module)."""
    x, y, z, th = pose.T
    rot = np.stack([g.c * np.sin(th), np.full_like(th, g.b), g.c * np.cos(th)], axis=-1)
    P = pose[:, :3]
    B = np.stack([P + rot, P + rot, P - rot, P - rot], axis=1)
    O = np.array([[0, g.a, g.d], [0, g.a, g.d], [0, -g.a, -g.d], [0, -g.a, -g.d]], float)
    A = O[None] + q[..., None] * np.array([1.0, 0, 0])
    return A, B


@pytest.mark.parametrize("g", [G, TILTED])
def test_inverse_gives_legs_of_length_R(g):
    poses = workspace_poses(g)
    assert len(poses) > 50
    q = inverse(g, poses)
    A, B = leg_ends(g, poses, q)
    assert np.allclose(np.linalg.norm(B - A, axis=-1), g.R, atol=1e-12)
    assert np.all(q[:, 0] > q[:, 1]) and np.all(q[:, 2] > q[:, 3])


@pytest.mark.parametrize("g", [G, TILTED])
@pytest.mark.parametrize("mode", [(1, -1, 1, -1), (-1, 1, -1, 1), (1, -1, -1, 1)])
def test_forward_inverts_inverse_on_each_ik_branch(g, mode):
    poses = workspace_poses(g)
    back = forward(g, inverse(g, poses, mode))
    assert np.allclose(back, poses, atol=1e-9)


@pytest.mark.parametrize("g", [G, TILTED])
def test_upper_forward_branch_is_the_mirror_assembly(g):
    poses = workspace_poses(g)
    q = inverse(g, poses)
    upper = forward(g, q, lower=False)
    assert np.all(branch_side(g, upper) > 0)
    A, B = leg_ends(g, upper, q)                                   # also closes every leg
    assert np.allclose(np.linalg.norm(B - A, axis=-1), g.R, atol=1e-9)
    assert np.allclose(forward(g, inverse(g, upper), lower=False), upper, atol=1e-9)


def test_unreachable_pose_and_impossible_actuator_positions_raise():
    with pytest.raises(UnreachableError, match="out of reach"):
        inverse(G, [[0.0, 0.0, -0.6, 0.0]])
    assert np.isnan(inverse(G, [0.0, 0.0, -0.6, 0.0], strict=False)).all()
    q = inverse(G, [0.0, 0.0, -0.3, 0.0])
    with pytest.raises(BranchError, match="2c"):
        forward(G, q + np.array([0.1, 0.1, 0, 0]))               # |r1 - r2| = 0.1 > 2c
    with pytest.raises(BranchError, match="2R"):
        forward(G, [0.5, -0.5, 0.3, -0.3])
    with pytest.raises(BranchError, match="do not meet"):
        forward(G, [0.05, -0.05, 0.39, -0.39])     # pair circles of radii 0.397 and 0.089 m, centres 0.24 m apart: one inside the other
    assert np.isnan(forward(G, [0.05, -0.05, 0.39, -0.39], strict=False)).all()


def test_geometry_check_names_the_field():
    with pytest.raises(ParameterError, match="geometry.a"):
        Geometry(0.02, 0.02, 0.04, 0.04, 0.4, 0.5, 1.5).check()
    with pytest.raises(ParameterError, match="geometry.d_max_over_R"):
        Geometry(0.14, 0.02, 0.04, 0.04, 0.4, 0.5, 2.5).check()
    with pytest.raises(ParameterError, match="geometry.R"):
        Geometry(0.14, 0.02, 0.04, 0.04, 400.0, 0.5, 1.5).check()


@pytest.mark.parametrize("g", [G, TILTED])
def test_jacobian_matches_finite_differences_of_inverse(g):
    poses = workspace_poses(g, n=200)
    J = velocity_jacobian(g, poses, inverse(g, poses))
    h = 1e-6
    fd = np.stack([(inverse(g, poses + h * np.eye(4)[k]) - inverse(g, poses - h * np.eye(4)[k]))
                   / (2 * h) for k in range(4)], axis=-1)
    assert np.allclose(J, fd, rtol=1e-6, atol=1e-7)
    # A and B separately: B xdot - A qdot is the time derivative of the leg constraints / 2
    A, B = jacobians(g, poses, inverse(g, poses))
    xdot = np.random.default_rng(3).normal(size=poses.shape)
    qdot = np.einsum("nij,nj->ni", fd, xdot)
    assert np.allclose(np.einsum("nij,nj->ni", A, qdot), np.einsum("nij,nj->ni", B, xdot),
                       atol=1e-7)
    # the seed's sign of the fourth column does not satisfy A qdot = B xdot when theta moves
    Bs = seed_B(B)
    assert not np.allclose(np.einsum("nij,nj->ni", A, qdot), np.einsum("nij,nj->ni", Bs, xdot),
                           atol=1e-4)


@pytest.mark.parametrize("g", [G, TILTED])
def test_det_B_closed_form_and_the_seeds(g):
    poses = workspace_poses(g)
    q = inverse(g, poses)
    _, B = jacobians(g, poses, q)
    det = np.linalg.det(B)
    assert np.allclose(det_B_closed_form(g, poses, q), det, rtol=1e-9, atol=1e-15)
    assert np.allclose(np.linalg.det(seed_B(B)), -det, rtol=1e-9, atol=1e-15)
    # eq. 2.25 as written: right only where (c cos(theta) - d) y = 0 (e.g. c = d, theta = 0)
    level = poses.copy()
    level[:, 3] = 0.0
    level = level[in_workspace(g, level)]
    ql = inverse(g, level)
    agree = np.allclose(np.abs(det_B_seed(g, level, ql)),
                        np.abs(np.linalg.det(jacobians(g, level, ql)[1])), rtol=1e-9)
    assert agree == (g.c == g.d)


def test_det_B_vanishes_on_our_type2_line_not_on_the_seeds():
    g = TILTED
    y = np.array([-0.05, -0.02, 0.03, 0.06])
    for theta in (0.0, 0.5, 1.0):
        line = np.stack([np.zeros(4), y, type2_line_z(g, y, theta), np.full(4, theta)], axis=-1)
        assert np.allclose(np.linalg.det(jacobians(g, line, inverse(g, line))[1]), 0, atol=1e-13)
        seed = line.copy()
        seed[:, 2] = type2_line_z(g, y, theta, seed=True)
        assert np.abs(np.linalg.det(jacobians(g, seed, inverse(g, seed))[1])).min() > 1e-8


def test_det_A_and_det_B_vanish_where_a_pair_is_at_full_reach():
    g = TILTED                                   # theta = 0: pair points (y -+ e, z +- (c - d))
    y1, z1 = -0.9839 * g.R, np.sqrt(1 - 0.9839 ** 2) * g.R
    pose = np.array([0.0, y1 + g.e, z1 - (g.c - g.d), 0.0])
    A, B = jacobians(g, pose, inverse(g, pose))
    assert abs(np.linalg.det(A)) < 1e-12 and abs(np.linalg.det(B)) < 1e-12   # type 3


def test_grubler_counts_the_seeds_structure():
    assert sum(SEED_JOINT_FREEDOMS) == 22 == 4 + 6 * 3          # eq. 2.3
    assert grubler(SEED_LINKS, SEED_JOINT_FREEDOMS) == (4, 3)
    assert grubler(4, (1, 1, 1, 1), lam=3) == (1, 1)            # a planar four-bar


def test_eq_2_17_needs_a_minus_b_on_its_y_term_and_eq_2_18_is_right():
    g = TILTED
    poses = workspace_poses(g)
    q = inverse(g, poses)
    d1, d2 = q[:, 0] - q[:, 1], q[:, 2] - q[:, 3]
    y, z, gz = poses[:, 1], poses[:, 2], g.c * np.cos(poses[:, 3]) - g.d
    lhs = (d1 ** 2 - d2 ** 2) / 4
    assert np.allclose(lhs, 4 * y * (g.a - g.b) - 4 * z * gz, atol=1e-14)
    assert not np.allclose(lhs, 4 * y * (g.b - g.a) - 4 * z * gz, atol=1e-4)
    s = np.sqrt(4 * g.c ** 2 - (q[:, :2].mean(1) - q[:, 2:].mean(1)) ** 2) - 2 * g.d
    assert np.allclose(y, (d1 ** 2 - d2 ** 2 + 8 * z * s) / (16 * (g.a - g.b)), atol=1e-12)
