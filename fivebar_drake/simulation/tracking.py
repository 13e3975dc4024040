"""A controller that tracks an optimal motion: the controller variant "tracking" (scenario
`controller: {kind: tracking}`), for the gaits with a floor (optimal/gait_floor.py: trot, walk,
bound, pronk), the jump and the drop (optimal/vertical_jump.py: the push and the landing's
catch, JumpTrackingController).

For a gait, from its takeover (Tracking.takeover: the ramp's end by default; at its start the
body enters the floor's periodic motion while the path grows, which spares the default bound's
first full cycle the motors' limits, 16 ms of them, but not the pronk its flight), blended in
over one period, it commands, on each foot the support holds, the floor's ground force at that
instant of the period in full (feed-forward, turned from the world's x-z plane into
the leg plane by the body's measured rotation) plus a feedback wrench on the body's deviation
from the floor's motion, shared by the feet down as the virtual model shares its wrench (least
weighted norm, F_z >= 0, inside the friction cone, and no yaw moment: on a diagonal pair a
pitch moment has no lever but a yaw couple of the feet's x forces, which the split must not
use): height and vertical speed, forward speed,
pitch and pitch rate (towards the floor's), roll and roll rate (towards level), with the foot/leg
controller's gains (FootLeg.gains). The swing legs, the support's memory, the links' weight and
everything before the takeover are the foot/leg controller's (FootLegController), with two
changes once the tracking is in full:
- the gait's clock waits for late feet: the feet that land together (a trot's diagonal, a
  bound's pair, a pronk's four) move the clock the controller follows (the path's references
  and the floor's motion) back by their mean lateness after their scheduled touchdown (an
  early foot counting as on time: it is held where it lands, the foot/leg controller's
  touchdown detection), so the floor's stance starts where the feet do: a pair that lands
  late no longer starts its stance with the floor's force at its plateau and the body falling
  faster than the floor's, the feedback's catch-up that put the A motors beyond their peak
  current;
- each swing lands where the floor's body puts the ground: the last LANDING_ZONE_M of its
  descent reaches the floor's hip height at its touchdown (Plan.touchdown_heights: the floor
  lets the body heave and pitch, the path ends each swing at y_home under the hip), and a foot
  due on the ground and not yet on it looks for it there."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from fivebar_drake.core.validation import check_number, require
from fivebar_drake.core.variants import documented
from fivebar_drake.gaits import cycle_phase, reference_parts
from fivebar_drake.mechanisms.fivebar import KNEES_OUT
from fivebar_drake.optimal.gait_floor import KINDS, GaitFloor, gait_floor, whole_body
from fivebar_drake.optimal.vertical_jump import (Catch, Jump, catch, landing_need,
                                                 landing_stroke, maneuver_push, reach, stroke)
from fivebar_drake.robots.quadruped.control_law import (body_attitude, plane_forces,
                                                        split_wrench)
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.robots.quadruped.sdf import body_height
from fivebar_drake.simulation.systems import FootLeg, FootLegController, register_controller

PUSH_WINDOW_SLACK = 0.25   # a tracked push may last this share longer than planned
LATE_WINDOW = 0.3          # a foot landing within this share of a period after its schedule
LANDING_ZONE_M = 0.01      # the last part of a swing's descent that reaches the floor's ground;
#                            the reach is held within half of it, so the descent stays monotonic


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

    def _knots(self, t: float) -> tuple[int, int, float]:
        """(knot, next knot, share of the way to it) at time t (s) of the period."""
        n = self.floor.t.size
        u = (t % self.period) / self.period * n
        k = int(math.floor(u)) % n
        return k, (k + 1) % n, u - math.floor(u)

    def at(self, t: float):
        """(forces (legs, 2), body (5,)) at time t (s) of the period, linear between knots."""
        k, k1, s = self._knots(t)
        forces = (1 - s) * self.floor.force_N[:, k] + s * self.floor.force_N[:, k1]
        return forces, (1 - s) * self.body[k] + s * self.body[k1]

    def touchdown_heights(self, hips, phases, stance_start: float) -> np.ndarray:
        """(legs,) m: each hip's height above its nominal one at the leg's scheduled touchdown
        (cycle phase stance_start, the leg at its gait phase phases (rad)), the floor's heave z
        and pitch theta there: z - sin(theta) x + (cos(theta) - 1) z_hip; hips (legs, 2) m the
        hips' (x, z) from the centre of mass, in the body frame."""
        out = np.empty(len(phases))
        for i, phase in enumerate(phases):
            k, k1, s = self._knots((stance_start - phase / (2.0 * math.pi)) % 1.0 * self.period)
            z, theta = ((1 - s) * v[k] + s * v[k1] for v in (self.floor.z_m, self.floor.pitch_rad))
            out[i] = z - math.sin(theta) * hips[i][0] + (math.cos(theta) - 1.0) * hips[i][1]
        return out


