"""The 4-DOF parallel manipulator behind the package's Mechanism interface (mechanisms/base.py),
where it fits: the tool point is the platform point P = (x, y, z) in {O} (d = 3) and the pose
is the platform's (x, y, z, theta); q are the actuator positions l1 .. l4 (m)."""

from __future__ import annotations

import numpy as np

from fivebar_drake.mechanisms.parallel4.geometry import Geometry
from fivebar_drake.mechanisms.parallel4.kinematics import (SEED_MODE, forward, inverse,
                                                           velocity_jacobian)
from fivebar_drake.mechanisms.parallel4.statics import holding_forces

MIRROR_MODE = tuple(-s for s in SEED_MODE)


class Parallel4:
    """Kinematics and statics of one manipulator; poses (..., 4) are (x, y, z, theta)."""

    motors = ("l1", "l2", "l3", "l4")
    modes = (SEED_MODE, MIRROR_MODE)

    def __init__(self, geometry: Geometry):
        self.geometry = geometry.check()

    def forward(self, q, branch=None) -> np.ndarray:
        """Pose of actuator positions q; branch "lower" (the seed's, default) or "upper"."""
        if branch not in (None, "lower", "upper"):
            raise ValueError(f"branch = {branch!r}: must be 'lower' or 'upper'")
        return forward(self.geometry, q, lower=branch != "upper")

    def inverse(self, pose, mode=SEED_MODE, strict: bool = True) -> np.ndarray:
        """Actuator positions of platform poses (..., 4): the tool point alone does not fix
        the platform angle, so this takes the whole pose."""
        return inverse(self.geometry, pose, mode, strict)

    def tool_jacobian(self, pose, mode=SEED_MODE) -> np.ndarray:
        """d(x, y, z)/dq (..., 3, 4): the first three rows of J^-1, J = A^-1 B."""
        J = velocity_jacobian(self.geometry, pose, inverse(self.geometry, pose, mode))
        return np.linalg.inv(J)[..., :3, :]

    def static_torques(self, load, pose, mode=SEED_MODE) -> np.ndarray:
        """Actuator forces (..., 4), N, holding poses against the platform wrench `load`
        (f_x, f_y, f_z, M_y) in N and N*m."""
        return holding_forces(self.geometry, pose, load, mode)
