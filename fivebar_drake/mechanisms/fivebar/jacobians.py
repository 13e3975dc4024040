"""Analytic Jacobians and velocity-product accelerations of the 5-bar leg (seed 003 section 3).

Everything is in the leg plane (m, rad), vectorised over poses: a pose array (..., 2) gives
Jacobians (..., 2, 2) with columns d/d(theta_A), d/d(theta_B). Links are ordered AC, BD, CE, DE.
E follows from implicit differentiation of the two loop circles: A v_E = B q_dot, J_E = A^-1 B;
the foot F = E + (EF/DE)(E - D) gives J_F = (1 + EF/DE) J_E - (EF/DE) J_D = (37 J_E - 8 J_D)/29.
"""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.mechanisms.fivebar.geometry import LINK_NAMES, LegGeometry, LinkInertia
from fivebar_drake.mechanisms.fivebar.kinematics import LegPose


LINK_ENDS = ((0, 2), (1, 3), (2, 4), (3, 4))   # link i joins points (A, B, C, D, E)[p] -> [q]


@jit
def pose_jacobians(geom, cx, cy, dx, dy, ex, ey, pts, jac):
    """One pose: the points A, B, C, D, E (m) into pts (5, 2) and their velocity Jacobians
    (m/rad) into jac (5, 2, 2) (A and B fixed: zero)."""
    ax, ay, bx, by = geom[0], geom[1], geom[2], geom[3]
    pts[0, 0], pts[0, 1], pts[1, 0], pts[1, 1] = ax, ay, bx, by
    pts[2, 0], pts[2, 1], pts[3, 0], pts[3, 1], pts[4, 0], pts[4, 1] = cx, cy, dx, dy, ex, ey
    ra_x, ra_y = cx - ax, cy - ay                    # A -> C
    rb_x, rb_y = dx - bx, dy - by                    # B -> D
    a11, a12, a21, a22 = ex - cx, ey - cy, ex - dx, ey - dy   # rows E - C, E - D of A
    b11 = ra_x * a12 - ra_y * a11          # l1 [(ye - yc) cos(tA) - (xe - xc) sin(tA)]
    b22 = rb_x * a22 - rb_y * a21          # l2 [(ye - yd) cos(tB) - (xe - xd) sin(tB)]
    det = a11 * a22 - a12 * a21
    jac[:] = 0.0
    jac[2, 0, 0], jac[2, 1, 0] = -ra_y, ra_x
    jac[3, 0, 1], jac[3, 1, 1] = -rb_y, rb_x
    jac[4, 0, 0], jac[4, 0, 1] = a22 * b11 / det, -a12 * b22 / det
    jac[4, 1, 0], jac[4, 1, 1] = -a21 * b11 / det, a11 * b22 / det


@jit
def foot_from(geom, e, d, out):
    """F = (1 + k) E - k D with k = EF/DE, elementwise for equal-shaped e, d into out."""
    k = geom[8] / geom[7]
    for j in range(e.size):
        out.flat[j] = (1.0 + k) * e.flat[j] - k * d.flat[j]


@jit
def point_jacobian_arrays(geom, cx, cy, dx, dy, ex, ey):
    """Velocity Jacobians (n, 2, 2) in m/rad of C, D, E and F for flat pose arrays (n,)."""
    n = cx.shape[0]
    jc, jd, je, jf = (np.empty((n, 2, 2)), np.empty((n, 2, 2)), np.empty((n, 2, 2)),
                      np.empty((n, 2, 2)))
    pts, jac = np.empty((5, 2)), np.empty((5, 2, 2))
    for i in range(n):
        pose_jacobians(geom, cx[i], cy[i], dx[i], dy[i], ex[i], ey[i], pts, jac)
        jc[i], jd[i], je[i] = jac[2], jac[3], jac[4]
        foot_from(geom, jac[4], jac[3], jf[i])
    return jc, jd, je, jf


@jit
def link_jacobians_at(geom, com_fraction, pts, jac, jv, jw):
    """One pose: COM Jacobians jv (4, 2, 2) m/rad and angular Jacobians jw (4, 2) of the links
    from its points pts (5, 2) and their Jacobians jac (5, 2, 2) (pose_jacobians). A COM at
    fraction s of link P->Q moves with J_P + s (J_Q - J_P); the link turns at (u x u') / L^2,
    u = Q - P, L = |PQ|."""
    for i in range(4):
        p, q = LINK_ENDS[i]
        ux, uy = pts[q, 0] - pts[p, 0], pts[q, 1] - pts[p, 1]
        for j in range(2):
            rx, ry = jac[q, 0, j] - jac[p, 0, j], jac[q, 1, j] - jac[p, 1, j]
            jv[i, 0, j] = jac[p, 0, j] + com_fraction[i] * rx
            jv[i, 1, j] = jac[p, 1, j] + com_fraction[i] * ry
            jw[i, j] = (ux * ry - uy * rx) / geom[4 + i] ** 2


@jit
def link_jacobian_arrays(geom, com_fraction, cx, cy, dx, dy, ex, ey):
    """COM Jacobians jv (n, 4, 2, 2) m/rad, angular Jacobians jw (n, 4, 2) and J_F (n, 2, 2)
    of the links AC, BD, CE, DE for flat pose arrays (n,); com_fraction (4,): COM distance from
    the first joint over the link's joint distance (link_jacobians_at)."""
    n = cx.shape[0]
    jv, jw, jf = np.empty((n, 4, 2, 2)), np.empty((n, 4, 2)), np.empty((n, 2, 2))
    pts, jac = np.empty((5, 2)), np.empty((5, 2, 2))
    for i in range(n):
        pose_jacobians(geom, cx[i], cy[i], dx[i], dy[i], ex[i], ey[i], pts, jac)
        link_jacobians_at(geom, com_fraction, pts, jac, jv[i], jw[i])
        foot_from(geom, jac[4], jac[3], jf[i])
    return jv, jw, jf


