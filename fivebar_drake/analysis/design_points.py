"""Many designs at once: the full model's torque analysis (torques.analyze, model "full_trot" or
"full") over one gait cycle for a batch of parameter sets, vectorised over the designs that share
a leg (a sweep's `analysis` fidelity).

A design is the base parameters with some fields changed by dotted path ("gait.frequency_hz",
"leg.ce_m", ...; robots/quadruped/config.with_changes). Designs with the same leg geometry, links, gravity, sample
count and duty factor are solved together: one IK with mode tracking over all their cycles (time first, one
column per design), one pass of the mechanism's Jacobians and dynamics.
"""

from __future__ import annotations

import dataclasses
import numpy as np

from fivebar_drake.verdicts.checks import Checks, checks_of, torque_check, verdict
from fivebar_drake.gaits import cycle_phase, foot_path, path_arrays, stance_loads
from fivebar_drake.actuators.motor import Motor
from fivebar_drake.actuators.thermal import thermal_margin
from fivebar_drake.core.validation import require
from fivebar_drake.mechanisms.fivebar import (MOTORS, UnreachableError, periodic_derivatives,
                                              track_modes)
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.legs import TROT_PHASES_RAD
from fivebar_drake.robots.quadruped.params import Params

MODELS = ("full_trot", "full")   # leg_loads.trot_model, leg_loads.full_model
def motor_figures(motor: Motor, checks: Checks, torque, speed) -> dict:
    """Per-motor figures of joint torques (N*m) at joint speeds (rad/s) sampled over one cycle
    (N, motors), time first: peak |torque|, RMS torque, the safety factor (the torque check's,
    as analyze's answer and the simulation give it: each sample against its own quadrant's
    limit, with the friction) beside the seed's (peak_torque / peak, seed_safety_factor), peak
    |speed|, and on the motor's operating points (Motor.delivered_torque: the joint
    torque plus the output friction) the least ratio of the envelope's torque to the demand in
    its quadrant (Motor.torque_margins), the RMS current and the motor's checks
    (verdicts/checks.motor_checks: each sample against its own quadrant's limit; the margins and
    currents of both motors in one call each)."""
    total = np.abs(torque)
    peak = total.max(0)
    demand = motor.delivered_torque(torque, speed)
    margins, outside = motor.speed_margins(demand, speed)
    current = np.sqrt(np.mean(np.square(motor.currents(demand, speed)), 0))
    out = {"peak_torque_Nm": peak, "rms_torque_Nm": np.sqrt(np.mean(torque**2, 0)),
           "seed_safety_factor": motor.peak_torque_Nm / peak,
           "peak_speed_rad_s": np.abs(speed).max(0),
           "torque_speed_margin": np.min(motor.torque_margins(demand, speed), 0),
           "rms_current_A": current}
    per_motor = [checks_of(motor, checks, torque_check(checks, motor, demand[:, j], speed[:, j]),
                           margins[:, j], outside[:, j], current[j])
                 for j in range(torque.shape[1])]
    out["safety_factor"] = np.array([np.inf if c["torque"]["sf"] is None else c["torque"]["sf"]
                                     for c in per_motor])
    out["speed_margin"] = np.array([c["speed"]["least_margin"] if c["speed"]["least_margin"]
                                    is not None else np.inf for c in per_motor])
    out["speed_outside_fraction"] = np.array([c["speed"]["outside_fraction"] for c in per_motor])
    out["thermal_current_margin"] = np.array([c["thermal"]["margin"] or np.inf for c in per_motor])
    out["checks"] = per_motor
    return out


def _group_key(params: Params):
    return (params.leg, tuple(sorted(params.links.items())), params.robot.gravity_m_s2,
            params.gait.samples, params.gait.duty_factor)


