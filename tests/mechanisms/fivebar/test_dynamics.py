import dataclasses

import numpy as np
import pytest

from fivebar_drake.analysis.torques import analyze
from fivebar_drake.robots.quadruped.config import with_gait
from fivebar_drake.mechanisms.fivebar import (LINK_NAMES, coriolis, forward, mass_matrix,
                                              physical_izz, torques)
from fivebar_drake.robots.quadruped.leg_loads import full_model, seed_model

from helpers import central_difference, link_geometry, random_poses


def no_foot_load(model):
    return dataclasses.replace(model, foot_load_N=0.0)


def test_virtual_work_foot_load(params, rng):
    """Motor power tau . q_dot equals the power the foot delivers to the ground, F . v_F, with
    v_F from finite differences of FK and F = -m_leg g y (the foot pushes down)."""
    q = random_poses(params, rng)
    qd = rng.uniform(-5, 5, q.shape)
    pose = forward(params.leg, q)
    model = full_model(params)
    tb = torques(params.leg, params.links, model, pose, qd, np.zeros_like(qd))
    h = 1e-6
    branch = pose.e_branch
    v_foot = (forward(params.leg, q + h * qd, branch).f
              - forward(params.leg, q - h * qd, branch).f) / (2 * h)
    force_on_ground = np.array([0.0, -model.foot_load_N])
    power_motors = np.sum(tb.foot_load * qd, -1)
    power_foot = v_foot @ force_on_ground
    assert np.max(np.abs(power_motors - power_foot)) < 1e-6 * np.max(np.abs(power_foot))


def test_mass_matrix_symmetric_positive_definite(params, rng):
    pose = forward(params.leg, random_poses(params, rng))
    for izz in (physical_izz(params.leg, params.links), seed_model(params).izz):
        m = mass_matrix(params.leg, params.links, izz, pose)
        assert np.allclose(m, np.swapaxes(m, -1, -2), atol=1e-16)
        assert np.all(np.linalg.eigvalsh(m) > 0)


def test_coriolis_matches_christoffel_symbols_and_skew_symmetry(params, rng):
    """C(q, qd)_kj = sum_i Gamma_kij qd_i with Gamma from finite differences of M: C qd must equal
    the code's c(q, qd), and M_dot - 2C must be skew-symmetric."""
    q = random_poses(params, rng, 60)
    qd = rng.uniform(-6, 6, q.shape)
    izz = physical_izz(params.leg, params.links)
    branch = forward(params.leg, q).e_branch
    dm = central_difference(
        lambda x: mass_matrix(params.leg, params.links, izz, forward(params.leg, x, branch)), q,
        h=1e-5)                                                   # (n, k, j, i) = dM_kj/dq_i
    gamma = 0.5 * (dm + np.swapaxes(dm, -1, -2) - np.moveaxis(dm, -1, -3))  # Gamma_kji
    c_mat = np.einsum("nkji,ni->nkj", gamma, qd)
    m_dot = np.einsum("nkji,ni->nkj", dm, qd)
    c_code = coriolis(params.leg, params.links, izz, forward(params.leg, q), qd)
    assert np.max(np.abs(np.einsum("nkj,nj->nk", c_mat, qd) - c_code)) < 1e-6 * np.max(np.abs(c_code))
    n = m_dot - 2 * c_mat
    assert np.max(np.abs(n + np.swapaxes(n, -1, -2))) < 1e-8


