"""What every mechanism offers the layers above it: the analysis, the controllers and the plant
assembly use a mechanism through this interface only.

Coordinates: q (..., motors) are the actuated joints (rad or m); points, such as the foot or
tool point, are in the mechanism's own frame (m), with d coordinates (d = 2 for a planar
mechanism such as the 5-bar leg, 3 or more for a spatial one: its docstring says which); tree
coordinates x (..., n_tree) are the joint positions of the mechanism's Drake model, a tree cut
open where a loop closes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np


@dataclass(frozen=True)
class Bushing:
    """A linear bushing closing a loop: force stiffness (N/m) and damping (N*s/m)."""

    stiffness_N_m: float
    damping_N_s_m: float


@dataclass(frozen=True)
class SdfLook:
    """How the robot dresses a mechanism's SDF: link cross-section width (m); the tool's
    collision and visual elements, with "{pose}" where the mechanism puts the tool point's
    <pose>; and what follows an actuated joint's <xyz> (its limit, the closing </axis>, the
    drive: rotor inertia, gear ratio)."""

    link_width_m: float
    tool_xml: str
    actuated_joint_xml: str


@runtime_checkable
class Mechanism(Protocol):
    """A mechanism: kinematics with assembly modes, the tool Jacobian, torques for a load,
    the tree model's coordinates and loop gaps, and its SDF elements."""

    motors: tuple[str, ...]          # actuated joints, in the order of q
    modes: tuple[tuple[int, ...], ...]   # assembly modes inverse() can take

    def forward(self, q, branch=None):
        """Pose (the mechanism's pose type; .q, and .f the tool point) for joint coordinates q;
        branch selects the forward-kinematics branch (None: the mechanism's default)."""

    def inverse(self, point, mode, strict: bool = True):
        """Pose reaching the tool point(s) (..., d) in assembly mode; strict: raise where out of
        reach (else NaN)."""

    def tool_jacobian(self, pose) -> np.ndarray:
        """d(tool point)/dq (..., d, motors)."""

    def mass_matrix(self, pose) -> np.ndarray:
        """Joint-space mass matrix of the links (..., motors, motors), physical inertias."""

    def torques(self, model, pose, qd, qdd):
        """Actuator torques and their parts for a load model (the mechanism's model type)."""

    def static_torques(self, model, pose) -> np.ndarray:
        """Actuator torques (..., motors) holding the poses at rest under the model's loads."""

    def tree_positions(self, pose) -> np.ndarray:
        """Tree coordinates x (..., n_tree) of poses."""

    def loop_gaps(self, x) -> np.ndarray:
        """Distance (m) across each cut loop for tree coordinates x (..., n_tree)."""

    def sdf_elements(self, prefix: str, parent: str, frame: str, closure: str,
                     bushing: Bushing | None, look: SdfLook) -> str:
        """SDF links, joints and loop closure of one mechanism placed in the SDF frame `frame`,
        its actuated joints on the link `parent`; names start with prefix."""
