"""The figures of a one-shot maneuver from its plant steps (signals.StepSignals: every step's
contact forces and state, the motor's every sample), so that they do not depend on the log
interval: the jump (takeoff, apex, height, agility, the push-off's work and the rise it bounds),
the landing (touchdown speed, impulse, peak force and torque, compression), each beside its
plan where the maneuver plans it (planned), and the force the motors hold along both against the
force the ground asked (maneuver_figures, capability_along); why a jump did not leave the
ground."""

from __future__ import annotations

import math

import numpy as np

from fivebar_drake.mechanisms.fivebar import MOTORS, forward, held_force, link_jacobians
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import standing_height
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.signals import StepSignals

AIRBORNE_N = 1.0     # a total ground force below this at a plant step: every foot is off
MIN_FLIGHT_S = 0.01  # a flight lasts at least this long: shorter gaps are the contact chattering
GIVE_WAY_S = 0.005   # a landing motor asked to brake beyond its braking limit this long (in all)
#                      gives way: the leg folds faster than the landing planned


def flight(t, fz, after: float) -> tuple[int, int] | None:
    """The first flight after time after (s): (the last step with ground contact before it, -1
    if the run starts in the air; the first step with contact after it, len(t) if none) for
    the first run of steps with the total ground force fz below AIRBORNE_N lasting at least
    MIN_FLIGHT_S (or to the run's end); None if there is none."""
    air = (fz < AIRBORNE_N) & (t > after)
    k = 0
    while k < len(t):
        if not air[k]:
            k += 1
            continue
        end = k
        while end < len(t) and air[end]:
            end += 1
        since = t[k - 1] if k > 0 else t[0] - (t[1] - t[0] if len(t) > 1 else 0.0)
        if end == len(t) or t[end - 1] - since >= MIN_FLIGHT_S:
            return k - 1, end
        k = end
    return None


