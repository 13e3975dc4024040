"""Kinematics of the planar 5-bar leg with the offset foot (seed 003), vectorised over poses.

Frame: the leg plane, x right, y up, origin midway between motors A and B; metres and radians,
angles from +x, counter-clockwise positive. Motor angles q = [theta_A, theta_B] with shape (..., 2).
Points are arrays of shape (..., 2). The foot F lies on the extension of D->E beyond E:
F = E + (EF/DE) (E - D).

Assembly modes, named by what a person sees. On the robot the leg plane's -x is forward
(robots/quadruped/legs.py); motor A is the front one (x_A <= x_B). Each knee is bent *forward* or
*back*: knee C is forward when it lies on the forward side of the line from its hip A to the
point E it drives, knee D when it lies on the forward side of the line from B to the foot F (for
a foot below the hips: C left of line A->E in the seed's picture; in general, the turn from
A->E to A->C is clockwise, cross(E - A, C - A) < 0, and likewise cross(F - B, D - B) < 0 for D).
The definition uses neither motor's position relative to the other, so a knee keeps its name as
the hip spacing goes to 0 (coaxial hips). A mode is a pair (c, d) with c = +1 for C forward and
d = +1 for D back, i.e. +1 = the knee away from the leg's centre line ("out"):
MODE_NAMES = knees_out (C forward, D back: the diamond), knees_forward, knees_back,
knees_in (C back, D forward: the knees cross the centre line). The former names out_out,
out_in, in_out, in_in (knee C, knee D) map to them in MODE_ALIASES (written into report.json
for readers of older reports). The E branch of forward kinematics is the side of line C->D on which E lies
(sign of cross(D - C, E - C)); the seed's rule is "E with the lower y".
The inverse kinematics respects the leg's mechanical limits (limits.py): a pose past one is
unreachable.
"""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.mechanisms.fivebar.geometry import LegGeometry
from fivebar_drake.mechanisms.fivebar.limits import first_past, limit_tests, past_any


KNEES_OUT = (1, 1)
ALL_MODES = ((1, 1), (1, -1), (-1, 1), (-1, -1))
MODE_NAMES = ("knees_out", "knees_forward", "knees_back", "knees_in")   # of ALL_MODES
MODE_ALIASES = {"out_out": "knees_out", "out_in": "knees_forward", "in_out": "knees_back",
                "in_in": "knees_in"}   # the names before 2026-11 (knee C, knee D: out/in)


def mode_name(mode) -> str:
    """The name (MODE_NAMES) of an assembly mode (c, d)."""
    return MODE_NAMES[ALL_MODES.index(tuple(int(m) for m in mode))]


class UnreachableError(ValueError):
    """A foot target or motor pose for which the linkage cannot close or that lies past a
    limit: why (reason), the flat index of the first such pose (None if not known), the
    [limits] field it lies past ("" for a reach) and where it is on a path ("" if not known)."""

    def __init__(self, reason: str, index: int | None = None, field: str = "", where: str = ""):
        super().__init__(f"{where}: {reason}" if where else reason)
        self.reason, self.index, self.field, self.where = reason, index, field, where

    def at_sample(self, path: str, times) -> UnreachableError:
        """The same error located on one path of poses sampled at times (n,) s: where = "path,
        sample i of n at t = ... s"."""
        t = np.ravel(times)
        if self.index is None or self.index >= t.size:
            return self
        return UnreachableError(self.reason, self.index, self.field,
                                f"{path}, sample {self.index} of {t.size} at "
                                f"t = {t[self.index]:.4f} s")


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@jit
def circle_point(p0x, p0y, r0, p1x, p1y, r1, side):
    """Point (x, y) with |X - P0| = r0 and |X - P1| = r1 on the given side of line P0->P1
    (side = sign of cross(P1 - P0, X - P0)), for one pose; NaN where the circles miss."""
    dx, dy = p1x - p0x, p1y - p0y
    d2 = dx * dx + dy * dy
    along = (r0 * r0 - r1 * r1 + d2) / (2.0 * d2)      # fraction of P0->P1 to the chord
    h2 = r0 * r0 / d2 - along * along                  # (half-chord / |P0P1|)^2
    h = side * np.sqrt(h2) if h2 >= 0.0 else np.nan
    return p0x + along * dx - h * dy, p0y + along * dy + h * dx


