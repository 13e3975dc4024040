"""The Diagram's blocks: gait source, leg controller, motor model.

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). Torque vectors (8) are in the plant's actuation order (LegIndices.actuators).
"""

from __future__ import annotations

import numpy as np
from pydrake.systems.framework import LeafSystem

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.footpath import (Gait, path_constants, path_point, phase_of, stance_start,
                                         stance_weight_at)
from fivebar_drake.mechanisms.fivebar import (LINK_NAMES, com_fractions, physical_izz)
from fivebar_drake.robots.quadruped.control_law import ControlGains, LawConstants, leg_command
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.robots.quadruped.legs import plane_rotation
from fivebar_drake.robots.quadruped.sdf import body_height


@jit
def foot_references(path, stance_start_u, transfer_s, home, phases, start_s, ramp_s, t):
    """The foot references at time t (s) as one vector (7 legs / 2, GaitSource): targets,
    velocities and accelerations (legs x (x, y) each), then stance weights (legs);
    path: footpath.path_constants."""
    n = phases.shape[0]
    out = np.zeros(7 * n)
    targets, vel, acc = (out[:2 * n].reshape(n, 2), out[2 * n:4 * n].reshape(n, 2),
                         out[4 * n:6 * n].reshape(n, 2))
    weights = out[6 * n:]
    weights[:] = 1.0
    tau = t - start_s
    if tau < 0.0:
        targets[:, 0], targets[:, 1] = home[0], home[1]
        return out
    s, ds = (tau / ramp_s, 1.0 / ramp_s) if ramp_s > 0 and tau < ramp_s else (1.0, 0.0)
    for i in range(n):
        u = phase_of(path[5], tau, phases[i])
        x, y, vx, vy, ax, ay, _ = path_point(*path, u)
        for j, (rel, v, a) in enumerate(((x - home[0], vx, ax), (y - home[1], vy, ay))):
            targets[i, j] = home[j] + s * rel
            vel[i, j] = ds * rel + s * v
            acc[i, j] = 2.0 * ds * v + s * a
        weights[i] = 1.0 - s * (1.0 - stance_weight_at(u, stance_start_u, path[6], transfer_s))
    return out


class GaitSource(LeafSystem):
    """Time (s) -> foot targets of all legs in their leg planes and the stance schedule,
    sampled every period_s (the controller's period).

    Output port "foot_references" (7 legs / 2): foot targets (legs x (x, y), m), velocities
    (m/s), accelerations (m/s^2), then the stance weights (legs, in [0, 1]).
    The foot path (footpath.path_point) with gait time tau = t - start_s, each leg at its phase
    (rad), about the home point (x_c, y_home) scaled by s ramping 0 -> 1 over ramp_s; the
    stance weights blend from all-stance to the schedule with the same s. While standing
    (t < start_s) the feet rest at home, all in stance. The path is known ahead, so at each
    tick t the source stores the values of the next tick: a block sampling it at a tick reads
    the values at that tick, computed once, with no Python on the output port."""

    def __init__(self, gait: Gait, path: str, phases, start_s: float, ramp_s: float,
                 transfer_s: float, period_s: float):
        super().__init__()
        self._args = (path_constants(gait, path), stance_start(gait, path), float(transfer_s),
                      np.array([gait.x_center_m, gait.y_home_m]),
                      np.asarray(phases, dtype=float), float(start_s), float(ramp_s))
        self._period = period_s
        self._group = self.DeclareDiscreteState(self.references(0.0))
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareStateOutputPort("foot_references", self._group)

    def references(self, t: float) -> np.ndarray:
        """The output port's value at time t (s)."""
        return foot_references(*self._args, float(t))

    def _update(self, context, discrete_state):
        discrete_state.set_value(self._group, self.references(context.get_time() + self._period))


def derive_gains(mass_kg: float, inertia_kg_m2, leg_inertia_kg_m2: float, swing_hz: float,
                 body_hz: float, damping_ratio: float) -> ControlGains:
    """Gains that place a second-order mode at the given frequency and damping ratio: a swing
    joint of inertia leg_inertia (kg*m^2, links and reflected rotor about the motor axis) at
    swing_hz; the body's height, roll and pitch (mass kg, inertia (3, 3) kg*m^2 about the COM)
    at body_hz; the forward speed as a first-order loop at body_hz."""
    ws, wb, z = 2 * np.pi * swing_hz, 2 * np.pi * body_hz, damping_ratio
    i_att = np.array([inertia_kg_m2[0][0], inertia_kg_m2[1][1]])
    return ControlGains(kp=float(leg_inertia_kg_m2 * ws**2),
                        kd=float(2 * z * leg_inertia_kg_m2 * ws), kz=float(mass_kg * wb**2),
                        dz=float(2 * z * mass_kg * wb), dx=float(mass_kg * wb),
                        k_att=i_att * wb**2, d_att=2 * z * i_att * wb)


