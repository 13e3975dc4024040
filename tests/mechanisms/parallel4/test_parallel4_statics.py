"""Statics, stiffness and workspace of the 4-DOF parallel manipulator against virtual work,
finite-difference energy Hessians and hand-computed areas."""

import numpy as np

from fivebar_drake.mechanisms.parallel4.geometry import Geometry
from fivebar_drake.mechanisms.parallel4.kinematics import inverse, reach, type2_line_z
from fivebar_drake.mechanisms.parallel4.statics import (
    condition_number, holding_forces, in_workspace, poses_yz, stiffness, translational_block,
    translational_free_rotation, yz_grid)

G = Geometry(a=0.13, b=0.02, c=0.05, d=0.03, R=0.4, d_min_over_R=0.5, d_max_over_R=1.7)
POSES = np.array([[0.1, 0.02, -0.3, 0.2], [-0.2, -0.05, -0.28, -0.6], [0.0, 0.04, -0.32, 1.0]])
K_ACT = np.array([2e6, 1.5e6, 1e6, 3e6])


def fd(f, x, h=1e-6):
    return np.stack([(f(x + h * np.eye(4)[k]) - f(x - h * np.eye(4)[k])) / (2 * h)
                     for k in range(4)], axis=-1)


def test_holding_forces_do_no_virtual_work_with_the_load():
    load = np.array([3.0, -2.0, -40.0, 1.5])
    for pose in POSES:
        tau = holding_forces(G, pose, load)
        dq = fd(lambda p: inverse(G, p), pose)          # dq/dx by finite differences
        for dx in np.eye(4):
            assert abs(tau @ dq @ dx + load @ dx) < 1e-6 * np.abs(load).max()


def test_stiffness_is_the_hessian_of_the_actuator_spring_energy():
    for pose in POSES:
        q0 = inverse(G, pose)

        def energy(p):
            return 0.5 * np.sum(K_ACT * (inverse(G, p) - q0) ** 2)

        h = 1e-5
        hess = np.array([[(energy(pose + h * (ei + ej)) - energy(pose + h * (ei - ej))
                           - energy(pose - h * (ei - ej)) + energy(pose - h * (ei + ej)))
                          / (4 * h * h) for ej in np.eye(4)] for ei in np.eye(4)])
        K = stiffness(G, pose, K_ACT)
        assert np.allclose(K, hess, rtol=1e-4, atol=1e-3 * np.abs(K).max() * 1e-3)


def test_stiffness_spd_and_condition_grows_toward_the_type2_line():
    K = stiffness(G, POSES, K_ACT)
    assert np.allclose(K, np.swapaxes(K, -1, -2))
    assert np.all(np.linalg.eigvalsh(K) > 0)
    for M in (K, translational_block(K), translational_free_rotation(K)):
        assert np.all(condition_number(M) >= 1)
    theta, y_line = 0.3, 0.05
    z_line = type2_line_z(G, y_line, theta)                # the assembly folds here
    gaps = np.array([0.05, 0.02, 0.01, 0.003, 0.001, 0.0003])
    poses = np.stack([np.zeros(6), np.full(6, y_line), z_line - gaps, np.full(6, theta)], -1)
    cond = condition_number(stiffness(G, poses, K_ACT))
    assert np.all(np.diff(cond) > 0) and cond[-1] > 10 * cond[0]
    # toward det A = 0: at y = 0 pair 2's point (e, z - g) reaches R at z = g - sqrt(R^2 - e^2)
    g_ = G.c * np.cos(theta) - G.d
    z_reach = g_ - np.sqrt(G.R ** 2 - G.e ** 2)
    poses = np.stack([np.zeros(6), np.zeros(6), z_reach + gaps, np.full(6, theta)], -1)
    assert np.allclose(reach(G, poses)[:, 1], 0, atol=2 * G.R * gaps.max() + 1e-3)
    cond = condition_number(stiffness(G, poses, K_ACT))
    assert np.all(np.diff(cond) > 0) and cond[-1] > 10 * cond[0]


def test_condition_number_of_known_matrices():
    assert np.isclose(condition_number(np.diag([9.0, 4.0, 1.0])), 3.0)
    assert np.isinf(condition_number(np.diag([1.0, 0.0])))


def test_unit_scale_rescales_the_rotation_column():
    K = stiffness(G, POSES[0], K_ACT)
    Kdeg = stiffness(G, POSES[0], K_ACT, scale=(1, 1, 1, 180 / np.pi))
    D = np.diag([1, 1, 1, np.pi / 180])
    assert np.allclose(Kdeg, D @ K @ D)


def test_workspace_area_of_one_pair_annulus_by_hand():
    # c = d, theta = 0 and no stroke limits: the pair circles are discs of radius R centred at
    # (y, z) = (+-(a - b), 0); the workspace is the part of their lens below z = 0
    g = Geometry(a=0.06, b=0.0, c=0.04, d=0.04, R=0.4, d_min_over_R=1e-9, d_max_over_R=2.0)
    Y, Z, cell = yz_grid(0.5, -0.5, 0.0, 0.001)
    r, h = g.R, g.e
    lens = 2 * r * r * np.arccos(h / r) - 2 * h * np.sqrt(r * r - h * h)
    area = in_workspace(g, poses_yz(Y, Z, 0.0)).sum() * cell
    assert np.isclose(area, lens / 2, rtol=2e-3)
    assert not in_workspace(g, poses_yz(np.array([0.0]), np.array([0.01]), 0.0))[0]