class TrackingController(FootLegController):
    """The foot/leg controller (FootLegController) whose stance feet track the floor's forces
    and motion (module docstring) from takeover_s (s), blended in over one period; the floor's
    period starts at start_s (s), with the gait's. The gait (its references at a time: the
    Diagram's GaitSource, path with its phases (rad), stance start and y_home (m)) is followed
    on the controller's own clock, which lags the run's time by the late touchdowns once the
    tracking is in full (discrete state "clock": the lag (s), then whether each foot was in the
    support at the last tick)."""

    def __init__(self, params, layout, gains, knobs, transfer_s, plan: Plan, start_s: float,
                 takeover_s: float, gait, path):
        super().__init__(params, layout, gains, knobs, transfer_s)
        self._plan, self._start_s, self._takeover_s = plan, start_s, takeover_s
        self._gait, self._gait_params = gait, params.gait
        self._phases = np.array([path.leg_phase(leg) for leg in layout.legs])
        self._stance_start = path.stance_start(params.gait)
        self._y_home = params.gait.y_home_m
        k = self.constants
        self.landing_m = np.clip(plan.touchdown_heights(k.hips_m[:, [0, 2]] - k.com_m[[0, 2]],
                                                        self._phases, self._stance_start),
                                 -LANDING_ZONE_M / 2, LANDING_ZONE_M / 2)
        # each foot's share of the lag: 1 / the feet landing with it (their mean lateness)
        together = np.isclose(np.mod(self._phases[:, None] - self._phases[None, :], 2 * math.pi),
                              0.0).sum(1)
        self._lag_share = 1.0 / together
        self._clock = self.DeclareDiscreteState(np.zeros(1 + len(layout.legs)))

    def _in_full(self, t: float) -> bool:
        """Whether the tracking is in full at time t (s): one period after the takeover."""
        return t - self._takeover_s >= self._plan.period

    def _update(self, context, discrete_state):
        clock = context.get_discrete_state(self._clock).get_value()
        state, loads, memory, t, impulse = self._tick(context)
        gait_s, was = t - clock[0], clock[1:] > 0.5
        new = self.command(self.references(gait_s, was, t), state, loads, memory, t, gait_s)
        self._store(discrete_state, memory, impulse, new)
        discrete_state.set_value(self._clock, np.append(
            self.lag(clock[0], was, memory[:, 0] > 0.5, t, gait_s), memory[:, 0]))

    def references(self, gait_s: float, was, t: float) -> np.ndarray:
        """The foot references (GaitSource) at the gait's clock gait_s (s), with the tracking
        in full at time t (s) each swing landing at the floor's hip height (landing_m, over the
        last LANDING_ZONE_M of its descent: its target, speed and acceleration) and each foot due
        and not in the support at the last tick (was: (legs,) bool) looking for it there."""
        out = np.array(self._gait.references(gait_s), dtype=float)
        if not self._in_full(t):
            return out
        targets, velocities, accelerations, weights = reference_parts(out)   # views
        for i, depth in enumerate(self.landing_m):
            if weights[i] == 0.0 and velocities[i, 1] < 0.0:
                r = 1.0 - (targets[i, 1] - self._y_home) / LANDING_ZONE_M
                if r > 0.0:             # y - depth r^2, r' = -y'/zone, r'' = -y''/zone
                    rate, curve = -velocities[i, 1] / LANDING_ZONE_M, \
                        -accelerations[i, 1] / LANDING_ZONE_M
                    targets[i, 1] -= depth * r * r
                    velocities[i, 1] -= 2.0 * depth * r * rate
                    accelerations[i, 1] -= 2.0 * depth * (rate * rate + r * curve)
            elif weights[i] > 0.0 and not was[i]:
                targets[i, 1] -= depth
        return out

    def lag(self, lag_s: float, was, on, t: float, gait_s: float) -> float:
        """The clock's lag (s) after a tick at time t (s), the gait's clock at gait_s (s): each
        foot that joined the support (was not, is on: (legs,) bool) within LATE_WINDOW of a
        period after its scheduled touchdown adds its lateness over the number of feet that land
        with it (the clock follows their mean lateness), once the tracking is in full."""
        joined = on & ~was
        if not (joined.any() and self._in_full(t)):
            return lag_s
        u = cycle_phase(self._gait_params, gait_s - self._start_s, self._phases)
        late = np.mod(u - self._stance_start, 1.0)
        joined &= late < LATE_WINDOW
        return lag_s + float((self._lag_share * late)[joined].sum()) * self._plan.period

    def stance_torques(self, plan, state, t: float, gait_s: float) -> tuple:
        """The foot/leg controller's until the takeover; then, blended in over one
        period (the virtual model's forces giving way to the tracking ones), the floor's forces
        and the feedback on the stance feet, at the gait's clock gait_s (s)."""
        share = (t - self._takeover_s) / self._plan.period
        if share <= 0.0:
            return super().stance_torques(plan, state, t, gait_s)
        forces_w, body = self._plan.at(gait_s - self._start_s)
        forces = self._forces_plane(plan, np.asarray(state, dtype=float), forces_w, body)
        if share < 1.0:
            forces = share * forces + (1.0 - share) * super().stance_torques(
                plan, state, t, gait_s)[2]
        return plan.base, plan.jf, forces

    def _forces_plane(self, plan, state, forces_w, body) -> np.ndarray:
        """Leg-plane ground forces (legs, 2) N: the floor's, in full on every foot the support
        holds (its weight > 0: scaled by the weight's ramp, the feet gave the floor's motion too
        little impulse after touchdown, the body sank 9 mm below it and the feedback then asked
        the rear motors beyond their limits at the top speed), plus the shared feedback
        wrench."""
        k, r_wb = self.constants, plan.r_wb
        w0 = k.state.nq + k.state.body_v
        r_bw = r_wb.T
        roll, pitch, omega_b = body_attitude(k, state, r_wb)
        v_w = state[w0 + 3:w0 + 6]
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
        extra = np.zeros(2 * weights.size)            # the feedback, no yaw moment
        if weights.sum() > 0.0:
            extra = split_wrench(k, weights, plan.fx, plan.fy, np.append(wrench, 0.0), 5)
        down = (weights > 0.0).astype(float)    # the floor's force in full once down
        return plane_forces(k, down * body_f[:, 0] + extra[0::2],
                            down * body_f[:, 2] + extra[1::2])


