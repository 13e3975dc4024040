"""The parts a mechanism can offer the layers above it, each a small Protocol: Kinematics,
Statics, Dynamics, DrakeModel (the tree's coordinates and loop gaps) and SdfElements. A
mechanism class names the parts it implements in `parts` (keys of PARTS) and implements each in
full; tests/mechanisms/test_parts.py runs one generic check per part over every mechanism of
mechanisms/registry.py. Code that needs more than a part (the quadruped's use of the 5-bar's
link Jacobians, compiled kernels and link names) imports that mechanism's package by name.

Coordinates: q (..., motors) are the actuated joints (rad or m); a pose (the mechanism's pose
type) has .q and .f, the tool point (the foot, the tool, the platform's pose) in the mechanism's
own frame, with d coordinates (d = 2 for a planar mechanism such as the 5-bar leg, 3 or more for
a spatial one: its docstring says which); tree coordinates x (..., n_tree) are the joint
positions of the mechanism's Drake model, a tree cut open where a loop closes.
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
class LoopCut:
    """Where a mechanism's loop is cut in its SDF tree: the point p_a (m) of body_a that meets the
    point p_b (m) of body_b when the loop is closed, and the frames frame_a, frame_b at those
    points (z along the hinge). A loop closure writes its SDF element from it."""

    body_a: str
    p_a: tuple[float, float, float]
    frame_a: str
    body_b: str
    p_b: tuple[float, float, float]
    frame_b: str


@dataclass(frozen=True)
class SdfLook:
    """How the robot dresses a mechanism's SDF: link cross-section width (m); the tool's
    collision and visual elements, with "{pose}" where the mechanism puts the tool point's
    <pose>; an actuated joint's effort limit (N*m or N; the mechanism writes the <limit> with
    its own joint ranges) and drive (the elements after the <axis>: rotor inertia, gear
    ratio)."""

    link_width_m: float
    tool_xml: str
    effort_limit: float
    drive_xml: str


@runtime_checkable
class Kinematics(Protocol):
    """Forward and inverse kinematics with assembly modes, and the tool Jacobian."""

    motors: tuple[str, ...]               # actuated joints, in the order of q
    modes: tuple[tuple[int, ...], ...]    # assembly modes inverse() can take
    branches: tuple                       # forward branches forward() can take

    def forward(self, q, branch=None):
        """Pose for joint coordinates q (..., motors); branch (one of `branches`) selects the
        forward-kinematics branch, None the mechanism's default."""

    def inverse(self, point, mode, strict: bool = True):
        """Pose reaching the tool point(s) (..., d) in assembly mode; strict: raise where out of
        reach (else NaN)."""

    def tool_jacobian(self, pose) -> np.ndarray:
        """d(tool point)/dq (..., d, motors)."""


@runtime_checkable
class Statics(Protocol):
    """Actuator forces holding a pose at rest."""

    def static_torques(self, load, pose) -> np.ndarray:
        """Actuator torques or forces (..., motors), N*m or N, holding poses at rest against
        `load` (the mechanism's load type: a model of gravity and foot load, a tool force, a
        platform wrench)."""


@runtime_checkable
class Dynamics(Statics, Protocol):
    """The joint-space equations of motion M(q) q'' + c(q, q') + static torques = tau."""

    def mass_matrix(self, pose) -> np.ndarray:
        """Joint-space mass matrix of the links (..., motors, motors), kg*m^2 or kg."""

    def bias_torques(self, pose, qd) -> np.ndarray:
        """Velocity-product (Coriolis and centrifugal) torques c(q, q') (..., motors) at joint
        speeds qd (..., motors), N*m or N."""


@runtime_checkable
class DrakeModel(Protocol):
    """The coordinates of the mechanism's Drake model: a tree, cut open where a loop closes."""

    def tree_positions(self, pose) -> np.ndarray:
        """Tree coordinates x (..., n_tree) of poses."""

    def loop_gaps(self, x) -> np.ndarray:
        """Distance (m) across each cut loop (..., loops) for tree coordinates x (..., n_tree)."""


@runtime_checkable
class SdfElements(Protocol):
    """The mechanism's SDF links, joints and loop closures, to place in a robot's model."""

    def sdf_elements(self, prefix: str, parent: str, frame: str, closure,
                     bushing: Bushing | None, look: SdfLook) -> str:
        """SDF links, joints and loop closure of one mechanism placed in the SDF frame `frame`,
        its actuated joints (one per motor) on the link `parent`; names start with prefix.
        closure: None (the loops left cut) or an object whose sdf(LoopCut, bushing) gives the
        SDF element closing a loop ("" where it declares none)."""


PARTS = {"kinematics": Kinematics, "statics": Statics, "dynamics": Dynamics,
         "drake_model": DrakeModel, "sdf_elements": SdfElements}


def missing_parts(mechanism) -> list[str]:
    """The parts `mechanism` names in its `parts` that it does not implement (their attributes
    are missing), and any name that is not a part."""
    return [name for name in mechanism.parts
            if name not in PARTS or not isinstance(mechanism, PARTS[name])]
