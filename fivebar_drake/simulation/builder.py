"""Assemble the quadruped Diagram from a scenario: closure parameters and run checks, controller
gains, gait source -> leg controller -> motor model -> plant, and the recorders."""

from __future__ import annotations

import math
from dataclasses import dataclass
import numpy as np
from pydrake.multibody.plant import ApplyMultibodyPlantConfig, MultibodyPlant
from pydrake.systems.framework import DiagramBuilder, TriggerType, LeafSystem
from pydrake.systems.primitives import (DiscreteTimeDelay, DiscreteTimeIntegrator, Multiplexer,
                                        VectorLogSink)

from fivebar_drake.core.drake_configs import check_plant_config_values, config_with
from fivebar_drake.core.validation import ParameterError, check_number, require
from fivebar_drake.mechanisms.fivebar import UnreachableError
from fivebar_drake.robots.quadruped.closure import design_closure
from fivebar_drake.robots.quadruped.config import check_path
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import ClosureDesign, Modifiers, RobotLayout, add_robot
from fivebar_drake.simulation.gait_source import GaitSource
from fivebar_drake.simulation.motor_model import MotorModel
from fivebar_drake.simulation.scenario import Scenario


SAP_APPROXIMATIONS = ("sap", "lagged", "similar")   # Drake's approximations solved by SAP
PERIODIC = {TriggerType.kPeriodic}   # the logs: periodic rows only, whatever the simulator
#                                     publishes (SimulatorConfig.publish_every_time_step)
MAX_PLANT_STEPS = 20_000_000   # duration / time step: at ~0.3 ms of wall time per plant step
#                                (measured, 2 cores) about two hours
MIN_LOG_INTERVALS_PER_CYCLE = 100   # the statistics take peaks and percentiles of the recorded
#                                     interval means: coarser intervals smear a cycle's peaks
MAX_EVENT_STEPS = 500_000   # a one-shot maneuver keeps every plant step's state and contact
#                             forces for its event figures (~0.5 kB a step): 500 s at 1 ms


@dataclass
class Setup:
    """What the builder made: the plant and its model instance, the plain-data layout, the
    closure design it was built with, the controller's gains and the blocks the runner reads."""

    plant: object
    instance: object
    layout: RobotLayout
    design: ClosureDesign
    gains: tuple | None
    recorder: VectorLogSink
    motor_log: VectorLogSink
    motor_samples_per_row: int
    controller: LeafSystem
    actuation_log: VectorLogSink | None = None
    step_log: VectorLogSink | None = None


def closure_design(scenario: Scenario, params: Params) -> ClosureDesign:
    """The scenario's loop closure, designed before assembly (closure.design_closure)."""
    return design_closure(params, scenario.closure, scenario.target_loop_gap_m,
                          scenario.time_step_s, scenario.log_period_s)


def recorded_periods(scenario: Scenario, time_step: float) -> tuple[float, int]:
    """(the recorder's period s: whole plant steps of time_step s nearest log_period_s, the
    number of motor samples in it, rounded)."""
    log_period = time_step * max(1, round(scenario.log_period_s / time_step))
    return log_period, round(log_period / scenario.motor_period_s)


def check_plant_config(scenario: Scenario, time_step: float) -> None:
    """scenario.plant_config fits this robot and the closure (ParameterError naming the field):
    its time step is the closure's, the output ports unsampled (the controller and the motor
    model read the state at their tick), a SAP solver for the SAP constraint closures, and
    Drake accepts it."""
    config, field = scenario.plant_config, "scenario.plant_config"
    check_plant_config_values(config, field)
    require(config.time_step == 0.0, f"{field}.time_step", config.time_step,
            "must be 0: the plant's step is scenario.time_step_s (0 = derived for the closure)")
    require(not config.use_sampled_output_ports, f"{field}.use_sampled_output_ports", True,
            "must be false: the controller and the motor model read the state at their tick")
    if scenario.closure.sap:
        require(config.discrete_contact_approximation in SAP_APPROXIMATIONS,
                f"{field}.discrete_contact_approximation", config.discrete_contact_approximation,
                f"the '{scenario.closure}' closure is a SAP constraint: use one of "
                f"{list(SAP_APPROXIMATIONS)} (another solver would ignore it)")
    try:
        ApplyMultibodyPlantConfig(config_with(config, time_step=time_step),
                                  MultibodyPlant(time_step))
    except (RuntimeError, ValueError) as err:
        raise ParameterError(f"{field}: Drake refuses it: {err}", field) from None