@jit
def forward_pose(geom, ta, tb, side, seed_rule):
    """Forward kinematics of one pose: motor angles ta, tb rad -> C, D, E, F as
    (cx, cy, dx, dy, ex, ey, fx, fy) in m; E on the given side of line C->D, or with seed_rule
    the seed's E with the lower y. geom: LegGeometry.core."""
    ax, ay, bx, by, ac, bd, ce, de, ef = geom
    cx, cy = ax + ac * np.cos(ta), ay + ac * np.sin(ta)
    dx, dy = bx + bd * np.cos(tb), by + bd * np.sin(tb)
    if seed_rule:
        side = -1.0 if dx - cx > 0 else 1.0
    ex, ey = circle_point(cx, cy, ce, dx, dy, de, side)
    k = ef / de
    return cx, cy, dx, dy, ex, ey, ex + k * (ex - dx), ey + k * (ey - dy)


@jit
def forward_points(geom, ta, tb, side, seed_rule):
    """forward_pose on flat arrays ta, tb, side (n,): a tuple of 8 arrays (n,)."""
    out = np.empty((8, ta.shape[0]))
    for i in range(ta.shape[0]):
        out[:, i] = forward_pose(geom, ta[i], tb[i], side[i], seed_rule)
    return out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7]


@jit
def inverse_pose(geom, fx, fy, mode_c, mode_d):
    """Inverse kinematics of one foot target fx, fy m in assembly mode (mode_c, mode_d) ->
    (theta_A, theta_B, cx, cy, dx, dy, ex, ey), NaN out of reach.

    D lies on the circle of radius BD about B and of radius DE + EF about F; E divides DF; C lies
    on the circle of radius AC about A and of radius CE about E."""
    ax, ay, bx, by, ac, bd, ce, de, ef = geom
    df = de + ef
    dx, dy = circle_point(bx, by, bd, fx, fy, df, mode_d)
    k = de / df
    ex, ey = dx + k * (fx - dx), dy + k * (fy - dy)
    cx, cy = circle_point(ax, ay, ac, ex, ey, ce, -mode_c)
    return np.arctan2(cy - ay, cx - ax), np.arctan2(dy - by, dx - bx), cx, cy, dx, dy, ex, ey


@jit
def inverse_points(geom, fx, fy, mode_c, mode_d):
    """inverse_pose on flat arrays fx, fy (n,): a tuple of 8 arrays (n,)."""
    out = np.empty((8, fx.shape[0]))
    for i in range(fx.shape[0]):
        out[:, i] = inverse_pose(geom, fx[i], fy[i], mode_c, mode_d)
    return out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7]


def _require_reach(x, p0x, p0y, r0, p1x, p1y, r1, what):
    """Raise UnreachableError naming the first NaN of x (a circle_point result) with what(i)."""
    bad = np.isnan(x)
    if np.any(bad):
        dist = np.broadcast_to(np.hypot(p1x - p0x, p1y - p0y), bad.shape)
        i = int(np.flatnonzero(bad)[0])
        raise UnreachableError(
            f"{what(i)} = {dist[i] * 1e3:.3f} mm is outside the reach "
            f"{abs(r0 - r1) * 1e3:.3f} .. {(r0 + r1) * 1e3:.3f} mm"
            f" ({int(np.count_nonzero(bad))} of {bad.size} poses out of reach)", i)


def _flat(x):
    return np.ascontiguousarray(np.ravel(np.asarray(x, dtype=float)))


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

    def flat(self) -> tuple[np.ndarray, ...]:
        """(cx, cy, dx, dy, ex, ey) as flat arrays, as the compiled kernels take a pose."""
        return tuple(_flat(p[..., i]) for p in (self.c, self.d, self.e) for i in (0, 1))


def _pose(shape, q, *xy) -> LegPose:
    pts = [np.stack(xy[i:i + 2], axis=-1).reshape(shape + (2,)) for i in range(0, len(xy), 2)]
    return LegPose(q, *pts)


def forward(leg: LegGeometry, q, e_branch=None) -> LegPose:
    """Forward kinematics. q (..., 2) motor angles in rad. e_branch None picks the seed's E
    (lower y); +1/-1 (scalar or array) picks the side of line C->D."""
    q = np.asarray(q, dtype=float)
    shape = q.shape[:-1]
    ta, tb = _flat(q[..., 0]), _flat(q[..., 1])
    side = np.ones_like(ta) if e_branch is None else _flat(np.broadcast_to(e_branch, shape))
    cx, cy, dx, dy, ex, ey, fx, fy = forward_points(leg.core, ta, tb, side, e_branch is None)
    _require_reach(ex, cx, cy, leg.ce_m, dx, dy, leg.de_m,
                   lambda i: f"motor angles {np.degrees(q.reshape(-1, 2)[i]).round(3).tolist()} "
                             "deg cannot close the lower links: knee distance |CD|")
    return _pose(shape, q, cx, cy, dx, dy, ex, ey, fx, fy)