def maneuver_figures(record: SimulationRecord, start: float, steps: StepSignals) -> dict:
    """A maneuver's figures from its plant steps (steps: step_signals(record); start: the
    maneuver's start, s):
    - jump (a plan with a takeoff): takeoff = the last step with ground contact before the first
      flight (flight) after the push-off's onset; takeoff speed = the centre of mass's vertical
      speed there; height_m = the body's apex above its standing height; time_to_apex_s from the
      onset; agility_m_s = height / that time (Haldane et al. 2016); the push-off's motor work
      (delivered torque at each motor sample x joint speed, every step, summed over the eight
      motors) and the centre of mass's rise it bounds (W / (m g));
    - landing (a jump's or a drop's): from the first step with ground contact after the flight
      to the first whose end has the centre of mass at rest or rising: touchdown speed, the
      ground's impulse and peak force (every step), the motors' peak delivered torque (every
      motor sample), the body's drop (landing_compression_m);
    - force_capability along the push-off and the landing (capability_along);
    - phases: each phase's demand and delivered peaks and braking beyond the limit
      (phase_times, phase_figures).
    - planned beside the jump's and the landing's figures: the plan's value of each figure it
      plans (planned: a jump's height_m, onset_s and takeoff_s, a landing's touchdown_s).
    None where the event did not happen (why_grounded says why no foot left)."""
    scenario, params, lay = record.scenario, record.params, record.layout
    events = {k: start + v for k, v in scenario.gait.events(params.gait).planned().items()}
    mass, g = lay.mass_kg, params.robot.gravity_m_s2
    fz, t = steps.ground_force[:, 2], steps.t
    dt = np.diff(t, prepend=t[0] - record.design.time_step_s)
    out = {"jump": None, "landing": None, "force_capability": None, "why_grounded": "",
           "phases": None}
    phases = {}
    fly = None
    if "takeoff" in events:
        onset = events["onset"]
        fly = flight(t, fz, onset)
        if fly is None:
            out["why_grounded"] = why_grounded(steps, record, (t > onset)
                                               & (t <= events["takeoff"]))
        else:
            k_to, k_td = fly
            k_apex = k_to + int(np.argmax(steps.body_p[k_to:k_td, 2]))
            push = (t > onset) & (t <= t[k_to])
            held = np.searchsorted(steps.motor_t, t - dt, side="right") - 1
            torque = steps.motor_torque[np.maximum(held, 0)]
            work = float(np.sum((torque * steps.qd * dt[:, None, None])[push]))
            height = float(steps.body_p[k_apex, 2]) - standing_height(params)
            k_on = int(np.searchsorted(t, onset))
            out["jump"] = {
                "height_m": height, "takeoff_speed_m_s": float(steps.com_v[k_to, 2]),
                "takeoff_s": float(t[k_to]), "apex_s": float(t[k_apex]), "onset_s": onset,
                "time_to_apex_s": float(t[k_apex] - onset),
                "agility_m_s": height / float(t[k_apex] - onset),
                "com_rise_after_takeoff_m": float(steps.com_p[k_apex:k_td, 2].max()
                                                  - steps.com_p[k_to, 2]),
                "com_rise_m": float(steps.com_p[k_apex:k_td, 2].max() - steps.com_p[k_on, 2]),
                "push_work_J": work, "energy_bound_rise_m": work / (mass * g)}
            out["jump"]["planned"] = planned(out["jump"], scenario.gait.fields(), events)
            phases["push-off"] = push
    elif "touchdown" in events:
        fly = flight(t, fz, t[0] - 1.0)
    if fly is not None and fly[1] < len(t):
        k_td = fly[1]
        rest = np.flatnonzero((np.arange(len(t)) > k_td) & (steps.com_v[:, 2] >= 0.0))
        k_end = int(rest[0]) if rest.size else len(t) - 1
        land = slice(k_td, k_end + 1)
        v_td = float(steps.com_v[k_td - 1, 2])
        t_td, t_end = float(t[k_td - 1]), float(t[k_end])
        samples = (steps.motor_t >= t_td) & (steps.motor_t < t_end)
        landing = {
            "touchdown_s": t_td, "end_s": t_end,
            "touchdown_speed_m_s": -v_td, "duration_s": t_end - t_td,
            "impulse_N_s": float(np.sum(fz[land] * dt[land])),
            "momentum_change_N_s": float(mass * (steps.com_v[k_end, 2] - v_td)),
            "peak_force_N": float(fz[land].max()),
            "peak_torque_Nm": float(np.abs(steps.motor_torque[samples]).max()),
            "compression_m": float(steps.body_p[k_td - 1, 2] - steps.body_p[land, 2].min())}
        landing["planned"] = planned(landing, scenario.gait.fields(), events)
        out["landing"] = landing
        phases["landing"] = np.zeros(len(t), dtype=bool)
        phases["landing"][land] = True
        if out["jump"] is not None:
            out["jump"]["landing_peak_torque_Nm"] = landing["peak_torque_Nm"]
            out["jump"]["landing_compression_m"] = landing["compression_m"]
    if phases:
        out["force_capability"] = capability_along(steps, params, phases, lay.legs)
    out["phases"] = phase_figures(steps, params, phase_times(out, float(t[0]), float(t[-1]),
                                                             events), lay.legs)
    return out


def planned(figures: dict, plan: dict, events: dict) -> dict[str, float]:
    """The plan of each measured figure the plan names: a field of the maneuver (plan:
    Variant.fields) or an event (events: name -> s, as "<name>_s") of the figure's key, e.g. a
    jump's planned height_m and takeoff_s beside the measured ones."""
    named = {**plan, **{f"{name}_s": t for name, t in events.items()}}
    return {key: float(named[key]) for key in figures if key in named
            and isinstance(named[key], (int, float)) and not isinstance(named[key], bool)}


def phase_times(figures: dict, t0: float, t1: float, events: dict) -> dict:
    """The maneuver's measured phases (name -> (start, end) s) from its figures: a jump's
    crouch (to the push-off's onset), push-off (to takeoff), flight, landing (to the end of
    the landing) and recovery (to the run's end); a drop's fall, landing and recovery; a
    maneuver without these events, its whole run as one phase."""
    jump, landing = figures["jump"], figures["landing"]
    marks = [("before", t0)]
    if jump:
        marks += [("crouch", t0), ("push-off", jump["onset_s"]), ("flight", jump["takeoff_s"])]
    elif "takeoff" in events:
        marks += [("crouch", t0), ("push-off", events["onset"])]
    elif landing:
        marks += [("fall", t0)]
    else:
        marks += [("whole", t0)]
    if landing:
        marks += [("landing", landing["touchdown_s"]), ("recovery", landing["end_s"])]
    marks = marks[1:]
    return {name: (start, marks[k + 1][1] if k + 1 < len(marks) else t1)
            for k, (name, start) in enumerate(marks)}


