"""The 4-DOF parallel manipulator with the kinematics and statics parts of mechanisms/base.py:
the tool point is the platform's pose f = (x, y, z, theta) in {O} (m, rad; d = 4; the point P
alone does not fix the platform's angle) and q are the actuator positions l1 .. l4 (m)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fivebar_drake.mechanisms.parallel4.geometry import Geometry
from fivebar_drake.mechanisms.parallel4.kinematics import (SEED_MODE, forward, inverse,
                                                           velocity_jacobian)
from fivebar_drake.mechanisms.parallel4.statics import holding_forces

MIRROR_MODE = tuple(-s for s in SEED_MODE)


@dataclass(frozen=True)
class PlatformPose:
    """Actuator positions q (..., 4) in m and the platform's pose f (..., 4) = (x, y, z, theta)
    in m and rad."""

    q: np.ndarray
    f: np.ndarray


class Parallel4:
    """Kinematics and statics of one manipulator (module docstring)."""

    motors = ("l1", "l2", "l3", "l4")
    modes = (SEED_MODE, MIRROR_MODE)
    branches = ("lower", "upper")
    parts = ("kinematics", "statics")

    def __init__(self, geometry: Geometry):
        self.geometry = geometry.check()

    def forward(self, q, branch=None) -> PlatformPose:
        """Pose of actuator positions q; branch "lower" (the seed's, default) or "upper"."""
        if branch not in (None, *self.branches):
            raise ValueError(f"branch = {branch!r}: must be 'lower' or 'upper'")
        q = np.asarray(q, dtype=float)
        return PlatformPose(q, forward(self.geometry, q, lower=branch != "upper"))

    def inverse(self, point, mode=SEED_MODE, strict: bool = True) -> PlatformPose:
        """Pose reaching platform poses point (..., 4) in an IK mode (4 signs)."""
        point = np.asarray(point, dtype=float)
        return PlatformPose(inverse(self.geometry, point, mode, strict), point)

    def tool_jacobian(self, pose: PlatformPose) -> np.ndarray:
        """d(x, y, z, theta)/dq (..., 4, 4) = J^-1, J = A^-1 B (m/m, rad/m in the last row)."""
        return np.linalg.inv(velocity_jacobian(self.geometry, pose.f, pose.q))

    def static_torques(self, load, pose: PlatformPose) -> np.ndarray:
        """Actuator forces (..., 4), N, holding poses against the platform wrench `load`
        (f_x, f_y, f_z, M_y) in N and N*m."""
        return holding_forces(self.geometry, pose.f, load, q=pose.q)
