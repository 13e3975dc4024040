"""The Diagram's blocks: gait source, leg controller, motor model, interval recorder.

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). Torque vectors (8) are in the plant's actuation order (LegIndices.actuators).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RotationMatrix
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import BasicVector, LeafSystem, ValueProducer

from .dynamics import full_model, static_torques, torques
from .footpath import evaluate, stance_weight
from .gait import wrap
from .jacobians import bias_accelerations, link_jacobians
from .kinematics import forward, inverse
from .params import Gait, Motor, Params
from .sdf_model import body_height, plane_rotation


TOUCHDOWN_BAND_M = 0.004   # a descending swing foot this close to the ground joins the support


class GaitSource(LeafSystem):
    """Time (s) -> foot targets of all legs in their leg planes and the stance schedule.

    Output ports (legs x (x, y) where two values per leg): "foot_targets" (8) m,
    "foot_velocities" (8) m/s, "foot_accelerations" (8) m/s^2, "stance_weights" (4) in [0, 1].
    The foot path (footpath.evaluate) with gait time tau = t - start_s, each leg at its phase
    (rad), about the home point (x_c, y_home) scaled by s ramping 0 -> 1 over ramp_s; the
    stance weights blend from all-stance to the schedule with the same s. While standing
    (t < start_s) the feet rest at home, all in stance."""

    def __init__(self, gait: Gait, path: str, phases, start_s: float, ramp_s: float,
                 transfer_s: float):
        super().__init__()
        self._gait, self._path, self._phases = gait, path, np.asarray(phases, dtype=float)
        self._start, self._ramp, self._transfer = start_s, ramp_s, transfer_s
        self._home = np.array([gait.x_center_m, gait.y_home_m])
        n = len(self._phases)
        # computed once per time for all four ports
        self._cache = self.DeclareCacheEntry(
            "foot references", ValueProducer(
                allocate=lambda: AbstractValue.Make(dict()),
                calc=lambda c, value: value.set_value(self.targets(c.get_time()))),
            prerequisites_of_calc={self.time_ticket()})
        for name, size in (("foot_targets", 2 * n), ("foot_velocities", 2 * n),
                           ("foot_accelerations", 2 * n), ("stance_weights", n)):
            self.DeclareVectorOutputPort(
                name, size, lambda c, o, name=name: o.SetFromVector(
                    self._cache.Eval(c)[name].ravel()),
                prerequisites_of_calc={self._cache.ticket()})

    def targets(self, t: float) -> dict:
        """The output ports' values at time t (s), each (legs, 2) or (legs,)."""
        tau = t - self._start
        if tau < 0.0:
            zero = np.zeros((len(self._phases), 2))
            return {"foot_targets": np.tile(self._home, (len(self._phases), 1)),
                    "foot_velocities": zero, "foot_accelerations": zero,
                    "stance_weights": np.ones(len(self._phases))}
        ramping = self._ramp > 0 and tau < self._ramp
        s, ds = (tau / self._ramp, 1.0 / self._ramp) if ramping else (1.0, 0.0)
        p = evaluate(self._gait, self._path, tau, self._phases)
        rel = p.pos - self._home
        weights = stance_weight(self._gait, self._path, tau, self._phases, self._transfer)
        return {"foot_targets": self._home + s * rel, "foot_velocities": ds * rel + s * p.vel,
                "foot_accelerations": 2.0 * ds * p.vel + s * p.acc,
                "stance_weights": 1.0 - s * (1.0 - weights)}


@dataclass(frozen=True)
class ControlGains:
    """Gains of FootLegController (SI). Swing: joint PD kp (N*m/rad), kd (N*m*s/rad). Body
    (virtual model): height kz (N/m), dz (N*s/m); forward speed dx (N*s/m); roll and pitch
    k_att (N*m/rad, per axis), d_att (N*m*s/rad, per axis)."""

    kp: float
    kd: float
    kz: float
    dz: float
    dx: float
    k_att: np.ndarray
    d_att: np.ndarray


