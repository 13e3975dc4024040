"""The SCARA arm as a Drake MultibodyPlant, from a generated SDF (ScaraArm.sdf_elements), and
Drake's rigid-body terms along a motion (the independent check of the Lagrange model)."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import MultibodyForces

from fivebar_drake.core.sdf import document, element
from fivebar_drake.mechanisms.scara import Inertia, ScaraArm, ScaraParams

JOINTS = ("q1", "q2", "q3")


def sdf_text(params: ScaraParams, inertia: Inertia) -> str:
    """SDF of the arm: a base link and ScaraArm.sdf_elements placed in it."""
    arm = ScaraArm(params.kinematics, inertia)
    return document("scara", element("link", name="base"), arm.sdf_elements("", "base", "base"))


@dataclass(frozen=True)
class ArmPlant:
    """A finalized plant of the arm and the index maps: q_index[i] (v_index[i]) is the plant
    position (velocity) of joint i of (q1, q2, q3)."""

    plant: object
    q_index: np.ndarray
    v_index: np.ndarray


def add_arm(builder, params: ScaraParams, inertia: Inertia, time_step_s: float = 0.0) -> ArmPlant:
    """Add the finalized arm (base welded to the world, gravity of the parameters) to a
    DiagramBuilder, or make a lone plant if builder is None."""
    if builder is None:
        plant = MultibodyPlant(time_step_s)
    else:
        plant, _ = AddMultibodyPlant(MultibodyPlantConfig(time_step=time_step_s), builder)
    Parser(plant).AddModelsFromString(sdf_text(params, inertia), "sdf")
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("base"), RigidTransform())
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -inertia.g])
    plant.Finalize()
    joints = [plant.GetJointByName(n) for n in JOINTS]
    return ArmPlant(plant, np.array([j.position_start() for j in joints]),
                    np.array([j.velocity_start() for j in joints]))


def drake_terms(params: ScaraParams, inertia: Inertia, q, qd, qdd) -> dict[str, np.ndarray]:
    """Drake's terms at each sample of q, qd, qdd (n, 3), in the joint order (q1, q2, q3):
    inverse-dynamics forces with gravity (n, 3), mass matrices (n, 3, 3), bias C qd (n, 3)
    and the gravity forces as G = -tau_g (n, 3)."""
    arm = add_arm(None, params, inertia)
    plant, iq, iv = arm.plant, arm.q_index, arm.v_index
    context, forces = plant.CreateDefaultContext(), MultibodyForces(plant)
    n = len(q)
    out = {"inverse_dynamics": np.zeros((n, 3)), "mass_matrix": np.zeros((n, 3, 3)),
           "bias": np.zeros((n, 3)), "gravity": np.zeros((n, 3))}
    x, v, a = np.zeros(plant.num_positions()), np.zeros(plant.num_velocities()), \
        np.zeros(plant.num_velocities())
    for k in range(n):
        x[iq], v[iv], a[iv] = q[k], qd[k], qdd[k]
        plant.SetPositions(context, x)
        plant.SetVelocities(context, v)
        plant.CalcForceElementsContribution(context, forces)      # gravity
        out["inverse_dynamics"][k] = plant.CalcInverseDynamics(context, a, forces)[iv]
        out["mass_matrix"][k] = plant.CalcMassMatrix(context)[np.ix_(iv, iv)]
        out["bias"][k] = plant.CalcBiasTerm(context)[iv]
        out["gravity"][k] = -plant.CalcGravityGeneralizedForces(context)[iv]
    return out

