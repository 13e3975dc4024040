"""SCARA kinematics (seed 002 section 2.1): DH forward kinematics, the closed-form inverse with
both elbows and a continuity rule along a path, the tool Jacobian and its rate, the Cardan angles
of the tool, and the exact workspace boundary under the joint limits.

Frame 0: z up, origin on the axis of joint 1 at the floor. q = (q1, q2 rad, q3 m); the tool
point E = (a1 c1 + a2 c12, a1 s1 + a2 s12, d1 + d2 + s q3) with s = q3_direction (eq. 2.20)."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.mechanisms.scara.params import Kinematics

ELBOWS = (1, -1)


class OutOfReach(ValueError):
    """A point the arm cannot reach, or a path leaving the joint limits."""


@dataclass(frozen=True)
class ScaraPose:
    """Joint coordinates q (..., 3) and the tool point f (..., 3) in frame 0 (m)."""

    q: np.ndarray
    f: np.ndarray


class Scara:
    """The arm's kinematics for a Kinematics section (the Kinematics part of mechanisms/base.py:
    motors, modes = the two elbows, one forward branch, forward, inverse, tool_jacobian)."""

    motors = ("q1", "q2", "q3")
    modes = ((1,), (-1,))
    branches = (None,)
    parts = ("kinematics",)

    def __init__(self, k: Kinematics):
        self.k = k
        self.a1, self.a2, self.s = k.a1_m, k.a2_m, float(k.q3_direction)
        self.z0 = k.d1_m + k.d2_m
        self.lower = np.array([np.radians(k.q1_limits_deg[0]), np.radians(k.q2_limits_deg[0]),
                               k.q3_limits_m[0]])
        self.upper = np.array([np.radians(k.q1_limits_deg[1]), np.radians(k.q2_limits_deg[1]),
                               k.q3_limits_m[1]])

    def forward(self, q, branch=None) -> ScaraPose:
        """Tool pose for joint coordinates q (..., 3) (eq. 2.20; branch is unused: a serial
        arm has one forward solution)."""
        q = np.asarray(q, dtype=float)
        q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2]
        f = np.stack([self.a1 * np.cos(q1) + self.a2 * np.cos(q1 + q2),
                      self.a1 * np.sin(q1) + self.a2 * np.sin(q1 + q2),
                      self.z0 + self.s * q3], axis=-1)
        return ScaraPose(q, f)

    def inverse(self, point, mode=1, strict: bool = True) -> ScaraPose:
        """Joint coordinates reaching tool point(s) (..., 3) with elbow mode (+1: q2 >= 0, the
        seed's eq. 2.42; -1: q2 <= 0), q1 by the seed's determinants (eq. 2.40-2.41). strict:
        OutOfReach where the point is out of reach or the joints leave their limits; else NaN."""
        elbow = mode[0] if isinstance(mode, tuple) else mode
        p = np.asarray(point, dtype=float)
        x, y, z = p[..., 0], p[..., 1], p[..., 2]
        r2 = x * x + y * y
        cos2 = (r2 - self.a1**2 - self.a2**2) / (2.0 * self.a1 * self.a2)
        with np.errstate(invalid="ignore"):
            q2 = elbow * np.arccos(cos2)
        det_x = self.a2 * (x * np.cos(q2) + y * np.sin(q2)) + self.a1 * x
        det_y = self.a2 * (y * np.cos(q2) - x * np.sin(q2)) + self.a1 * y
        q1 = np.arctan2(det_y, det_x)
        q3 = self.s * (z - self.z0)
        q = np.stack([q1, q2, q3], axis=-1)
        bad = (np.abs(cos2) > 1.0) | ~self.within_limits(q)
        if np.any(bad):
            if strict:
                first = p.reshape(-1, 3)[np.flatnonzero(np.ravel(bad))[0]]
                raise OutOfReach(f"tool point {first.round(6).tolist()} m is out of reach with "
                                 f"elbow {elbow:+d} under the joint limits")
            q = np.where(bad[..., None], np.nan, q)
        return ScaraPose(q, p)

    def within_limits(self, q, tol: float = 1e-12) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        return np.all((q >= self.lower - tol) & (q <= self.upper + tol), axis=-1)

    def inverse_path(self, points, elbow: int) -> np.ndarray:
        """Joint coordinates (n, 3) along a path of tool points (n, 3): one elbow throughout
        (the continuity rule: the elbow never flips, q1 is unwrapped from sample to sample);
        OutOfReach naming the first sample out of reach or out of the joint limits."""
        p = np.asarray(points, dtype=float)
        q = self.inverse(p, elbow, strict=False).q
        q[:, 0] = np.unwrap(q[:, 0]) if not np.isnan(q[:, 0]).any() else q[:, 0]
        bad = np.isnan(q).any(axis=1) | ~self.within_limits(q)
        if bad.any():
            k = int(np.argmax(bad))
            raise OutOfReach(f"path sample {k} at {p[k].round(6).tolist()} m is out of reach "
                             f"with elbow {elbow:+d} under the joint limits")
        return q

    def tool_jacobian(self, pose) -> np.ndarray:
        """dE/dq (..., 3, 3) (eq. 2.25) of a pose or joint coordinates."""
        q = np.asarray(getattr(pose, "q", pose), dtype=float)
        q1, q12 = q[..., 0], q[..., 0] + q[..., 1]
        j = np.zeros(q.shape[:-1] + (3, 3))
        j[..., 0, 0] = -self.a1 * np.sin(q1) - self.a2 * np.sin(q12)
        j[..., 0, 1] = -self.a2 * np.sin(q12)
        j[..., 1, 0] = self.a1 * np.cos(q1) + self.a2 * np.cos(q12)
        j[..., 1, 1] = self.a2 * np.cos(q12)
        j[..., 2, 2] = self.s
        return j

    def jacobian_rate(self, q, qd) -> np.ndarray:
        """d/dt of tool_jacobian (..., 3, 3) at joint speeds qd."""
        q, qd = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)
        q1, q12 = q[..., 0], q[..., 0] + q[..., 1]
        w1, w12 = qd[..., 0], qd[..., 0] + qd[..., 1]
        jd = np.zeros(q.shape[:-1] + (3, 3))
        jd[..., 0, 0] = -self.a1 * np.cos(q1) * w1 - self.a2 * np.cos(q12) * w12
        jd[..., 0, 1] = -self.a2 * np.cos(q12) * w12
        jd[..., 1, 0] = -self.a1 * np.sin(q1) * w1 - self.a2 * np.sin(q12) * w12
        jd[..., 1, 1] = -self.a2 * np.sin(q12) * w12
        return jd

    def joint_motion(self, points, velocity, acceleration, elbow: int):
        """Joint positions, speeds, accelerations (n, 3) along a tool path given with its
        velocity and acceleration (n, 3): q by inverse_path, qd = J^-1 v, qdd = J^-1 (a - Jd qd)."""
        q = self.inverse_path(points, elbow)
        j = self.tool_jacobian(q)
        qd = np.linalg.solve(j, np.asarray(velocity, dtype=float)[..., None])[..., 0]
        rhs = np.asarray(acceleration, dtype=float) - np.einsum(
            "...ij,...j->...i", self.jacobian_rate(q, qd), qd)
        qdd = np.linalg.solve(j, rhs[..., None])[..., 0]
        return q, qd, qdd

    @staticmethod
    def cardan_angles(q) -> np.ndarray:
        """Tool orientation as the seed's Cardan angles (alpha, beta, eta) (..., 3) rad:
        (0, 0, q1 + q2 - pi/2) (eq. 2.24)."""
        q = np.asarray(q, dtype=float)
        eta = q[..., 0] + q[..., 1] - np.pi / 2
        return np.stack([np.zeros_like(eta), np.zeros_like(eta), eta], axis=-1)

    def reachable_xy(self, xy, tol_rad: float = 1e-9) -> np.ndarray:
        """Whether plane points (..., 2) are reachable with either elbow under the q1, q2
        limits (boolean; tol_rad absorbs the rounding of points on a limit)."""
        xy = np.asarray(xy, dtype=float)
        p = np.concatenate([xy, np.full(xy.shape[:-1] + (1,), self.z0)], axis=-1)
        lower, upper = self.lower[:2] - tol_rad, self.upper[:2] + tol_rad
        ok = np.zeros(xy.shape[:-1], dtype=bool)
        for elbow in ELBOWS:
            q = self.inverse(p, elbow, strict=False).q[..., :2]
            ok |= np.all((q >= lower) & (q <= upper), axis=-1)
        return ok

    def seed_grid(self) -> np.ndarray:
        """Tool points (n, 2) of the seed's Matlab grid (Fig. 2.4): q1, q2 from their lower
        limits in steps of seed_grid_step_deg."""
        step = np.radians(self.k.seed_grid_step_deg)
        q1 = np.arange(self.lower[0], self.upper[0] + 1e-12, step)
        q2 = np.arange(self.lower[1], self.upper[1] + 1e-12, step)
        g1, g2 = np.meshgrid(q1, q2)
        q = np.stack([g1.ravel(), g2.ravel(), np.zeros(g1.size)], axis=-1)
        return self.forward(q).f[:, :2]

    def boundary_candidates(self, n: int = 2000) -> list[np.ndarray]:
        """The curves the workspace boundary lies on (each (n, 2), exact points): the images
        of the edges of the (q1, q2) limit box and of the fold q2 = 0 (the stretched arm)."""
        (l1, l2), (u1, u2) = self.lower[:2], self.upper[:2]
        s1, s2 = np.linspace(l1, u1, n), np.linspace(l2, u2, n)
        curves = [np.stack([s1, np.full(n, v)], axis=-1) for v in (l2, u2, 0.0)]
        curves += [np.stack([np.full(n, v), s2], axis=-1) for v in (l1, u1)]
        pad = np.zeros((n, 1))
        return [self.forward(np.concatenate([c, pad], axis=-1)).f[:, :2] for c in curves]

    def workspace_boundary(self, n: int = 2000, step_m: float = 1e-6) -> list[np.ndarray]:
        """The boundary of the reachable plane region under the q1, q2 limits as polylines
        (m): the parts of boundary_candidates with a reachable point on one side and an
        unreachable one on the other (step_m along the normal)."""
        pieces = []
        for curve in self.boundary_candidates(n):
            tangent = np.gradient(curve, axis=0)
            normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=-1)
            normal /= np.linalg.norm(normal, axis=1, keepdims=True)
            edge = (self.reachable_xy(curve + step_m * normal)
                    != self.reachable_xy(curve - step_m * normal))
            runs = np.flatnonzero(np.diff(np.r_[0, edge.astype(int), 0]))
            pieces += [curve[a:b] for a, b in zip(runs[::2], runs[1::2]) if b - a > 1]
        return pieces

    def radial_extent(self) -> tuple[float, float]:
        """Smallest and largest horizontal reach (m) under the q2 limits (|E| grows as |q2|
        falls on [0, pi])."""
        lo, hi = self.lower[1], self.upper[1]
        nearest = 0.0 if lo <= 0.0 <= hi else min(abs(lo), abs(hi))
        farthest = max(abs(lo), abs(hi))
        reach = [np.sqrt(self.a1**2 + self.a2**2 + 2 * self.a1 * self.a2 * np.cos(v))
                 for v in (farthest, nearest)]
        return float(reach[0]), float(reach[1])
