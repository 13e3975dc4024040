"""Drake MultibodyPlant of the leg or the quadruped, built from the generated SDF, and the maps
between the seed's motor angles and the plant's tree coordinates.

Tree coordinates of one leg: x = [theta_A, theta_B, phi_C, phi_D] (rad), phi_C = angle(CE) -
theta_A and phi_D = angle(DE) - theta_B are the passive knee angles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from .rotation import wrap
from .kinematics import LegPose
from .params import Params
from .sdf_model import LEGS, Bushing, quadruped_sdf, single_leg_sdf

# Loop closures at E: "bushing", the bushing's force law (a translational spring-damper at E, free
# about the hinge) as two compliant SAP distance constraints, treated implicitly; "bushing_rpy",
# Drake's explicit LinearBushingRollPitchYaw; "ball", a rigid SAP ball constraint.
CLOSURES = ("bushing", "bushing_rpy", "ball")
JOINTS = ("A", "B", "C", "D")
OFFSET_M = 0.02   # the second distance constraint's point on DE: this far off the link at E


def check_closure(closure: str) -> None:
    if closure not in CLOSURES:
        raise ValueError(f"closure = {closure!r}: allowed {list(CLOSURES)}")


def add_model(plant: MultibodyPlant, params: Params, model: str, closure: str | None,
              bushing: Bushing | None = None):
    """Parse the generated SDF ("leg": one fixed-hip leg named "leg"; "quadruped": body + legs
    FL, FR, RL, RR) into plant and close each loop (closure None: the open tree, for kinematics
    and mass properties). Returns (model instance, leg names).

    The "bushing" closure joins E on CE to D on DE at the length DE and to the point Q 20 mm off
    DE at E (perpendicular, in the leg plane) at 20 mm: both springs have the bushing's stiffness
    and damping, their directions at E are orthogonal, so E feels an isotropic in-plane spring,
    and both lines of action pass through E: no torque about the hinge."""
    if closure is not None:
        check_closure(closure)
    if closure in ("bushing", "bushing_rpy") and bushing is None:
        raise ValueError(f"closure {closure!r} needs bushing parameters")
    text = (single_leg_sdf if model == "leg" else quadruped_sdf)(params, closure, bushing)
    parser = Parser(plant)
    parser.SetStrictParsing()
    (instance,) = parser.AddModelsFromString(text, "sdf")
    legs = ("leg",) if model == "leg" else LEGS
    if closure == "bushing":
        g, k, d = params.leg, bushing.stiffness_N_m, bushing.damping_N_s_m
        for leg in legs:
            ce = plant.GetBodyByName(f"{leg}_CE", instance)
            de = plant.GetBodyByName(f"{leg}_DE", instance)
            plant.AddDistanceConstraint(ce, [g.ce_m, 0.0, 0.0], de, [0.0, 0.0, 0.0], g.de_m, k, d)
            plant.AddDistanceConstraint(ce, [g.ce_m, 0.0, 0.0], de, [g.de_m, OFFSET_M, 0.0],
                                        OFFSET_M, k, d)
    return instance, legs


@dataclass(frozen=True)
class LegIndices:
    """Where one leg's joints A, B, C, D sit in the plant's q and v, and its motors' actuator
    indices in the actuation vector (A, B)."""

    q: np.ndarray
    v: np.ndarray
    actuators: np.ndarray


def leg_indices(plant: MultibodyPlant, instance, leg: str) -> LegIndices:
    joints = [plant.GetJointByName(f"{leg}_{j}", instance) for j in JOINTS]
    actuators = [plant.GetJointActuatorByName(f"{leg}_{j}", instance).input_start()
                 for j in ("A", "B")]
    return LegIndices(q=np.array([j.position_start() for j in joints]),
                      v=np.array([j.velocity_start() for j in joints]),
                      actuators=np.array(actuators))


def tree_positions(pose: LegPose) -> np.ndarray:
    """[theta_A, theta_B, phi_C, phi_D] (..., 4) in rad for leg poses."""
    ce, de = pose.e - pose.c, pose.e - pose.d
    phi_c = np.arctan2(ce[..., 1], ce[..., 0]) - pose.q[..., 0]
    phi_d = np.arctan2(de[..., 1], de[..., 0]) - pose.q[..., 1]
    phi = [np.asarray(wrap(phi))[..., None] for phi in (phi_c, phi_d)]
    return np.concatenate([pose.q, *phi], axis=-1)


def loop_gaps(params: Params, x) -> np.ndarray:
    """Loop gap (m) |E on CE - E on DE| for tree coordinates x (..., 4) of one leg."""
    g = params.leg
    ta, tb, pc, pd = np.moveaxis(np.asarray(x), -1, 0)
    u = lambda a: np.stack([np.cos(a), np.sin(a)], -1)  # noqa: E731
    e_ce = g.a + g.ac_m * u(ta) + g.ce_m * u(ta + pc)
    e_de = g.b + g.bd_m * u(tb) + g.de_m * u(tb + pd)
    return np.linalg.norm(e_ce - e_de, axis=-1)