def derive_gains(mass_kg: float, inertia_kg_m2, leg_inertia_kg_m2: float, swing_hz: float,
                 body_hz: float, damping_ratio: float) -> ControlGains:
    """Gains that place a second-order mode at the given frequency and damping ratio: a swing
    joint of inertia leg_inertia (kg*m^2, links and reflected rotor about the motor axis) at
    swing_hz; the body's height, roll and pitch (mass kg, inertia (3, 3) kg*m^2 about the COM)
    at body_hz; the forward speed as a first-order loop at body_hz."""
    ws, wb, z = 2 * np.pi * swing_hz, 2 * np.pi * body_hz, damping_ratio
    i_att = np.array([inertia_kg_m2[0][0], inertia_kg_m2[1][1]])
    return ControlGains(kp=leg_inertia_kg_m2 * ws**2, kd=2 * z * leg_inertia_kg_m2 * ws,
                        kz=mass_kg * wb**2, dz=2 * z * mass_kg * wb, dx=mass_kg * wb,
                        k_att=i_att * wb**2, d_att=2 * z * i_att * wb)


@dataclass(frozen=True)
class RobotLayout:
    """What the controller needs to know about the plant: per leg (legs, 2) the plant q and v
    indices of motors A and B and their actuation indices; the body's first position index
    (quaternion w, x, y, z, then position) and velocity index (angular then linear, world
    frame); nq, nx; hip positions (legs, 3) m and the robot's COM (3,) m in the body frame;
    robot mass (kg) and inertia about the COM (3, 3) kg*m^2."""

    q_index: np.ndarray
    v_index: np.ndarray
    actuators: np.ndarray
    body_q: int
    body_v: int
    nq: int
    nx: int
    hips_m: np.ndarray
    com_m: np.ndarray
    mass_kg: float
    inertia_kg_m2: np.ndarray


