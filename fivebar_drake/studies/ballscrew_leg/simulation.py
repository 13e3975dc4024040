"""A short squat of the ball-screw leg in Drake: the squat rig (hip on a carriage of mass
foot_force / g on a vertical rail, foot pinned to the ground, hip free) driven by the screw
motor alone through the motor model (peak torque and torque-speed line of the parameter file),
its summary.

Diagram, C++ systems only: reference motor angle and speed (TrajectorySource, the closed-form
squat q1(t) -> q2 = -2 q1 -> q2l -> 2 pi q2l / lead) -> PidController (PD on the motor angle,
gains from the motor's felt inertia and the file's bandwidth) + feed-forward (TrajectorySource:
the Drake model's projected static torque along the reference) -> MotorModel -> plant (SAP,
ball constraints at D and at the foot). The screw in Drake is lossless: the motor torques are
those of a 100 % screw; the report gives what the seed's 90 % makes of them."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from pydrake.systems.analysis import Simulator
from pydrake.systems.controllers import PidController
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import Adder, LogVectorOutput, TrajectorySource
from pydrake.trajectories import PiecewisePolynomial

from fivebar_drake.core.interrupts import advance
from fivebar_drake.studies.base import duration_limits as base_limits
from fivebar_drake.actuators.motor import clip_flags
from fivebar_drake.simulation.motor_model import MotorModel
from fivebar_drake.mechanisms.ballscrew_leg import TREE_JOINTS, Params, ball_screw_leg
from fivebar_drake.studies.ballscrew_leg.model import LegModel, build_model

FEEDFORWARD_STEP_S = 0.005       # the feed-forward's samples along the reference
MAX_DURATION_S = 60.0
STANDING_SETTLE_S = 0.1          # the start's transient (the loop and the PD settle) is left out


def reference(params: Params, t) -> tuple[np.ndarray, np.ndarray]:
    """Hip angle q1 (rad) and its rate (rad/s) of the squat at times t (s): hold at the top,
    down to the bottom and up again along half cosines, hold."""
    s = params.simulation
    top, bottom = np.radians(s.q1_top_deg), np.radians(s.q1_bottom_deg)
    t = np.asarray(t, dtype=float)
    down = np.clip((t - s.hold_s) / s.down_s, 0.0, 1.0)
    up = np.clip((t - s.hold_s - s.down_s) / s.down_s, 0.0, 1.0)
    phase = np.where(t < s.hold_s + s.down_s, down, 1.0 - up)
    moving = (phase > 0.0) & (phase < 1.0)
    sign = np.where(t < s.hold_s + s.down_s, 1.0, -1.0)
    q1 = top + (bottom - top) * 0.5 * (1.0 - np.cos(np.pi * phase))
    q1d = np.where(moving, sign * (bottom - top) * 0.5 * np.pi / s.down_s * np.sin(np.pi * phase),
                   0.0)
    return q1, q1d


def duration_limits(params: Params) -> dict:
    """A run's duration: the whole squat by default, at most MAX_DURATION_S."""
    return base_limits(params.simulation.duration_s, params.simulation.time_step_s,
                       MAX_DURATION_S)


def _positions(model: LegModel, q1):
    pose = model.leg.points(q1, -2.0 * np.asarray(q1))
    return pose, model.positions(pose, -pose.f[..., 1])


@dataclass
class SquatRun:
    """A run as plain data: times (s), plant states (rows, nx), the motor record (rows, 3:
    command, delivered, applied N*m), the layout's indices, the PD gains, the feed-forward (the
    Drake model's static torque along the reference: times s, N*m), the wall time."""

    params: Params
    t: np.ndarray
    state: np.ndarray
    motor: np.ndarray
    q_index: np.ndarray
    v_index: np.ndarray
    rail_q: int
    gains: tuple
    feedforward: tuple
    wall_s: float
    interrupted: str = ""       # the signal that stopped the run early ("" if it did not)


