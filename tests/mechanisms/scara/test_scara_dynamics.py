"""The Lagrange model: M against the seed's eq. 2.69 and a hand sum over the links, properties
(symmetric, positive definite, Mdot - 2C skew), C against the seed's eq. 2.72, G by virtual work,
and the power balance along a motion."""

import math

import numpy as np
import pytest

from fivebar_drake.mechanisms.scara import Dynamics, Scara, load_params, seed_inertia


@pytest.fixture(scope="module")
def params():
    return load_params()


@pytest.fixture(scope="module")
def dyn(params):
    return Dynamics(params.kinematics, seed_inertia(params.links, 20.0))


def states(rng, n=100):
    q = rng.uniform([-2.8, -2.5, 0.0], [2.8, 2.5, 0.4], (n, 3))
    return q, rng.normal(size=(n, 3)), rng.normal(size=(n, 3))


def test_seed_inertias(params):
    i = seed_inertia(params.links)
    assert i.izz1 == pytest.approx(8.2 * 0.175**2 / 12)
    assert i.izz2 == pytest.approx(11.8 * 0.25**2 / 12)
    assert i.izz3 == pytest.approx(2 * 0.0125**2 / 2)
    assert seed_inertia(params.links, 20.0).m3 == 24.0


def test_mass_matrix_against_the_seeds_eq_2_69(params, rng):
    i = seed_inertia(params.links)
    a1, a2, m1, m2, m3 = 0.35, 0.5, 14.2, 14.34, 4.0
    q2 = rng.uniform(-2.5, 2.5, 50)
    c = np.cos(q2)
    m11 = (i.izz1 + i.izz2 + i.izz3 + a1**2 / 4 * m1 + (a1**2 + a2**2 / 4 + a1 * a2 * c) * m2
           + (a1**2 + a2**2 + 2 * a1 * a2 * c) * m3)
    m12 = i.izz2 + i.izz3 + (a1 * a2 * c / 2 + a2**2 / 4) * m2 + (a2**2 + a1 * a2 * c) * m3
    m22 = i.izz2 + i.izz3 + a2**2 / 4 * m2 + a2**2 * m3
    m = Dynamics(params.kinematics, i).mass_matrix(np.stack([0 * q2, q2, 0 * q2], 1))
    assert m[:, 0, 0] == pytest.approx(m11) and m[:, 0, 1] == pytest.approx(m12)
    assert m[:, 1, 1] == pytest.approx(m22) and m[:, 2, 2] == pytest.approx(m3)
    assert m[:, 0, 2] == pytest.approx(0 * q2) and m[:, 1, 2] == pytest.approx(0 * q2)


def test_mass_matrix_from_the_link_jacobians(params, dyn, rng):
    # eq. 2.56: sum of m J_T^T J_T + J_R^T I J_R with the COM Jacobians by finite differences
    i, k = dyn.i, params.kinematics
    q, _, _ = states(rng, 20)
    h = 1e-6

    def coms(q):
        q1, q12 = q[..., 0], q[..., 0] + q[..., 1]
        e = np.stack([k.a1_m * np.cos(q1), k.a1_m * np.sin(q1)], -1)
        c1 = np.stack([i.c1 * np.cos(q1), i.c1 * np.sin(q1), 0 * q1], -1)
        c2 = np.concatenate([e + i.c2 * np.stack([np.cos(q12), np.sin(q12)], -1),
                             0 * q1[..., None]], -1)
        c3 = Scara(k).forward(q).f
        return [c1, c2, c3]

    for qk in q:
        jac = [np.zeros((3, 3)) for _ in range(3)]
        for j in range(3):
            dq = np.zeros(3)
            dq[j] = h
            for b, (p, m) in enumerate(zip(coms(qk + dq), coms(qk - dq))):
                jac[b][:, j] = (p - m) / (2 * h)
        jr = [np.array([1.0, 0, 0]), np.array([1.0, 1, 0]), np.array([1.0, 1, 0])]
        m = sum(mass * jt.T @ jt for mass, jt in zip((i.m1, i.m2, i.m3), jac))
        m = m + sum(izz * np.outer(r, r) for izz, r in zip((i.izz1, i.izz2, i.izz3), jr))
        assert dyn.mass_matrix(qk) == pytest.approx(m, abs=1e-7)


