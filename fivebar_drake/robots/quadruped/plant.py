"""The quadruped in a Drake MultibodyPlant: model loading with the loop closures, joint indices, the
plain-data layout the controller needs, ground and standing pose."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple
import numpy as np
from pydrake.geometry import AddContactMaterial, Box, ProximityProperties
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser
from pydrake.multibody.tree import SpatialInertia
from pydrake.multibody.plant import (AddMultibodyPlant, CoulombFriction, MultibodyPlant,
                                     MultibodyPlantConfig)
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.mechanisms.fivebar import JOINTS
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.core.drake_configs import config_with
from fivebar_drake.core.variants import Variant
from fivebar_drake.mechanisms.base import Bushing
from fivebar_drake.robots.quadruped.legs import LEGS, hip_positions
from fivebar_drake.robots.quadruped.sdf import body_height, quadruped_sdf, single_leg_sdf


@dataclass(frozen=True)
class ClosureDesign:
    """A loop closure designed before the plant is assembled (plain data): the closure (a
    closure.Closure), the plant's time step (s), the bushing (None for the ball) and what it was
    designed from, the knee's effective mass (kg) and the largest loop force (N)."""

    closure: Variant
    time_step_s: float
    bushing: Bushing | None
    m_eff_kg: float
    loop_force_N: float


def add_model(plant: MultibodyPlant, params: Params, model: str, closure: Variant | None,
              bushing: Bushing | None = None):
    """Parse the generated SDF ("leg": one fixed-hip leg named "leg"; "quadruped": body + legs
    FL, FR, RL, RR) into plant and close each loop with closure (a closure.Closure: its SDF
    element, then closure.add_to; bushing: the designed one, None for the ball; closure None: the
    open tree, for kinematics and mass properties). Returns (model instance, leg names)."""
    text = (single_leg_sdf if model == "leg" else quadruped_sdf)(params, closure, bushing)
    parser = Parser(plant)
    parser.SetStrictParsing()
    (instance,) = parser.AddModelsFromString(text, "sdf")
    legs = ("leg",) if model == "leg" else LEGS
    if closure is not None:
        closure.add_to(plant, instance, legs, params, bushing)
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

GROUND_SIZE_M = 40.0   # flat ground, top face at z = 0
GROUND_DEPTH_M = 1.0
PAYLOAD_RADIUS_M = 0.02   # a payload is a solid sphere this size (its own inertia is small)


def robot_layout(plant, instance, legs, params: Params) -> RobotLayout:
    """The controller's view of the finalized plant (see systems.RobotLayout): indices, hips,
    and the whole robot's mass, COM and inertia in the standing pose."""
    indices = {leg: leg_indices(plant, instance, leg) for leg in legs}
    context = plant.CreateDefaultContext()
    set_standing_pose(plant, context, instance, legs, params)
    body = plant.GetBodyByName("body", instance)
    spatial = plant.CalcSpatialInertia(context, body.body_frame(),
                                       plant.GetBodyIndices(instance))
    com = spatial.get_com()
    inertia = spatial.Shift(com).CalcRotationalInertia().CopyToFullMatrix3()
    return RobotLayout(
        legs=tuple(legs), indices=indices, state=StateIndices(
            q_index=np.array([indices[leg].q[:2] for leg in legs]),
            v_index=np.array([indices[leg].v[:2] for leg in legs]),
            contact_v_index=np.array([indices[leg].v[[1, 3]] for leg in legs]),
            actuators=np.array([indices[leg].actuators for leg in legs]),
            body_q=body.floating_positions_start(), body_v=body.floating_velocities_start_in_v(),
            nq=plant.num_positions()),
        nv=plant.num_velocities(), nx=plant.num_multibody_states(),
        hips_m=np.array([hip_positions(params)[leg] for leg in legs]), com_m=np.asarray(com),
        mass_kg=spatial.get_mass(), inertia_kg_m2=inertia,
        gravity_m_s2=np.array(plant.gravity_field().gravity_vector()))


def default_plant_config() -> MultibodyPlantConfig:
    """The plant this robot needs: SAP (the loop closures are SAP constraints); unsampled output
    ports, so a block updating at tick t reads the state at t, as a driver would. time_step 0
    here (not Drake's default): the closure design sets it."""
    return MultibodyPlantConfig(time_step=0.0, discrete_contact_approximation="sap",
                                use_sampled_output_ports=False)


class Modifiers(NamedTuple):
    """What a scenario changes about the robot and its ground: a payload (kg, a solid sphere of
    PAYLOAD_RADIUS_M fixed to the body at payload_offset_m (3,) m in the body frame) and the ground's slope (rad,
    walking up it along the body's x)."""

    payload_kg: float = 0.0
    payload_offset_m: tuple = (0.0, 0.0, 0.0)
    slope_rad: float = 0.0