def phase_figures(steps: StepSignals, params: Params, times: dict, legs) -> dict:
    """Per phase (name -> (start, end) s) from the motor's every sample: the largest demand
    (the command) and delivered torque (N*m, any motor, and which), and the time (s, summed
    over samples) any motor was asked to brake (command against the joint's speed) beyond its
    braking limit at that speed (Motor.limits); a landing where that time exceeds GIVE_WAY_S
    gives way (gives_way)."""
    motor = params.motor
    upper, lower = motor.limits(steps.motor_speed)
    command, speed = steps.motor_command, steps.motor_speed
    braking = command * speed < 0.0
    beyond = braking & ((command > upper) | (command < lower))
    period = float(np.median(np.diff(steps.motor_t))) if len(steps.motor_t) > 1 else 0.0
    out = {}
    for name, (start, end) in times.items():
        rows = (steps.motor_t >= start) & (steps.motor_t < end)
        if not rows.any():
            continue
        demand = np.abs(command[rows]).max(axis=0)
        k = np.unravel_index(np.argmax(demand), demand.shape)
        over = float(beyond[rows].any(axis=(1, 2)).sum() * period)
        out[name] = {"start_s": start, "end_s": end, "demand_peak_Nm": float(demand[k]),
                     "demand_peak_motor": f"{legs[k[0]]} {MOTORS[k[1]]}",
                     "delivered_peak_Nm": float(np.abs(steps.motor_torque[rows]).max()),
                     "braking_beyond_limit_s": over}
        if name == "landing":
            out[name]["gives_way"] = over > GIVE_WAY_S
    return out


def why_grounded(steps: StepSignals, record: SimulationRecord, push) -> str:
    """Why no foot left the ground: the largest ground force of the push-off (steps) against
    the weight, and what the legs' torque box holds vertically at the crouch (the figure that
    stops the jump)."""
    params, lay = record.params, record.layout
    weight = lay.mass_kg * params.robot.gravity_m_s2
    if not push.any():
        return "the run ended before the push-off"
    k = int(np.flatnonzero(push)[0])
    jf = link_jacobians(params.leg, params.links, forward(params.leg, steps.q[k])).jf
    held = held_force(jf, params.motor.peak_torque_Nm, -params.motor.peak_torque_Nm,
                      np.array([0.0, 1.0])).sum()
    return (f"the push-off's largest ground force was {steps.ground_force[push, 2].max():.0f} N "
            f"against the weight {weight:.0f} N; at the crouch the legs hold at most {held:.0f} N "
            f"vertically with their {params.motor.peak_torque_Nm:.2f} N·m motors")


def capability_along(sig: StepSignals, params: Params, phases: dict, legs) -> dict:
    """The measured ground force on each foot against the force the motors can hold along it,
    over the steps of each phase (a name -> step mask) where the foot carries more than a tenth
    of its share of the weight: the torque box |tau| <= peak and the envelope at the joint speeds
    (Motor.limits) through J_F^T (held_force). Arrays per phase (steps; foot height y in the leg
    plane, required and available N, per leg) and the least ratio available / required."""
    motor = params.motor
    pose = forward(params.leg, sig.q)
    jf = link_jacobians(params.leg, params.links, pose).jf
    force = sig.foot_force_plane
    size = np.linalg.norm(force, axis=-1)
    unit = force / np.maximum(size, 1e-12)[..., None]
    box = held_force(jf, motor.peak_torque_Nm, -motor.peak_torque_Nm, unit)
    upper, lower = motor.limits(sig.qd)
    envelope = held_force(jf, upper, lower, unit)
    floor = 0.1 * params.robot.total_mass_kg * params.robot.gravity_m_s2 / force.shape[1]
    out, least = {"phases": {}}, {"box": (math.inf, None), "envelope": (math.inf, None)}
    for name, rows in phases.items():
        loaded = rows[:, None] & (size > floor)
        out["phases"][name] = {"t": sig.t[rows], "foot_y_m": pose.f[rows, :, 1],
                               "required_N": np.where(loaded, size, np.nan)[rows],
                               "box_N": box[rows], "envelope_N": envelope[rows]}
        for key, held in (("box", box), ("envelope", envelope)):
            ratio = np.where(loaded, held / np.maximum(size, 1e-12), np.inf)
            k = np.unravel_index(np.argmin(ratio), ratio.shape)
            if ratio[k] < least[key][0]:
                least[key] = (float(ratio[k]), (name, float(sig.t[k[0]]), int(k[1])))
    for key, (ratio, where) in least.items():
        out[f"least_ratio_{key}"] = ratio if where else None
        out[f"least_{key}_at"] = {"phase": where[0], "t_s": where[1], "leg": legs[where[2]]} \
            if where else None
    return out