def test_mass_matrix_symmetric_positive_definite(dyn, rng):
    q, _, _ = states(rng)
    m = dyn.mass_matrix(q)
    assert m == pytest.approx(np.swapaxes(m, 1, 2), abs=0)
    assert np.linalg.eigvalsh(m).min() > 0


def test_mdot_minus_2c_is_skew(dyn, rng):
    q, qd, _ = states(rng)
    h = 1e-6
    mdot = (dyn.mass_matrix(q + h * qd) - dyn.mass_matrix(q - h * qd)) / (2 * h)
    n = mdot - 2 * dyn.coriolis_matrix(q, qd)
    assert n == pytest.approx(-np.swapaxes(n, 1, 2), abs=1e-7)


def test_coriolis_against_the_seeds_eq_2_72(params, rng):
    dyn = Dynamics(params.kinematics, seed_inertia(params.links))
    q, qd, _ = states(rng, 30)
    c = dyn.coriolis_matrix(q, qd)
    k = (14.34 / 2 + 4.0) * 0.35 * 0.5 * np.sin(q[:, 1])
    assert c[:, 0, 0] == pytest.approx(-k * qd[:, 1])
    assert c[:, 0, 1] == pytest.approx(-k * (qd[:, 0] + qd[:, 1]))
    assert c[:, 1, 0] == pytest.approx(k * qd[:, 0])
    for i, j in ((0, 2), (1, 1), (1, 2), (2, 0), (2, 1), (2, 2)):
        assert c[:, i, j] == pytest.approx(0 * k, abs=1e-15)


def test_gravity_by_virtual_work(params, dyn, rng):
    # G = dV/dq with V = m3 g z_tool (links 1, 2 move horizontally)
    q, _, _ = states(rng, 20)
    h = 1e-6
    scara = Scara(params.kinematics)
    for j in range(3):
        dq = np.zeros(3)
        dq[j] = h
        dv = dyn.i.m3 * dyn.i.g * (scara.forward(q + dq).f[:, 2] - scara.forward(q - dq).f[:, 2])
        assert dyn.gravity(q)[:, j] == pytest.approx(dv / (2 * h), abs=1e-6)
    assert dyn.gravity(q)[0, 2] == pytest.approx(-24.0 * 9.81)     # tool down: q3 along -z


def test_power_balance(dyn):
    # d/dt (kinetic + potential energy) = qd . tau along a smooth motion
    t = np.linspace(0, 1, 20001)
    q = np.stack([np.sin(2 * t), 1.2 * np.cos(3 * t), 0.2 + 0.1 * np.sin(5 * t)], 1)
    qd = np.stack([2 * np.cos(2 * t), -3.6 * np.sin(3 * t), 0.5 * np.cos(5 * t)], 1)
    qdd = np.stack([-4 * np.sin(2 * t), -10.8 * np.cos(3 * t), -2.5 * np.sin(5 * t)], 1)
    tau = dyn.torques(q, qd, qdd)["total"]
    ke = 0.5 * np.einsum("ni,nij,nj->n", qd, dyn.mass_matrix(q), qd)
    pe = dyn.i.m3 * dyn.i.g * (-q[:, 2])
    power = np.gradient(ke + pe, t)
    assert power[5:-5] == pytest.approx(np.einsum("ni,ni->n", qd, tau)[5:-5], abs=1e-4)


def test_torque_parts_add_up(dyn, rng):
    q, qd, qdd = states(rng)
    parts = dyn.torques(q, qd, qdd)
    assert parts["total"] == pytest.approx(parts["inertial"] + parts["coriolis"]
                                           + parts["gravity"])
    assert math.isclose(parts["inertial"][0, 2], 24.0 * qdd[0, 2])