class JumpPlan:
    """A jump's optimal push (optimal/vertical_jump.maneuver_push) as functions of the hip's
    height u above the foot (m, the leg plane), linear between its nodes up to takeoff: each
    motor's delivered torque (2,) N*m and speed (2,) rad/s and the hip's rising speed (m/s); the
    takeoff height takeoff_u (m), the push's start onset_s and its window end_s (s, the run's
    time)."""

    def __init__(self, jump: Jump, onset_s: float, end_s: float):
        k = jump.takeoff
        self.u = jump.stroke.u[:k + 1]
        self.torque = np.vstack([jump.delivered_Nm, jump.delivered_Nm[-1:]])
        self.speed = np.vstack([jump.speed_rad_s, jump.stroke.dq[k] * jump.w[k]])
        self.w = jump.w
        self.takeoff_u, self.onset_s, self.end_s = float(self.u[-1]), onset_s, end_s

    def at(self, u: float) -> tuple[np.ndarray, np.ndarray, float]:
        """(delivered torques (2,) N*m, joint speeds (2,) rad/s, hip speed m/s) at hip height u
        (m)."""
        def line(values):
            return np.array([np.interp(u, self.u, values[:, j]) for j in range(2)])
        return line(self.torque), line(self.speed), float(np.interp(u, self.u, self.w))


class CatchPlan:
    """A landing's least-torque catch (optimal/vertical_jump.landing_floor) as functions of the
    hip's height u above the foot (m), linear between its nodes from the stop to the top: the
    vertical ground force the optimum's foot carries (N: the quarter robot decelerated and the
    links' terms) and the hip's sinking speed w (m/s, <= 0); followed from start_s to end_s (s,
    the run's time)."""

    def __init__(self, catch: Catch, start_s: float, end_s: float):
        s = catch.stroke
        w = catch.w
        if w.size < 2:                  # the legs give way at the top: the touchdown speed held
            w = np.full(2, w[-1] if w.size else 0.0)
        first = s.u.size - w.size
        self.u, self.w = s.u[first:], w
        x = self.w**2
        b = 0.5 * np.gradient(x, self.u)                    # u'' = d(u'^2)/du / 2
        self.force = s.fy[first:, 0] * b + s.fy[first:, 1] * x + s.fy[first:, 2]
        self.start_s, self.end_s = start_s, end_s

    def at(self, u: float) -> tuple[float, float]:
        """(vertical ground force N, hip speed m/s) at hip height u (m)."""
        return float(np.interp(u, self.u, self.force)), float(np.interp(u, self.u, self.w))