def run_squat(params: Params, duration_s: float | None = None, stop=None) -> SquatRun:
    """Simulate the squat for duration_s (None: the whole squat, hold-down-up-hold; at most
    MAX_DURATION_S)."""
    s = params.simulation
    duration = s.duration_s if duration_s is None else duration_s
    builder = DiagramBuilder()
    model = build_model(params, s.lever_m, "squat", builder)
    plant, leg = model.plant, model.leg
    screw_q, screw_v = (int(i[TREE_JOINTS.index("screw")]) for i in (model.q_index,
                                                                      model.v_index))
    nx = plant.num_multibody_states()
    # the reference: motor angle and speed, and the static feed-forward along it
    tt = np.arange(0.0, duration + s.time_step_s, s.time_step_s)
    q1, q1d = reference(params, tt)
    pose = leg.points(q1, -2.0 * q1)
    angle = 2.0 * np.pi * pose.q[:, 1] / leg.lead_m
    speed = 2.0 * np.pi / leg.lead_m * leg.screw_rate(pose.q2) * (-2.0 * q1d)
    desired = builder.AddNamedSystem("reference", TrajectorySource(
        PiecewisePolynomial.CubicHermite(tt, angle[None], speed[None]), 1))
    tf = np.arange(0.0, duration + FEEDFORWARD_STEP_S, FEEDFORWARD_STEP_S)
    ff = model.static_torques(_positions(model, reference(params, tf)[0])[1])[:, 0]
    feedforward = builder.AddNamedSystem("feedforward", TrajectorySource(
        PiecewisePolynomial.FirstOrderHold(tf, ff[None])))
    inertia = model.motor_inertia(_positions(model, 0.5 * (q1.min() + q1.max()))[1])
    w = 2.0 * np.pi * s.pd_bandwidth_hz
    kp, kd = inertia * w**2, 2.0 * s.pd_damping_ratio * inertia * w
    select = np.zeros((2, nx))
    select[0, screw_q], select[1, plant.num_positions() + screw_v] = 1.0, 1.0
    pd = builder.AddNamedSystem("pd", PidController(select, [kp], [0.0], [kd]))
    total = builder.AddNamedSystem("command", Adder(2, 1))
    motor = builder.AddNamedSystem("motor", MotorModel(
        params.motor, [plant.num_positions() + screw_v], nx, s.motor_period_s, s.time_step_s))
    builder.Connect(plant.get_state_output_port(), pd.get_input_port_estimated_state())
    builder.Connect(desired.get_output_port(), pd.get_input_port_desired_state())
    builder.Connect(pd.get_output_port_control(), total.get_input_port(0))
    builder.Connect(feedforward.get_output_port(), total.get_input_port(1))
    builder.Connect(total.get_output_port(), motor.GetInputPort("torque_command"))
    builder.Connect(plant.get_state_output_port(), motor.GetInputPort("plant_state"))
    builder.Connect(motor.GetOutputPort("applied_torque"), plant.get_actuation_input_port())
    states = LogVectorOutput(plant.get_state_output_port(), builder, s.time_step_s)
    record = LogVectorOutput(motor.GetOutputPort("motor_record"), builder, s.time_step_s)
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    plant.SetPositions(plant.GetMyMutableContextFromRoot(context), _positions(model, q1[0])[1])
    simulator.Initialize()
    start = time.perf_counter()
    interrupted = advance(simulator, duration, stop)
    wall = time.perf_counter() - start
    log_x, log_m = (lg.FindLog(context) for lg in (states, record))
    return SquatRun(params=params, t=log_x.sample_times(), state=log_x.data().T,
                    motor=log_m.data().T, q_index=model.q_index,
                    v_index=model.v_index + plant.num_positions(), rail_q=model.rail[0],
                    gains=(kp, kd), feedforward=(tf, ff), wall_s=wall, interrupted=interrupted)


