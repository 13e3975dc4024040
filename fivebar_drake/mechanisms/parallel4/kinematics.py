"""Closed-form kinematics of the 4-DOF parallel manipulator (seed 004, sections 2.2.1-2.2.4),
vectorised over leading axes.

pose (..., 4): platform point P = (x, y, z) in m and its angle theta about y in rad.
q (..., 4): actuator positions l1 .. l4 along x (m). mode (4 signs): l_i = x_pair +- sqrt(...);
the seed's mode is (+1, -1, +1, -1) (eq. 2.10-2.13): in a pair the odd actuator leads.
"""

from __future__ import annotations

import numpy as np

from fivebar_drake.mechanisms.parallel4.geometry import Geometry

SEED_MODE = (1, -1, 1, -1)
PAIR = (0, 0, 1, 1)          # the leg pair (platform point B12 or B34) of each leg


class KinematicsError(ValueError):
    """A pose or actuator position outside the closed forms' domain; the text says which."""


class UnreachableError(KinematicsError):
    """Inverse kinematics: a leg cannot reach its platform point."""


class BranchError(KinematicsError):
    """Forward kinematics: no assembly for these actuator positions, or not on the asked branch."""


def _first_bad(mask) -> str:
    index = np.argwhere(np.asarray(mask))[0]
    return f" (first at index {tuple(int(i) for i in index)})" if index.size else ""


def pair_points(g: Geometry, pose) -> np.ndarray:
    """Coordinates (..., 2, 3) of each pair's platform point relative to its actuator line
    (eq. 2.10-2.13: (x1, y1, z1) and (x2, y2, z2))."""
    pose = np.asarray(pose, dtype=float)
    x, y, z, th = np.moveaxis(pose, -1, 0)
    cs, g_ = g.c * np.sin(th), g.c * np.cos(th) - g.d
    first = np.stack([x + cs, y - g.e, z + g_], axis=-1)
    second = np.stack([x - cs, y + g.e, z - g_], axis=-1)
    return np.stack([first, second], axis=-2)


def platform_offsets(g: Geometry, theta) -> np.ndarray:
    """Rot_y(theta) PB of each pair (..., 2, 3), m: B12 - P and B34 - P in {O}."""
    theta = np.asarray(theta, dtype=float)
    r = np.stack([g.c * np.sin(theta), np.full_like(theta, g.b), g.c * np.cos(theta)], axis=-1)
    return np.stack([r, -r], axis=-2)


def reach(g: Geometry, pose) -> np.ndarray:
    """R^2 - y_i^2 - z_i^2 of each pair (..., 2), m^2: negative where the legs cannot reach."""
    p = pair_points(g, pose)
    return g.R ** 2 - p[..., 1] ** 2 - p[..., 2] ** 2


def inverse(g: Geometry, pose, mode=SEED_MODE, strict: bool = True) -> np.ndarray:
    """Actuator positions q (..., 4), m, of platform poses (eq. 2.10-2.13). strict: raise
    UnreachableError where a leg cannot reach (else NaN there)."""
    p = pair_points(g, pose)
    h = reach(g, pose)
    if strict and np.any(~(h >= 0)):
        bad = ~(h >= 0)
        raise UnreachableError(
            f"pose out of reach{_first_bad(bad.any(axis=-1))}: a leg pair's platform point is "
            f"{np.sqrt(g.R ** 2 - h[bad][0]):.6g} m from its actuator line, more than R = "
            f"{g.R:g} m")
    root = np.sqrt(np.where(h >= 0, h, np.nan))
    pair = list(PAIR)
    return p[..., pair, 0] + np.asarray(mode, dtype=float) * root[..., pair]


def forward(g: Geometry, q, lower: bool = True, strict: bool = True) -> np.ndarray:
    """Platform pose (..., 4) of actuator positions q (..., 4): the seed's closed form (eq.
    2.14, 2.15, 2.18, 2.20) with theta in (-90, 90) deg (cos theta >= 0, eq. 2.15). lower: the
    root z = (-B - sqrt(B^2 - 4AC))/2A the seed takes (below the line through the two pair
    circles' centres); else the other assembly. strict: raise BranchError naming the failed
    condition (else NaN there)."""
    q = np.asarray(q, dtype=float)
    l1, l2, l3, l4 = np.moveaxis(q, -1, 0)
    r1, r2, d1, d2 = (l1 + l2) / 2, (l3 + l4) / 2, l1 - l2, l3 - l4
    e = g.e
    tilt = 4 * g.c ** 2 - (r1 - r2) ** 2
    spread = np.maximum(np.abs(d1), np.abs(d2)) - 2 * g.R
    s = np.sqrt(np.where(tilt >= 0, tilt, np.nan)) - 2 * g.d          # 2 (c cos(theta) - d)
    A = s ** 2 / (2 * e ** 2) + 2
    B = (d1 ** 2 - d2 ** 2) * s / (8 * e ** 2)
    C = ((d1 ** 2 + d2 ** 2) / 4 - 2 * g.R ** 2 + 2 * e ** 2 + s ** 2 / 2
         + (d1 ** 2 - d2 ** 2) ** 2 / (128 * e ** 2))
    disc = B ** 2 - 4 * A * C
    if strict:
        for bad, why in ((~(tilt >= 0), "|r1 - r2| > 2c: no platform angle joins the pairs "
                          "(eq. 2.15)"),
                         (~(spread <= 0), "|l1 - l2| or |l3 - l4| > 2R: a leg pair cannot meet"),
                         (~(disc >= 0), "B^2 - 4AC < 0: the two pair circles do not meet, no "
                          "assembly (eq. 2.20)")):
            if np.any(bad):
                raise BranchError(f"no forward kinematics{_first_bad(bad)}: {why}")
    ok = (tilt >= 0) & (spread <= 0) & (disc >= 0)
    root = np.sqrt(np.where(ok, disc, np.nan))
    z = (-B - root) / (2 * A) if lower else (-B + root) / (2 * A)
    y = (d1 ** 2 - d2 ** 2 + 8 * z * s) / (16 * e)
    theta = np.arcsin(np.clip((r1 - r2) / (2 * g.c), -1, 1))
    return np.where(ok[..., None], np.stack([(r1 + r2) / 2, y, z, theta], axis=-1), np.nan)


