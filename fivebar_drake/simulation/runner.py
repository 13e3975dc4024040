"""Run a scenario: load it with its parameters, simulate with progress, stop requests and divergence
diagnosis, and turn the recorders into one row per log interval of a plain-data SimulationRecord
(no Drake object: it pickles, so it can cross a process boundary)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
import sys
import time
from typing import Callable
import numpy as np
from pydrake.systems.analysis import ApplySimulatorConfig, Simulator

from fivebar_drake.core.files import say
from fivebar_drake.core.progress import Progress
from fivebar_drake.actuators.motor import clip_flags
from fivebar_drake.core.rotation import tilt_deg
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.optimal.top_speed import top_speed
from fivebar_drake.robots.quadruped.control_law import ControlGains
from fivebar_drake.robots.quadruped.config import with_path_defaults
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import ClosureDesign, RobotLayout, set_standing_pose
from fivebar_drake.simulation.builder import (MIN_LOG_INTERVALS_PER_CYCLE, Setup, build_diagram,
                                             check_run)
from fivebar_drake.simulation.scenario import Scenario, load_scenario, source_of


def load_run(path: "str | Path | None" = None, **overrides) -> tuple[Scenario, Params]:
    """load_scenario, the scenario's parameters, and every check before a run
    (builder.check_run); errors name their file or the command line."""

    scenario = load_scenario(path, **overrides)
    given = {k: v for k, v in overrides.items() if v is not None}
    try:
        scenario, params = at_top_speed(scenario, scenario.load_params())
        check_run(scenario, params)
    except ParameterError as err:
        if path and scenario.params_file and "params_file" not in given \
                and err.source == scenario.params_file:
            err = ParameterError(f"{err.message} (the params_file of {path})", err.field,
                                 err.source)
        raise err.located(source_of(err, path, given)) from None
    return scenario, params

def at_top_speed(scenario: Scenario, params: Params) -> tuple[Scenario, Params]:
    """A scenario whose gait runs at its top speed (Scenario.top_speed) as the optimum's path
    (optimal/top_speed.py on params and the scenario's payload, over the path's own duty factor
    where it has one: its duty factor and swing shape at its stride and frequency, the frequency
    times Scenario.top_speed_share), its load
    transfer at most a quarter of the stance and its recording's interval at most
    1/MIN_LOG_INTERVALS_PER_CYCLE of the period (the statistics' least; 1 ms at the least:
    beyond 10 Hz ParameterError); with the design at that gait. Any other scenario as it is.
    ParameterError where no speed of the gait passes, naming why."""
    if not scenario.top_speed:
        return scenario, params
    duty = scenario.gait.duty_factor
    found = top_speed(params, scenario.gait.kind, scenario.payload_kg,
                      duties=None if duty is None else (duty,))
    if not math.isfinite(found.speed_m_s):
        raise ParameterError(f"no {found.kind} at any speed: {found.limited_by}",
                             "scenario.gait.speed_m_s")
    frequency = found.frequency_hz * scenario.top_speed_share
    period = 1.0 / frequency
    gait = {"a_m": found.stride_m / 2.0, "frequency_hz": frequency}
    resolved = scenario.replaced(
        gait=found.path, top_speed=False, top_speed_share=1.0,
        load_transfer_s=min(scenario.load_transfer_s, 0.25 * found.duty_factor * period),
        log_period_s=max(0.001, min(scenario.log_period_s,
                                    math.floor(period / MIN_LOG_INTERVALS_PER_CYCLE * 1e3) / 1e3)),
        **{f"gait_{k}": v for k, v in gait.items()})
    resolved.validate()
    return resolved, with_path_defaults(params, found.path, **gait)


FALL_TILT_DEG = 45.0   # a body tilted further has fallen: the run stops
FELL_OVER = "the robot fell over"   # the start of a fallen run's error
SLICE_S = 0.01         # simulated time between checks for divergence and a stop request
DIVERGED_GAP_M = 1e-3  # a loop open by more than this (1 % of a link) has come apart


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
    # copies: the log's arrays are views into the Drake log, which the record must not hold
    times, data = log.sample_times().copy(), log.data().T.copy()
    states, integrals = data[:, :lay.nx], data[:, lay.nx:]
    dt = np.diff(times)[:, None]
    q_act = np.zeros((len(times), lay.state.q_index.size))
    q_act[:, lay.state.actuators.ravel()] = states[:, lay.state.q_index.ravel()]
    tree_q = np.array([lay.indices[leg].q for leg in lay.legs])
    # the motor's samples in each interval: those from its start up to before its end
    motor = setup.motor_log.FindLog(context)
    rows = len(times) - 1
    per_row = setup.motor_samples_per_row
    samples = motor.data().T[:rows * per_row].copy().reshape(rows, per_row, 3, -1)
    command, delivered, applied = (samples[:, :, i] for i in range(3))
    at_peak, at_line = clip_flags(params.motor, command, delivered)
    return {"t": times[1:], "state": states[1:],
            "gap": params.fivebar_leg.loop_gaps(states[1:, tree_q]).reshape(len(dt), -1),
            "speed": np.diff(q_act, axis=0) / dt,
            "contact_generalized": np.diff(integrals, axis=0) / dt,
            "command": command.mean(1), "motor_torque": delivered.mean(1),
            "applied": applied.mean(1), "clipped_peak": at_peak.mean(1),
            "clipped_line": at_line.mean(1)}


def step_table(setup: Setup, context) -> dict | None:
    """A one-shot maneuver's plant steps (None without the step log): t (steps,) s, the state
    (steps, nx) at each step's end and the step's generalized contact forces (steps, nv; the
    contact integral's change over the step / its length); the motor's samples: motor_t
    (samples,) s, the command it took and the torque it delivered (samples, n) N*m, held until
    the next sample."""
    if setup.step_log is None:
        return None
    log = setup.step_log.FindLog(context)
    times, data = log.sample_times().copy(), log.data().T.copy()
    nx = setup.layout.nx
    motor = setup.motor_log.FindLog(context)
    n = setup.layout.state.actuators.size
    return {"t": times[1:], "state": data[1:, :nx],
            "contact_generalized": np.diff(data[:, nx:], axis=0) / np.diff(times)[:, None],
            "motor_t": motor.sample_times().copy(), "motor_command": motor.data().T[:, :n].copy(),
            "motor_torque": motor.data().T[:, n:2 * n].copy()}


@dataclass(frozen=True)
class SimulationRecord:
    """A simulated run as plain data (numpy arrays and dataclasses, no Drake object), all that
    post-processing needs: the scenario and parameters it ran with, the plant's layout
    (RobotLayout: legs, joint and state indices, hips, mass properties), the closure design
    (ClosureDesign: time step s, bushing), the controller gains (ControlGains, SI; None for a controller without); the
    recorder's table (interval_table: one row per log interval, SI); the wall time of the
    stepping (s); the error text if the run stopped early ("" if not), the signal that stopped
    it ("SIGINT", "SIGTERM"; "" if none); with log_actuation the times (steps,) s and joint
    torques (steps, n) N*m in actuation order the plant received at every step, else None;
    for a one-shot maneuver its plant steps (step_table), else None."""

    scenario: Scenario
    params: Params
    layout: RobotLayout
    design: ClosureDesign
    gains: ControlGains | None
    table: dict[str, np.ndarray]
    wall_s: float
    error: str = ""
    interrupted: str = ""
    actuation: tuple[np.ndarray, np.ndarray] | None = None
    steps: dict[str, np.ndarray] | None = None

    @property
    def completed(self) -> bool:
        """The run reached its requested duration (neither stopped early nor interrupted)."""
        return not self.error and not self.interrupted


def simulate(scenario: Scenario, params: Params, progress=True, log_actuation=False,
             stop: Callable[[], str] | None = None) -> SimulationRecord:
    """Check (check_run), build and run the scenario; returns its SimulationRecord. A failure
    mid-run keeps what was logged up to it (SimulationRecord.error says what happened, for a
    divergence with its likely cause). stop: polled every SLICE_S of simulated time; a non-empty
    answer (the name of a signal) ends the run there (SimulationRecord.interrupted).
    log_actuation: see build_diagram."""
    scenario, params = at_top_speed(scenario, params)
    design = check_run(scenario, params)
    diagram, setup = build_diagram(scenario, params, design, log_actuation)
    simulator = Simulator(diagram)
    ApplySimulatorConfig(scenario.simulator_config, simulator)
    context = simulator.get_mutable_context()
    set_standing_pose(setup.plant, setup.plant.GetMyMutableContextFromRoot(context),
                      setup.instance, setup.layout.legs, params,
                      scenario.gait.home(params.gait), scenario.gait.lift_m(params.gait))
    simulator.Initialize()
    # every discrete update once, outside the timing: loads (or on a first run compiles) the
    # compiled kernels
    diagram.CalcForcedDiscreteVariableUpdate(context, diagram.AllocateDiscreteVariables())
    tell = (lambda text: say(text, sys.stderr)) if progress else (lambda text: None)
    duration = scenario.duration_s
    tell(f"simulating {duration:g} s, closure {scenario.closure}, "
         f"time step {setup.design.time_step_s * 1e3:.3f} ms")
    start, error, interrupted = time.perf_counter(), "", ""
    slices = max(1, math.ceil(duration / SLICE_S - 1e-9))
    bar = Progress(duration, 0.0, progress, "simulate", "s simulated", failures=False)
    try:
        for k in range(1, slices + 1):
            t = min(k * SLICE_S, duration)
            simulator.AdvanceTo(t)
            plant_state = setup.plant.GetPositionsAndVelocities(
                setup.plant.GetMyContextFromRoot(context))
            if not np.all(np.isfinite(plant_state)):
                raise RuntimeError("the plant state is not finite")
            tilt = tilt_deg(plant_state[setup.layout.state.body_q:setup.layout.state.body_q + 4])
            if tilt > FALL_TILT_DEG:
                raise ValueError(f"{FELL_OVER}: tilt {tilt:.0f} deg")
            interrupted = stop() if stop else ""
            if interrupted:
                tell(f"{interrupted} received: stopped at t = {t:.2f} s; writing what was "
                     "simulated")
                break
            bar.note = f"{t / (time.perf_counter() - start):.2f}x real time"
            bar.add(t - bar.done)
    except RuntimeError as err:   # Drake's own errors: a divergence
        error = divergence(str(err), context.get_time(), scenario, params, setup.layout,
                           setup.design, interval_table(setup, params, context))
    except ValueError as err:     # a fall, an unreachable target
        error = f"{err} (t = {context.get_time():.3f} s)"
    if error:
        tell(f"simulation stopped early: {error}")
    wall = time.perf_counter() - start
    actuation = None
    if setup.actuation_log is not None:
        log = setup.actuation_log.FindLog(context)
        actuation = (log.sample_times().copy(), log.data().T.copy())
    return SimulationRecord(scenario=scenario, params=params, layout=setup.layout,
                            design=setup.design, gains=setup.gains,
                            table=interval_table(setup, params, context), wall_s=wall,
                            error=error, interrupted=interrupted, actuation=actuation,
                            steps=step_table(setup, context))


def divergence(message: str, t: float, scenario: Scenario, params: Params, layout: RobotLayout,
               design: ClosureDesign, table: dict) -> str:
    """What diverged, when and its likely cause in this tool's terms, from the last recorded
    intervals before the failure (Drake's message at the end)."""
    finite = np.all(np.isfinite(table["state"]), axis=1)
    first_bad = len(finite) if finite.all() else int(np.argmin(finite))
    recent = {k: v[max(0, first_bad - 10):first_bad] for k, v in table.items()}
    drake = message.strip().splitlines()[0] if message.strip() else "no message"
    head = f"the simulation diverged at t = {t:.3f} s"
    step = f"scenario.time_step_s = {design.time_step_s:g} s"
    if not len(recent["t"]):
        return f"{head} at its start ({drake}); check the time step ({step}) and the gains"
    gap = recent["gap"].max(axis=0)
    height = recent["state"][:, layout.state.body_q + 6]
    speed = np.abs(recent["speed"]).max()
    clipped = float(np.mean(recent["clipped_peak"] + recent["clipped_line"]))
    if gap.max() > DIVERGED_GAP_M:
        leg = layout.legs[int(np.argmax(gap))]
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
                f"their limits; likely cause: the controller's gains "
                f"({scenario.controller.described()}): lower the bandwidths")
    return f"{head}: {what} (Drake: {drake})"