class JumpTrackingController(FootLegController):
    """The foot/leg controller (FootLegController) following a jump's or a drop's optimal
    strokes:
    - the push (a jump's; JumpPlan): from its onset until each leg reaches the takeoff height
      (or the push's window ends), the leg's motors deliver the optimal push's torques at its
      measured hip height (feed-forward: the links' and rotors' inertia, the links' weight,
      -J_F^T F of the optimal ground force, friction) plus -J_F^T of a feedback ground force:
      along the leg's y the hip's speed towards the optimum's at its height, along x the foot
      towards the stroke's line x_center (both at the body loop's bandwidth on a quarter of
      the robot), roll and pitch towards level (_level); within the envelope at the joints'
      measured speeds and the optimum's (_within);
    - the flight: a leg off the ground (support weight 0) after its push, or a drop's before
      touchdown, is held at the touchdown pose (the catch's top) by the swing loop's joint PD,
      with no weight to carry in free fall, whatever the path's clock says;
    - the landing (CatchPlan): on each foot measured on the ground while its hip sinks, the
      stance law's vertical force gives way to the least-torque catch's at the measured hip
      height, in full from the first contact, plus the levelling moment's share and a
      feedback on the hip's sinking speed towards the catch's (at the body loop's bandwidth);
      the horizontal force stays the stance law's.
    The crouch, the recovery and the links' weight are the foot/leg controller's."""

    def __init__(self, params, layout, gains, knobs, transfer_s, push: JumpPlan | None,
                 landing: CatchPlan):
        super().__init__(params, layout, gains, knobs, transfer_s)
        self._push, self._landing = push, landing
        self._x_center, self._motor = params.gait.x_center_m, params.motor
        quarter = layout.mass_kg / len(layout.legs)
        omega = 2.0 * math.pi * knobs.body_bandwidth_hz
        self._kx, self._dx = quarter * omega**2, 2.0 * knobs.damping_ratio * quarter * omega
        self._dw = quarter * omega
        self._landing_q = params.fivebar_leg.inverse(      # the touchdown pose, the catch's top
            np.array([params.gait.x_center_m, -landing.u[-1]]), KNEES_OUT).q

    def stance_torques(self, plan, state, t: float, gait_s: float) -> tuple:
        base, jf, forces = super().stance_torques(plan, state, t, gait_s)
        push, land, k = self._push, self._landing, self.constants
        landing = land.start_s <= t < land.end_s
        if not (landing or push is not None and push.onset_s <= t < push.end_s):
            return base, jf, forces
        state = np.asarray(state, dtype=float)
        qd = state[k.state.nq + k.state.v_index]                  # (legs, 2)
        level = self._level(plan, state)
        base, forces = base.copy(), forces.copy()
        q = state[k.state.q_index]                                 # (legs, 2)
        for i in range(qd.shape[0]):
            u, v = -plan.fy[i], jf[i] @ qd[i]                      # the foot's, from the hip
            if not landing and u < push.takeoff_u:                # pushing
                torque, speed, w_ref = push.at(u)
                force = level[i] + (self._kx * (plan.fx[i] - self._x_center) + self._dx * v[0],
                                    self._dw * (w_ref + v[1]))
                base[k.state.actuators[i]] = self._within(torque, -jf[i].T @ force, qd[i], speed)
                forces[i] = 0.0
            elif plan.weights[i] == 0.0:                          # pushed, in the air
                base[k.state.actuators[i]] = (k.gains.kp * (self._landing_q - q[i])
                                              - k.gains.kd * qd[i])
                forces[i] = 0.0
            elif landing and v[1] > 0.0:                          # down, sinking
                force, w_ref = land.at(u)
                forces[i, 1] = force + level[i, 1] + self._dw * (w_ref + v[1])
        return base, jf, forces

    def _within(self, torque, feedback, speed, planned) -> np.ndarray:
        """The feed-forward torques (2,) N*m plus the largest share (0 .. 1) of the feedback
        torques that the envelope holds both at the joints' speeds and at the optimum's (rad/s),
        the feed-forward itself clipped to it: the optimal push's split between the motors is
        kept where the feedback asks more than they have (the ground force's direction with
        it), and a joint about to start does not get the braking quadrant's larger torque."""
        (up_now, lo_now), (up_plan, lo_plan) = (self._motor.limits(speed),
                                                self._motor.limits(planned))
        upper, lower = np.minimum(up_now, up_plan), np.maximum(lo_now, lo_plan)
        torque = np.clip(torque, lower, upper)
        share = 1.0
        for j in range(2):
            room = upper[j] - torque[j] if feedback[j] > 0.0 else lower[j] - torque[j]
            if feedback[j] != 0.0:
                share = min(share, room / feedback[j])
        return torque + max(share, 0.0) * feedback

    def _level(self, plan, state) -> np.ndarray:
        """Leg-plane ground forces (legs, 2) N of no net force whose moment turns the body
        towards level (roll and pitch, the foot/leg controller's attitude gains)."""
        k = self.constants
        roll, pitch, omega_b = body_attitude(k, state, plan.r_wb)
        g = k.gains
        wrench = np.array([0.0, 0.0, -g.k_att[0] * roll - g.d_att[0] * omega_b[0],
                           -g.k_att[1] * pitch - g.d_att[1] * omega_b[1], 0.0])
        split = split_wrench(k, np.ones(plan.weights.size), plan.fx, plan.fy, wrench, 4)
        return np.stack([k.plane[0, j] * split[0::2] + k.plane[2, j] * split[1::2]
                         for j in range(2)], -1)