class FootLegController(LeafSystem):
    """Foot targets, stance schedule and the sampled plant state -> motor torque commands.

    Input ports: "foot_references" (GaitSource), "plant_state" (nx). Output port:
    "torque_command" (8) N*m in actuation order. Every period_s the controller samples its
    inputs and computes a command that it releases delay_periods ticks later (0: at once), held
    in between.

    - Swing (weight 1 - w per leg): joint PD to the closed-form IK of the target (knees out) with
      the full model's inverse dynamics (M q'' + c + G of the links, reflected rotor inertia) of
      the target's motion as feed-forward.
    - Stance (weight w): the links' weight at the measured pose, and a virtual-model
      controller. The body's targets follow from the stance feet's targets: height z = foot
      radius - hip z - y, vertical speed -y', forward speed the feet's x' (leg-plane x points
      backwards). The wrench on the body, in the body frame,
      F_x = m dx (v_x* - v_x), F_z = m (g + z*'') + kz (z* - z) + dz (z*' - z'),
      M_roll,pitch = -k_att angle - d_att rate, is shared by the stance feet: the in-plane ground
      forces of least weighted norm (weights w) that produce it, vertical forces >= 0 and
      horizontal ones inside the friction cone. That split already gives each foot its share
      (none at w = 0), so each motor pair adds -J_F(q)^T F in full, not blended by w: the feet
      deliver the whole wrench while a foot takes up or gives off its load.
    - Swing legs catch the body (catch_gain > 0): under a hip that the tilt lowers, the swing
      foot's target reaches down (control_law.catch_offset); with touchdown_detection a
      descending swing foot that meets the ground early joins the support
      (control_law.early_touchdown). The legs
      are planar and cannot step sideways: with a diagonal pair alone on the ground nothing
      else stops the body tipping about the diagonal.
    - The links' weight is compensated on every leg."""

    def __init__(self, params: Params, layout: RobotLayout, gains: ControlGains, period_s: float,
                 delay_periods: int, catch_gain: float, catch_rate_s: float,
                 touchdown_detection: bool):
        super().__init__()
        self._mechanism, self._layout = params.mechanism, layout
        self.constants = LawConstants(
            state=layout.state,
            hips_m=np.ascontiguousarray(layout.hips_m, dtype=float),
            com_m=np.asarray(layout.com_m, dtype=float), mass_kg=float(layout.mass_kg),
            plane=plane_rotation(), geom=params.leg.core,
            com_fraction=com_fractions(params.leg, params.links),
            masses=np.array([params.links[n].mass_kg for n in LINK_NAMES]),
            izz=np.array(physical_izz(params.leg, params.links)), gravity=params.robot.gravity_m_s2,
            reflected_inertia=params.motor.reflected_inertia_kg_m2, gains=gains,
            foot_radius_m=params.body.foot_radius_m,
            stand_offset_m=float(body_height(params, 0.0)), mu=params.body.foot_friction,
            catch_gain=float(catch_gain), catch_rate_s=float(catch_rate_s),
            catch_limit_m=params.gait.b_m, touchdown=bool(touchdown_detection))
        n = layout.state.q_index.size
        self._references = self.DeclareVectorInputPort("foot_references", 7 * n // 2)
        self._state = self.DeclareVectorInputPort("plant_state", layout.nx)
        # the released command (the output) and the delay_periods commands after it, oldest first
        self._released = self.DeclareDiscreteState(n)
        self._queue = self.DeclareDiscreteState(delay_periods * n)
        self._delayed = delay_periods > 0
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareStateOutputPort("torque_command", self._released)

    def command(self, references, state) -> np.ndarray:
        """Torque command (8) in actuation order from the foot references (GaitSource) and the
        plant state vector (nx,) (control_law.leg_command). Raises UnreachableError naming the
        target or pose where the legs cannot close."""
        out, goal, finite = leg_command(self.constants, np.asarray(references, dtype=float),
                                        np.asarray(state, dtype=float))
        if not finite:                        # name the reason, if it is a reach
            self._mechanism.inverse(goal)
            self._mechanism.forward(state[self._layout.state.q_index])
        return out

    def _update(self, context, discrete_state):
        new = self.command(self._references.Eval(context), self._state.Eval(context))
        if self._delayed:
            queue = np.concatenate([context.get_discrete_state(self._queue).get_value(), new])
            new = queue[:new.size]
            discrete_state.set_value(self._queue, queue[new.size:])
        discrete_state.set_value(self._released, new)
