"""Build the quadruped Diagram from a scenario and simulate it.

gait source -> IK controller -> motor model -> plant (+ scene graph), loggers on the plant state
(every step), the commands, applied torques, saturation flags and foot contact forces.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field

import numpy as np
from pydrake.geometry import AddContactMaterial, Box, ProximityProperties
from pydrake.math import RigidTransform
from pydrake.multibody.plant import (AddMultibodyPlantSceneGraph, CoulombFriction,
                                     MultibodyPlantConfig, ApplyMultibodyPlantConfig)
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import LogVectorOutput

from .bushing import bushing_parameters, loop_load
from .kinematics import inverse
from .params import Params
from .plant_model import add_model, leg_indices, tree_positions
from .scenario import Scenario
from .sdf_model import hip_positions
from .systems import FootContactForces, FootIKController, GaitSource, MotorModel

BALL_TIME_STEP_S = 1e-3
GROUND_SIZE_M = 40.0   # flat ground, top face at z = 0
GROUND_DEPTH_M = 1.0


@dataclass
class Setup:
    """What the builder made: plant handles, indices and the derived closure parameters."""

    plant: object
    instance: object
    legs: tuple
    indices: dict
    time_step_s: float
    bushing: object
    m_eff_kg: float
    loop_force_N: float
    loggers: dict = field(default_factory=dict)


def closure_parameters(scenario: Scenario, params: Params):
    """(time step s, Bushing or None, m_eff kg, loop force N) for the scenario's closure."""
    m_eff, force = loop_load(params)
    if scenario.closure == "ball":
        return scenario.time_step_s or BALL_TIME_STEP_S, None, m_eff, force
    bushing, dt = bushing_parameters(m_eff, force, scenario.target_loop_gap_m)
    if scenario.time_step_s > dt:
        raise ValueError(
            f"scenario.time_step_s = {scenario.time_step_s!r}: the bushing (k = "
            f"{bushing.stiffness_N_m:.3g} N/m, m_eff = {m_eff * 1e3:.2f} g) is stable up to "
            f"{dt:.3g} s; use 0 (derived) or a smaller step, or a larger target_loop_gap_m")
    return scenario.time_step_s or dt, bushing, m_eff, force


def build_diagram(scenario: Scenario, params: Params):
    """Assemble the Diagram for the scenario; returns (diagram, Setup)."""
    time_step, bushing, m_eff, force = closure_parameters(scenario, params)
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step)
    ApplyMultibodyPlantConfig(MultibodyPlantConfig(time_step=time_step,
                                                   discrete_contact_approximation="sap"), plant)
    instance, legs = add_model(plant, params, "quadruped", scenario.closure, bushing)
    ground = ProximityProperties()
    mu = params.body.foot_friction
    AddContactMaterial(friction=CoulombFriction(mu, mu), properties=ground)
    plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform([0, 0, -GROUND_DEPTH_M / 2]),
                                    Box(GROUND_SIZE_M, GROUND_SIZE_M, GROUND_DEPTH_M), "ground",
                                    ground)
    plant.Finalize()
    indices = {leg: leg_indices(plant, instance, leg) for leg in legs}
    nq, nx = plant.num_positions(), plant.num_multibody_states()
    q_index = np.array([indices[leg].q[:2] for leg in legs])
    v_index = np.array([indices[leg].v[:2] for leg in legs])
    actuators = np.array([indices[leg].actuators for leg in legs])

    gait = builder.AddNamedSystem("gait_source", GaitSource(
        params.gait, scenario.phases_rad, scenario.stand_s, scenario.ramp_s))
    body = plant.GetBodyByName("body", instance)
    controller = builder.AddNamedSystem("ik_controller", FootIKController(
        params, q_index, v_index, actuators, nq, nx, scenario.control_period_s,
        scenario.kp_Nm_rad, scenario.kd_Nm_s_rad, body_q=body.floating_positions_start(),
        body_v=body.floating_velocities_start_in_v(),
        hips_m=[hip_positions(params)[leg] for leg in legs],
        balance_gain=scenario.balance_gain, balance_rate_s=scenario.balance_rate_s))
    v_by_actuator = np.zeros(plant.num_actuators(), dtype=int)
    v_by_actuator[actuators.ravel()] = v_index.ravel() + nq
    motor = builder.AddNamedSystem("motor_model", MotorModel(
        params.motor, v_by_actuator, nx, scenario.motor_period_s))
    feet = builder.AddNamedSystem("foot_contact_forces", FootContactForces(
        [plant.GetBodyByName(f"{leg}_DE", instance).index() for leg in legs]))

    state = plant.get_state_output_port(instance)
    builder.Connect(gait.GetOutputPort("foot_targets"), controller.GetInputPort("foot_targets"))
    builder.Connect(gait.GetOutputPort("foot_velocities"),
                    controller.GetInputPort("foot_velocities"))
    builder.Connect(state, controller.GetInputPort("plant_state"))
    builder.Connect(controller.GetOutputPort("torque_command"), motor.GetInputPort("torque_command"))
    builder.Connect(state, motor.GetInputPort("plant_state"))
    builder.Connect(motor.GetOutputPort("applied_torque"), plant.get_actuation_input_port())
    builder.Connect(plant.get_contact_results_output_port(), feet.GetInputPort("contact_results"))

    period = scenario.log_period_s
    loggers = {
        "state": LogVectorOutput(state, builder),          # every plant step
        "command": LogVectorOutput(controller.GetOutputPort("torque_command"), builder, period),
        "applied": LogVectorOutput(motor.GetOutputPort("applied_torque"), builder, period),
        "saturated": LogVectorOutput(motor.GetOutputPort("saturated"), builder, period),
        "foot_forces": LogVectorOutput(feet.GetOutputPort("foot_forces"), builder, period),
    }
    for name, logger in loggers.items():
        logger.set_name(f"log_{name}")
    setup = Setup(plant=plant, instance=instance, legs=legs, indices=indices,
                  time_step_s=time_step, bushing=bushing, m_eff_kg=m_eff, loop_force_N=force,
                  loggers=loggers)
    return builder.Build(), setup


