"""Analytic Jacobians and velocity-product accelerations of the 5-bar leg (seed 003 section 3).

Everything is in the leg plane (m, rad), vectorised over poses: a pose array (..., 2) gives
Jacobians (..., 2, 2) with columns d/d(theta_A), d/d(theta_B). Links are ordered AC, BD, CE, DE.
E follows from implicit differentiation of the two loop circles: A v_E = B q_dot, J_E = A^-1 B;
the foot F = E + (EF/DE)(E - D) gives J_F = (1 + EF/DE) J_E - (EF/DE) J_D = (37 J_E - 8 J_D)/29.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .compiled import jit
from .kinematics import LegPose
from .params import LINK_NAMES, LegGeometry, LinkInertia


LINK_ENDS = ((0, 2), (1, 3), (2, 4), (3, 4))   # link i joins points (A, B, C, D, E)[p] -> [q]


@jit
def point_jacobian_arrays(geom, cx, cy, dx, dy, ex, ey):
    """Velocity Jacobians (n, 2, 2) in m/rad of C, D, E and F for flat pose arrays (n,)."""
    ax, ay, bx, by, ac, bd, ce, de, ef = geom
    n = cx.shape[0]
    ra_x, ra_y = cx - ax, cy - ay                    # A -> C
    rb_x, rb_y = dx - bx, dy - by                    # B -> D
    a11, a12, a21, a22 = ex - cx, ey - cy, ex - dx, ey - dy   # rows E - C, E - D of A
    b11 = ra_x * a12 - ra_y * a11          # l1 [(ye - yc) cos(tA) - (xe - xc) sin(tA)]
    b22 = rb_x * a22 - rb_y * a21          # l2 [(ye - yd) cos(tB) - (xe - xd) sin(tB)]
    det = a11 * a22 - a12 * a21
    jc, jd, je = np.zeros((n, 2, 2)), np.zeros((n, 2, 2)), np.empty((n, 2, 2))
    jc[:, 0, 0], jc[:, 1, 0] = -ra_y, ra_x
    jd[:, 0, 1], jd[:, 1, 1] = -rb_y, rb_x
    je[:, 0, 0], je[:, 0, 1] = a22 * b11 / det, -a12 * b22 / det
    je[:, 1, 0], je[:, 1, 1] = -a21 * b11 / det, a11 * b22 / det
    k = ef / de
    return jc, jd, je, (1.0 + k) * je - k * jd


@jit
def _points(geom, cx, cy, dx, dy, ex, ey):
    """Points A, B, C, D, E as (5, n, 2)."""
    n = cx.shape[0]
    pts = np.empty((5, n, 2))
    pts[0, :, 0], pts[0, :, 1], pts[1, :, 0], pts[1, :, 1] = geom[0], geom[1], geom[2], geom[3]
    pts[2, :, 0], pts[2, :, 1], pts[3, :, 0], pts[3, :, 1] = cx, cy, dx, dy
    pts[4, :, 0], pts[4, :, 1] = ex, ey
    return pts


@jit
def link_jacobian_arrays(geom, com_fraction, cx, cy, dx, dy, ex, ey):
    """COM Jacobians jv (n, 4, 2, 2) m/rad, angular Jacobians jw (n, 4, 2) and J_F (n, 2, 2)
    of the links AC, BD, CE, DE for flat pose arrays (n,); com_fraction (4,): COM distance from
    the first joint over the link's joint distance. A COM at fraction s of link P->Q moves with
    J_P + s (J_Q - J_P); the link turns at (u x u') / L^2, u = Q - P, L = |PQ|."""
    n = cx.shape[0]
    jc, jd, je, jf = point_jacobian_arrays(geom, cx, cy, dx, dy, ex, ey)
    jac = np.zeros((5, n, 2, 2))
    jac[2], jac[3], jac[4] = jc, jd, je
    pts = _points(geom, cx, cy, dx, dy, ex, ey)
    jv, jw = np.empty((n, 4, 2, 2)), np.empty((n, 4, 2))
    for i in range(4):
        p, q = LINK_ENDS[i]
        rel = jac[q] - jac[p]
        u = pts[q] - pts[p]
        length2 = geom[4 + i] ** 2
        jv[:, i] = jac[p] + com_fraction[i] * rel
        for j in range(2):
            jw[:, i, j] = (u[:, 0] * rel[:, 1, j] - u[:, 1] * rel[:, 0, j]) / length2
    return jv, jw, jf


@jit
def bias_arrays(geom, com_fraction, cx, cy, dx, dy, ex, ey, qda, qdb):
    """Velocity-product accelerations for motor rates qda, qdb (n,) rad/s: link COMs av
    (n, 4, 2) m/s^2, link angular aw (n, 4) rad/s^2, foot af (n, 2) m/s^2. From
    C'' = -tA'^2 (C - A), D'' = -tB'^2 (D - B) and the loop circles differentiated twice:
    A E'' = [(E-C).C'' - |E'-C'|^2, (E-D).D'' - |E'-D'|^2]."""
    n = cx.shape[0]
    jc, jd, je, _ = point_jacobian_arrays(geom, cx, cy, dx, dy, ex, ey)
    pts = _points(geom, cx, cy, dx, dy, ex, ey)
    vel = np.empty((3, n, 2))
    for i, jac in enumerate((jc, jd, je)):
        vel[i] = jac[:, :, 0] * qda[:, None] + jac[:, :, 1] * qdb[:, None]
    acc = np.zeros((5, n, 2))
    acc[2] = -(qda**2)[:, None] * (pts[2] - pts[0])
    acc[3] = -(qdb**2)[:, None] * (pts[3] - pts[1])
    a11, a12, a21, a22 = ex - cx, ey - cy, ex - dx, ey - dy
    rel_c, rel_d = vel[2] - vel[0], vel[2] - vel[1]
    rhs1 = a11 * acc[2, :, 0] + a12 * acc[2, :, 1] - (rel_c[:, 0] ** 2 + rel_c[:, 1] ** 2)
    rhs2 = a21 * acc[3, :, 0] + a22 * acc[3, :, 1] - (rel_d[:, 0] ** 2 + rel_d[:, 1] ** 2)
    det = a11 * a22 - a12 * a21
    acc[4, :, 0], acc[4, :, 1] = (a22 * rhs1 - a12 * rhs2) / det, (a11 * rhs2 - a21 * rhs1) / det
    av, aw = np.empty((n, 4, 2)), np.empty((n, 4))
    for i in range(4):
        p, q = LINK_ENDS[i]
        rel = acc[q] - acc[p]
        u = pts[q] - pts[p]
        av[:, i] = acc[p] + com_fraction[i] * rel
        aw[:, i] = (u[:, 0] * rel[:, 1] - u[:, 1] * rel[:, 0]) / geom[4 + i] ** 2
    k = geom[8] / geom[7]
    return av, aw, (1.0 + k) * acc[4] - k * acc[3]


def com_fractions(leg: LegGeometry, links: dict[str, LinkInertia]) -> np.ndarray:
    """COM distance from each link's first joint over its joint distance (AC, BD, CE, DE)."""
    lengths = (leg.ac_m, leg.bd_m, leg.ce_m, leg.de_m)
    return np.array([links[name].com_m / length for name, length in zip(LINK_NAMES, lengths)])


def point_jacobians(leg: LegGeometry, pose: LegPose) -> dict[str, np.ndarray]:
    """Velocity Jacobians (..., 2, 2) of the joints C, D, E and the foot F, in m/rad."""
    shape = pose.c.shape[:-1] + (2, 2)
    return {name: jac.reshape(shape)
            for name, jac in zip("CDEF", point_jacobian_arrays(leg.core, *pose.flat()))}


def foot_jacobian(leg: LegGeometry, pose: LegPose) -> np.ndarray:
    """J_F (..., 2, 2) in m/rad: foot velocity v_F = J_F q_dot."""
    return point_jacobians(leg, pose)["F"]


@dataclass(frozen=True)
class LinkJacobians:
    """COM velocity Jacobians jv (..., 4, 2, 2) in m/rad and angular velocity Jacobians
    jw (..., 4, 2) (dimensionless) of the links AC, BD, CE, DE; foot Jacobian jf (..., 2, 2)."""

    jv: np.ndarray
    jw: np.ndarray
    jf: np.ndarray


def link_jacobians(leg: LegGeometry, links: dict[str, LinkInertia], pose: LegPose) -> LinkJacobians:
    """Analytic COM and angular Jacobians of all four links (link_jacobian_arrays; the seed
    differentiates CE and DE numerically)."""
    shape = pose.c.shape[:-1]
    jv, jw, jf = link_jacobian_arrays(leg.core, com_fractions(leg, links), *pose.flat())
    return LinkJacobians(jv=jv.reshape(shape + (4, 2, 2)), jw=jw.reshape(shape + (4, 2)),
                         jf=jf.reshape(shape + (2, 2)))


def bias_accelerations(leg: LegGeometry, links: dict[str, LinkInertia], pose: LegPose, qd):
    """Velocity-product accelerations (the accelerations at q_ddot = 0, bias_arrays) for motor
    rates qd (..., 2) rad/s: link COMs av (..., 4, 2) m/s^2, link angular aw (..., 4) rad/s^2,
    and the foot af (..., 2) m/s^2."""
    shape = pose.c.shape[:-1]
    qd = np.broadcast_to(np.asarray(qd, dtype=float), shape + (2,))
    av, aw, af = bias_arrays(leg.core, com_fractions(leg, links), *pose.flat(),
                             np.ascontiguousarray(qd[..., 0]).ravel(),
                             np.ascontiguousarray(qd[..., 1]).ravel())
    return av.reshape(shape + (4, 2)), aw.reshape(shape + (4,)), af.reshape(shape + (2,))