def gravity_vector(gravity_m_s2: float, slope_rad: float) -> np.ndarray:
    """Gravity (3,) m/s^2 in the frame of a ground sloping up by slope_rad along +x: tilting
    gravity is exactly a tilted flat infinite ground, with the ground kept at z = 0."""
    return gravity_m_s2 * np.array([-np.sin(slope_rad), 0.0, -np.cos(slope_rad)])


def add_robot(builder: DiagramBuilder, params: Params, design: ClosureDesign,
              plant_config: MultibodyPlantConfig | None = None,
              modifiers: Modifiers = Modifiers()):
    """Add the finalized quadruped plant (plant_config, default default_plant_config, at the
    design's time step, loops closed as designed) and flat ground to builder, with the payload
    and the slope of `modifiers`; returns (plant, model instance, RobotLayout)."""
    config = config_with(plant_config or default_plant_config(), time_step=design.time_step_s)
    plant, _ = AddMultibodyPlant(config, builder)
    instance, legs = add_model(plant, params, "quadruped", design.closure, design.bushing)
    if modifiers.payload_kg > 0:
        payload = plant.AddRigidBody("payload", instance, SpatialInertia.SolidSphereWithMass(
            modifiers.payload_kg, PAYLOAD_RADIUS_M))
        plant.WeldFrames(plant.GetBodyByName("body", instance).body_frame(), payload.body_frame(),
                         RigidTransform(np.asarray(modifiers.payload_offset_m, dtype=float)))
    plant.mutable_gravity_field().set_gravity_vector(
        gravity_vector(params.robot.gravity_m_s2, modifiers.slope_rad))
    ground = ProximityProperties()
    mu = params.body.foot_friction
    AddContactMaterial(friction=CoulombFriction(mu, mu), properties=ground)
    plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform([0, 0, -GROUND_DEPTH_M / 2]),
                                    Box(GROUND_SIZE_M, GROUND_SIZE_M, GROUND_DEPTH_M), "ground",
                                    ground)
    plant.Finalize()
    return plant, instance, robot_layout(plant, instance, legs, params)


def standing_height(params: Params) -> float:
    """Body height (m) at which the feet, at (x_center, y_home), touch flat ground."""
    return float(body_height(params, params.gait.y_home_m))


def set_standing_pose(plant, context, instance, legs, params: Params, foot=None,
                      lift_m: float = 0.0) -> None:
    """Standing pose in a plant context: every loop closed exactly (closed-form IK), at rest,
    feet at `foot` (2,) m in the leg plane (default (x_center, y_home)) lift_m above the ground,
    or the body resting on its underside if the feet are folded above that (lying)."""
    if foot is None:
        foot = np.array([params.gait.x_center_m, params.gait.y_home_m])
    x = params.fivebar_leg.tree_positions(params.fivebar_leg.inverse(np.asarray(foot)))
    q = plant.GetPositions(context)
    for leg in legs:
        q[leg_indices(plant, instance, leg).q] = x
    plant.SetPositions(context, q)
    height = max(float(body_height(params, foot[1])) + lift_m, params.body.height_m / 2)
    plant.SetFreeBodyPose(context, plant.GetBodyByName("body", instance),
                          RigidTransform([0.0, 0.0, height]))


class StateIndices(NamedTuple):
    """Where the controller finds the motors and the body in the plant's state and actuation
    (a NamedTuple: the compiled control law takes it as it is): per leg (legs, 2) the plant q
    and v indices of motors A and B and their actuation indices; the v indices of the joints B
    and D (contact_v_index, the chain from the hip to the foot on link DE, where the ground's
    generalized forces are read); the body's first position index (quaternion w, x, y, z, then
    position) and velocity index (angular then linear, world frame); nq (the state is
    [q, v])."""

    q_index: np.ndarray
    v_index: np.ndarray
    contact_v_index: np.ndarray
    actuators: np.ndarray
    body_q: int
    body_v: int
    nq: int


@dataclass(frozen=True)
class RobotLayout:
    """The finalized plant as plain data (what the controller and the post-processing need):
    the leg names and each leg's joint indices (LegIndices); the motors' and the body's indices
    (StateIndices); nv, nx; hip positions (legs, 3) m and the robot's COM (3,) m in the body
    frame; robot mass (kg) and inertia about the COM (3, 3) kg*m^2, payload included; the
    plant's gravity (3,) m/s^2 in the world (the slope's frame)."""

    legs: tuple[str, ...]
    indices: dict[str, LegIndices]
    state: StateIndices
    nv: int
    nx: int
    hips_m: np.ndarray
    com_m: np.ndarray
    mass_kg: float
    inertia_kg_m2: np.ndarray
    gravity_m_s2: np.ndarray
