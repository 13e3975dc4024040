"""Kinematics of the planar 5-bar leg with the offset foot (seed 003), vectorised over poses.

Frame: the leg plane, x right, y up, origin midway between motors A and B; metres and radians,
angles from +x, counter-clockwise positive. Motor angles q = [theta_A, theta_B] with shape (..., 2).
Points are arrays of shape (..., 2). The foot F lies on the extension of D->E beyond E:
F = E + (EF/DE) (E - D).

Assembly modes: knee C is *out* when it lies on the far side of line A->E from B (left of A for a
foot below the hips), knee D is *out* when it lies on the far side of line B->F from A. A mode is
a pair (c, d) with +1 = out, -1 = in. The E branch of forward kinematics is the side of line C->D
on which E lies (sign of cross(D - C, E - C)); the seed's rule is "E with the lower y".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .params import LegGeometry

KNEES_OUT = (1, 1)
ALL_MODES = ((1, 1), (1, -1), (-1, 1), (-1, -1))


class UnreachableError(ValueError):
    """A foot target or motor pose for which the linkage cannot close."""


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _circle_intersection(p0x, p0y, r0, p1x, p1y, r1, side, what=None):
    """Point X with |X - P0| = r0 and |X - P1| = r1 on the given side of line P0->P1
    (side = sign of cross(P1 - P0, X - P0)). Where the circles miss, raises UnreachableError
    naming the first failure with what(index), or gives NaN if what is None."""
    dx, dy = p1x - p0x, p1y - p0y
    d2 = dx * dx + dy * dy
    along = (r0 * r0 - r1 * r1 + d2) / (2.0 * d2)      # fraction of P0->P1 to the chord
    h2 = r0 * r0 / d2 - along * along                  # (half-chord / |P0P1|)^2
    bad = ~(h2 >= 0.0)
    if what is not None and np.any(bad):
        d = np.sqrt(d2)
        i = np.flatnonzero(np.atleast_1d(bad))[0]
        dist = float(np.atleast_1d(d)[i])
        raise UnreachableError(
            f"{what(i)} = {dist * 1e3:.3f} mm is outside the reach "
            f"{abs(r0 - r1) * 1e3:.3f} .. {(r0 + r1) * 1e3:.3f} mm"
            f" ({int(np.count_nonzero(bad))} of {np.size(bad)} poses out of reach)")
    h = side * np.sqrt(np.where(bad, np.nan, h2))
    return p0x + along * dx - h * dy, p0y + along * dy + h * dx


@dataclass(frozen=True)
class LegPose:
    """Joint positions of the leg (m, leg plane), each (..., 2); q = motor angles (rad)."""

    q: np.ndarray
    c: np.ndarray
    d: np.ndarray
    e: np.ndarray
    f: np.ndarray

    @property
    def e_branch(self) -> np.ndarray:
        """Side of line C->D on which E lies (+1 left, -1 right)."""
        u, v = self.d - self.c, self.e - self.c
        return np.sign(_cross(u[..., 0], u[..., 1], v[..., 0], v[..., 1]))


def _points(*pairs):
    return tuple(np.stack(p, axis=-1) for p in pairs)


def _foot(leg: LegGeometry, ex, ey, dx, dy):
    k = leg.ef_m / leg.de_m
    return ex + k * (ex - dx), ey + k * (ey - dy)


def forward(leg: LegGeometry, q, e_branch=None) -> LegPose:
    """Forward kinematics. q (..., 2) motor angles in rad. e_branch None picks the seed's E
    (lower y); +1/-1 (scalar or array) picks the side of line C->D."""
    q = np.asarray(q, dtype=float)
    ta, tb = q[..., 0], q[..., 1]
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    cx, cy = ax + leg.ac_m * np.cos(ta), ay + leg.ac_m * np.sin(ta)
    dx, dy = bx + leg.bd_m * np.cos(tb), by + leg.bd_m * np.sin(tb)
    side = np.where(dx - cx > 0, -1.0, 1.0) if e_branch is None else e_branch
    ex, ey = _circle_intersection(
        cx, cy, leg.ce_m, dx, dy, leg.de_m, side,
        lambda i: f"motor angles {np.degrees(q.reshape(-1, 2)[i]).round(3).tolist()} deg "
                  f"cannot close the lower links: knee distance |CD|")
    fx, fy = _foot(leg, ex, ey, dx, dy)
    c, d, e, f = _points((cx, cy), (dx, dy), (ex, ey), (fx, fy))
    return LegPose(q=q, c=c, d=d, e=e, f=f)


def inverse(leg: LegGeometry, foot, mode=KNEES_OUT, strict=True) -> LegPose:
    """Closed-form inverse kinematics for foot targets (..., 2) in m in one assembly mode (c, d).

    D lies on the circle of radius BD about B and of radius DE + EF about F; E divides DF; C lies
    on the circle of radius AC about A and of radius CE about E. Raises UnreachableError naming
    the first target out of reach, or with strict=False gives NaN there."""
    foot = np.asarray(foot, dtype=float)
    fx, fy = foot[..., 0], foot[..., 1]
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    mode_c, mode_d = mode
    df = leg.de_m + leg.ef_m

    def target(joint):
        return (lambda i: f"foot target {(foot.reshape(-1, 2)[i] * 1e3).round(3).tolist()} mm "
                          f"is out of reach: |{joint}|") if strict else None

    dx, dy = _circle_intersection(bx, by, leg.bd_m, fx, fy, df, float(mode_d), target("BF"))
    k = leg.de_m / df
    ex, ey = dx + k * (fx - dx), dy + k * (fy - dy)
    cx, cy = _circle_intersection(ax, ay, leg.ac_m, ex, ey, leg.ce_m, -float(mode_c),
                                  target("AE"))
    q = np.stack([np.arctan2(cy - ay, cx - ax), np.arctan2(dy - by, dx - bx)], axis=-1)
    c, d, e = _points((cx, cy), (dx, dy), (ex, ey))
    return LegPose(q=q, c=c, d=d, e=e, f=foot)


def reachable(leg: LegGeometry, foot, mode=KNEES_OUT) -> np.ndarray:
    """Mask of foot targets (..., 2) in m that the assembly mode can reach."""
    return ~np.isnan(inverse(leg, foot, mode, strict=False).q).any(axis=-1)


def knee_modes(leg: LegGeometry, pose: LegPose) -> tuple[np.ndarray, np.ndarray]:
    """Assembly mode (c, d) of each pose: +1 knee out, -1 knee in (see module docstring)."""
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    c, d, e, f = pose.c, pose.d, pose.e, pose.f
    mode_c = -np.sign(_cross(e[..., 0] - ax, e[..., 1] - ay, c[..., 0] - ax, c[..., 1] - ay))
    mode_d = np.sign(_cross(f[..., 0] - bx, f[..., 1] - by, d[..., 0] - bx, d[..., 1] - by))
    return mode_c, mode_d