def evaluate_designs(designs: list[Params], path: str = "seed_ellipse",
                     model: str = "full_trot") -> list[dict]:
    """The figures of each design over one cycle of the foot path under the model (MODELS:
    "full_trot", the robot's weight shared by the feet the trot schedule has in stance, none in
    swing; "full", the seed's weight share on the foot all cycle), each as torques.analyze
    computes them: per motor
    (MOTORS) peak_torque_Nm, rms_torque_Nm, safety_factor (the torque check's),
    seed_safety_factor, peak_speed_rad_s, speed_ok (the
    seed's check), torque_speed_margin, speed_margin, speed_outside_fraction,
    thermal_current_margin, verdict (the worst of the torque, speed and thermal checks,
    verdicts/checks.motor_checks), deciding_check, torque_verdict; and stride_speed_m_s (2 a f, the
    foot's mean ground speed on the stride), and with the motor's thermal model thermal_margin_K
    and time_to_winding_limit_s (actuators.thermal.thermal_margin at the RMS current). A design
    whose path leaves the workspace or the leg's limits gets {"error": ...} instead."""
    rows: list[dict | None] = [None] * len(designs)
    groups: dict = {}
    for i, params in enumerate(designs):
        groups.setdefault(_group_key(params), []).append(i)
    require(model in MODELS, "model", model, f"must be one of {list(MODELS)}")
    for members in groups.values():
        for i, row in zip(members, _evaluate_group([designs[i] for i in members], path, model)):
            rows[i] = row
    return rows


def _evaluate_group(designs: list[Params], path: str, model: str) -> list[dict]:
    first = designs[0]
    n = first.gait.samples
    u = cycle_phase(first.gait, np.arange(n) * (first.gait.period_s / n))  # the same for all
    feet = np.empty((n, len(designs), 2))                                   # (N, designs, 2)
    kind = foot_path(path)
    for i, p in enumerate(designs):
        feet[:, i, 0], feet[:, i, 1] = path_arrays(kind.point, kind.constants(p.gait), u)[:2]
    try:
        pose, _ = track_modes(first.leg, feet)
    except UnreachableError as err:    # some designs out of reach: each alone, to name them
        if len(designs) > 1:
            return [row for p in designs for row in _evaluate_group([p], path, model)]
        return [{"error": f"the {path} path leaves the workspace or the leg's limits: {err}"}]
    dt = np.array([p.gait.period_s / p.gait.samples for p in designs])[:, None]
    qd, qdd = periodic_derivatives(pose.q, dt)
    if model == "full":
        load = np.array([p.robot.weight_share_kg * p.robot.gravity_m_s2 for p in designs])
    else:                     # the schedule's share of the weight: the same phases for all
        share = stance_loads(first.gait, path, np.arange(n) * (first.gait.period_s / n),
                             TROT_PHASES_RAD, 1.0)[0]
        load = share[:, None] * np.array([p.robot.total_mass_kg * p.robot.gravity_m_s2
                                          for p in designs])
    loads = dataclasses.replace(full_model(first), foot_load_N=load)
    joint = first.fivebar_leg.torques(loads, pose, qd, qdd).joint          # (N, designs, 2)
    rows = []
    for i, p in enumerate(designs):     # each design's motors add their own rotors
        total = joint[:, i] + p.motor.reflected_inertia_kg_m2 * qdd[:, i]
        figures = motor_figures(p.motor, p.checks, total, qd[:, i])
        checks = figures.pop("checks")
        if p.motor.has_thermal_model:    # the winding at the cycle's RMS current
            heat = thermal_margin(p.motor, figures["rms_current_A"])
            figures["thermal_margin_K"] = heat.margin_K
            figures["time_to_winding_limit_s"] = heat.time_to_limit_s
        row = {"stride_speed_m_s": 2.0 * p.gait.a_m * p.gait.frequency_hz}
        for j, motor in enumerate(MOTORS):
            one = {k: float(v[j]) for k, v in figures.items()}
            one["verdict"], one["deciding_check"] = checks[j]["verdict"], checks[j]["deciding_check"]
            one["torque_verdict"] = verdict(p.checks, one["safety_factor"])
            one["speed_ok"] = bool(one["peak_speed_rad_s"] <= p.motor.no_load_speed_rad_s)
            row[motor] = one
        rows.append(row)
    return rows

