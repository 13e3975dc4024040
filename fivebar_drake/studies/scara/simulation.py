"""The SCARA arm in a Drake Diagram following the seed's trajectory: trajectory sources (joint
positions and speeds, accelerations) -> computed-torque controller (Drake's
InverseDynamicsController: M(q) (qdd_d + kp e + kd e') + C qd + G on a model of the arm) -> one
MotorModel per joint with the sized limits -> the discrete plant carrying the payload."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
import numpy as np
from pydrake.systems.analysis import Simulator
from pydrake.systems.controllers import InverseDynamicsController
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import (Demultiplexer, LogVectorOutput, MatrixGain, Multiplexer,
                                        TrajectorySource)
from pydrake.trajectories import PiecewisePolynomial

from fivebar_drake.core.files import say
from fivebar_drake.core.interrupts import advance
from fivebar_drake.studies.base import duration_limits as base_limits
from fivebar_drake.actuators.motor import LineMotor, clip_flags
from fivebar_drake.simulation.motor_model import MotorModel
from fivebar_drake.mechanisms.scara import Dynamics, Scara, ScaraParams, seed_inertia
from fivebar_drake.mechanisms.scara.params import MAX_DURATION_S
from fivebar_drake.mechanisms.scara import sizing as sz
from fivebar_drake.studies.scara.analysis import Motion, screw, seed_motion
from fivebar_drake.studies.scara.model import add_arm


def sized_motors(params: ScaraParams) -> list[LineMotor]:
    """The drives at the joints (values at the joint: N·m and rad/s for joints 1, 2; N and m/s
    for joint 3; "gear ratio" motor rad per joint unit). Joints 1, 2: the seed's peak torques,
    the torque-speed line ending at servo_max_rpm through the reducer (the joint at n1, n2).
    Joint 3: the servo's peak torque through the belt and the ball screw (eq. 2.86 solved for
    the force), its line ending at the servo's top speed. No friction, no rotor inertia (the
    seed's ideal model)."""
    m, sp = params.motors, params.sizing
    out = [_line(peak, m.servo_max_rpm / n_rpm, n_rpm / sz.RPM_PER_RAD_S)
           for peak, n_rpm in ((m.peak1_Nm, sp.n1_rpm), (m.peak2_Nm, sp.n2_rpm))]
    s = screw(params)
    force = sz.screw_force(m.motor3_peak_Nm / m.belt_ratio, s["Dtb_m"], s["gamma_rad"],
                           s["phi_rad"])
    speed = m.motor3_max_rpm * m.belt_ratio / 60.0 * sp.screw_starts * sp.screw_lead_m
    ratio = 2 * math.pi / (sp.screw_starts * sp.screw_lead_m) / m.belt_ratio
    out.append(_line(force, ratio, speed))
    return out


def duration_limits(params: ScaraParams) -> dict:
    """A run's duration: the trajectory's by default, at least 10 plant steps, at most
    MAX_DURATION_S."""
    return base_limits(params.trajectory.duration_s, params.simulation.time_step_s,
                       MAX_DURATION_S)


def _line(peak, ratio, speed) -> LineMotor:
    """A lossless torque-speed line with this output peak and no-load speed behind the ratio."""
    return LineMotor("torque_speed_line", peak / ratio, speed * ratio, ratio, 0.0, 0.0, 0.0)


