"""Forces in the hinges of the closed chain (what bearings and link sections are sized from): a
planar Newton-Euler solve of the four links at each sample, independent of the Lagrangian
torques of the dynamics module (which it must reproduce: virtual work, less the rotors' reflected
inertia, which acts on the motor's side of the joint).

Unknowns per pose (12): the hinge forces F_A (ground on AC), F_B (ground on BD), F_C (AC on CE),
F_D (BD on DE), F_E (CE on DE), N, leg plane, and the torques tau_A on AC, tau_B on BD the
gearboxes deliver to the links (N*m, counter-clockwise). Equations (12): for each link, m a_G = sum F + m g and
Izz alpha = sum (r - r_G) x F (+ tau), with the foot load (upward ground force) on DE at F.
Accelerations: a_G = Jv q'' + bias, alpha = Jw q'' + bias (jacobians module).
"""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.mechanisms.fivebar import (LINK_NAMES, DynamicsModel, LegGeometry, LegPose,
                                              LinkInertia, bias_accelerations, com_fractions,
                                              link_jacobians)


JOINT_NAMES = ("A", "B", "C", "D", "E")
# Each hinge's force acts on the first link named (+) and on the second (-): the link
# downstream of it in the chain from the ground, and its upstream neighbour (None: the ground).
JOINT_LINKS = {"A": ("AC", None), "B": ("BD", None), "C": ("CE", "AC"), "D": ("DE", "BD"),
               "E": ("DE", "CE")}
MOTOR_LINKS = ("AC", "BD")
LINK_ENDS = {"AC": ("A", "C"), "BD": ("B", "D"), "CE": ("C", "E"), "DE": ("D", "E")}


@dataclass(frozen=True)
class JointLoads:
    """forces (..., 5, 2) N of the hinges JOINT_NAMES on their downstream link (JOINT_LINKS),
    torques the gearboxes deliver to the links AC, BD (..., 2) N*m, and the inputs each link's balance needs: points (..., 6, 2) m
    of A, B, C, D, E, F, COMs (..., 4, 2) m, COM accelerations (..., 4, 2) m/s^2, angular
    accelerations (..., 4) rad/s^2, foot load (...) N."""

    forces: np.ndarray
    torques: np.ndarray
    points: np.ndarray
    coms: np.ndarray
    com_acc: np.ndarray
    ang_acc: np.ndarray
    foot_load_N: np.ndarray


def _moment_row(point, com):
    """Coefficients of (Fx, Fy) in the moment about com (..., 2) of a force at point (..., 2)."""
    r = point - com
    return np.stack([-r[..., 1], r[..., 0]], axis=-1)


def joint_loads(leg: LegGeometry, links: dict[str, LinkInertia], model: DynamicsModel,
                pose: LegPose, qd, qdd) -> JointLoads:
    """Newton-Euler solve (module docstring) at poses (...) with motor rates qd and
    accelerations qdd (..., 2), under a physical model's loads (link weights down, Coriolis
    kept): its Izz, gravity and foot load (upward, N, a number or one per pose)."""
    if model.link_weight_sign != 1.0 or not model.coriolis:
        raise ValueError(f"model {model.name!r} is not physical: Newton-Euler needs the link "
                         "weights down and the velocity terms kept")
    shape = pose.c.shape[:-1]
    lj = link_jacobians(leg, links, pose)
    av, aw, _ = bias_accelerations(leg, links, pose, qd)
    qdd = np.asarray(qdd, dtype=float)
    com_acc = np.einsum("...kij,...j->...ki", lj.jv, qdd) + av
    ang_acc = np.einsum("...kj,...j->...k", lj.jw, qdd) + aw
    pts = dict(zip("ABCDEF", (np.broadcast_to(leg.a, pose.c.shape),
                              np.broadcast_to(leg.b, pose.c.shape), pose.c, pose.d, pose.e,
                              pose.f)))
    frac = com_fractions(leg, links)
    coms = np.stack([pts[p] + s * (pts[q] - pts[p])
                     for s, (p, q) in zip(frac, (LINK_ENDS[n] for n in LINK_NAMES))], axis=-2)
    masses = np.array([links[n].mass_kg for n in LINK_NAMES])
    load = np.broadcast_to(np.asarray(model.foot_load_N, dtype=float), shape)
    weight = np.array([0.0, -model.gravity_m_s2])
    a = np.zeros(shape + (12, 12))
    rhs = np.zeros(shape + (12,))
    for i, name in enumerate(LINK_NAMES):
        rows = slice(3 * i, 3 * i + 2)
        com = coms[..., i, :]
        for j, joint in enumerate(JOINT_NAMES):
            if name in JOINT_LINKS[joint]:
                sign = 1.0 if JOINT_LINKS[joint][0] == name else -1.0
                cols = slice(2 * j, 2 * j + 2)
                a[..., rows, cols] = sign * np.eye(2)
                a[..., 3 * i + 2, cols] = sign * _moment_row(pts[joint], com)
        if name in MOTOR_LINKS:
            a[..., 3 * i + 2, 10 + MOTOR_LINKS.index(name)] = 1.0
        rhs[..., rows] = masses[i] * (com_acc[..., i, :] - weight)
        rhs[..., 3 * i + 2] = model.izz[i] * ang_acc[..., i]
    # the foot load acts on DE at F: move it to the right-hand side
    foot = np.stack([np.zeros(shape), load], axis=-1)
    de = LINK_NAMES.index("DE")
    rhs[..., 3 * de:3 * de + 2] -= foot
    rhs[..., 3 * de + 2] -= np.einsum("...i,...i->...", _moment_row(pts["F"], coms[..., de, :]),
                                      foot)
    x = np.linalg.solve(a, rhs[..., None])[..., 0]
    return JointLoads(forces=x[..., :10].reshape(shape + (5, 2)), torques=x[..., 10:],
                      points=np.stack([pts[p] for p in "ABCDEF"], axis=-2), coms=coms,
                      com_acc=com_acc, ang_acc=ang_acc, foot_load_N=np.asarray(load))
