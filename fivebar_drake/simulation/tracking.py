"""A controller that tracks a gait's optimal motion (optimal/gait_floor.py): the controller
variant "tracking" (scenario `controller: {kind: tracking}`), for the gaits with a floor (trot,
walk, bound, pronk).

Once the gait source's ramp has ended it commands, on each foot the support holds, the floor's
ground force at that instant of the period (feed-forward, turned from the world's x-z plane into
the leg plane by the body's measured rotation) plus a feedback wrench on the body's deviation
from the floor's motion, shared by the feet down as the virtual model shares its wrench (least
weighted norm, F_z >= 0, inside the friction cone): height and vertical speed, forward speed,
pitch and pitch rate (towards the floor's), roll and roll rate (towards level), with the foot/leg
controller's gains (FootLeg.gains). The swing legs, the support's memory, the links' weight and
everything before the ramp's end are the foot/leg controller's (FootLegController)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from fivebar_drake.core.validation import require
from fivebar_drake.optimal.gait_floor import KINDS, GaitFloor, gait_floor, whole_body
from fivebar_drake.robots.quadruped.control_law import (leg_plan, leg_torques, plane_forces,
                                                        split_wrench)
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.robots.quadruped.sdf import body_height
from fivebar_drake.simulation.systems import FootLeg, FootLegController, register_controller

class Plan:
    """The floor's motion as functions of time within its period: the feet's forces (legs, 2)
    N (world x, z), the body's origin height (m) and vertical speed (m/s), forward speed (m/s)
    and pitch (rad) and pitch rate (rad/s), linear between the knots."""

    def __init__(self, floor: GaitFloor, params, speed_m_s: float, com_z_m: float):
        self.floor, self.period = floor, params.gait.period_s
        dt = self.period / floor.t.size
        height = float(body_height(params, params.gait.y_home_m)) + com_z_m

        def rate(p):
            return (np.roll(p, -1) - np.roll(p, 1)) / (2.0 * dt)

        self.body = np.stack([height + floor.z_m - com_z_m, rate(floor.z_m),
                              speed_m_s + rate(floor.x_m), floor.pitch_rad,
                              rate(floor.pitch_rad)], -1)              # (knots, 5)

    def at(self, t: float):
        """(forces (legs, 2), body (5,)) at time t (s) of the period, linear between knots."""
        n = self.floor.t.size
        u = (t % self.period) / self.period * n
        k = int(math.floor(u)) % n
        s = u - math.floor(u)
        k1 = (k + 1) % n
        forces = (1 - s) * self.floor.force_N[:, k] + s * self.floor.force_N[:, k1]
        return forces, (1 - s) * self.body[k] + s * self.body[k1]


class TrackingController(FootLegController):
    """The foot/leg controller (FootLegController) whose stance feet track the floor's forces
    and motion (module docstring) once the gait source's ramp has ended (start_s + ramp_s, s;
    the floor's period starts at start_s, with the gait's)."""

    def __init__(self, params, layout, gains, knobs, transfer_s, plan: Plan, start_s: float,
                 ramp_s: float):
        super().__init__(params, layout, gains, knobs, transfer_s)
        self._plan, self._start_s, self._ramp_s = plan, start_s, ramp_s

    def command(self, references, state, loads_N=None, support=None, t: float = 0.0):
        """The foot/leg controller's command until the ramp's end; then, blended in over the
        gait's next period (the virtual model's forces giving way to the tracking ones), the
        floor's forces and the feedback on the stance feet."""
        share = (t - self._start_s - self._ramp_s) / self._plan.period
        if share <= 0.0:
            return super().command(references, state, loads_N, support, t)
        k = self.constants
        memory = self.standing_support() if support is None else support
        loads = np.full(memory.shape[0], np.inf) if loads_N is None else np.asarray(loads_N)
        state = np.asarray(state, dtype=float)
        plan = leg_plan(k, np.asarray(references, dtype=float), state, loads, memory, float(t))
        forces_w, body = self._plan.at(t - self._start_s)
        forces = self._forces_plane(plan, state, forces_w, body)
        if share < 1.0:
            forces = share * forces + (1.0 - share) * self._forces(
                k, plan.body, plan.weights, plan.share, plan.fx, plan.fy, state, plan.r_wb)
        out, finite = leg_torques(k.state.actuators, plan.base, plan.jf, forces)
        if not finite:
            self._mechanism.inverse(plan.goal)
            self._mechanism.forward(state[self._layout.state.q_index])
        return out

    def _forces_plane(self, plan, state, forces_w, body) -> np.ndarray:
        """Leg-plane ground forces (legs, 2) N: the floor's on the feet down (scaled by their
        support weights) plus the shared feedback wrench."""
        k, r_wb = self.constants, plan.r_wb
        w0 = k.state.nq + k.state.body_v
        r_bw = r_wb.T
        omega_b = r_bw @ state[w0:w0 + 3]
        v_w = state[w0 + 3:w0 + 6]
        roll = math.atan2(r_wb[2, 1], r_wb[2, 2])
        pitch = -math.asin(min(max(r_wb[2, 0], -1.0), 1.0))
        z_ref, vz_ref, vx_ref, pitch_ref, rate_ref = body
        g = k.gains
        feedback_w = np.array([g.dx * (vx_ref - v_w[0]), 0.0,
                               g.kz * (z_ref - state[k.state.body_q + 6])
                               + g.dz * (vz_ref - v_w[2])])
        wrench = np.concatenate([(r_bw @ feedback_w)[[0, 2]],
                                 [-g.k_att[0] * roll - g.d_att[0] * omega_b[0],
                                  g.k_att[1] * (pitch_ref - pitch)
                                  + g.d_att[1] * (rate_ref - omega_b[1])]])
        weights = plan.weights
        body_f = np.zeros((weights.size, 3))          # the floor's forces in the body frame
        body_f[:, 0], body_f[:, 2] = forces_w[:, 0], forces_w[:, 1]
        body_f = body_f @ r_wb                         # rows: R^T f
        extra = np.zeros(2 * weights.size)            # the feedback (no yaw row: 4 of 5)
        if weights.sum() > 0.0:
            extra = split_wrench(k, weights, plan.fx, plan.fy, np.append(wrench, 0.0), 4)
        return plane_forces(k, weights * body_f[:, 0] + extra[0::2],
                            weights * body_f[:, 2] + extra[1::2])


@register_controller
@dataclass(frozen=True)
class Tracking(FootLeg):
    """The tracking controller (module docstring): the foot/leg controller's knobs; the floor is
    the scenario's gait's (gait_floor at the scenario's payload)."""

    kind: ClassVar[str] = "tracking"

    def check_scenario(self, scenario) -> None:
        path = scenario.gait
        require(path.kind in KINDS, "scenario.gait", path.kind,
                f"the tracking controller follows a gait's floor: one of {list(KINDS)}")
        own = [path.leg_phase(leg) for leg in LEGS]
        require(np.allclose(scenario.phases_rad, own), "scenario.phases_rad",
                scenario.phases_rad, f"the tracking controller follows the gait's own leg "
                                     f"phases, {own}")

    def add_to(self, builder, params, layout, scenario) -> TrackingController:
        path = scenario.gait
        plan = Plan(gait_floor(params, path, scenario.payload_kg), params,
                    path.stance_speed(params.gait), whole_body(params, scenario.payload_kg)[1])
        return builder.AddNamedSystem("leg_controller", TrackingController(
            params, layout, self.gains(params, layout), self, scenario.load_transfer_s, plan,
            path.start_s(scenario.stand_s), scenario.ramp_s))
