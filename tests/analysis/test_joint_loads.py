"""Hinge loads of the Newton-Euler solve: each link's forces and moments balance its mass times
accelerations taken by finite differences of the joint points (not the Jacobians' bias terms),
the ground reactions carry the foot load and the link weights, the motor torques are the
Lagrangian ones (virtual work), and a massless link is a two-force member."""

import dataclasses

import numpy as np
import pytest

from helpers import link_geometry

from fivebar_drake.analysis.joint_loads import JOINT_LINKS, JOINT_NAMES, joint_loads
from fivebar_drake.mechanisms.fivebar import LINK_NAMES, forward, inverse, sample_gait
from fivebar_drake.robots.quadruped.leg_loads import full_model, seed_model, trot_model

H = 1e-4   # s, finite-difference step of the test motion


def motion(params, t):
    """A smooth motion about a gait pose: q(t) = q0 + 0.2 sin(3 t + (0, 1)) rad, with its
    analytic rates and accelerations."""
    q0 = sample_gait(params.leg, params.gait).pose.q[17]
    phase = 3.0 * np.asarray(t)[..., None] + np.array([0.0, 1.0])
    return q0 + 0.2 * np.sin(phase), 0.6 * np.cos(phase), -1.8 * np.sin(phase)


def test_each_link_balances(params):
    model = full_model(params)
    t0 = 0.4
    q, qd, qdd = motion(params, t0)
    branch = inverse(params.leg, forward(params.leg, q).f).e_branch   # the gait's E branch
    pose = forward(params.leg, q, branch)
    jl = joint_loads(params.leg, params.links, model, pose, qd, qdd)
    qs = np.stack([motion(params, t)[0] for t in (t0 - H, t0, t0 + H)])
    coms, angles = link_geometry(params, qs, branch)
    acc = (coms[2] - 2 * coms[1] + coms[0]) / H**2
    alpha = (angles[2] - 2 * angles[1] + angles[0]) / H**2
    points = dict(zip("ABCDEF", jl.points))
    g = np.array([0.0, -params.robot.gravity_m_s2])
    izz = dict(zip(LINK_NAMES, model.izz))
    for i, name in enumerate(LINK_NAMES):
        mass = params.links[name].mass_kg
        force, moment = mass * g, 0.0
        for j, joint in enumerate(JOINT_NAMES):
            if name in JOINT_LINKS[joint]:
                f = jl.forces[j] * (1 if JOINT_LINKS[joint][0] == name else -1)
                r = points[joint] - coms[1, i]
                force, moment = force + f, moment + r[0] * f[1] - r[1] * f[0]
        if name == "DE":
            foot = np.array([0.0, model.foot_load_N])
            r = points["F"] - coms[1, i]
            force, moment = force + foot, moment + r[0] * foot[1] - r[1] * foot[0]
        if name in ("AC", "BD"):
            moment += jl.torques[("AC", "BD").index(name)]
        scale = np.abs(jl.forces).max()
        np.testing.assert_allclose(force, mass * acc[i], atol=1e-6 * scale, err_msg=name)
        assert moment == pytest.approx(izz[name] * alpha[i], abs=1e-7 * scale), name


def test_ground_carries_foot_load_and_weights_at_rest(params, rng):
    model = full_model(params)
    pose = sample_gait(params.leg, params.gait).pose
    jl = joint_loads(params.leg, params.links, model, pose, np.zeros(2), np.zeros(2))
    weights = sum(params.links[n].mass_kg for n in LINK_NAMES) * params.robot.gravity_m_s2
    ground = jl.forces[:, 0] + jl.forces[:, 1]               # A and B on the links
    np.testing.assert_allclose(ground[:, 0], 0.0, atol=1e-9)
    np.testing.assert_allclose(ground[:, 1], weights - model.foot_load_N, rtol=1e-12)


@pytest.mark.parametrize("which", ["full", "full_trot"])
def test_motor_torques_are_the_lagrangian_ones(params, rng, which):
    gait = sample_gait(params.leg, params.gait)
    model = full_model(params) if which == "full" else trot_model(params, "seed_ellipse", gait.t)
    qd, qdd = rng.normal(0, 3, gait.qd.shape), rng.normal(0, 30, gait.qdd.shape)
    for rates in ((gait.qd, gait.qdd), (qd, qdd)):
        jl = joint_loads(params.leg, params.links, model, gait.pose, *rates)
        # the motors also spin their rotors (reflected N^2 J): the links get the rest
        tb = params.fivebar_leg.torques(model, gait.pose, *rates)
        want = tb.joint
        np.testing.assert_allclose(tb.total - want, model.rotor_inertia_kg_m2 * rates[1],
                                   rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(jl.torques, want, rtol=1e-10, atol=1e-12)


def test_massless_coupler_is_a_two_force_member(params):
    links = dict(params.links, CE=dataclasses.replace(params.links["CE"], mass_kg=0.0,
                                                      izz_kg_m2=0.0))
    model = dataclasses.replace(full_model(params), izz=(1e-5, 1e-5, 0.0, 8e-5))
    pose = sample_gait(params.leg, params.gait).pose
    jl = joint_loads(params.leg, links, model, pose, np.ones(2), np.full(2, 10.0))
    along = pose.e - pose.c
    c, e = jl.forces[:, JOINT_NAMES.index("C")], jl.forces[:, JOINT_NAMES.index("E")]
    cross = c[:, 0] * along[:, 1] - c[:, 1] * along[:, 0]
    np.testing.assert_allclose(cross, 0.0, atol=1e-9 * np.abs(c).max())
    np.testing.assert_allclose(c, e, atol=1e-12 * np.abs(c).max())


def test_the_seed_reading_is_refused(params):
    pose = sample_gait(params.leg, params.gait).pose
    with pytest.raises(ValueError, match="not physical"):
        joint_loads(params.leg, params.links, seed_model(params), pose, 0.0, 0.0)
