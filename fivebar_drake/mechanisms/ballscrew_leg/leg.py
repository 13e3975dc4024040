"""The serial two-link leg whose knee is driven by a ball screw (seed 001): closed forms.

Plane x right, y up, the hip O at the origin. The thigh OA = l1 hangs at the hip angle q1 from
straight down, the shank AP = l2 at the knee angle q2 from the thigh's line, so the foot is
P = (l1 sin q1 + l2 sin(q1 + q2), -(l1 cos q1 + l2 cos(q1 + q2))) (seed). The lever DA = s1 is
the shank's extension beyond the knee (D, A, P on one line, A between D and P, as on Spot), so
the angle OAD equals the knee's bend -q2; the screw OD pivots at the hip and its length q2l sets
the knee by the law of cosines, q2l^2 = l1^2 + s1^2 - 2 l1 s1 cos q2, i.e. the seed's
q2 = -acos((l1^2 + s1^2 - q2l^2) / (2 l1 s1)) (the knee bends to q2 <= 0).

Joint coordinates q = (q1 rad, q2l m): the hip motor's angle and the screw's length (the screw
motor's angle is 2 pi q2l / lead). Generalized forces for q are (hip torque N*m, screw force N,
positive pushing D away from O).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

KNEE_BACK = (-1,)          # the one assembly mode: the knee bends to q2 <= 0 (seed)
MOTORS = ("hip", "screw")
TREE_JOINTS = ("hip", "knee", "screw_pivot", "screw")   # the Drake model's tree, in x's order


class UnreachableError(ValueError):
    """A foot point or screw length the leg cannot reach."""


@dataclass(frozen=True)
class Pose:
    """A pose: q = (q1, q2l), the knee angle q2 (rad) and the points O, A, D, P (..., 2) in m."""

    q: np.ndarray
    q2: np.ndarray
    o: np.ndarray
    a: np.ndarray
    d: np.ndarray
    f: np.ndarray


def _unit(angle):
    """Unit vector of a link hanging at `angle` from straight down: (sin, -cos), (..., 2)."""
    return np.stack([np.sin(angle), -np.cos(angle)], axis=-1)


@dataclass(frozen=True)
class BallScrewLeg:
    """The leg with its screw knee: thigh l1, shank l2, lever s1 (m), screw lead (m/turn).
    Parts (mechanisms/base.py): kinematics, statics (the load: a foot force), drake_model."""

    thigh_m: float
    shank_m: float
    lever_m: float
    lead_m: float
    motors = MOTORS
    modes = (KNEE_BACK,)
    branches = (None,)
    parts = ("kinematics", "statics", "drake_model")

    # -- knee <-> screw -----------------------------------------------------------------------
    def screw_range(self) -> tuple[float, float]:
        """Shortest and longest screw length (m): the straight leg and the folded knee."""
        return self.thigh_m - self.lever_m, self.thigh_m + self.lever_m

    def knee_from_screw(self, q2l, strict: bool = True):
        """Knee angle q2 (rad, <= 0) of screw lengths q2l (m), the seed's law of cosines."""
        l1, s1 = self.thigh_m, self.lever_m
        c = (l1**2 + s1**2 - np.asarray(q2l, dtype=float)**2) / (2.0 * l1 * s1)
        if strict and np.any(np.abs(c) > 1.0 + 1e-12):
            lo, hi = self.screw_range()
            raise UnreachableError(f"screw length outside [{lo:g}, {hi:g}] m")
        return -np.arccos(np.clip(c, -1.0, 1.0))

    def screw_from_knee(self, q2):
        """Screw length q2l (m) of knee angles q2 (rad)."""
        l1, s1 = self.thigh_m, self.lever_m
        return np.sqrt(l1**2 + s1**2 - 2.0 * l1 * s1 * np.cos(q2))

    def screw_rate(self, q2):
        """dq2l/dq2 (m/rad) = l1 s1 sin q2 / q2l: the screw's moment arm about the knee, signed
        (negative: bending the knee lengthens the screw)."""
        return self.thigh_m * self.lever_m * np.sin(q2) / self.screw_from_knee(q2)

    def stroke_window(self, stroke_m: float, retracted_bend_rad: float):
        """The two ends of the nut's travel: screw lengths (m) and knee bends -q2 (rad), fully
        retracted at the bend retracted_bend_rad, extended by stroke_m (at most to the folded
        knee)."""
        short = float(self.screw_from_knee(-retracted_bend_rad))
        long = min(short + stroke_m, self.screw_range()[1])
        return (short, long), tuple(float(-self.knee_from_screw(x)) for x in (short, long))

    # -- kinematics -----------------------------------------------------------------------------
    def points(self, q1, q2) -> Pose:
        """The pose of hip and knee angles (rad)."""
        q1, q2 = np.broadcast_arrays(np.asarray(q1, dtype=float), np.asarray(q2, dtype=float))
        thigh, shank = _unit(q1), _unit(q1 + q2)
        a = self.thigh_m * thigh
        q = np.stack([q1, self.screw_from_knee(q2)], axis=-1)
        return Pose(q=q, q2=q2, o=np.zeros_like(a), a=a, d=a - self.lever_m * shank,
                    f=a + self.shank_m * shank)

    def forward(self, q, branch=None) -> Pose:
        """The pose of joint coordinates q (..., 2) = (q1 rad, q2l m); one branch only."""
        q = np.asarray(q, dtype=float)
        return self.points(q[..., 0], self.knee_from_screw(q[..., 1]))

    def inverse(self, point, mode=KNEE_BACK, strict: bool = True) -> Pose:
        """The pose putting the foot at point(s) (..., 2) in m, knee bent back (q2 <= 0);
        strict: UnreachableError outside the annulus the links reach (else NaN)."""
        p = np.asarray(point, dtype=float)
        l1, l2 = self.thigh_m, self.shank_m
        r2 = np.sum(p**2, axis=-1)
        c = (r2 - l1**2 - l2**2) / (2.0 * l1 * l2)
        out = np.abs(c) > 1.0 + 1e-12
        if strict and np.any(out):
            raise UnreachableError(f"foot point beyond the reach {abs(l1 - l2):g} .. "
                                   f"{l1 + l2:g} m of the hip")
        q2 = np.where(out, np.nan, mode[0] * np.arccos(np.clip(c, -1.0, 1.0)))
        q1 = np.arctan2(p[..., 0], -p[..., 1]) - np.arctan2(l2 * np.sin(q2),
                                                            l1 + l2 * np.cos(q2))
        return self.points(q1, q2)

    def knee_jacobian(self, q1, q2) -> np.ndarray:
        """d(foot)/d(q1, q2) (..., 2, 2) of the geared knee (seed's J_s, with its (2, 2) entry
        read as l2 sin(q1 + q2): the seed prints l1, equal in value for l1 = l2)."""
        c1, s1, c12, s12 = np.cos(q1), np.sin(q1), np.cos(q1 + q2), np.sin(q1 + q2)
        l1, l2 = self.thigh_m, self.shank_m
        return np.stack([np.stack([l1 * c1 + l2 * c12, l2 * c12], -1),
                         np.stack([l1 * s1 + l2 * s12, l2 * s12], -1)], -2)

    def tool_jacobian(self, pose: Pose) -> np.ndarray:
        """d(foot)/d(q1, q2l) (..., 2, 2), the seed's formula: the knee column times
        dq2/dq2l = -q2l / (l1 s1 sqrt(1 - c^2)), c = (l1^2 + s1^2 - q2l^2) / (2 l1 s1)."""
        l1, s1 = self.thigh_m, self.lever_m
        q1, q2l = pose.q[..., 0], pose.q[..., 1]
        c = (l1**2 + s1**2 - q2l**2) / (2.0 * l1 * s1)
        dq2 = -q2l / (l1 * s1 * np.sqrt(1.0 - c**2))
        j = self.knee_jacobian(q1, pose.q2)
        return np.stack([j[..., 0], j[..., 1] * dq2[..., None]], -1)

    def angle_odp(self, pose: Pose):
        """The angle ODP (rad) at the lever's end D between the screw D->O and the lever's line
        D->P: the screw pushes the knee hardest where it is 90 deg."""
        u, v = pose.o - pose.d, pose.f - pose.d
        cos = np.sum(u * v, axis=-1) / (np.linalg.norm(u, axis=-1) * np.linalg.norm(v, axis=-1))
        return np.arccos(np.clip(cos, -1.0, 1.0))

    # -- statics --------------------------------------------------------------------------------
    def static_torques(self, foot_force_N, pose: Pose) -> np.ndarray:
        """Generalized forces (..., 2) = (hip N*m, screw N) holding poses at rest against the
        external force foot_force_N (2,) on the foot (N): -J^T F."""
        return -np.einsum("...ij,i->...j", self.tool_jacobian(pose),
                          np.asarray(foot_force_N, dtype=float))

    def screw_force(self, knee_torque_Nm, q2):
        """Screw force (N) giving a knee torque (N*m), by virtual work: tau dq2 = F dq2l."""
        return np.asarray(knee_torque_Nm) / self.screw_rate(q2)

    def screw_motor_torque(self, force_N, efficiency: float, driving: bool = True):
        """Screw motor torque (N*m) for a screw force (N): F lead / (2 pi eta) when the motor
        drives the screw (forward efficiency), F lead eta / (2 pi) when the load drives it
        (back-driven)."""
        ideal = np.asarray(force_N) * self.lead_m / (2.0 * np.pi)
        return ideal / efficiency if driving else ideal * efficiency

    # -- the Drake model's tree -----------------------------------------------------------------
    def tree_positions(self, pose: Pose) -> np.ndarray:
        """Tree coordinates x (..., 4) in TREE_JOINTS order: hip q1, knee q2, the screw's pivot
        angle from the thigh (rad) and the screw joint's angle 2 pi q2l / lead (rad)."""
        d_in_thigh = np.stack([self.thigh_m - self.lever_m * np.cos(pose.q2),
                               -self.lever_m * np.sin(pose.q2)], -1)
        pivot = np.arctan2(d_in_thigh[..., 1], d_in_thigh[..., 0])
        return np.stack([pose.q[..., 0], pose.q2, pivot,
                         2.0 * np.pi * pose.q[..., 1] / self.lead_m], -1)

    def loop_gaps(self, x) -> np.ndarray:
        """Distance (m) between the nut and the lever's end D for tree coordinates x (..., 4)."""
        x = np.asarray(x, dtype=float)
        pose = self.points(x[..., 0], x[..., 1])
        nut = _unit(x[..., 0] + x[..., 2]) * (self.lead_m * x[..., 3] / (2.0 * np.pi))[..., None]
        return np.linalg.norm(pose.d - nut, axis=-1)
