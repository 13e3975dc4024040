"""The signals of a simulated run, per recorded interval, from its record alone (Signals,
signals): body motion, per leg and motor joint angles and speeds, torques, clip flags, foot
forces, the gait schedule, the leg's limit tests, the robot's centre of mass and the ground's
total force.

Every series is a mean over one log interval of plant steps (builder.add_recorders), so a contact
spike counts for the time it lasts. Per leg and motor, over the poses the robot went through:
- applied: the torque the motor delivered (the command after saturation); demand: the command;
- static_seed: the seed's G(q) with m_leg g at the foot; static_trot: the full model's static
  torque with the scheduled stance load (the weight shared by the feet in stance);
- static_contact: -J_P(q)^T F, F the measured ground force and J_P the Jacobian of the contact
  point (the bottom of the foot sphere on flat ground);
- the applied torque split into contact, links (M q'' + c + G of the links), rotor (N^2 J q'')
  and friction."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from fivebar_drake.gaits import evaluate, shared_loads
from fivebar_drake.core.rotation import body_rotations, tilt_deg
from fivebar_drake.mechanisms.fivebar import (LINK_NAMES, LimitTest, forward, inverse, limit_tests,
                                              link_coms, link_jacobians, static_torques, torques)
from fivebar_drake.robots.quadruped.control_law import contact_force_plane
from fivebar_drake.robots.quadruped.leg_loads import full_model, seed_model
from fivebar_drake.robots.quadruped.legs import plane_rotation
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.simulation.runner import SimulationRecord

SWING_CONTACT_N = 1.0     # a swing foot pressing harder than this (~1.5 % of the weight) drags

@dataclass(frozen=True)
class Signals:
    """Per log interval (rows): t (s, interval end); body position (rows, 3) m, quaternion
    (rows, 4), velocity (rows, 3) m/s (world), tilt (rows,) deg; per leg and motor (rows, legs,
    2): q (rad), qd (rad/s, interval mean), command, applied, static_seed, static_trot,
    static_contact, links, rotor, friction (N*m), clipped_peak, clipped_line (fractions);
    foot_force_plane (rows, legs, 2) N (leg plane), foot_force_world (rows, legs, 3); gap (rows, legs) m (worst per interval);
    stance (rows, legs) scheduled stance; swing_fraction (rows, legs) how far through its
    scheduled swing a foot is (0 .. 1; nan in stance); swing_contact (rows, legs) foot pressing
    the ground with more than SWING_CONTACT_N in scheduled swing; limits: the leg's limit tests
    (limits.py) over the poses (rows, legs); the whole robot's centre of mass com_p (rows, 3) m
    and its velocity com_v (rows, 3) m/s at each interval's end (from the state alone,
    com_motion); ground_force (rows, 3) N, the interval mean of the total contact force on the
    robot (world; the floating body's rows of the generalized contact forces)."""

    t: np.ndarray
    body_p: np.ndarray
    body_quat: np.ndarray
    body_v: np.ndarray
    tilt_deg: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    command: np.ndarray
    applied: np.ndarray
    static_seed: np.ndarray
    static_trot: np.ndarray
    static_contact: np.ndarray
    links: np.ndarray
    rotor: np.ndarray
    friction: np.ndarray
    clipped_peak: np.ndarray
    clipped_line: np.ndarray
    foot_force_plane: np.ndarray
    foot_force_world: np.ndarray
    gap: np.ndarray
    stance: np.ndarray
    swing_fraction: np.ndarray
    swing_contact: np.ndarray
    limits: list[LimitTest]
    com_p: np.ndarray
    com_v: np.ndarray
    ground_force: np.ndarray


def per_motor(record: SimulationRecord, column: str) -> np.ndarray:
    """A recorder column in actuation order (rows, 8) per leg and motor (rows, legs, 2)."""
    return record.table[column][:, record.layout.state.actuators]


def signals(record: SimulationRecord) -> Signals:
    """The run's signals (Signals) from its record alone: the recorder's table, the layout's
    indices, the parameters and the scenario's gait schedule."""
    table, lay = record.table, record.layout
    params, scenario = record.params, record.scenario
    st, t = table["state"], table["t"]
    qd = per_motor(record, "speed")
    period = np.median(np.diff(t)) if len(t) > 1 else scenario.log_period_s
    q = st[:, lay.state.q_index] - qd * period / 2        # pose at the middle of each interval
    # the mean acceleration over each interval is exactly its change of speed over its length
    # (the run starts at rest), consistent with the impulse-averaged contact forces
    qd_end = st[:, lay.state.v_index + lay.state.nq]
    qdd = np.diff(qd_end, axis=0, prepend=0.0 * qd_end[:1]) / np.diff(t, prepend=0.0)[:, None, None]
    pose = forward(params.leg, q)
    lj = link_jacobians(params.leg, params.links, pose)
    quat = st[:, lay.state.body_q:lay.state.body_q + 4]
    r_wb = body_rotations(np.ascontiguousarray(quat))                   # body -> world
    r_world_plane = r_wb @ plane_rotation()
    # contact point: the bottom of the foot sphere, (0, 0, -r) from its centre in the world
    down = -params.body.foot_radius_m * r_world_plane[:, 2, :2]          # leg plane (x, y)
    force = foot_forces(table["contact_generalized"], lay, params, pose, down)
    force_world = np.einsum("sij,slj->sli", r_world_plane[..., :2], force)
    jw_de = lj.jw[..., 3, :]                                            # (rows, legs, 2)
    j_contact = lj.jf.copy()
    j_contact[..., 0, :] -= down[:, None, 1:2] * jw_de
    j_contact[..., 1, :] += down[:, None, 0:1] * jw_de
    static_contact = -np.einsum("slji,slj->sli", j_contact, force)
    path = scenario.gait
    tau_gait = t - path.start_s(scenario.stand_s)
    gaiting = tau_gait[:, None] >= 0
    stance = np.stack([evaluate(params.gait, path, tau_gait, ph).stance
                       for ph in scenario.phases_rad], 1) & gaiting
    u = np.stack([path.phase(params.gait, tau_gait, ph) for ph in scenario.phases_rad], 1)
    swing = gaiting & ~stance & path.periodic
    swing_fraction = np.where(swing, u / np.where(swing, path.stance_start(params.gait), 1.0),
                              np.nan)
    weight = lay.mass_kg * params.robot.gravity_m_s2
    loads = np.where(gaiting, shared_loads(stance, weight, axis=1), weight / len(lay.legs))
    full = full_model(params)
    trot_static = static_torques(params.leg, params.links,
                                 dataclasses.replace(full, foot_load_N=loads), pose, lj)
    links = torques(params.leg, params.links, dataclasses.replace(full, foot_load_N=0.0), pose, qd,
                    qdd, lj).joint
    rotor = params.motor.reflected_inertia_kg_m2 * qdd
    return Signals(
        t=t, body_p=st[:, lay.state.body_q + 4:lay.state.body_q + 7], body_quat=quat,
        body_v=st[:, lay.state.nq + lay.state.body_v + 3:lay.state.nq + lay.state.body_v + 6], tilt_deg=tilt_deg(quat),
        q=q, qd=qd, command=per_motor(record, "command"),
        applied=per_motor(record, "motor_torque"),
        static_seed=static_torques(params.leg, params.links, seed_model(params), pose, lj),
        static_trot=trot_static, static_contact=static_contact, links=links, rotor=rotor,
        friction=per_motor(record, "motor_torque") - per_motor(record, "applied"),
        clipped_peak=per_motor(record, "clipped_peak"),
        clipped_line=per_motor(record, "clipped_line"), foot_force_plane=force,
        foot_force_world=force_world, gap=table["gap"],
        stance=stance, swing_fraction=swing_fraction,
        swing_contact=(~stance) & gaiting & (force_world[..., 2] > SWING_CONTACT_N),
        limits=limit_tests(params.leg, pose),
        **dict(zip(("com_p", "com_v"), com_motion(params, lay, st, r_wb))),
        ground_force=table["contact_generalized"][:, lay.state.body_v + 3:lay.state.body_v + 6])


def com_motion(params: Params, lay: RobotLayout, st, r_wb) -> tuple[np.ndarray, np.ndarray]:
    """The robot's centre of mass (rows, 3) m and its velocity (rows, 3) m/s in the world from
    the plant states st (rows, nx) alone: the layout's COM (body frame, standing pose) moved by
    the links' COMs away from their standing places, and the body's velocity plus the links'
    relative motion (J_v q_dot per link, leg plane) weighted by their masses. r_wb: the body's
    rotation to the world per row (rows, 3, 3)."""
    leg, links = params.leg, params.links
    masses = np.array([links[n].mass_kg for n in LINK_NAMES])
    q = st[:, lay.state.q_index]                                       # (rows, legs, 2)
    qd = st[:, lay.state.nq + lay.state.v_index]
    pose = forward(leg, q)
    standing = link_coms(leg, links, inverse(leg, np.array([params.gait.x_center_m,
                                                            params.gait.y_home_m])))
    shift = np.einsum("k,slkj->sj", masses, link_coms(leg, links, pose) - standing)
    rate = np.einsum("k,slkij,slj->si", masses, link_jacobians(leg, links, pose).jv, qd,
                     optimize=True)
    plane = plane_rotation()[:, :2]
    r_b = lay.com_m + (shift @ plane.T) / lay.mass_kg                  # (rows, 3) body frame
    r_w = np.einsum("sij,sj->si", r_wb, r_b)
    w0 = lay.state.nq + lay.state.body_v
    omega, v_body = st[:, w0:w0 + 3], st[:, w0 + 3:w0 + 6]
    p_body = st[:, lay.state.body_q + 4:lay.state.body_q + 7]
    v_rel = np.einsum("sij,sj->si", r_wb, (rate @ plane.T) / lay.mass_kg)
    return p_body + r_w, v_body + np.cross(omega, r_w) + v_rel


@dataclass(frozen=True)
class StepSignals:
    """A one-shot maneuver's plant steps (record.steps): t (steps,) s at each step's end; body
    position (steps, 3) m, the centre of mass com_p and its velocity com_v (steps, 3) m, m/s at
    each step's end (com_motion); per leg and motor q (rad) and qd (rad/s, at the step's end);
    the step's foot forces foot_force_plane (steps, legs, 2) N (leg plane) and the total ground
    force ground_force (steps, 3) N (world); the motor's samples motor_t (samples,) s, the
    command it took motor_command and the torque it delivered motor_torque (samples, legs, 2)
    N*m, held until the next sample, and the joint speed at each sample motor_speed (samples,
    legs, 2) rad/s (the step it starts)."""

    t: np.ndarray
    body_p: np.ndarray
    com_p: np.ndarray
    com_v: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    foot_force_plane: np.ndarray
    ground_force: np.ndarray
    motor_t: np.ndarray
    motor_command: np.ndarray
    motor_torque: np.ndarray
    motor_speed: np.ndarray


def step_signals(record: SimulationRecord) -> StepSignals:
    """The StepSignals of a record with plant steps (record.steps, a one-shot maneuver's)."""
    steps, lay, params = record.steps, record.layout, record.params
    st = steps["state"]
    q = st[:, lay.state.q_index]
    pose = forward(params.leg, q)
    r_wb = body_rotations(np.ascontiguousarray(st[:, lay.state.body_q:lay.state.body_q + 4]))
    down = -params.body.foot_radius_m * (r_wb @ plane_rotation())[:, 2, :2]
    generalized = steps["contact_generalized"]
    com_p, com_v = com_motion(params, lay, st, r_wb)
    qd = st[:, lay.state.nq + lay.state.v_index]
    return StepSignals(
        t=steps["t"], body_p=st[:, lay.state.body_q + 4:lay.state.body_q + 7], com_p=com_p,
        com_v=com_v, q=q, qd=qd,
        foot_force_plane=foot_forces(generalized, lay, params, pose, down),
        ground_force=generalized[:, lay.state.body_v + 3:lay.state.body_v + 6],
        motor_t=steps["motor_t"], motor_command=steps["motor_command"][:, lay.state.actuators],
        motor_torque=steps["motor_torque"][:, lay.state.actuators],
        motor_speed=qd[np.clip(np.searchsorted(steps["t"], steps["motor_t"]), 0, len(qd) - 1)])


def foot_forces(generalized, layout: RobotLayout, params: Params, pose, down) -> np.ndarray:
    """Mean ground force on each foot (rows, legs, 2) in N, leg plane, from the interval means
    of the generalized contact forces (rows, nv) on the joints B and D (contact_v_index) at the
    contact point P (foot centre + down, leg plane): the controller's formula
    (control_law.contact_force_plane); the A side of the loop is not touched."""
    p = pose.f + down[:, None, :]
    tau = generalized[:, layout.state.contact_v_index]                  # (rows, legs, 2)
    b = params.leg.b
    return np.stack(contact_force_plane(
        float(b[0]), float(b[1]), np.ascontiguousarray(pose.d[..., 0]),
        np.ascontiguousarray(pose.d[..., 1]), np.ascontiguousarray(p[..., 0]),
        np.ascontiguousarray(p[..., 1]), np.ascontiguousarray(tau[..., 0]),
        np.ascontiguousarray(tau[..., 1])), -1)
