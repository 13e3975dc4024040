"""Build the quadruped Diagram from a scenario and simulate it.

gait source -> leg controller -> motor model -> plant (+ scene graph), and a recorder that
measures every plant step and keeps the means of each log interval.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from pydrake.geometry import AddContactMaterial, Box, ProximityProperties
from pydrake.math import RigidTransform
from pydrake.multibody.plant import (AddMultibodyPlantSceneGraph, CoulombFriction,
                                     MultibodyPlantConfig, ApplyMultibodyPlantConfig)
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import DiscreteTimeIntegrator, Multiplexer, VectorLogSink

from .bushing import bushing_parameters, loop_load
from .dynamics import mass_matrix, physical_izz
from .files import say
from .footpath import stance_start
from .kinematics import inverse
from .params import ParameterError, Params, check_number, require
from .plant_model import add_model, leg_indices, loop_gaps, tree_positions
from .scenario import Scenario
from .sdf_model import body_height, hip_positions
from .rotation import tilt_deg
from .leg_control import ControlGains
from .systems import (FootLegController, GaitSource, MotorModel, RobotLayout, clip_flags,
                      derive_gains)

IMPLICIT_TIME_STEP_S = 1e-3   # plant step of the closures SAP treats implicitly
FALL_TILT_DEG = 45.0   # a body tilted further has fallen: the run stops
GROUND_SIZE_M = 40.0   # flat ground, top face at z = 0
GROUND_DEPTH_M = 1.0
SLICE_S = 0.01         # simulated time between checks for divergence and a stop request
PROGRESS_LINES = 20    # progress lines over a run
MAX_PLANT_STEPS = 20_000_000   # duration / time step: at ~0.3 ms of wall time per plant step
#                                (measured, 2 cores) about two hours
MIN_LOG_INTERVALS_PER_CYCLE = 100   # the statistics take peaks and percentiles of the recorded
#                                     interval means: coarser intervals smear a cycle's peaks
DIVERGED_GAP_M = 1e-3  # a loop open by more than this (1 % of a link) has come apart


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
    layout: RobotLayout
    gains: ControlGains
    recorder: VectorLogSink
    motor_log: VectorLogSink
    motor_samples_per_row: int
    controller: FootLegController
    actuation_log: VectorLogSink | None = None


def closure_parameters(scenario: Scenario, params: Params):
    """(time step s, Bushing or None, m_eff kg, loop force N) for the scenario's closure. The
    bushing's stiffness and damping come from the knee's effective mass, the loop force and the
    accepted gap (bushing.bushing_parameters); SAP treats the compliant "bushing" implicitly, so
    it runs at IMPLICIT_TIME_STEP_S, while the explicit "bushing_rpy" needs the step its
    stability bound allows."""
    m_eff, force = loop_load(params)
    if scenario.closure == "ball":
        return scenario.time_step_s or IMPLICIT_TIME_STEP_S, None, m_eff, force
    bushing, dt = bushing_parameters(m_eff, force, scenario.target_loop_gap_m)
    if scenario.closure == "bushing":
        return scenario.time_step_s or IMPLICIT_TIME_STEP_S, bushing, m_eff, force
    if scenario.time_step_s > dt:
        raise ParameterError(
            f"scenario.time_step_s = {scenario.time_step_s!r}: the explicit bushing (k = "
            f"{bushing.stiffness_N_m:.3g} N/m, m_eff = {m_eff * 1e3:.2f} g) is stable up to "
            f"{dt:.3g} s; use 0 (derived) or a smaller step, a larger target_loop_gap_m, or the "
            "implicit closure 'bushing'", "scenario.time_step_s")
    # the largest stable step that divides the log period, so every log interval has whole steps
    derived = scenario.log_period_s / math.ceil(scenario.log_period_s / dt - 1e-9)
    return scenario.time_step_s or derived, bushing, m_eff, force


def recorded_periods(scenario: Scenario, time_step: float) -> tuple[float, int]:
    """(the recorder's period s: whole plant steps of time_step s nearest log_period_s, the
    number of motor samples in it, rounded)."""
    log_period = time_step * max(1, round(scenario.log_period_s / time_step))
    return log_period, round(log_period / scenario.motor_period_s)


def check_run(scenario: Scenario, params: Params) -> float:
    """The plant's time step (s) for the scenario, after the checks that need the parameters
    and the step (ParameterError naming the field): the step against the motor model's period,
    the foot contact's time scale and the number of steps; the recorded interval against the
    step and the gait, the pose rate against the interval; the load transfer against the
    stance."""
    step = closure_parameters(scenario, params)[0]
    field = "scenario.time_step_s"
    derived = "" if scenario.time_step_s else f"; 0 derives {step:g} s for the closure"
    check_number(field, step, high=scenario.motor_period_s,
                 why="the plant steps at least as often as the motor model updates "
                     f"(scenario.motor_period_s), or its torques are skipped{derived}")
    check_number(field, step, high=params.body.foot_relaxation_time_s,
                 why="a touchdown must span more than one plant step: "
                     f"body.foot_relaxation_time_s is the foot contact's time scale{derived}")
    check_number(field, step, low=scenario.duration_s / MAX_PLANT_STEPS,
                 why=f"scenario.duration_s = {scenario.duration_s:g} s may take at most "
                     f"{MAX_PLANT_STEPS:g} plant steps (about two hours){derived}")
    period = params.gait.period_s
    check_number("scenario.log_period_s", scenario.log_period_s, step,
                 period / MIN_LOG_INTERVALS_PER_CYCLE,
                 why=f"at least one plant step and at least {MIN_LOG_INTERVALS_PER_CYCLE} "
                     f"intervals per gait cycle of {period:g} s")
    check_number("scenario.pose_rate_hz", scenario.pose_rate_hz, high=1.0 / scenario.log_period_s,
                 why="poses are taken from the recorded intervals: at most 1 / log_period_s")
    log_period, per_row = recorded_periods(scenario, step)
    require(per_row >= 1 and math.isclose(per_row * scenario.motor_period_s, log_period,
                                          rel_tol=1e-9),
            "scenario.log_period_s", scenario.log_period_s,
            f"the recorder logs every {log_period:.6g} s (whole plant steps of {step:.6g} s), "
            f"which must be a whole number of motor periods (scenario.motor_period_s = "
            f"{scenario.motor_period_s:g} s): the motor's samples are averaged per interval")
    stance_s = (1.0 - stance_start(params.gait, scenario.gait)) * period
    check_number("scenario.load_transfer_s", scenario.load_transfer_s, high=stance_s / 2,
                 why=f"a foot must take up its load and give it off within its stance of "
                     f"{stance_s:g} s")
    return step


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
        q_index=np.array([indices[leg].q[:2] for leg in legs]),
        v_index=np.array([indices[leg].v[:2] for leg in legs]),
        actuators=np.array([indices[leg].actuators for leg in legs]),
        body_q=body.floating_positions_start(), body_v=body.floating_velocities_start_in_v(),
        nq=plant.num_positions(), nx=plant.num_multibody_states(),
        hips_m=np.array([hip_positions(params)[leg] for leg in legs]), com_m=np.asarray(com),
        mass_kg=spatial.get_mass(), inertia_kg_m2=inertia)


def controller_gains(scenario: Scenario, params: Params, layout: RobotLayout) -> ControlGains:
    """Gains from the robot's numbers: the swing joint's inertia is the largest diagonal entry
    of the leg's mass matrix at home plus the reflected rotor inertia (systems.derive_gains)."""
    home = inverse(params.leg, np.array([params.gait.x_center_m, params.gait.y_home_m]))
    leg_inertia = (np.max(np.diag(mass_matrix(params, physical_izz(params), home)))
                   + params.motor.reflected_inertia_kg_m2)
    return derive_gains(layout.mass_kg, layout.inertia_kg_m2, leg_inertia,
                        scenario.swing_bandwidth_hz, scenario.body_bandwidth_hz,
                        scenario.damping_ratio)


