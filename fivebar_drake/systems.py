"""The Diagram's blocks: gait source, IK controller, motor model, foot contact forces.

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). Torque vectors (8) are in the plant's actuation order (LegIndices.actuators).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.common.value import AbstractValue
from pydrake.math import RotationMatrix
from pydrake.multibody.plant import ContactResults
from pydrake.systems.framework import BasicVector, LeafSystem

from .dynamics import full_model, static_torques
from .gait import wrap
from .jacobians import link_jacobians
from .kinematics import inverse
from .params import Gait, Motor, Params


class GaitSource(LeafSystem):
    """Time (s) -> foot targets of all legs in their leg planes.

    Output ports: "foot_targets" (8) in m, "foot_velocities" (8) in m/s, legs x (x, y).
    The seed's ellipse x = x_c + s a cos(w tau + phase), y = y_home + s b sin(w tau + phase) with
    tau = t - start_s and an amplitude s ramping 0 -> 1 over ramp_s (feet at (x_c, y_home) while
    standing). phases (rad) per leg."""

    def __init__(self, gait: Gait, phases, start_s: float, ramp_s: float):
        super().__init__()
        self._gait, self._phases = gait, np.asarray(phases, dtype=float)
        self._start, self._ramp = start_s, ramp_s
        n = 2 * len(self._phases)
        self.DeclareVectorOutputPort("foot_targets", n, self._calc_targets)
        self.DeclareVectorOutputPort("foot_velocities", n, self._calc_velocities)

    def targets(self, t: float):
        """Foot targets (legs, 2) in m and velocities (legs, 2) in m/s at time t (s)."""
        g = self._gait
        w = 2.0 * np.pi * g.frequency_hz
        tau = max(t - self._start, 0.0)
        s = min(tau / self._ramp, 1.0) if self._ramp > 0 else float(tau > 0)
        ds = (1.0 / self._ramp if 0 < tau < self._ramp else 0.0) if self._ramp > 0 else 0.0
        ang = w * tau + self._phases
        c, sn = np.cos(ang), np.sin(ang)
        pos = np.stack([g.x_center_m + s * g.a_m * c, g.y_home_m + s * g.b_m * sn], -1)
        vel = np.stack([ds * g.a_m * c - s * g.a_m * w * sn, ds * g.b_m * sn + s * g.b_m * w * c], -1)
        if t < self._start:
            vel[:] = 0.0
        return pos, vel

    def _calc_targets(self, context, output: BasicVector):
        output.SetFromVector(self.targets(context.get_time())[0].ravel())

    def _calc_velocities(self, context, output: BasicVector):
        output.SetFromVector(self.targets(context.get_time())[1].ravel())


def weight_shares(foot_y, y_home: float, band: float) -> np.ndarray:
    """Share of the robot's weight each foot carries (sums to 1), from the foot targets' heights
    (m): 1 for a foot more than band below y_home, 0 for one more than band above, linear in
    between, normalised; so a foot takes over its load smoothly at touchdown."""
    w = np.clip(0.5 - (np.asarray(foot_y) - y_home) / (2.0 * band), 0.0, 1.0)
    return w / w.sum() if w.sum() > 0 else np.full(len(w), 1.0 / len(w))


class FootIKController(LeafSystem):
    """Foot targets and measured plant state -> motor torque commands, at its own rate.

    Input ports: "foot_targets" (8) m, "foot_velocities" (8) m/s, "plant_state" (nq + nv).
    Output port: "torque_command" (8) N*m in actuation order, held between updates.
    Every period_s: closed-form IK (knees-out) gives q_des, J_F^-1 v gives q_dot_des, and
    tau = kp wrap(q_des - q) + kd (q_dot_des - q_dot) + tau_ff, where tau_ff is the full model's
    static torque at q_des with the robot's weight shared by the feet whose target is below
    y_home (all four while standing, the diagonal pair in a trot; see weight_shares).

    Balance (balance_gain > 0): each foot target's y is moved by balance_gain (dz + balance_rate_s
    dz') with dz the height change of the leg's hip from the body's tilt (hip positions hips_m in
    the body frame), so a leg under a sinking hip extends and one under a rising hip shortens;
    the offset is limited to +-b (the gait's step height)."""

    def __init__(self, params: Params, q_index, v_index, actuators, nq: int, nx: int,
                 period_s: float, kp: float, kd: float, body_q: int = -1, body_v: int = -1,
                 hips_m=None, balance_gain: float = 0.0, balance_rate_s: float = 0.0):
        super().__init__()
        self._params, self._kp, self._kd = params, kp, kd
        self._body_q, self._body_w = body_q, nq + body_v
        self._hips = None if hips_m is None else np.asarray(hips_m, dtype=float)
        self._balance = (balance_gain, balance_rate_s)
        self._q_index = np.asarray(q_index)     # (legs, 2) plant q indices of A, B
        self._v_index = np.asarray(v_index) + nq  # into the state vector
        self._actuators = np.asarray(actuators)   # (legs, 2) actuation indices
        self._model = full_model(params)
        self._weight = params.robot.total_mass_kg * params.robot.gravity_m_s2
        n = self._q_index.size
        self._targets = self.DeclareVectorInputPort("foot_targets", n)
        self._velocities = self.DeclareVectorInputPort("foot_velocities", n)
        self._state = self.DeclareVectorInputPort("plant_state", nx)
        self._command = self.DeclareDiscreteState(n)
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareStateOutputPort("torque_command", self._command)

    def command(self, targets, velocities, state):
        """Torque command (8) in actuation order from foot targets (legs, 2) m, velocities
        (legs, 2) m/s and the plant state vector."""
        p = self._params
        load = self._weight * weight_shares(targets[:, 1], p.gait.y_home_m, p.gait.b_m / 6)
        if self._balance[0] > 0:
            targets = targets.copy()
            targets[:, 1] += self._balance_offset(state)
        pose = inverse(p.leg, targets)
        lj = link_jacobians(p.leg, p.links, pose)
        qd_des = np.linalg.solve(lj.jf, velocities[..., None])[..., 0]
        q, qd = state[self._q_index], state[self._v_index]
        model = dataclasses.replace(self._model, foot_load_N=load)
        ff = static_torques(p, model, pose, lj)
        tau = self._kp * wrap(pose.q - q) + self._kd * (qd_des - qd) + ff
        out = np.zeros(self._q_index.size)
        out[self._actuators.ravel()] = tau.ravel()
        return out

    def _balance_offset(self, state):
        """Foot target y offsets (legs,) in m from the body's tilt (see class docstring)."""
        hips_w = self._hips @ body_rotation(state[self._body_q:self._body_q + 4]).T  # world axes
        omega = state[self._body_w:self._body_w + 3]              # world frame, rad/s
        dz = hips_w[:, 2] - self._hips[:, 2]
        dz_dot = omega[0] * hips_w[:, 1] - omega[1] * hips_w[:, 0]   # (omega x r)_z
        gain, rate = self._balance
        limit = self._params.gait.b_m
        return np.clip(gain * (dz + rate * dz_dot), -limit, limit)

    def _update(self, context, discrete_state):
        targets = self._targets.Eval(context).reshape(-1, 2)
        velocities = self._velocities.Eval(context).reshape(-1, 2)
        state = self._state.Eval(context)
        discrete_state.set_value(self._command, self.command(targets, velocities, state))


def body_rotation(quaternion_wxyz) -> np.ndarray:
    """Rotation matrix (3, 3) of a floating body's quaternion [w, x, y, z] as stored in the
    plant state (normalised first: the state drifts from unit length)."""
    q = np.asarray(quaternion_wxyz, dtype=float)
    return RotationMatrix(Quaternion(q / np.linalg.norm(q))).matrix()


def motor_torque(motor: Motor, command, speed, smoothing_rad_s: float = 0.05):
    """Torque (N*m) at the gearbox output for a command (N*m) at joint speed (rad/s), and whether
    the command was clipped. Motoring (torque and speed of the same sign) is limited by the linear
    torque-speed line tau_max (1 - |w| / w_0); braking by tau_max. Friction: Coulomb
    tau_c tanh(w / w_s) plus viscous b w opposes the motion."""
    command, speed = np.asarray(command, dtype=float), np.asarray(speed, dtype=float)
    peak = motor.peak_torque_Nm
    line = peak * np.clip(1.0 - np.abs(speed) / motor.no_load_speed_rad_s, 0.0, 1.0)
    upper = np.where(speed > 0, line, peak)
    lower = np.where(speed < 0, -line, -peak)
    clipped = np.clip(command, lower, upper)
    friction = (motor.coulomb_friction_Nm * np.tanh(speed / smoothing_rad_s)
                + motor.viscous_friction_Nm_s * speed)
    return clipped - friction, clipped != command


class MotorModel(LeafSystem):
    """Commanded torque and joint speed -> torque applied at the joints (see motor_torque).

    Input ports: "torque_command" (n) N*m, "plant_state" (nq + nv). Output ports:
    "applied_torque" (n) N*m, "saturated" (n) 1.0 where the command was clipped. Sampled every
    period_s (zero-order hold). The rotor's reflected inertia N^2 J_rotor is in the plant
    (<drake:rotor_inertia>, <drake:gear_ratio>), not here."""

    def __init__(self, motor: Motor, v_index_in_state, nx: int, period_s: float):
        super().__init__()
        self._motor = motor
        self._v = np.asarray(v_index_in_state)   # state index of each actuator's joint speed
        n = len(self._v)
        self._command = self.DeclareVectorInputPort("torque_command", n)
        self._state = self.DeclareVectorInputPort("plant_state", nx)
        self._applied = self.DeclareDiscreteState(n)
        self._saturated = self.DeclareDiscreteState(n)
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareStateOutputPort("applied_torque", self._applied)
        self.DeclareStateOutputPort("saturated", self._saturated)

    def _update(self, context, discrete_state):
        speed = self._state.Eval(context)[self._v]
        applied, saturated = motor_torque(self._motor, self._command.Eval(context), speed)
        discrete_state.set_value(self._applied, applied)
        discrete_state.set_value(self._saturated, saturated.astype(float))


class FootContactForces(LeafSystem):
    """Contact results -> ground force on each foot (N, world frame).

    Input port: "contact_results" (ContactResults). Output port: "foot_forces" (3 per foot)."""

    def __init__(self, foot_body_indices):
        super().__init__()
        self._feet = {int(b): i for i, b in enumerate(foot_body_indices)}
        self._input = self.DeclareAbstractInputPort("contact_results",
                                                    AbstractValue.Make(ContactResults()))
        self.DeclareVectorOutputPort("foot_forces", 3 * len(self._feet), self._calc)

    def _calc(self, context, output: BasicVector):
        results = self._input.Eval(context)
        forces = np.zeros((len(self._feet), 3))
        for i in range(results.num_point_pair_contacts()):
            info = results.point_pair_contact_info(i)
            a, b = int(info.bodyA_index()), int(info.bodyB_index())
            if b in self._feet:
                forces[self._feet[b]] += info.contact_force()
            elif a in self._feet:
                forces[self._feet[a]] -= info.contact_force()
        output.SetFromVector(forces.ravel())