def check_run(scenario: Scenario, params: Params) -> ClosureDesign:
    """The scenario's closure design (closure_design), after the checks that need the
    parameters and the plant's step (ParameterError naming the field): the step against the
    motor model's period, the foot contact's time scale and the number of steps; the recorded
    interval against the step and the gait, the pose rate against the interval; the load
    transfer against the stance; the scenario's foot path (with its own fields) in the workspace
    and within the leg's limits."""
    check_path(params, scenario.gait)
    design = closure_design(scenario, params)
    step = design.time_step_s
    check_plant_config(scenario, step)
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
    if not scenario.gait.periodic:
        check_number(field, step, low=scenario.duration_s / MAX_EVENT_STEPS,
                     why=f"a one-shot maneuver keeps every plant step for its event figures: "
                         f"scenario.duration_s = {scenario.duration_s:g} s may take at most "
                         f"{MAX_EVENT_STEPS:g} of them{derived}")
    period = scenario.gait.span_s(params.gait)
    check_number("scenario.log_period_s", scenario.log_period_s, step,
                 period / MIN_LOG_INTERVALS_PER_CYCLE,
                 why=f"at least one plant step and at least {MIN_LOG_INTERVALS_PER_CYCLE} "
                     f"intervals per gait cycle (or maneuver) of {period:g} s")
    check_number("scenario.pose_rate_hz", scenario.pose_rate_hz, high=1.0 / scenario.log_period_s,
                 why="poses are taken from the recorded intervals: at most 1 / log_period_s")
    log_period, per_row = recorded_periods(scenario, step)
    require(per_row >= 1 and math.isclose(per_row * scenario.motor_period_s, log_period,
                                          rel_tol=1e-9),
            "scenario.log_period_s", scenario.log_period_s,
            f"the recorder logs every {log_period:.6g} s (whole plant steps of {step:.6g} s), "
            f"which must be a whole number of motor periods (scenario.motor_period_s = "
            f"{scenario.motor_period_s:g} s): the motor's samples are averaged per interval")
    if scenario.gait.periodic:       # a maneuver's feet switch at its events, not smoothly
        stance_s = (1.0 - scenario.gait.stance_start(params.gait)) * period
        check_number("scenario.load_transfer_s", scenario.load_transfer_s, high=stance_s / 2,
                     why=f"a foot must take up its load and give it off within its stance of "
                         f"{stance_s:g} s")
    check_start_pose(scenario, params)
    return design


def check_start_pose(scenario: Scenario, params: Params) -> None:
    """The foot path's start (FootPath.home, the maneuvers' first point) is in the legs' reach,
    on the forward kinematics' branch (ParameterError naming scenario.gait)."""
    home = scenario.gait.home(params.gait)
    leg = params.fivebar_leg
    try:
        again = leg.forward(leg.inverse(home).q).f
    except UnreachableError as err:
        raise ParameterError(f"scenario.gait = {scenario.gait}: its start, the foot at "
                             f"({home[0]:g}, {home[1]:g}) m, is out of the legs' reach: {err}",
                             "scenario.gait") from None
    require(np.allclose(again, home, atol=1e-9), "scenario.gait", str(scenario.gait),
            f"its start, the foot at ({home[0]:g}, {home[1]:g}) m, folds the leg past the "
            "forward kinematics' branch (E above its lower circle intersection) the controller "
            "reads the legs with: start lower or further out")


def add_contact_integral(builder: DiagramBuilder, plant, instance, layout: RobotLayout,
                         time_step: float) -> DiscreteTimeIntegrator:
    """Add the integral of the plant's generalized contact forces over every plant step (C++):
    what the recorders average per interval and the controller per tick."""
    integrator = builder.AddNamedSystem("contact_integral",
                                        DiscreteTimeIntegrator(layout.nv, time_step))
    builder.Connect(plant.get_generalized_contact_forces_output_port(instance),
                    integrator.get_input_port())
    return integrator


def actuator_speeds(layout: RobotLayout) -> np.ndarray:
    """Each actuator's joint speed as its index in the plant state (actuation order)."""
    index = np.zeros(layout.state.actuators.size, dtype=int)
    index[layout.state.actuators.ravel()] = layout.state.v_index.ravel() + layout.state.nq
    return index