def add_robot(builder: DiagramBuilder, params: Params, closure: str, bushing, time_step: float):
    """Add the finalized quadruped plant (SAP, closed loops) and flat ground to builder;
    returns (plant, model instance, leg names)."""
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step)
    # unsampled output ports: a block updating at tick t reads the state at t, as a driver would
    ApplyMultibodyPlantConfig(MultibodyPlantConfig(
        time_step=time_step, discrete_contact_approximation="sap",
        use_sampled_output_ports=False), plant)
    instance, legs = add_model(plant, params, "quadruped", closure, bushing)
    ground = ProximityProperties()
    mu = params.body.foot_friction
    AddContactMaterial(friction=CoulombFriction(mu, mu), properties=ground)
    plant.RegisterCollisionGeometry(plant.world_body(), RigidTransform([0, 0, -GROUND_DEPTH_M / 2]),
                                    Box(GROUND_SIZE_M, GROUND_SIZE_M, GROUND_DEPTH_M), "ground",
                                    ground)
    plant.Finalize()
    return plant, instance, legs


def build_diagram(scenario: Scenario, params: Params, log_actuation: bool = False):
    """Assemble the Diagram for the scenario; returns (diagram, Setup). log_actuation: also log
    the joint torques the plant receives at every step (Setup.actuation_log), to replay the run
    on the plant alone."""
    time_step, bushing, m_eff, force = closure_parameters(scenario, params)
    builder = DiagramBuilder()
    plant, instance, legs = add_robot(builder, params, scenario.closure, bushing, time_step)
    indices = {leg: leg_indices(plant, instance, leg) for leg in legs}
    layout = robot_layout(plant, instance, legs, params)
    gains = controller_gains(scenario, params, layout)

    gait = builder.AddNamedSystem("gait_source", GaitSource(
        params.gait, scenario.gait, scenario.phases_rad, scenario.stand_s, scenario.ramp_s,
        scenario.load_transfer_s, scenario.control_period_s))
    controller = builder.AddNamedSystem("leg_controller", FootLegController(
        params, layout, gains, scenario.control_period_s, scenario.control_delay_periods,
        scenario.catch_gain, scenario.catch_rate_s, scenario.touchdown_detection))
    speed_index = np.zeros(plant.num_actuators(), dtype=int)    # joint speed of each actuator
    speed_index[layout.actuators.ravel()] = layout.v_index.ravel() + layout.nq
    motor = builder.AddNamedSystem("motor_model", MotorModel(
        params.motor, speed_index, layout.nx, scenario.motor_period_s))
    # every plant step counted in C++: the integral of the contact forces; one row per log
    # interval (the plant state and that integral at its end); the motor's held values once
    # per motor sample (they are constant in between)
    n_act, nv = plant.num_actuators(), plant.num_velocities()
    integrator = builder.AddNamedSystem("contact_integral", DiscreteTimeIntegrator(nv, time_step))
    rows = builder.AddNamedSystem("rows", Multiplexer([layout.nx, nv]))
    log_period, per_row = recorded_periods(scenario, time_step)
    recorder = builder.AddNamedSystem("recorder", VectorLogSink(layout.nx + nv, log_period))
    motor_log = builder.AddNamedSystem("motor_log", VectorLogSink(3 * n_act,
                                                                  scenario.motor_period_s))

    state = plant.get_state_output_port(instance)
    builder.Connect(gait.GetOutputPort("foot_references"), controller.GetInputPort("foot_references"))
    builder.Connect(state, controller.GetInputPort("plant_state"))
    builder.Connect(controller.GetOutputPort("torque_command"), motor.GetInputPort("torque_command"))
    builder.Connect(state, motor.GetInputPort("plant_state"))
    builder.Connect(motor.GetOutputPort("applied_torque"), plant.get_actuation_input_port())
    builder.Connect(plant.get_generalized_contact_forces_output_port(instance),
                    integrator.get_input_port())
    builder.Connect(motor.GetOutputPort("motor_record"), motor_log.get_input_port())
    builder.Connect(state, rows.get_input_port(0))
    builder.Connect(integrator.get_output_port(), rows.get_input_port(1))
    builder.Connect(rows.get_output_port(), recorder.get_input_port())
    actuation_log = None
    if log_actuation:
        actuation_log = builder.AddNamedSystem("actuation_log", VectorLogSink(n_act, time_step))
        builder.Connect(motor.GetOutputPort("applied_torque"), actuation_log.get_input_port())
    setup = Setup(plant=plant, instance=instance, legs=legs, indices=indices,
                  time_step_s=time_step, bushing=bushing, m_eff_kg=m_eff, loop_force_N=force,
                  layout=layout, gains=gains, recorder=recorder, motor_log=motor_log,
                  motor_samples_per_row=per_row, controller=controller,
                  actuation_log=actuation_log)
    return builder.Build(), setup