@dataclass(frozen=True)
class Signals:
    """A run's signals in SI: q1 and its reference (rad), motor speed (rad/s), the torques
    (N*m: command, delivered, applied, the closed-form static torque of the load alone with a
    lossless screw, Drake's static torque along the reference, links included), the loop gaps
    at D and at the foot (m), the carriage height (m), the points O, A, D, P and the nut
    (rows, 5, 2) in m."""

    t: np.ndarray
    q1: np.ndarray
    q1_ref: np.ndarray
    motor_speed: np.ndarray
    command: np.ndarray
    delivered: np.ndarray
    applied: np.ndarray
    static: np.ndarray
    static_drake: np.ndarray
    gap_d: np.ndarray
    gap_foot: np.ndarray
    height: np.ndarray
    points: np.ndarray


def signals(run: SquatRun) -> Signals:
    p = run.params
    model_leg = ball_screw_leg(p, p.simulation.lever_m)
    x = run.state[:, run.q_index]
    height = run.state[:, run.rail_q]
    pose = model_leg.points(x[:, 0], x[:, 1])
    offset = np.column_stack([np.zeros_like(height), height])
    foot = pose.f + offset
    nut_dir = np.stack([np.sin(x[:, 0] + x[:, 2]), -np.cos(x[:, 0] + x[:, 2])], -1)
    nut = nut_dir * (model_leg.lead_m * x[:, 3] / (2.0 * np.pi))[:, None] + offset
    closed = model_leg.static_torques((0.0, p.load.foot_force_N), pose)[:, 1]
    return Signals(
        t=run.t, q1=x[:, 0], q1_ref=reference(p, run.t)[0],
        motor_speed=run.state[:, run.v_index[TREE_JOINTS.index("screw")]],
        command=run.motor[:, 0], delivered=run.motor[:, 1], applied=run.motor[:, 2],
        static=model_leg.screw_motor_torque(closed, 1.0),
        static_drake=np.interp(run.t, *run.feedforward),
        gap_d=model_leg.loop_gaps(x), gap_foot=np.linalg.norm(foot, axis=-1), height=height,
        points=np.stack([pose.o + offset, pose.a + offset, pose.d + offset, foot, nut], 1))


def summarize(run: SquatRun, sig: Signals) -> dict:
    """summary.json's dictionary."""
    p = run.params
    m = p.motor
    peak, line = clip_flags(m, sig.command, sig.delivered)
    standing = (reference(p, sig.t)[1] == 0.0) & (sig.t >= STANDING_SETTLE_S)
    err = np.degrees(sig.q1 - sig.q1_ref)
    eta = p.screw.efficiency
    top = float(np.max(np.abs(sig.applied)))
    out = {
        "mechanism": "ballscrew_leg", "lever_m": p.simulation.lever_m,
        "duration_s": float(sig.t[-1]), "wall_time_s": run.wall_s,
        "real_time_factor": float(sig.t[-1] / run.wall_s) if run.wall_s > 0 else None,
        "pd_gains": {"kp_Nm_rad": run.gains[0], "kd_Nm_s_rad": run.gains[1]},
        "q1_tracking_error_deg": {"rms": float(np.sqrt(np.mean(err**2))),
                                  "max": float(np.max(np.abs(err)))},
        "max_loop_gap_m": {"D": float(np.max(sig.gap_d)), "foot": float(np.max(sig.gap_foot))},
        "peak_applied_torque_Nm": top,
        "peak_static_closed_form_Nm": float(np.max(np.abs(sig.static))),
        "peak_applied_with_screw_efficiency_Nm": {"forward": top / eta, "back-driven": top * eta},
        "motor_peak_torque_Nm": m.peak_torque_Nm,
        "peak_motor_speed_rad_s": float(np.max(np.abs(sig.motor_speed))),
        "motor_no_load_speed_rad_s": m.no_load_speed_rad_s,
        "clipped_share": {"peak": float(np.mean(peak)), "torque_speed_line": float(np.mean(line))},
        "standing_applied_vs_static": {
            "closed_form": _relative(sig.applied[standing], sig.static[standing]),
            "drake": _relative(sig.applied[standing], sig.static_drake[standing])},
    }
    return out


def _relative(values, reference):
    """mean(values) / mean(reference) - 1, None without samples."""
    return float(np.mean(values) / np.mean(reference) - 1.0) if len(values) else None