@pytest.mark.parametrize("model_fn, balances", [(full_model, True), (seed_model, False)])
def test_power_balance(params, model_fn, balances):
    """tau . qd = d/dt (kinetic + potential energy of the links, kinetic of the rotors reflected
    through the gearbox) along a smooth motion, energy computed from link geometry only. The seed's link-weight sign breaks the balance."""
    t = np.linspace(0.0, 1.0, 4001)
    dt = t[1] - t[0]
    q0 = forward(params.leg, [[-1.7, -0.3]]).q[0]
    q = q0 + np.stack([0.3 * np.sin(2 * np.pi * t), 0.25 * np.sin(4 * np.pi * t + 1)], -1)
    qd = np.gradient(q, dt, axis=0)
    qdd = np.gradient(qd, dt, axis=0)
    model = no_foot_load(model_fn(params))
    pose = forward(params.leg, q)
    tau = torques(params.leg, params.links, model, pose, qd, qdd).total
    com, ang = link_geometry(params, q, pose.e_branch)
    m = np.array([params.links[n].mass_kg for n in LINK_NAMES])
    izz = np.asarray(physical_izz(params.leg, params.links))
    v = np.gradient(com, dt, axis=0)
    w = np.gradient(ang, dt, axis=0)
    g = params.robot.gravity_m_s2
    energy = 0.5 * np.sum(m[:, None] * v**2, (-1, -2)) + 0.5 * np.sum(izz * w**2, -1) \
        + g * np.sum(m * com[..., 1], -1) \
        + 0.5 * model.rotor_inertia_kg_m2 * np.sum(qd**2, -1)      # the rotors, reflected
    power_in = np.sum(tau * qd, -1)[5:-5]
    power_store = np.gradient(energy, dt)[5:-5]
    err = np.max(np.abs(power_in - power_store)) / np.max(np.abs(power_store))
    if balances:
        assert err < 1e-3
    else:
        assert err > 0.1


def test_dynamic_torque_tends_to_static_as_frequency_goes_to_zero(params):
    gaps = []
    for f in (1.0, 0.5, 0.1, 0.001):
        an = analyze(with_gait(params, frequency_hz=f))
        tb = an.torques["full"]
        gaps.append(np.max(np.abs(tb.total - tb.static)))
        r = an.results["results"]["full"]["A"]
        if f == 0.001:
            assert abs(r["dynamic_to_static_ratio"] - 1) < 1e-8
    # inertial and Coriolis torques scale with f^2
    assert gaps[0] / gaps[1] == pytest.approx(4.0, rel=1e-6)
    assert gaps[2] / gaps[3] == pytest.approx(1e4, rel=1e-6)


def test_seed_and_full_gravity_differ_only_in_link_weight_sign(params, rng):
    pose = forward(params.leg, random_poses(params, rng, 20))
    zero = np.zeros_like(pose.q)
    seed = torques(params.leg, params.links, seed_model(params), pose, zero, zero)
    full = torques(params.leg, params.links, full_model(params), pose, zero, zero)
    assert np.allclose(seed.link_weight, -full.link_weight)
    assert np.allclose(seed.foot_load, full.foot_load)


@pytest.mark.parametrize("path", ["seed_ellipse", "trot"])
def test_trot_model_loads_stance_only(params, path):
    """FL's scheduled load: half the weight when only its diagonal pair is in stance, a quarter
    when all four feet are, none in swing; stance read from the path's own definition."""
    an = analyze(params, path)
    load = an.models["full_trot"].foot_load_N
    weight = params.robot.total_mass_kg * params.robot.gravity_m_s2
    u = np.mod(an.samples.t * params.gait.frequency_hz, 1.0)           # FL phase 0
    u_other = np.mod(u + 0.5, 1.0)                                    # FR, RL half a cycle on
    start = 0.5 if path == "seed_ellipse" else 1.0 - params.gait.duty_factor
    stance, other = u >= start, u_other >= start
    if path == "seed_ellipse":                                       # lower half of the ellipse
        stance = an.samples.foot[:, 1] < params.gait.y_home_m - 1e-12
        other = an.samples.foot[:, 1] > params.gait.y_home_m + 1e-12
    assert np.all(load[~stance] == 0)
    assert np.allclose(load[stance & ~other], weight / 2)
    assert np.allclose(load[stance & other], weight / 4)
    assert (stance & other).any() == (path == "trot")