def standing_height(params: Params) -> float:
    """Body height (m) at which the feet, at (x_center, y_home), touch flat ground."""
    return float(body_height(params, params.gait.y_home_m))


def set_standing_pose(plant, context, instance, legs, params: Params) -> None:
    """Standing pose in a plant context: every loop closed exactly (closed-form IK), at rest,
    feet at (x_center, y_home) on the ground."""
    foot = np.array([params.gait.x_center_m, params.gait.y_home_m])
    x = tree_positions(inverse(params.leg, foot))
    q = plant.GetPositions(context)
    for leg in legs:
        q[leg_indices(plant, instance, leg).q] = x
    plant.SetPositions(context, q)
    plant.SetFreeBodyPose(context, plant.GetBodyByName("body", instance),
                          RigidTransform([0.0, 0.0, standing_height(params)]))


def interval_table(setup: Setup, params: Params, context) -> dict:
    """The recorder's rows as one row per log interval (arrays, SI): t (s, the interval's end),
    state (nx) at t, gap (legs) m at t, and the interval means of the joint speeds of the
    actuators (rad/s, from the positions: the discrete plant moves them with each step's end
    speed), the generalized contact forces (nv; J^T F of every contact, every plant step), the
    command, the motor's delivered torque and the torque applied to the joints (n, N*m) and the
    clip flags (n, fraction of the motor samples; systems.clip_flags). context: the simulated
    Diagram's root context."""
    log = setup.recorder.FindLog(context)
    lay = setup.layout
    times, data = log.sample_times(), log.data().T
    states, integrals = data[:, :lay.nx], data[:, lay.nx:]
    dt = np.diff(times)[:, None]
    q_act = np.zeros((len(times), lay.q_index.size))
    q_act[:, lay.actuators.ravel()] = states[:, lay.q_index.ravel()]
    tree_q = np.array([setup.indices[leg].q for leg in setup.legs])
    # the motor's samples in each interval: those from its start up to before its end
    motor = setup.motor_log.FindLog(context)
    rows = len(times) - 1
    per_row = setup.motor_samples_per_row
    samples = motor.data().T[:rows * per_row].reshape(rows, per_row, 3, -1)
    command, delivered, applied = (samples[:, :, i] for i in range(3))
    at_peak, at_line = clip_flags(params.motor, command, delivered)
    return {"t": times[1:], "state": states[1:],
            "gap": loop_gaps(params, states[1:, tree_q]).reshape(len(dt), -1),
            "speed": np.diff(q_act, axis=0) / dt,
            "contact_generalized": np.diff(integrals, axis=0) / dt,
            "command": command.mean(1), "motor_torque": delivered.mean(1),
            "applied": applied.mean(1), "clipped_peak": at_peak.mean(1),
            "clipped_line": at_line.mean(1)}


