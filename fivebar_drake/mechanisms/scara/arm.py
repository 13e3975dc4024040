"""The SCARA arm with all the parts of mechanisms/base.py: the kinematics of Scara with the
Lagrange dynamics of an Inertia model and its SDF elements. A serial arm has no loop: the tree
coordinates are the joint coordinates and there are no loop gaps."""

from __future__ import annotations

import numpy as np

from fivebar_drake.core.sdf import axis, element, inertial, joint, limit, pose
from fivebar_drake.mechanisms.base import Bushing, SdfLook
from fivebar_drake.mechanisms.scara.dynamics import Dynamics, Inertia
from fivebar_drake.mechanisms.scara.kinematics import Scara
from fivebar_drake.mechanisms.scara.params import Kinematics


class ScaraArm(Scara):
    """Scara with the physical inertias `inertia` (mass matrix, bias torques) and the parts of
    mechanisms/base.py; the load of static_torques is an Inertia (e.g. with another payload)."""

    parts = ("kinematics", "statics", "dynamics", "drake_model", "sdf_elements")

    def __init__(self, kin: Kinematics, inertia: Inertia):
        super().__init__(kin)
        self.inertia = inertia

    def mass_matrix(self, pose) -> np.ndarray:
        return Dynamics(self.k, self.inertia).mass_matrix(getattr(pose, "q", pose))

    def bias_torques(self, pose, qd) -> np.ndarray:
        """C(q, qd) qd (..., 3), N*m and N."""
        q = getattr(pose, "q", pose)
        return np.einsum("...ij,...j->...i", Dynamics(self.k, self.inertia).coriolis_matrix(q, qd),
                         np.asarray(qd, dtype=float))

    def static_torques(self, model: Inertia, pose) -> np.ndarray:
        return Dynamics(self.k, model).gravity(getattr(pose, "q", pose))

    def tree_positions(self, pose) -> np.ndarray:
        return np.asarray(getattr(pose, "q", pose), dtype=float)

    def loop_gaps(self, x) -> np.ndarray:
        return np.zeros(np.shape(x)[:-1] + (0,))

    def sdf_elements(self, prefix: str, parent: str, frame: str, closure=None,
                     bushing: Bushing | None = None, look: SdfLook | None = None) -> str:
        """SDF links <prefix>link1..3 and joints <prefix>q1..q3, placed in the SDF frame
        `frame`, joint 1 on the link `parent`. Link frames sit on the joint axes, aligned with
        `frame` at q = 0: link1 at (0, 0, d1), link2 at (a1, 0, d1 + d2), link3 (screw, gripper
        and payload, a mass on the axis) at (a1 + a2, 0, d1 + d2) with the tool point at its
        origin; joint 3 slides along q3_direction * z. closure, bushing and look do not apply
        (no loop; no visual geometry). ASSUMPTION: Ixx = Iyy = Izz of each link (the seed gives
        Izz only; the horizontal moments never enter the motion, every joint axis being
        vertical)."""
        k, i = self.k, self.inertia
        z2 = k.d1_m + k.d2_m
        links = (("link1", (0.0, 0.0, k.d1_m), i.m1, i.c1, i.izz1),
                 ("link2", (k.a1_m, 0.0, z2), i.m2, i.c2, i.izz2),
                 ("link3", (k.a1_m + k.a2_m, 0.0, z2), i.m3, 0.0, i.izz3))
        text = "".join(element("link", pose(*xyz, relative_to=frame),
                               inertial(m, (izz, izz, izz), (com, 0, 0)), name=f"{prefix}{name}")
                       for name, xyz, m, com, izz in links)
        axes = (("revolute", "0 0 1"), ("revolute", "0 0 1"),
                ("prismatic", f"0 0 {k.q3_direction}"))
        parents = (parent, f"{prefix}link1", f"{prefix}link2")
        for n, ((kind, xyz), up, lo, hi) in enumerate(zip(axes, parents, self.lower, self.upper)):
            text += joint(f"{prefix}q{n + 1}", kind, up, f"{prefix}link{n + 1}",
                          axis(xyz, limit(lower=lo, upper=hi)))
        return text