@register_controller
@dataclass(frozen=True)
class Tracking(FootLeg):
    """The tracking controller (module docstring): the foot/leg controller's knobs and when a
    gait's tracking takes over; the floor is the scenario's gait's (gait_floor at the scenario's
    payload)."""

    kind: ClassVar[str] = "tracking"
    takeover: float = documented(1.0, "when a gait's tracking takes over from the foot/leg "
                                      "controller, as a share of the gait's ramp (0: its start, "
                                      "1: its end), blended in over one period")

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.takeover", self.takeover, 0.0, 1.0)

    def check_scenario(self, scenario) -> None:
        path = scenario.gait
        require(path.kind in KINDS or path.lands, "scenario.gait", path.kind,
                f"the tracking controller follows a gait's floor or a jump's or a drop's optimal "
                f"strokes: one of {[*KINDS, 'jump', 'drop']}")
        own = [path.leg_phase(leg) for leg in LEGS]
        require(np.allclose(scenario.phases_rad, own), "scenario.phases_rad",
                scenario.phases_rad, f"the tracking controller follows the gait's own leg "
                                     f"phases, {own}")

    def add_to(self, builder, params, layout, scenario) -> FootLegController:
        path = scenario.gait
        if path.lands:
            return self._add_strokes(builder, params, layout, scenario)
        plan = Plan(gait_floor(params, path, scenario.payload_kg), params,
                    path.stance_speed(params.gait), whole_body(params, scenario.payload_kg)[1])
        return builder.AddNamedSystem("leg_controller", TrackingController(
            params, layout, self.gains(params, layout), self, scenario.load_transfer_s, plan,
            path.start_s(scenario.stand_s),
            path.start_s(scenario.stand_s) + self.takeover * scenario.ramp_s,
            builder.GetSubsystemByName("gait_source"), path))

    def _add_strokes(self, builder, params, layout, scenario) -> JumpTrackingController:
        """A jump's or a drop's controller: a jump's optimal push to the path's height (or the
        highest one) from the path's push-off onwards, its window the longer of the path's push
        and the optimum's, and PUSH_WINDOW_SLACK more; the landing's least-torque catch of the
        path's touchdown speed within its landing stroke (the soonest stop, where none does),
        from the push's window's end (a drop: its start) to the planned touchdown and twice the
        catch's time."""
        path, g, payload = scenario.gait, params.gait, scenario.payload_kg
        start, events = path.start_s(scenario.stand_s), path.events(g)
        push, falling = None, start
        if path.pushes:
            jump = maneuver_push(params, path, payload)
            onset = start + events.onset
            falling = onset + max(path.timing(g)[0], jump.stance_s) * (1.0 + PUSH_WINDOW_SLACK)
            push = JumpPlan(jump, onset, falling)
        legs, touchdown = landing_stroke(params, path, payload), path.touchdown_speed(g)
        need = landing_need(params, path, payload)
        # the least-torque catch on the landing stroke, or over the leg's whole reach beyond it;
        # where even that gives way, the soonest stop over the whole reach (the run then says
        # the legs gave way: not achieved)
        landing = need.found if need.found is not None else catch(
            stroke(params, reach(params)[0], float(legs.u[-1]), payload), touchdown)
        return builder.AddNamedSystem("leg_controller", JumpTrackingController(
            params, layout, self.gains(params, layout), self, scenario.load_transfer_s, push,
            CatchPlan(landing, falling, start + events.touchdown + 2.0 * landing.duration_s)))
