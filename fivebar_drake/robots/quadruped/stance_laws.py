"""Stance force laws: the stage of the foot/leg controller (simulation/systems.FootLeg,
stance_law) that shares the body's wrench among the feet on the ground. Each is a variant
registered by kind in STANCE_LAWS (register_stance_law) whose `forces` is a compiled function
(core.compiled.jit, cached on disk in its own module):

    forces(k, body, weights, share, fx, fy, state, r_wb) -> (legs, 2) N

the ground forces on the feet in their leg planes (x, y) from the law's constants k
(control_law.LawConstants: masses, gains, hips, friction, state indices), the body's targets
body = (z* m, z*' m/s, z*'' m/s^2, v_x* m/s) (control_law.body_targets), the feet's support
weights (legs,), the share (0 .. 1) of the wrench the feet down deliver, the measured leg-plane
feet fx, fy (legs,) m, the plant state (nx,) and the body's rotation r_wb (3, 3). A foot with
weight 0 must get no force. The controller adds -J_F^T F to each leg (control_law.leg_torques).

A new law is a module with its compiled function and a registered StanceLaw subclass (the
README's template); a package outside this one registers its module through the entry point
group fivebar_drake.plugins (core/plugins.py)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from fivebar_drake.core.variants import Variant, registrar
from fivebar_drake.robots.quadruped.control_law import ground_forces

STANCE_LAWS: dict[str, type["StanceLaw"]] = {}   # the stance force laws by kind
register_stance_law = registrar(STANCE_LAWS, "stance law")


@dataclass(frozen=True)
class StanceLaw(Variant):
    """A stance force law (module docstring): subclasses set `kind` and `forces`."""

    forces: ClassVar = None


@register_stance_law
@dataclass(frozen=True)
class VirtualModel(StanceLaw):
    """The virtual model (control_law.ground_forces): the least weighted-norm ground forces
    that produce the body's wrench (height, forward speed, roll, pitch), F_z >= 0, inside the
    friction cone."""

    kind: ClassVar[str] = "virtual_model"
    forces: ClassVar = staticmethod(ground_forces)