def add_controller(builder: DiagramBuilder, scenario: Scenario, params: Params, plant,
                   instance, layout: RobotLayout, contact: DiscreteTimeIntegrator,
                   time_step: float) -> tuple[LeafSystem, MotorModel]:
    """Add gait source -> leg controller (-> Drake's DiscreteTimeDelay of its
    control_delay_periods) -> motor model -> the plant's actuation (the controller variant adds
    its own block: Controller.add_to), the controller and the motor model
    sampling the plant state, the controller the contact integral if it has that input, the
    motor model keeping its memory at every plant step of time_step (s);
    returns (controller, motor model)."""
    gait = GaitSource.add_to(builder, params.gait, scenario.gait, scenario.phases_rad,
                             scenario.stand_s, scenario.ramp_s, scenario.load_transfer_s)
    controller = scenario.controller.add_to(builder, params, layout, scenario)
    motor = builder.AddNamedSystem("motor_model", MotorModel(
        params.motor, actuator_speeds(layout), layout.nx, scenario.motor_period_s, time_step))
    state = plant.get_state_output_port(instance)
    builder.Connect(gait.GetOutputPort("foot_references"),
                    controller.GetInputPort("foot_references"))
    builder.Connect(state, controller.GetInputPort("plant_state"))
    if controller.HasInputPort("contact_impulse"):
        builder.Connect(contact.get_output_port(), controller.GetInputPort("contact_impulse"))
    command = controller.GetOutputPort("torque_command")
    delay = scenario.controller.control_delay_periods
    if delay:   # its sample at a tick is the command of the tick before: one period already
        held = builder.AddNamedSystem("control_delay", DiscreteTimeDelay(
            scenario.controller.control_period_s, delay - 1, command.size()))
        builder.Connect(command, held.get_input_port())
        command = held.get_output_port()
    builder.Connect(command, motor.GetInputPort("torque_command"))
    builder.Connect(state, motor.GetInputPort("plant_state"))
    builder.Connect(motor.GetOutputPort("applied_torque"), plant.get_actuation_input_port())
    return controller, motor


def add_recorders(builder: DiagramBuilder, scenario: Scenario, plant, instance,
                  layout: RobotLayout, motor: MotorModel, time_step: float,
                  integrator: DiscreteTimeIntegrator):
    """Add the measurements, all in C++: one row per log interval (the plant state and the
    contact integral at its end); the motor's held values once per motor sample (constant in
    between); for a one-shot maneuver the same row at every plant step (its event figures).
    Returns (recorder, motor log, motor samples per row, step log or None)."""
    rows = builder.AddNamedSystem("rows", Multiplexer([layout.nx, layout.nv]))
    log_period, per_row = recorded_periods(scenario, time_step)
    recorder = builder.AddNamedSystem("recorder", VectorLogSink(
        layout.nx + layout.nv, PERIODIC, log_period))
    motor_log = builder.AddNamedSystem("motor_log", VectorLogSink(
        3 * layout.state.actuators.size, PERIODIC, scenario.motor_period_s))
    builder.Connect(motor.GetOutputPort("motor_record"), motor_log.get_input_port())
    builder.Connect(plant.get_state_output_port(instance), rows.get_input_port(0))
    builder.Connect(integrator.get_output_port(), rows.get_input_port(1))
    builder.Connect(rows.get_output_port(), recorder.get_input_port())
    step_log = None
    if not scenario.gait.periodic:
        step_log = builder.AddNamedSystem("step_log", VectorLogSink(
            layout.nx + layout.nv, PERIODIC, time_step))
        builder.Connect(rows.get_output_port(), step_log.get_input_port())
    return recorder, motor_log, per_row, step_log


def build_diagram(scenario: Scenario, params: Params, design: ClosureDesign,
                  log_actuation: bool = False):
    """Assemble the Diagram for the scenario with its closure designed beforehand (check_run,
    closure_design): the robot, the controller, the recorders. Returns (diagram, Setup).
    log_actuation: also log the joint torques the plant receives at every step
    (Setup.actuation_log), to replay the run on the plant alone."""
    builder = DiagramBuilder()
    plant, instance, layout = add_robot(builder, params, design, scenario.plant_config,
                                        Modifiers(scenario.payload_kg,
                                                  tuple(scenario.payload_offset_m),
                                                  math.radians(scenario.slope_deg)))
    contact = add_contact_integral(builder, plant, instance, layout, design.time_step_s)
    controller, motor = add_controller(builder, scenario, params, plant, instance, layout,
                                       contact, design.time_step_s)
    recorder, motor_log, per_row, step_log = add_recorders(
        builder, scenario, plant, instance, layout, motor, design.time_step_s, contact)
    actuation_log = None
    if log_actuation:
        actuation_log = builder.AddNamedSystem("actuation_log", VectorLogSink(
            layout.state.actuators.size, PERIODIC, design.time_step_s))
        builder.Connect(motor.GetOutputPort("applied_torque"), actuation_log.get_input_port())
    setup = Setup(plant=plant, instance=instance, layout=layout, design=design,
                  gains=getattr(controller, "gains", None), recorder=recorder, motor_log=motor_log,
                  motor_samples_per_row=per_row, controller=controller,
                  actuation_log=actuation_log, step_log=step_log)
    return builder.Build(), setup
