"""The 5-bar leg with all the parts of mechanisms/base.py: its geometry and link inertias, with
the kinematics, Jacobians, dynamics, loop and SDF of this folder behind them, and the torque
breakdown of a DynamicsModel (torques) that the quadruped's analysis reads."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fivebar_drake.mechanisms.base import Bushing, SdfLook
from fivebar_drake.mechanisms.fivebar import dynamics, kinematics, loop, sdf
from fivebar_drake.mechanisms.fivebar.geometry import (MOTORS, LegGeometry, LinkInertia,
                                                        physical_izz)
from fivebar_drake.mechanisms.fivebar.jacobians import foot_jacobian


@dataclass(frozen=True)
class FiveBarLeg:
    """A 5-bar leg: geometry (m) and the mass properties of its links AC, BD, CE, DE. Joint
    coordinates q = (theta_A, theta_B) rad; the tool point is the foot F in the leg plane (m);
    assembly modes (knee C, knee D), +1 out, -1 in; forward branch: the side of line C->D on
    which E lies, +1 left, -1 right (None: the seed's lower E)."""

    geometry: LegGeometry
    links: dict[str, LinkInertia]
    motors = MOTORS
    modes = kinematics.ALL_MODES
    branches = (1, -1)
    parts = ("kinematics", "statics", "dynamics", "drake_model", "sdf_elements")

    def forward(self, q, branch=None) -> kinematics.LegPose:
        return kinematics.forward(self.geometry, q, branch)

    def inverse(self, point, mode=kinematics.KNEES_OUT, strict: bool = True) -> kinematics.LegPose:
        return kinematics.inverse(self.geometry, point, mode, strict)

    def tool_jacobian(self, pose) -> np.ndarray:
        return foot_jacobian(self.geometry, pose)

    def mass_matrix(self, pose) -> np.ndarray:
        return dynamics.mass_matrix(self.geometry, self.links,
                                    physical_izz(self.geometry, self.links), pose)

    def bias_torques(self, pose, qd) -> np.ndarray:
        return dynamics.coriolis(self.geometry, self.links,
                                 physical_izz(self.geometry, self.links), pose, qd)

    def torques(self, model: dynamics.DynamicsModel, pose, qd, qdd) -> dynamics.TorqueBreakdown:
        return dynamics.torques(self.geometry, self.links, model, pose, qd, qdd)

    def static_torques(self, model: dynamics.DynamicsModel, pose) -> np.ndarray:
        return dynamics.static_torques(self.geometry, self.links, model, pose)

    def tree_positions(self, pose) -> np.ndarray:
        return loop.tree_positions(pose)

    def loop_gaps(self, x) -> np.ndarray:
        return loop.loop_gaps(self.geometry, x)

    def sdf_elements(self, prefix: str, parent: str, frame: str, closure,
                     bushing: Bushing | None, look: SdfLook) -> str:
        """The leg's SDF (sdf.sdf_elements): links in the leg-plane frame `frame`, motors on
        the link `parent`."""
        return sdf.sdf_elements(self.geometry, self.links, prefix, parent, frame, closure,
                                bushing, look)