@dataclass
class SimResult:
    """What the recorder measured (interval_table: t, state, gap, speed, contact_generalized,
    command, motor_torque, applied, clipped_peak, clipped_line), wall time (s), the error text
    if the run stopped early, the signal that stopped it ("SIGINT", "SIGTERM"; "" if none), and
    with log_actuation the times (steps,) s and joint torques (steps, n) N*m the plant received
    at every step."""

    table: dict
    wall_s: float
    error: str = ""
    actuation: tuple | None = None
    interrupted: str = ""


def simulate(scenario: Scenario, params: Params, progress=True, log_actuation=False,
             stop: Callable[[], str] | None = None):
    """Check (check_run), build and run the scenario; returns (SimResult, Setup). A failure
    mid-run keeps what was logged up to it (SimResult.error says what happened, for a divergence
    with its likely cause). stop: polled every SLICE_S of simulated time; a non-empty answer
    (the name of a signal) ends the run there (SimResult.interrupted). log_actuation: see
    build_diagram."""
    check_run(scenario, params)
    diagram, setup = build_diagram(scenario, params, log_actuation)
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    set_standing_pose(setup.plant, setup.plant.GetMyMutableContextFromRoot(context),
                      setup.instance, setup.legs, params)
    simulator.Initialize()
    # every discrete update once, outside the timing: loads (or on a first run compiles) the
    # compiled kernels
    diagram.CalcForcedDiscreteVariableUpdate(context, diagram.AllocateDiscreteVariables())
    tell = (lambda text: say(text, sys.stderr)) if progress else (lambda text: None)
    duration = scenario.duration_s
    tell(f"simulating {duration:g} s, closure {scenario.closure}, "
         f"time step {setup.time_step_s * 1e3:.3f} ms")
    start, error, interrupted = time.perf_counter(), "", ""
    slices = max(1, math.ceil(duration / SLICE_S - 1e-9))
    every = max(1, slices // PROGRESS_LINES)
    try:
        for k in range(1, slices + 1):
            t = min(k * SLICE_S, duration)
            simulator.AdvanceTo(t)
            plant_state = setup.plant.GetPositionsAndVelocities(
                setup.plant.GetMyContextFromRoot(context))
            if not np.all(np.isfinite(plant_state)):
                raise RuntimeError("the plant state is not finite")
            tilt = tilt_deg(plant_state[setup.layout.body_q:setup.layout.body_q + 4])
            if tilt > FALL_TILT_DEG:
                raise ValueError(f"the robot fell over: tilt {tilt:.0f} deg")
            interrupted = stop() if stop else ""
            if interrupted:
                tell(f"{interrupted} received: stopped at t = {t:.2f} s; writing what was "
                     "simulated")
                break
            if k % every == 0 or k == slices:
                wall = time.perf_counter() - start
                tell(f"  t = {t:6.2f} s / {duration:g} s  ({t / wall:4.2f}x real time)")
    except RuntimeError as err:   # Drake's own errors: a divergence
        error = divergence(str(err), context.get_time(), scenario, params, setup,
                           interval_table(setup, params, context))
    except ValueError as err:     # a fall, an unreachable target
        error = f"{err} (t = {context.get_time():.3f} s)"
    if error:
        tell(f"simulation stopped early: {error}")
    wall = time.perf_counter() - start
    actuation = None
    if setup.actuation_log is not None:
        log = setup.actuation_log.FindLog(context)
        actuation = (log.sample_times(), log.data().T)
    return SimResult(table=interval_table(setup, params, context), wall_s=wall, error=error,
                     actuation=actuation, interrupted=interrupted), setup


def divergence(message: str, t: float, scenario: Scenario, params: Params, setup: Setup,
               table: dict) -> str:
    """What diverged, when and its likely cause in this tool's terms, from the last recorded
    intervals before the failure (Drake's message at the end)."""
    finite = np.all(np.isfinite(table["state"]), axis=1)
    first_bad = len(finite) if finite.all() else int(np.argmin(finite))
    recent = {k: v[max(0, first_bad - 10):first_bad] for k, v in table.items()}
    drake = message.strip().splitlines()[0] if message.strip() else "no message"
    head = f"the simulation diverged at t = {t:.3f} s"
    step = f"scenario.time_step_s = {setup.time_step_s:g} s"
    if not len(recent["t"]):
        return f"{head} at its start ({drake}); check the time step ({step}) and the gains"
    gap = recent["gap"].max(axis=0)
    height = recent["state"][:, setup.layout.body_q + 6]
    speed = np.abs(recent["speed"]).max()
    clipped = float(np.mean(recent["clipped_peak"] + recent["clipped_line"]))
    if gap.max() > DIVERGED_GAP_M:
        leg = setup.legs[int(np.argmax(gap))]
        what = (f"the loop of leg {leg} came apart (gap {gap.max() * 1e3:.2f} mm); likely cause: "
                f"{step} is too coarse for the {scenario.closure} closure's stiffness: use a "
                "smaller time step, a larger target_loop_gap_m, or the closure 'bushing'")
    elif height.min() < params.body.height_m / 2:
        what = (f"the body sank to {height.min() * 1e3:.0f} mm, into the ground; likely cause: "
                f"{step} is too coarse for the foot contact (body.foot_stiffness_N_m, "
                "foot_relaxation_time_s): use a smaller time step")
    elif speed > params.motor.no_load_speed_rad_s or clipped > 0.5:
        what = (f"the motors could not follow (joint speed {speed:.1f} rad/s against the "
                f"no-load {params.motor.no_load_speed_rad_s:.1f} rad/s, torque clipped "
                f"{clipped:.0%} of the last intervals); likely cause: the gait is too fast for "
                "the motors: lower gait_frequency_hz or the stride gait_a_m")
    else:
        what = (f"no loop came apart, the body stayed above the ground and the motors within "
                f"their limits; likely cause: the controller's gains (swing_bandwidth_hz = "
                f"{scenario.swing_bandwidth_hz:g}, body_bandwidth_hz = "
                f"{scenario.body_bandwidth_hz:g}, damping_ratio = {scenario.damping_ratio:g}) "
                f"at control_period_s = {scenario.control_period_s:g} s: lower the bandwidths")
    return f"{head}: {what} (Drake: {drake})"
