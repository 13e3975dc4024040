import numpy as np

from fivebar_drake.mechanisms.fivebar import (LegGeometry, bias_accelerations, forward,
                                              link_jacobians, point_jacobians)

from helpers import central_difference, link_geometry, random_poses
from test_kinematics import coaxial_leg


def test_foot_and_joint_jacobians_match_finite_differences(params, rng):
    q = random_poses(params, rng)
    pose = forward(params.leg, q)
    branch = pose.e_branch
    jac = point_jacobians(params.leg, pose)
    for name in ("C", "D", "E", "F"):
        fd = central_difference(lambda x: getattr(forward(params.leg, x, branch), name.lower()), q)
        assert np.max(np.abs(jac[name] - fd)) < 1e-7, name
    # seed 003 section 3.4 with the seed's lengths
    assert np.allclose(jac["F"], (37 * jac["E"] - 8 * jac["D"]) / 29, atol=1e-14)


def test_link_jacobians_match_finite_differences(params, rng):
    q = random_poses(params, rng)
    pose = forward(params.leg, q)
    lj = link_jacobians(params.leg, params.links, pose)
    branch = pose.e_branch
    fd_com = central_difference(lambda x: link_geometry(params, x, branch)[0], q)
    fd_ang = central_difference(lambda x: link_geometry(params, x, branch)[1], q)
    assert np.max(np.abs(lj.jv - fd_com)) < 1e-7
    assert np.max(np.abs(lj.jw - fd_ang)) < 1e-6


def test_bias_accelerations_match_second_differences(params, rng):
    """a = d^2/dt^2 of COM positions along q(t) = q0 + qd t (q_ddot = 0), by finite differences."""
    q0 = random_poses(params, rng, 50)
    qd = rng.uniform(-8, 8, q0.shape)
    pose = forward(params.leg, q0)
    branch = pose.e_branch
    h = 1e-4
    geo = [link_geometry(params, q0 + s * h * qd, branch) for s in (-1, 0, 1)]
    fd_com = (geo[0][0] - 2 * geo[1][0] + geo[2][0]) / h**2
    fd_ang = (geo[0][1] - 2 * geo[1][1] + geo[2][1]) / h**2
    feet = [forward(params.leg, q0 + s * h * qd, branch).f for s in (-1, 0, 1)]
    fd_foot = (feet[0] - 2 * feet[1] + feet[2]) / h**2
    av, aw, af = bias_accelerations(params.leg, params.links, pose, qd)
    scale = np.max(np.abs(fd_com))
    assert np.max(np.abs(av - fd_com)) < 1e-4 * scale
    assert np.max(np.abs(aw - fd_ang)) < 1e-4 * np.max(np.abs(fd_ang))
    assert np.max(np.abs(af - fd_foot)) < 1e-4 * np.max(np.abs(fd_foot))


def test_coaxial_foot_jacobian_matches_closed_form(rng):
    """E = r(gamma) (cos psi, sin psi), psi = (tA + tB)/2, gamma = (tB - tA)/2 (Minitaur)."""
    leg: LegGeometry = coaxial_leg()
    l1, l2 = leg.ac_m, leg.ce_m
    gamma = rng.uniform(0.2, 1.5, 100)
    psi = rng.uniform(-np.pi, np.pi, 100)
    q = np.stack([psi - gamma, psi + gamma], -1)
    root = np.sqrt(l2**2 - l1**2 * np.sin(gamma) ** 2)
    r = l1 * np.cos(gamma) + root
    dr = -l1 * np.sin(gamma) - l1**2 * np.sin(gamma) * np.cos(gamma) / root
    radial = np.stack([np.cos(psi), np.sin(psi)], -1)
    tangential = np.stack([-np.sin(psi), np.cos(psi)], -1)
    # d/dtA: dpsi = 1/2, dgamma = -1/2; d/dtB: dpsi = 1/2, dgamma = 1/2
    expect = np.stack([0.5 * (r[:, None] * tangential - dr[:, None] * radial),
                       0.5 * (r[:, None] * tangential + dr[:, None] * radial)], -1)
    pose = forward(leg, q, e_branch=-1.0)  # E beyond the chord CD, away from the hips
    assert np.allclose(pose.f, r[:, None] * radial, atol=1e-12)
    assert np.max(np.abs(point_jacobians(leg, pose)["F"] - expect)) < 1e-12
