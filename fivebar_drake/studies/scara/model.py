"""The SCARA arm as a Drake MultibodyPlant, from a generated SDF, and Drake's rigid-body terms
along a motion (the independent check of the Lagrange model).

Link frames sit on the joint axes, aligned with frame 0 at q = 0: link1 at (0, 0, d1), link2 at
(a1, 0, d1 + d2), link3 (screw, gripper and payload, a mass on the axis) at (a1 + a2, 0,
d1 + d2) with the tool point E at its origin; joint 3 slides along q3_direction * z."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import MultibodyForces

from fivebar_drake.core.sdf import fmt, inertial
from fivebar_drake.mechanisms.scara import Inertia, ScaraParams, seed_inertia

JOINTS = ("q1", "q2", "q3")


def sdf_text(params: ScaraParams, inertia: Inertia) -> str:
    """SDF of the arm. ASSUMPTION: Ixx = Iyy = Izz of each link (the seed gives Izz only; the
    horizontal moments never enter the motion, every joint axis being vertical)."""
    k = params.kinematics
    z2 = k.d1_m + k.d2_m
    links = (("link1", (0.0, 0.0, k.d1_m), inertia.m1, inertia.c1, inertia.izz1),
             ("link2", (k.a1_m, 0.0, z2), inertia.m2, inertia.c2, inertia.izz2),
             ("link3", (k.a1_m + k.a2_m, 0.0, z2), inertia.m3, 0.0, inertia.izz3))
    body = "".join(f'<link name="{name}"><pose>{fmt(*xyz, 0, 0, 0)}</pose>'
                   f"{inertial(m, com, izz, izz, izz)}</link>"
                   for name, xyz, m, com, izz in links)
    limits = [np.radians(k.q1_limits_deg), np.radians(k.q2_limits_deg), k.q3_limits_m]
    joints = ""
    for (name, kind, axis), parent, child, (lo, hi) in zip(
            (("q1", "revolute", "0 0 1"), ("q2", "revolute", "0 0 1"),
             ("q3", "prismatic", f"0 0 {k.q3_direction}")),
            ("base", "link1", "link2"), ("link1", "link2", "link3"), limits):
        joints += (f'<joint name="{name}" type="{kind}"><parent>{parent}</parent>'
                   f"<child>{child}</child><axis><xyz>{axis}</xyz><limit><lower>{lo:.12g}"
                   f"</lower><upper>{hi:.12g}</upper></limit></axis></joint>")
    return (f'<?xml version="1.0"?><sdf version="1.9"><model name="scara">'
            f'<link name="base"/>{body}{joints}</model></sdf>')


@dataclass(frozen=True)
class ArmPlant:
    """A finalized plant of the arm and the index maps: q_index[i] (v_index[i]) is the plant
    position (velocity) of joint i of (q1, q2, q3); actuation[i] the actuator of joint i."""

    plant: object
    q_index: np.ndarray
    v_index: np.ndarray


def add_arm(builder, params: ScaraParams, inertia: Inertia, time_step_s: float = 0.0) -> ArmPlant:
    """Add the finalized arm (base welded to the world, gravity of the parameters) to a
    DiagramBuilder, or make a lone plant if builder is None."""
    config = MultibodyPlantConfig(time_step=time_step_s)
    if builder is None:
        from pydrake.multibody.plant import MultibodyPlant
        plant = MultibodyPlant(time_step_s)
    else:
        plant, _ = AddMultibodyPlant(config, builder)
    Parser(plant).AddModelsFromString(sdf_text(params, inertia), "sdf")
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("base"), RigidTransform())
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -inertia.g])
    plant.Finalize()
    joints = [plant.GetJointByName(n) for n in JOINTS]
    return ArmPlant(plant, np.array([j.position_start() for j in joints]),
                    np.array([j.velocity_start() for j in joints]))


def drake_terms(params: ScaraParams, inertia: Inertia, q, qd, qdd) -> dict[str, np.ndarray]:
    """Drake's terms at each sample of q, qd, qdd (n, 3), in the joint order (q1, q2, q3):
    inverse-dynamics forces with gravity (n, 3), mass matrices (n, 3, 3), bias C qd (n, 3) and the gravity
    forces as G = -tau_g (n, 3)."""
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


def packaged_inertia(params: ScaraParams, payload_kg: float) -> Inertia:
    """The seed's inertia data as written, with a payload at the tool."""
    return seed_inertia(params.links, payload_kg)