@dataclass
class Run:
    """A finished run: times (n,) s, joint positions and speeds (n, 3), the desired motion, the
    motors' records (n, 3, 3: command, delivered, applied per joint), wall time (s)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    desired: Motion
    record: np.ndarray
    motors: list
    wall_s: float
    interrupted: str = ""       # the signal that stopped the run early ("" if it did not)


def run(params: ScaraParams, duration_s: float | None = None, progress: bool = False,
        stop=None) -> Run:
    """Simulate the arm following the seed's trajectory for duration_s (default: the
    trajectory's duration; see duration_limits)."""
    sim = params.simulation
    duration = params.trajectory.duration_s if duration_s is None else duration_s
    desired = seed_motion(params, duration)
    inertia = seed_inertia(params.links, sim.payload_kg)
    builder = DiagramBuilder()
    arm = add_arm(builder, params, inertia, sim.time_step_s)
    model = add_arm(None, params, inertia)           # the controller's model, same arm
    plant, iq, iv = arm.plant, arm.q_index, arm.v_index
    nq, nx = plant.num_positions(), plant.num_multibody_states()
    x_des = np.zeros((len(desired.t), nx))
    x_des[:, iq], x_des[:, nq + iv] = desired.q, desired.qd
    vd_des = np.zeros((len(desired.t), plant.num_velocities()))
    vd_des[:, iv] = desired.qdd
    positions = PiecewisePolynomial.CubicHermite(desired.t, x_des[:, :nq].T, x_des[:, nq:].T)
    source = builder.AddNamedSystem("trajectory", TrajectorySource(positions, 1))
    accel = builder.AddNamedSystem("acceleration", TrajectorySource(
        PiecewisePolynomial.FirstOrderHold(desired.t, vd_des.T)))
    w, zeta = sim.natural_frequency_rad_s, sim.damping_ratio
    ctrl = builder.AddNamedSystem("controller", InverseDynamicsController(
        model.plant, np.full(nq, w * w), np.zeros(nq), np.full(nq, 2 * zeta * w), True))
    builder.Connect(plant.get_state_output_port(), ctrl.get_input_port_estimated_state())
    builder.Connect(source.get_output_port(), ctrl.get_input_port_desired_state())
    builder.Connect(accel.get_output_port(), ctrl.get_input_port_desired_acceleration())
    split = builder.AddNamedSystem("split", Demultiplexer(plant.num_velocities()))
    builder.Connect(ctrl.get_output_port_control(), split.get_input_port())
    joined = builder.AddNamedSystem("joined", Multiplexer(3))
    motors = sized_motors(params)
    records = []
    for i, motor in enumerate(motors):
        block = builder.AddNamedSystem(f"motor_q{i + 1}", MotorModel(
            motor, [nq + iv[i]], nx, sim.time_step_s, sim.time_step_s))
        builder.Connect(split.get_output_port(int(iv[i])), block.get_input_port(0))
        builder.Connect(plant.get_state_output_port(), block.GetInputPort("plant_state"))
        builder.Connect(block.GetOutputPort("applied_torque"), joined.get_input_port(i))
        records.append(LogVectorOutput(block.GetOutputPort("motor_record"), builder,
                                       sim.time_step_s))
    to_actuators = np.zeros((plant.num_actuators(), 3))
    for a in range(plant.num_actuators()):
        joint = plant.get_joint_actuator(plant.GetJointActuatorIndices()[a]).joint()
        to_actuators[a, [arm.v_index.tolist().index(joint.velocity_start())]] = 1.0
    actuation = builder.AddNamedSystem("to_actuators", MatrixGain(to_actuators))
    builder.Connect(joined.get_output_port(), actuation.get_input_port())
    builder.Connect(actuation.get_output_port(), plant.get_actuation_input_port())
    state_log = LogVectorOutput(plant.get_state_output_port(), builder, sim.time_step_s)
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    plant.SetPositionsAndVelocities(plant.GetMyMutableContextFromRoot(context), x_des[0])
    start = time.perf_counter()
    interrupted = ""
    for t_stop in np.append(np.arange(1.0, duration, 1.0), duration):
        interrupted = advance(simulator, float(t_stop), stop)
        if interrupted:
            break
        if progress:
            say(f"  simulated {t_stop:.1f} of {duration:g} s")
    wall = time.perf_counter() - start
    log = state_log.FindLog(context)
    x = log.data().T
    rec = np.stack([r.FindLog(context).data().T for r in records], axis=2)   # (n, 3, joint)
    return Run(log.sample_times(), x[:, iq], x[:, nq + iv], desired,
               np.transpose(rec, (0, 2, 1)), motors, wall, interrupted)


def summarize(params: ScaraParams, r: Run) -> dict:
    """Tracking error of the tool, and per joint the applied, commanded and clipped forces
    against the sized motors and the Lagrange model's peak along the desired motion."""
    scara = Scara(params.kinematics)
    tool = scara.forward(r.q).f
    t_des = r.desired.t
    wanted = np.stack([np.interp(r.t, t_des, r.desired.p[:, i]) for i in range(3)], axis=1)
    err = np.linalg.norm(tool - wanted, axis=1)
    k = int(np.argmax(err))
    tol = params.simulation.tracking_tolerance_m
    d = r.desired
    model = Dynamics(params.kinematics, seed_inertia(params.links, params.simulation.payload_kg))
    model_peak = np.abs(model.torques(d.q, d.qd, d.qdd)["total"]).max(axis=0)
    joints = []
    for j, (name, unit, motor) in enumerate(zip(("q1", "q2", "q3"), ("N·m", "N·m", "N"),
                                                r.motors)):
        command, delivered, applied = r.record[:, j, 0], r.record[:, j, 1], r.record[:, j, 2]
        at_peak, on_line = clip_flags(motor, command, delivered)
        peak = float(np.abs(applied).max())
        joints.append({"joint": name, "unit": unit, "peak_applied": peak,
                       "rms_applied": float(np.sqrt(np.mean(applied**2))),
                       "lagrange_peak": float(model_peak[j]),
                       "peak_command": float(np.abs(command).max()),
                       "limit": motor.peak_torque_Nm, "peak_over_limit": peak
                       / motor.peak_torque_Nm,
                       "no_load_speed": motor.no_load_speed_rad_s,
                       "peak_speed": float(np.abs(r.qd[:, j]).max()),
                       "clipped_by_peak_fraction": float(at_peak.mean()),
                       "clipped_by_line_fraction": float(on_line.mean())})
    ok = bool(err.max() <= tol)
    return {"mechanism": "scara", "source": params.source, "completed": True,
            "duration_s": float(r.t[-1]), "payload_kg": params.simulation.payload_kg,
            "controller": {"kind": "computed torque (Drake InverseDynamicsController)",
                           "kp": params.simulation.natural_frequency_rad_s**2,
                           "kd": 2 * params.simulation.damping_ratio
                           * params.simulation.natural_frequency_rad_s},
            "time_step_s": params.simulation.time_step_s,
            "tracking": {"max_error_m": float(err.max()), "at_s": float(r.t[k]),
                         "rms_error_m": float(np.sqrt(np.mean(err**2))), "tolerance_m": tol,
                         "within_tolerance": ok},
            "joints": joints, "verdict": "PASS" if ok else "FAIL",
            "real_time_factor": float(r.t[-1] / r.wall_s) if r.wall_s > 0 else None,
            "error_series": err}