def branch_side(g: Geometry, pose) -> np.ndarray:
    """(a - b) z + (c cos(theta) - d) y (..., m^2): negative on the seed's (lower) forward
    branch, zero on the type-2 singularity line through the two pair circles' centres."""
    pose = np.asarray(pose, dtype=float)
    return g.e * pose[..., 2] + (g.c * np.cos(pose[..., 3]) - g.d) * pose[..., 1]


def jacobians(g: Geometry, pose, q) -> tuple[np.ndarray, np.ndarray]:
    """A (..., 4, 4) and B (..., 4, 4) of A qdot = B xdot (eq. 2.21-2.23), xdot = (xdot, ydot,
    zdot, thetadot): A = diag(A_iB_i . i), row i of B = [A_iB_i, (r_i x A_iB_i) . j] with
    r_i = Rot_y(theta) PB_i (m, m^2). The seed writes (A_iB_i x PB_i) . j: the opposite sign
    of the fourth column (seed_B), which leaves |det B| and the condition numbers alone."""
    pose, q = np.asarray(pose, dtype=float), np.asarray(q, dtype=float)
    p = pair_points(g, pose)[..., list(PAIR), :]                      # (..., 4, 3)
    ab = p.copy()
    ab[..., 0] -= q                                   # A_iB_i = (x_i - l_i, y_i, z_i)
    r = platform_offsets(g, pose[..., 3])[..., list(PAIR), :]
    turn = r[..., 2] * ab[..., 0] - r[..., 0] * ab[..., 2]
    B = np.concatenate([ab, turn[..., None]], axis=-1)
    A = ab[..., 0, None] * np.eye(4)
    return A, B


def seed_B(B) -> np.ndarray:
    """The seed's B as written (eq. 2.23, 2.24): the fourth column of ours negated."""
    return np.asarray(B) * np.array([1.0, 1.0, 1.0, -1.0])


def det_B_closed_form(g: Geometry, pose, q) -> np.ndarray:
    """det B (m^5) of jacobians()' B in closed form: -4 c cos(theta) (l1 - l2)(l3 - l4)
    [(a - b) z + (c cos(theta) - d) y]; the seed's B (seed_B) has the opposite sign. Eq. 2.25
    writes the bracket (a - b) z + (d - c cos(theta)) y: the sign of its y term slipped."""
    pose, q = np.asarray(pose, dtype=float), np.asarray(q, dtype=float)
    return (-4 * g.c * np.cos(pose[..., 3]) * (q[..., 0] - q[..., 1]) * (q[..., 2] - q[..., 3])
            * branch_side(g, pose))


def det_B_seed(g: Geometry, pose, q) -> np.ndarray:
    """Eq. 2.25 as the seed writes it: 4 c (l1 - l2)(l3 - l4) cos(theta) [y (d - c cos(theta))
    - z (b - a)] (m^5)."""
    pose, q = np.asarray(pose, dtype=float), np.asarray(q, dtype=float)
    y, z, th = pose[..., 1], pose[..., 2], pose[..., 3]
    return (4 * g.c * (q[..., 0] - q[..., 1]) * (q[..., 2] - q[..., 3]) * np.cos(th)
            * (y * (g.d - g.c * np.cos(th)) - z * (g.b - g.a)))


def type2_line_z(g: Geometry, y, theta, seed: bool = False) -> np.ndarray:
    """z (m) of the type-2 singularity line at y (m), theta (rad): ours z = y (d - c cos)/(a - b);
    the seed's (eq. 2.25, case 3) z = y (d - c cos)/(b - a)."""
    z = np.asarray(y, dtype=float) * (g.d - g.c * np.cos(theta)) / g.e
    return -z if seed else z


def velocity_jacobian(g: Geometry, pose, q) -> np.ndarray:
    """J = A^-1 B (..., 4, 4): qdot = J xdot (dimensionless; m/rad in the fourth column)."""
    A, B = jacobians(g, pose, q)
    return B / np.diagonal(A, axis1=-2, axis2=-1)[..., None]