class FootLegController(LeafSystem):
    """Foot targets, stance schedule and the sampled plant state -> motor torque commands.

    Input ports: "foot_targets", "foot_velocities", "foot_accelerations" (8, legs x (x, y)),
    "stance_weights" (4), "plant_state" (nx). Output port: "torque_command" (8) N*m in actuation
    order. Every period_s the controller samples its inputs and computes a command that it
    releases delay_periods ticks later (0: at once), held in between.

    - Swing (weight 1 - w per leg): joint PD to the closed-form IK of the target (knees out) with
      the full model's inverse dynamics (M q'' + c + G of the links, reflected rotor inertia) of
      the target's motion as feed-forward.
    - Stance (weight w): a virtual-model controller. The body's targets follow from the stance
      feet's targets: height z = foot radius - hip z - y, vertical speed -y', forward speed the
      feet's x' (leg-plane x points backwards). The wrench on the body, in the body frame,
      F_x = m dx (v_x* - v_x), F_z = m (g + z*'') + kz (z* - z) + dz (z*' - z'),
      M_roll,pitch = -k_att angle - d_att rate, is shared by the stance feet: the in-plane ground
      forces of least weighted norm (weights w) that produce it, vertical forces >= 0 and
      horizontal ones inside the friction cone; each motor pair gives -J_F(q)^T F.
    - Swing legs catch the body (catch_gain > 0): under a hip that the tilt lowers, the swing
      foot's target reaches down (see _catch_offset); with touchdown_detection a descending
      swing foot that meets the ground early joins the support (see _early_touchdown). The legs
      are planar and cannot step sideways: with a diagonal pair alone on the ground nothing
      else stops the body tipping about the diagonal.
    - The links' weight is compensated on every leg."""

    def __init__(self, params: Params, layout: RobotLayout, gains: ControlGains, period_s: float,
                 delay_periods: int, catch_gain: float, catch_rate_s: float,
                 touchdown_detection: bool):
        super().__init__()
        self._params, self._layout, self._gains = params, layout, gains
        self._touchdown = touchdown_detection
        self._catch = (catch_gain, catch_rate_s)
        self._swing_model = dataclasses.replace(full_model(params), foot_load_N=0.0)
        self._plane = plane_rotation()
        self._mu = params.body.foot_friction
        n = layout.q_index.size
        for name in ("foot_targets", "foot_velocities", "foot_accelerations"):
            self.DeclareVectorInputPort(name, n)
        self.DeclareVectorInputPort("stance_weights", n // 2)
        self.DeclareVectorInputPort("plant_state", layout.nx)
        # commands of the last delay_periods + 1 ticks, oldest first; the oldest is the output
        self._queue = self.DeclareDiscreteState((delay_periods + 1) * n)
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareVectorOutputPort("torque_command", n, self._output,
                                     prerequisites_of_calc={self.xd_ticket()})

    def command(self, targets, velocities, accelerations, weights, state) -> np.ndarray:
        """Torque command (8) in actuation order from foot targets, velocities, accelerations
        (legs, 2), stance weights (legs,) and the plant state vector (nx,)."""
        p, lay, g = self._params, self._layout, self._gains
        q, qd = state[lay.q_index], state[lay.v_index + lay.nq]
        r_wb = body_rotation(state[lay.body_q:lay.body_q + 4])
        # swing: IK target (moved by the catch reflex), its rates and accelerations,
        # inverse-dynamics feed-forward
        pose_des = inverse(p.leg, targets + self._catch_offset(state, r_wb))
        lj_des = link_jacobians(p.leg, p.links, pose_des)
        qd_des = np.linalg.solve(lj_des.jf, velocities[..., None])[..., 0]
        bias = bias_accelerations(p.leg, p.links, pose_des, qd_des)
        qdd_des = np.linalg.solve(lj_des.jf, (accelerations - bias[2])[..., None])[..., 0]
        ff = torques(p, self._swing_model, pose_des, qd_des, qdd_des, lj_des, bias).total
        ff = ff + p.motor.reflected_inertia_kg_m2 * qdd_des
        swing = g.kp * wrap(pose_des.q - q) + g.kd * (qd_des - qd) + ff
        # stance: virtual model, links' weight at the measured pose
        pose = forward(p.leg, q)
        lj = link_jacobians(p.leg, p.links, pose)
        if self._touchdown:
            weights = np.maximum(weights, self._early_touchdown(pose, velocities, state, r_wb))
        links = static_torques(p, self._swing_model, pose, lj)
        forces = self._ground_forces(targets, velocities, accelerations, weights, pose, state,
                                     r_wb)
        stance = links - np.einsum("lji,lj->li", lj.jf, forces)
        w = weights[:, None]
        tau = w * stance + (1.0 - w) * swing
        out = np.zeros(lay.q_index.size)
        out[lay.actuators.ravel()] = tau.ravel()
        return out

    def _early_touchdown(self, pose, velocities, state, r_wb) -> np.ndarray:
        """Support weight (legs,) of swing feet that meet the ground early: a foot on its way
        down (target y' < 0) whose lowest point is within TOUCHDOWN_BAND_M of flat ground at
        z = 0 (kinematic contact estimate: body pose and leg angles) joins the support: fully
        within half the band, fading out linearly to none at the band."""
        lay = self._layout
        feet_b = lay.hips_m + np.column_stack([pose.f, np.zeros(len(pose.f))]) @ self._plane.T
        clearance = (state[lay.body_q + 6] + feet_b @ r_wb[2]) - self._params.body.foot_radius_m
        weight = np.clip(2.0 - clearance / (0.5 * TOUCHDOWN_BAND_M), 0.0, 1.0)
        return np.where(velocities[:, 1] < 0.0, weight, 0.0)

    def _catch_offset(self, state, r_wb) -> np.ndarray:
        """Swing foot target offsets (legs, 2) in m: a swing leg under a hip that the body's
        tilt lowers by dz reaches down by catch_gain (dz + catch_rate dz') (and up under a
        rising hip), limited to the step height, so the foot on the side the body falls to
        lands early and catches it."""
        lay = self._layout
        gain, rate = self._catch
        out = np.zeros((len(lay.hips_m), 2))
        if gain == 0.0:
            return out
        hips_w = lay.hips_m @ r_wb.T
        omega = state[lay.nq + lay.body_v:lay.nq + lay.body_v + 3]
        dz = hips_w[:, 2] - lay.hips_m[:, 2]
        dz_dot = omega[0] * hips_w[:, 1] - omega[1] * hips_w[:, 0]      # (omega x r)_z
        limit = self._params.gait.b_m
        out[:, 1] = np.clip(gain * (dz + rate * dz_dot), -limit, limit)
        return out

    def _ground_forces(self, targets, velocities, accelerations, weights, pose, state, r_wb):
        """Ground forces on the feet (legs, 2) in N, leg-plane (x, y), from the body wrench
        (r_wb: the body's rotation in the world)."""
        p, lay, g = self._params, self._layout, self._gains
        total = weights.sum()
        if total <= 0.0:
            return np.zeros((len(weights), 2))
        share = weights / total
        z = state[lay.body_q + 6]
        omega_b = r_wb.T @ state[lay.nq + lay.body_v:lay.nq + lay.body_v + 3]
        v_w = state[lay.nq + lay.body_v + 3:lay.nq + lay.body_v + 6]
        v_b = r_wb.T @ v_w
        roll, pitch = np.arctan2(r_wb[2, 1], r_wb[2, 2]), -np.arcsin(np.clip(r_wb[2, 0], -1, 1))
        # body targets from the stance feet's targets (leg plane: x backwards, y up)
        z_des = body_height(p, share @ targets[:, 1])
        vz_des, az_des = -share @ velocities[:, 1], -share @ accelerations[:, 1]
        vx_des = share @ velocities[:, 0]
        grav = p.robot.gravity_m_s2
        force_w = np.array([0.0, 0.0, lay.mass_kg * (grav + az_des) + g.kz * (z_des - z)
                            + g.dz * (vz_des - v_w[2])])
        force_b = r_wb.T @ force_w
        force_b[0] += g.dx * (vx_des - v_b[0])
        moment_b = np.zeros(3)
        moment_b[:2] = -g.k_att * np.array([roll, pitch]) - g.d_att * omega_b[:2]
        # feet relative to the COM, body frame
        foot_plane = np.column_stack([pose.f, np.zeros(len(weights))])
        r = lay.hips_m + foot_plane @ self._plane.T - lay.com_m
        # unknowns per foot: ground force along body x and z; rows: Fx, Fz, Mx, My, Mz
        a = np.zeros((5, 2 * len(weights)))
        a[0, 0::2], a[1, 1::2] = 1.0, 1.0
        a[2, 1::2] = r[:, 1]                       # Mx = y Fz
        a[3, 0::2], a[3, 1::2] = r[:, 2], -r[:, 0]  # My = z Fx - x Fz
        a[4, 0::2] = -r[:, 1]                      # Mz = -y Fx
        wrench = np.concatenate([force_b[[0, 2]], moment_b])
        scale = np.array([1, 1, 1 / 0.1, 1 / 0.1, 1 / 0.1])   # moments per 0.1 m lever
        sw = np.sqrt(np.repeat(weights, 2))
        sol = np.linalg.lstsq((a * scale[:, None]) * sw, wrench * scale, rcond=1e-6)[0] * sw
        fx, fz = sol[0::2], np.maximum(sol[1::2], 0.0)
        fx = np.clip(fx, -self._mu * fz, self._mu * fz)
        ground_b = np.column_stack([fx, np.zeros_like(fx), fz])
        return (ground_b @ self._plane)[:, :2]     # body -> leg plane (x, y)

    def _update(self, context, discrete_state):
        n = self._layout.q_index.size
        inputs = [self.get_input_port(i).Eval(context) for i in range(5)]
        targets, velocities, accelerations = (x.reshape(-1, 2) for x in inputs[:3])
        new = self.command(targets, velocities, accelerations, inputs[3], inputs[4])
        queue = context.get_discrete_state(self._queue).get_value()
        discrete_state.set_value(self._queue, np.concatenate([queue[n:], new]))

    def _output(self, context, output: BasicVector):
        output.SetFromVector(context.get_discrete_state(self._queue).get_value()[
            :self._layout.q_index.size])


def body_rotation(quaternion_wxyz) -> np.ndarray:
    """Rotation matrix (3, 3) of a floating body's quaternion [w, x, y, z] as stored in the
    plant state (normalised first: the state drifts from unit length)."""
    q = np.asarray(quaternion_wxyz, dtype=float)
    return RotationMatrix(Quaternion(q / np.linalg.norm(q))).matrix()


def tilt_deg(quat_wxyz) -> np.ndarray:
    """Angle (deg) between a floating body's z axis and the vertical, for quaternions
    [w, x, y, z] (..., 4) as stored in the plant state (not necessarily unit length)."""
    q = np.asarray(quat_wxyz, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return np.degrees(np.arccos(np.clip(1 - 2 * (q[..., 1] ** 2 + q[..., 2] ** 2), -1, 1)))


@dataclass(frozen=True)
class MotorOutput:
    """Motor model result (each like the command): delivered torque at the gearbox output
    (N*m, the command after saturation), friction (N*m, opposing the motion), the torque the
    joint receives (delivered - friction), and whether the command was clipped by the peak
    torque or by the torque-speed line."""

    delivered: np.ndarray
    friction: np.ndarray
    joint: np.ndarray
    clipped_peak: np.ndarray
    clipped_line: np.ndarray


def motor_torque(motor: Motor, command, speed, smoothing_rad_s: float = 0.05) -> MotorOutput:
    """Motor at joint speed (rad/s) given a command (N*m). Motoring (torque and speed of the
    same sign) is limited by the torque-speed line (Motor.torque_limit); braking by the peak
    torque. Friction: Coulomb tau_c tanh(w / w_s) plus viscous b w."""
    command, speed = np.asarray(command, dtype=float), np.asarray(speed, dtype=float)
    peak = motor.peak_torque_Nm
    line = motor.torque_limit(speed)
    upper = np.where(speed > 0, line, peak)
    lower = np.where(speed < 0, -line, -peak)
    delivered = np.clip(command, lower, upper)
    clipped = delivered != command
    clipped_peak = clipped & (np.abs(command) > peak) & (np.abs(delivered) >= peak)
    friction = (motor.coulomb_friction_Nm * np.tanh(speed / smoothing_rad_s)
                + motor.viscous_friction_Nm_s * speed)
    return MotorOutput(delivered=delivered, friction=friction, joint=delivered - friction,
                       clipped_peak=clipped_peak, clipped_line=clipped & ~clipped_peak)


class MotorModel(LeafSystem):
    """Commanded torque and joint speed -> torque at the joints (see motor_torque).

    Input ports: "torque_command" (n) N*m, "plant_state" (nx). Output ports: "applied_torque"
    (n) N*m at the joints (delivered - friction), "motor_torque" (n) N*m delivered by the motor,
    "clipped_peak" and "clipped_line" (n) 1.0 where the command was clipped. Sampled every
    period_s (zero-order hold). The rotor's reflected inertia N^2 J_rotor is in the plant
    (<drake:rotor_inertia>, <drake:gear_ratio>), not here."""

    def __init__(self, motor: Motor, v_index_in_state, nx: int, period_s: float):
        super().__init__()
        self._motor = motor
        self._v = np.asarray(v_index_in_state)   # state index of each actuator's joint speed
        n = len(self._v)
        self._command = self.DeclareVectorInputPort("torque_command", n)
        self._state = self.DeclareVectorInputPort("plant_state", nx)
        self._out = self.DeclareDiscreteState(4 * n)
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        for i, name in enumerate(("applied_torque", "motor_torque", "clipped_peak",
                                  "clipped_line")):
            self.DeclareVectorOutputPort(
                name, n, lambda c, o, i=i: o.SetFromVector(
                    c.get_discrete_state(self._out).get_value()[i * n:(i + 1) * n]),
                prerequisites_of_calc={self.xd_ticket()})

    def _update(self, context, discrete_state):
        speed = self._state.Eval(context)[self._v]
        m = motor_torque(self._motor, self._command.Eval(context), speed)
        discrete_state.set_value(self._out, np.concatenate(
            [m.joint, m.delivered, m.clipped_peak, m.clipped_line]).astype(float))


class IntervalRecorder(LeafSystem):
    """Keeps one row per log interval (a sink: the rows live in this system, one simulation per
    Diagram): the time, the plant state and the integrals since t = 0 of what acted on the plant
    at every step.

    Input ports: "plant_state" (nx) and "integrals" (m): the output of a DiscreteTimeIntegrator
    stepping with the plant, so every plant step is counted (generalized contact forces, the
    command, the motor torque, the clip flags); their interval means are differences of
    integrals over the interval's length, so a contact spike counts for the time it lasts.
    Memory grows with the number of intervals, not of steps."""

    def __init__(self, nx: int, n_integrals: int, period_s: float):
        super().__init__()
        self.DeclareVectorInputPort("plant_state", nx)
        self.DeclareVectorInputPort("integrals", n_integrals)
        self.times, self.states, self.integrals = [], [], []
        self.DeclarePeriodicPublishEvent(period_s, 0.0, self._on_interval)

    def _on_interval(self, context):
        self.times.append(context.get_time())
        self.states.append(self.get_input_port(0).Eval(context).copy())
        self.integrals.append(self.get_input_port(1).Eval(context).copy())

    def rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Times (rows,) s, states (rows, nx) and integrals (rows, m) recorded so far."""
        n = len(self.times)
        return (np.array(self.times), np.array(self.states).reshape(n, -1),
                np.array(self.integrals).reshape(n, -1))
