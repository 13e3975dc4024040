"""Analytic Jacobians and velocity-product accelerations of the 5-bar leg (seed 003 section 3).

Everything is in the leg plane (m, rad), vectorised over poses: a pose array (..., 2) gives
Jacobians (..., 2, 2) with columns d/d(theta_A), d/d(theta_B). Links are ordered AC, BD, CE, DE.
E follows from implicit differentiation of the two loop circles: A v_E = B q_dot, J_E = A^-1 B;
the foot F = E + (EF/DE)(E - D) gives J_F = (1 + EF/DE) J_E - (EF/DE) J_D = (37 J_E - 8 J_D)/29.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics import LegPose
from .params import LINK_NAMES, LegGeometry, LinkInertia


def _inv_times(a11, a12, a21, a22, x, y):
    """Solve [[a11, a12], [a21, a22]] [u, v]^T = [x, y]^T elementwise."""
    det = a11 * a22 - a12 * a21
    return (a22 * x - a12 * y) / det, (a11 * y - a21 * x) / det


def _matrix(m11, m12, m21, m22) -> np.ndarray:
    """Stack elementwise entries (arrays of one shape, or scalars) into matrices (..., 2, 2)."""
    shape = np.broadcast(m11, m12, m21, m22).shape
    out = np.empty(shape + (2, 2))
    out[..., 0, 0], out[..., 0, 1], out[..., 1, 0], out[..., 1, 1] = m11, m12, m21, m22
    return out


def _loop_matrix(pose: LegPose):
    """Rows (E - C) and (E - D) of the loop-closure matrix A (seed 003 section 3.3)."""
    e = pose.e
    return (e[..., 0] - pose.c[..., 0], e[..., 1] - pose.c[..., 1],
            e[..., 0] - pose.d[..., 0], e[..., 1] - pose.d[..., 1])


def point_jacobians(leg: LegGeometry, pose: LegPose) -> dict[str, np.ndarray]:
    """Velocity Jacobians (..., 2, 2) of the joints C, D, E and the foot F, in m/rad."""
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    ra_x, ra_y = pose.c[..., 0] - ax, pose.c[..., 1] - ay      # A -> C
    rb_x, rb_y = pose.d[..., 0] - bx, pose.d[..., 1] - by      # B -> D
    a11, a12, a21, a22 = _loop_matrix(pose)
    b11 = ra_x * a12 - ra_y * a11          # l1 [(ye - yc) cos(tA) - (xe - xc) sin(tA)]
    b22 = rb_x * a22 - rb_y * a21          # l2 [(ye - yd) cos(tB) - (xe - xd) sin(tB)]
    det = a11 * a22 - a12 * a21
    jc = _matrix(-ra_y, 0.0, ra_x, 0.0)
    jd = _matrix(0.0, -rb_y, 0.0, rb_x)
    je = _matrix(a22 * b11 / det, -a12 * b22 / det, -a21 * b11 / det, a11 * b22 / det)
    k = leg.ef_m / leg.de_m
    return {"C": jc, "D": jd, "E": je, "F": (1.0 + k) * je - k * jd}


def foot_jacobian(leg: LegGeometry, pose: LegPose) -> np.ndarray:
    """J_F (..., 2, 2) in m/rad: foot velocity v_F = J_F q_dot."""
    return point_jacobians(leg, pose)["F"]


def _link_ends(leg: LegGeometry):
    """For each link: (first joint, second joint, length from first to second joint)."""
    return (("A", "C", leg.ac_m), ("B", "D", leg.bd_m), ("C", "E", leg.ce_m),
            ("D", "E", leg.de_m))


def _points(leg: LegGeometry, pose: LegPose) -> dict[str, np.ndarray]:
    shape = pose.c.shape
    return {"A": np.broadcast_to(leg.a, shape), "B": np.broadcast_to(leg.b, shape),
            "C": pose.c, "D": pose.d, "E": pose.e}


def _angular(u, du, length):
    """Angular rate of a link of fixed length with direction u and rate of change du."""
    return (u[..., 0] * du[..., 1] - u[..., 1] * du[..., 0]) / length**2


@dataclass(frozen=True)
class LinkJacobians:
    """COM velocity Jacobians jv (..., 4, 2, 2) in m/rad and angular velocity Jacobians
    jw (..., 4, 2) (dimensionless) of the links AC, BD, CE, DE; foot Jacobian jf (..., 2, 2)."""

    jv: np.ndarray
    jw: np.ndarray
    jf: np.ndarray


def link_jacobians(leg: LegGeometry, links: dict[str, LinkInertia], pose: LegPose) -> LinkJacobians:
    """Analytic COM and angular Jacobians of all four links (the seed differentiates CE and DE
    numerically). A COM at distance r from the first joint P of link P->Q moves with
    J_P + (r/|PQ|)(J_Q - J_P)."""
    pj = point_jacobians(leg, pose)
    pts = _points(leg, pose)
    zero = np.zeros(pose.c.shape[:-1] + (2, 2))
    pj.update(A=zero, B=zero)
    jv, jw = [], []
    for name, (p, q, length) in zip(LINK_NAMES, _link_ends(leg)):
        s = links[name].com_m / length
        jv.append(pj[p] + s * (pj[q] - pj[p]))
        u = pts[q] - pts[p]
        jw.append(_angular(u[..., None, :], np.swapaxes(pj[q] - pj[p], -1, -2), length))
    return LinkJacobians(jv=np.stack(jv, -3), jw=np.stack(jw, -2), jf=pj["F"])


def bias_accelerations(leg: LegGeometry, links: dict[str, LinkInertia], pose: LegPose, qd):
    """Velocity-product accelerations (the accelerations at q_ddot = 0) for motor rates qd
    (..., 2) rad/s: link COMs av (..., 4, 2) m/s^2, link angular aw (..., 4) rad/s^2, and the
    foot af (..., 2) m/s^2. From C'' = -tA'^2 (C - A), D'' = -tB'^2 (D - B) and the second
    derivative of the loop circles: A E'' = [(E-C).C'' - |E'-C'|^2, (E-D).D'' - |E'-D'|^2]."""
    qd = np.asarray(qd, dtype=float)
    pj = point_jacobians(leg, pose)
    pts = _points(leg, pose)
    vel = {k: np.einsum("...ij,...j->...i", pj[k], qd) for k in ("C", "D", "E")}
    vel.update(A=np.zeros_like(pose.c), B=np.zeros_like(pose.c))
    acc = {"A": np.zeros_like(pose.c), "B": np.zeros_like(pose.c),
           "C": -qd[..., :1] ** 2 * (pose.c - pts["A"]),
           "D": -qd[..., 1:] ** 2 * (pose.d - pts["B"])}
    a11, a12, a21, a22 = _loop_matrix(pose)
    rel_c, rel_d = vel["E"] - vel["C"], vel["E"] - vel["D"]
    rhs1 = a11 * acc["C"][..., 0] + a12 * acc["C"][..., 1] - np.sum(rel_c**2, -1)
    rhs2 = a21 * acc["D"][..., 0] + a22 * acc["D"][..., 1] - np.sum(rel_d**2, -1)
    acc["E"] = np.stack(_inv_times(a11, a12, a21, a22, rhs1, rhs2), -1)
    av, aw = [], []
    for name, (p, q, length) in zip(LINK_NAMES, _link_ends(leg)):
        s = links[name].com_m / length
        av.append(acc[p] + s * (acc[q] - acc[p]))
        aw.append(_angular(pts[q] - pts[p], acc[q] - acc[p], length))
    k = leg.ef_m / leg.de_m
    af = (1.0 + k) * acc["E"] - k * acc["D"]
    return np.stack(av, -2), np.stack(aw, -1), af