def standing_height(params: Params) -> float:
    """Body height (m) at which the feet, at (x_center, y_home), touch flat ground."""
    return params.body.foot_radius_m - params.gait.y_home_m - params.body.hip_z_m


def set_initial_state(context, setup: Setup, params: Params) -> None:
    """Standing pose, every loop closed exactly (closed-form IK), at rest, feet on the ground."""
    plant = setup.plant
    pc = plant.GetMyMutableContextFromRoot(context)
    foot = np.array([params.gait.x_center_m, params.gait.y_home_m])
    x = tree_positions(inverse(params.leg, foot))
    q = plant.GetPositions(pc)
    for leg in setup.legs:
        q[setup.indices[leg].q] = x
    plant.SetPositions(pc, q)
    plant.SetFreeBodyPose(pc, plant.GetBodyByName("body", setup.instance),
                          RigidTransform([0.0, 0.0, standing_height(params)]))


@dataclass
class SimResult:
    """Logged signals. t_state (steps) and state (steps, nx); t_log (samples) and per-sample
    command/applied/saturated (samples, 8, actuation order), foot_forces (samples, 4, 3) N world;
    wall time (s); error text if the run stopped early."""

    t_state: np.ndarray
    state: np.ndarray
    t_log: np.ndarray
    command: np.ndarray
    applied: np.ndarray
    saturated: np.ndarray
    foot_forces: np.ndarray
    wall_s: float
    error: str = ""


def simulate(scenario: Scenario, params: Params, progress=True):
    """Build and run the scenario; returns (SimResult, Setup). A failure mid-run keeps what was
    logged up to it (SimResult.error says what happened)."""
    diagram, setup = build_diagram(scenario, params)
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    set_initial_state(context, setup, params)
    simulator.Initialize()
    say = (lambda text: print(text, file=sys.stderr, flush=True)) if progress else (lambda text: None)
    say(f"simulating {scenario.duration_s:g} s, closure {scenario.closure}, "
        f"time step {setup.time_step_s * 1e3:.3f} ms")
    start, error = time.perf_counter(), ""
    chunk = max(scenario.duration_s / 20, 0.05)
    t = 0.0
    try:
        while t < scenario.duration_s - 1e-12:
            t = min(t + chunk, scenario.duration_s)
            simulator.AdvanceTo(t)
            wall = time.perf_counter() - start
            say(f"  t = {t:6.2f} s / {scenario.duration_s:g} s  ({t / wall:4.2f}x real time)")
            plant_state = setup.plant.GetPositionsAndVelocities(
                setup.plant.GetMyContextFromRoot(context))
            if not np.all(np.isfinite(plant_state)):
                raise RuntimeError(f"the plant state is not finite at t = {t:.3f} s (diverged)")
    except (RuntimeError, ValueError) as err:   # divergence, unreachable targets
        error = str(err)
        say(f"simulation stopped early: {error}")
    wall = time.perf_counter() - start
    logs = {name: logger.FindLog(context) for name, logger in setup.loggers.items()}
    n_log = min(logs[k].data().shape[1] for k in logs if k != "state")
    data = {k: logs[k].data()[:, :n_log].T for k in logs if k != "state"}
    result = SimResult(
        t_state=logs["state"].sample_times().copy(), state=logs["state"].data().T.copy(),
        t_log=logs["command"].sample_times()[:n_log].copy(),
        command=data["command"], applied=data["applied"], saturated=data["saturated"],
        foot_forces=data["foot_forces"].reshape(n_log, -1, 3), wall_s=wall, error=error)
    return result, setup
