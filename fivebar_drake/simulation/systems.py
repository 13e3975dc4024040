"""The Diagram's blocks: the leg controller (the gait source is core/footpath.GaitSource, the
motor model core/motor.MotorModel).

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). Torque vectors (8) are in the plant's actuation order (LegIndices.actuators).
"""

from __future__ import annotations

import numpy as np
from pydrake.systems.framework import LeafSystem

from fivebar_drake.mechanisms.fivebar import (LINK_NAMES, com_fractions, physical_izz)
from fivebar_drake.robots.quadruped.control_law import ControlGains, LawConstants, leg_command
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.robots.quadruped.legs import plane_rotation
from fivebar_drake.robots.quadruped.sdf import body_height


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