@jit
def bias_at(geom, com_fraction, pts, jac, qda, qdb, acc, av, aw, af):
    """One pose at motor rates qda, qdb rad/s: velocity-product accelerations of the link COMs
    av (4, 2) m/s^2, link angular aw (4,) rad/s^2 and the foot af (2,) m/s^2, from its points
    pts and Jacobians jac (pose_jacobians); acc (5, 2) is scratch. From C'' = -tA'^2 (C - A),
    D'' = -tB'^2 (D - B) and the loop circles differentiated twice:
    A E'' = [(E-C).C'' - |E'-C'|^2, (E-D).D'' - |E'-D'|^2]."""
    acc[:] = 0.0
    for j in range(2):
        acc[2, j] = -qda * qda * (pts[2, j] - pts[0, j])
        acc[3, j] = -qdb * qdb * (pts[3, j] - pts[1, j])
    # velocities of E relative to C and to D
    rcx = (jac[4, 0, 0] - jac[2, 0, 0]) * qda + (jac[4, 0, 1] - jac[2, 0, 1]) * qdb
    rcy = (jac[4, 1, 0] - jac[2, 1, 0]) * qda + (jac[4, 1, 1] - jac[2, 1, 1]) * qdb
    rdx = (jac[4, 0, 0] - jac[3, 0, 0]) * qda + (jac[4, 0, 1] - jac[3, 0, 1]) * qdb
    rdy = (jac[4, 1, 0] - jac[3, 1, 0]) * qda + (jac[4, 1, 1] - jac[3, 1, 1]) * qdb
    a11, a12 = pts[4, 0] - pts[2, 0], pts[4, 1] - pts[2, 1]
    a21, a22 = pts[4, 0] - pts[3, 0], pts[4, 1] - pts[3, 1]
    rhs1 = a11 * acc[2, 0] + a12 * acc[2, 1] - (rcx * rcx + rcy * rcy)
    rhs2 = a21 * acc[3, 0] + a22 * acc[3, 1] - (rdx * rdx + rdy * rdy)
    det = a11 * a22 - a12 * a21
    acc[4, 0], acc[4, 1] = (a22 * rhs1 - a12 * rhs2) / det, (a11 * rhs2 - a21 * rhs1) / det
    for i in range(4):
        p, q = LINK_ENDS[i]
        rx, ry = acc[q, 0] - acc[p, 0], acc[q, 1] - acc[p, 1]
        av[i, 0] = acc[p, 0] + com_fraction[i] * rx
        av[i, 1] = acc[p, 1] + com_fraction[i] * ry
        aw[i] = ((pts[q, 0] - pts[p, 0]) * ry - (pts[q, 1] - pts[p, 1]) * rx) / geom[4 + i] ** 2
    foot_from(geom, acc[4], acc[3], af)


@jit
def bias_arrays(geom, com_fraction, cx, cy, dx, dy, ex, ey, qda, qdb):
    """Velocity-product accelerations for motor rates qda, qdb (n,) rad/s (bias_at): link COMs
    av (n, 4, 2) m/s^2, link angular aw (n, 4) rad/s^2, foot af (n, 2) m/s^2."""
    n = cx.shape[0]
    av, aw, af = np.empty((n, 4, 2)), np.empty((n, 4)), np.empty((n, 2))
    pts, jac, acc = np.empty((5, 2)), np.empty((5, 2, 2)), np.empty((5, 2))
    for i in range(n):
        pose_jacobians(geom, cx[i], cy[i], dx[i], dy[i], ex[i], ey[i], pts, jac)
        bias_at(geom, com_fraction, pts, jac, qda[i], qdb[i], acc, av[i], aw[i], af[i])
    return av, aw, af


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


def link_coms(leg: LegGeometry, links: dict[str, LinkInertia], pose: LegPose) -> np.ndarray:
    """COM positions (..., 4, 2) in m, leg plane, of the links AC, BD, CE, DE: each at its
    com_fractions along the line from its first joint to its second."""
    a, b = np.broadcast_to(leg.a, pose.c.shape), np.broadcast_to(leg.b, pose.d.shape)
    ends = ((a, pose.c), (b, pose.d), (pose.c, pose.e), (pose.d, pose.e))
    return np.stack([p + k * (r - p) for k, (p, r) in zip(com_fractions(leg, links), ends)], -2)


def held_force(jf, upper_Nm, lower_Nm, direction) -> np.ndarray:
    """Largest ground force (N) on the foot along the unit vector direction (..., 2) that motor
    torques within [lower_Nm, upper_Nm] (..., 2) hold, for foot Jacobians jf (..., 2, 2) in
    m/rad: the force s u takes tau = -J_F^T s u (virtual work, the links' weight aside), so
    motor i allows s <= upper_i / g_i (g_i = -(J_F^T u)_i > 0) or lower_i / g_i (g_i < 0)."""
    g = -np.einsum("...ki,...k->...i", jf, np.asarray(direction, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = np.where(g > 0, upper_Nm / g, np.where(g < 0, lower_Nm / g, np.inf))
    return np.min(bound, axis=-1)