def inverse(leg: LegGeometry, foot, mode=KNEES_OUT, strict=True) -> LegPose:
    """Closed-form inverse kinematics (inverse_points) for foot targets (..., 2) in m in one
    assembly mode (c, d). Raises UnreachableError naming the first target out of reach, or
    with strict=False gives NaN there; so for a pose past one of the leg's limits (limits.py;
    the error names the limit, the value and the bound). A pose whose knees C and D coincide (within
    COINCIDENT_KNEES_M: two modes of a coaxial leg with equal upper links) is no assembly: the
    loop collapses to a serial chain and the motors cannot hold the foot; it counts as out of
    reach."""
    foot = np.asarray(foot, dtype=float)
    shape = foot.shape[:-1]
    fx, fy = _flat(foot[..., 0]), _flat(foot[..., 1])
    ta, tb, cx, cy, dx, dy, ex, ey = inverse_points(leg.core, fx, fy, float(mode[0]),
                                                    float(mode[1]))
    collapsed = np.hypot(cx - dx, cy - dy) < COINCIDENT_KNEES_M
    if np.any(collapsed):
        if strict:
            i = int(np.flatnonzero(collapsed)[0])
            raise UnreachableError(
                f"foot target {(foot.reshape(-1, 2)[i] * 1e3).round(3).tolist()} mm in mode "
                f"{mode_name(mode)}: the knees C and D coincide, which is no "
                f"assembly ({int(np.count_nonzero(collapsed))} of {collapsed.size} poses)", i)
        for a in (ta, tb, cx, cy, dx, dy, ex, ey):
            a[collapsed] = np.nan
    if strict:
        def what(joint):
            return lambda i: (f"foot target {(foot.reshape(-1, 2)[i] * 1e3).round(3).tolist()} "
                              f"mm is out of reach: |{joint}|")
        (bx, by), (ax, ay) = leg.motor_b_m, leg.motor_a_m
        _require_reach(dx, bx, by, leg.bd_m, fx, fy, leg.de_m + leg.ef_m, what("BF"))
        _require_reach(cx, ax, ay, leg.ac_m, ex, ey, leg.ce_m, what("AE"))
    q = np.stack([ta, tb], axis=-1).reshape(shape + (2,))
    pose = _pose(shape, q, cx, cy, dx, dy, ex, ey, fx, fy)
    tests = limit_tests(leg, pose)
    past = past_any(tests, shape)
    if not np.any(past):
        return pose
    i = int(np.flatnonzero(past)[0])
    if strict:
        test = first_past(tests, i)
        raise UnreachableError(
            f"foot target {(foot.reshape(-1, 2)[i] * 1e3).round(3).tolist()} mm in mode "
            f"{mode_name(mode)}: {test.text(np.ravel(test.value)[i])} "
            f"({int(np.count_nonzero(past))} of {past.size} poses past a limit)", i, test.field)
    nan = lambda v: np.where(past[..., None], np.nan, v)  # noqa: E731
    return LegPose(nan(pose.q), nan(pose.c), nan(pose.d), nan(pose.e), pose.f)


COINCIDENT_KNEES_M = 1e-9   # knees this close are one point: no closed loop


def reachable(leg: LegGeometry, foot, mode=KNEES_OUT) -> np.ndarray:
    """Mask of foot targets (..., 2) in m that the assembly mode can reach."""
    return ~np.isnan(inverse(leg, foot, mode, strict=False).q).any(axis=-1)


def knee_modes(leg: LegGeometry, pose: LegPose) -> tuple[np.ndarray, np.ndarray]:
    """Assembly mode (c, d) of each pose: c = +1 knee C forward, d = +1 knee D back (the knee
    away from the centre line), -1 otherwise (see module docstring)."""
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    c, d, e, f = pose.c, pose.d, pose.e, pose.f
    mode_c = -np.sign(_cross(e[..., 0] - ax, e[..., 1] - ay, c[..., 0] - ax, c[..., 1] - ay))
    mode_d = np.sign(_cross(f[..., 0] - bx, f[..., 1] - by, d[..., 0] - bx, d[..., 1] - by))
    return mode_c, mode_d
