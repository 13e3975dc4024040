"""What a simulated run needed, against the static estimates: whole-cycle statistics per leg
and motor from its signals (simulation/signals.py), the checks and the verdict, the answer in one
sentence, summary.json and summary.md.

Statistics cover the whole gait cycles after the ramp (a one-shot maneuver: its span after
standing); a run with fewer than MIN_CYCLES of them, or one that stopped early, gets the verdict
"insufficient". The leg's limits (limits.py) are checked over the whole run: which leg reached
which limit, when first, for how long, how far. A maneuver's own figures (jump, landing, force
capability) come from simulation/maneuver_figures.py.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
import numpy as np

from fivebar_drake.core.checks import (CHECK_ORDER, SEVERITY, at_limit, demand_unmet,
                                       limit_shares, limit_shares_text, motor_checks,
                                       verdict)
from fivebar_drake.core.files import json_ready, write_atomic
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import standing_height
from fivebar_drake.simulation.maneuver_figures import maneuver_figures
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.scenario import Scenario
from fivebar_drake.simulation.signals import Signals, StepSignals


SUMMARY_FILES = ("summary.md", "summary.json")   # summary.json last: its presence means complete
MIN_CYCLES = 3            # fewer whole cycles than this give no verdict
PERCENTILE = 99.0

# Mid-swing, where a foot on the ground drags: after lift-off and before the descent to an early
# touchdown (the trot path lifts a foot 1.4 mm by 10 % of its swing, 18 mm by 70 %).
MID_SWING = (0.1, 0.7)

# A limit counts as reached within this of its bound, in the field's unit: Drake's joint limits
# (the motor ranges and the least knee angle, sdf.py) stop a joint at its bound, so a stopped
# joint lies at it, not past it.
LIMIT_REACHED = {"deg": 0.1, "m": 1e-4}


def limit_report(sig: Signals, params: Params, legs) -> dict:
    """The run against the leg's limits: the limits set ([limits], the file's units) and each
    (leg, limit) reached (within LIMIT_REACHED of its bound, or past it) in some recorded
    interval: its field, bound and unit, the time of the first such interval (its end, s), the
    share of the run's intervals, and the worst value with its time."""
    hits = []
    for test in sig.limits:
        reached = test.excess * test.scale > -LIMIT_REACHED[test.unit]
        for i, leg in enumerate(legs):
            rows = np.flatnonzero(reached[:, i])
            if not rows.size:
                continue
            worst = rows[np.argmax(test.excess[rows, i])]
            hits.append({"leg": leg, "limit": test.name, "field": f"limits.{test.field}",
                         "bound": test.bound * test.scale, "unit": test.unit,
                         "first_t_s": float(sig.t[rows[0]]),
                         "share_of_time": rows.size / len(sig.t),
                         "worst_value": float(test.value[worst, i] * test.scale),
                         "worst_t_s": float(sig.t[worst])})
    return {"set": params.limits.given, "hits": hits}


def limits_text(report: dict) -> str:
    """The limit report (limit_report) in one line."""
    if not report["set"]:
        return "limits: none set ([limits] of the parameter file)"
    if not report["hits"]:
        return f"limits: none reached ({len(report['set'])} set in [limits])"
    return "limits reached: " + "; ".join(
        f"{h['leg']} {h['limit']} first at t = {h['first_t_s']:.3f} s, {h['share_of_time']:.1%} "
        f"of the time, worst {h['worst_value']:.4g} {h['unit']} (bound {h['bound']:.4g} "
        f"{h['unit']}, {h['field']})" for h in report["hits"])


def cycle_window(scenario: Scenario, params: Params, t_end: float) -> tuple[float, float, int]:
    """Start and end (s) of the whole gait cycles after the ramp that fit before t_end, and
    their number. Cycles start where the gait time t - stand_s is a multiple of the period. A
    maneuver's window is its span from its start, 1 if it fits before t_end, else 0."""
    path = scenario.gait
    if not path.periodic:
        start = path.start_s(scenario.stand_s)
        end = start + path.span_s(params.gait)
        return start, end, int(t_end >= end - 1e-9)
    period = params.gait.period_s
    start = scenario.stand_s + math.ceil(scenario.ramp_s / period - 1e-9) * period
    cycles = max(0, math.floor((t_end - start) / period + 1e-9))
    return start, start + cycles * period, cycles


def window_rows(t, window_s) -> np.ndarray:
    """Which rows (interval-end times t, s) the statistics window window_s = [start, end] (s)
    holds: those whose interval's middle lies in it."""
    half_row = 0.5 * float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    return (t > window_s[0] + half_row) & (t <= window_s[1] + half_row)


def _p(x, q=PERCENTILE) -> float:
    return float(np.percentile(np.abs(x), q)) if np.size(x) else float("nan")


def _peak(x) -> float:
    return float(np.max(np.abs(x))) if np.size(x) else float("nan")


def _rms(x) -> float:
    return float(np.sqrt(np.mean(np.square(x)))) if np.size(x) else float("nan")


def _mean(x) -> float:
    return float(np.mean(x)) if np.size(x) else float("nan")


def _ratio(a: float, b: float) -> float:
    return a / b if b else float("nan")


def _spread(values) -> list[float]:
    return [float(min(values)), float(max(values))] if len(values) else [math.nan, math.nan]


def motor_summary(sig: Signals, params: Params, win, cycle, cycles: int, i: int, j: int) -> dict:
    """Statistics of motor j of leg i over the window rows `win` (cycle: each row's cycle)."""
    motor = params.motor
    applied, demand = sig.applied[win, i, j], sig.command[win, i, j]
    speed = sig.qd[win, i, j]
    parts = {"contact": sig.static_contact, "links": sig.links, "rotor": sig.rotor,
             "friction": sig.friction}
    k = int(np.argmax(np.abs(applied))) if applied.size else 0
    residual = applied - sum(v[win, i, j] for v in parts.values())
    per_cycle = [(applied[cycle == c], demand[cycle == c]) for c in range(cycles)]
    demand_p99, applied_p99 = _p(demand), _p(applied)
    static_seed, static_trot = _peak(sig.static_seed[win, i, j]), _peak(sig.static_trot[win, i, j])
    clipped_peak, clipped_line = sig.clipped_peak[win, i, j], sig.clipped_line[win, i, j]
    # the quadrant of each clipped interval: of the torque the motor delivered (applied here)
    shares = limit_shares(clipped_peak, clipped_line, applied * speed < 0.0)
    checks = at_limit(motor_checks(motor, params.checks, demand, speed, PERCENTILE, applied),
                      params.checks, motor, applied, speed, shares, 1.0 - PERCENTILE / 100,
                      PERCENTILE) if demand.size else None
    sf = checks["torque"]["sf"] if checks and checks["torque"]["sf"] is not None else math.nan
    clipped = clipped_peak + clipped_line
    saturated, unsaturated = _mean(clipped), demand[clipped == 0]
    return {
        "checks": checks, "unsaturated_demand_p99_Nm": _p(unsaturated),
        "peak_torque_Nm": _peak(applied), "p99_torque_Nm": applied_p99,
        "rms_torque_Nm": _rms(applied),
        "demand_peak_Nm": _peak(demand), "demand_p99_Nm": demand_p99,
        "static_seed_Nm": static_seed, "static_trot_Nm": static_trot,
        "static_contact_Nm": _peak(sig.static_contact[win, i, j]),
        "dynamic_to_seed_static": _ratio(demand_p99, static_seed),
        "dynamic_to_trot_static": _ratio(demand_p99, static_trot),
        "safety_factor": sf, "verdict": checks["verdict"] if checks else "insufficient",
        "deciding_check": checks["deciding_check"] if checks else None,
        "saturated_fraction": saturated, "limit_shares": shares,
        "clipped_peak_fraction": _mean(clipped_peak),
        "clipped_line_fraction": _mean(clipped_line),
        "peak_speed_rad_s": _peak(speed), "p99_speed_rad_s": _p(speed),
        "no_load_speed_rad_s": motor.no_load_speed_rad_s,
        "speed_ok": bool(_peak(speed) <= motor.no_load_speed_rad_s),
        "decomposition_rms_Nm": {**{name: _rms(v[win, i, j]) for name, v in parts.items()},
                                 "residual": _rms(residual)},
        "decomposition_at_peak_Nm": {name: float(v[win, i, j][k]) if applied.size else math.nan
                                     for name, v in parts.items()},
        "per_cycle_peak_Nm": [_peak(a) for a, _ in per_cycle],
        "per_cycle": {
            "peak_torque_Nm": _spread([_peak(a) for a, _ in per_cycle]),
            "rms_torque_Nm": _spread([_rms(a) for a, _ in per_cycle]),
            "demand_p99_Nm": _spread([_p(d) for _, d in per_cycle]),
        },
    }


def _drag(sig: Signals, win, i: int) -> float:
    """Fraction of the mid-swing samples (MID_SWING) of leg i in which its foot is loaded."""
    frac = sig.swing_fraction[win, i]
    mid = (frac >= MID_SWING[0]) & (frac <= MID_SWING[1])
    return float(np.mean(sig.swing_contact[win, i][mid])) if mid.any() else math.nan


def summarize(sig: Signals, record: SimulationRecord, seed_analysis: dict,
              steps: StepSignals | None) -> dict:
    """The summary.json dictionary (SI units) of a run from its signals (signals(record)), its
    plant steps (step_signals(record), a one-shot maneuver's; None for a gait) and record.
    seed_analysis: the analysis results of the seed model on the seed's ellipse (report.json's
    results.seed)."""
    scenario, params, design = record.scenario, record.params, record.design
    leg_names = record.layout.legs
    t_end = float(sig.t[-1]) if len(sig.t) else 0.0
    half_row = 0.5 * float(np.median(np.diff(sig.t))) if len(sig.t) > 1 else 0.0
    start, end, cycles = cycle_window(scenario, params, t_end + half_row)
    win = window_rows(sig.t, (start, end))
    cycle_s = scenario.gait.span_s(params.gait)
    cycle = np.clip(np.floor((sig.t[win] - start - half_row) / cycle_s), 0,
                    max(cycles - 1, 0)).astype(int)
    legs = {leg: {name: motor_summary(sig, params, win, cycle, cycles, i, j)
                  for j, name in enumerate(MOTORS)} for i, leg in enumerate(leg_names)}
    completed = record.completed
    sufficient = completed and cycles >= (MIN_CYCLES if scenario.gait.periodic else 1)
    p = sig.body_p[win]
    tw = sig.t[win]
    speed = float((p[-1, 0] - p[0, 0]) / (tw[-1] - tw[0])) if len(tw) > 1 else math.nan
    gait_speed = scenario.gait.stance_speed(params.gait)
    max_tilt = float(np.max(sig.tilt_deg)) if len(sig.t) else math.nan
    maneuver = maneuver_figures(record, start, steps) if not scenario.gait.periodic else None
    run_why = achievement(params, speed, gait_speed, max_tilt, scenario.gait.goal,
                          float(sig.body_p[win][-1, 2]) if win.any() else math.nan,
                          standing_height(params), maneuver)
    for ms in legs.values():
        for m in ms.values():
            if m["checks"] is not None:
                m["checks"]["achieved"] = motor_achieved(params, m, run_why)
                if m["checks"]["achieved"]["verdict"] == "not_achieved":
                    m["verdict"], m["deciding_check"] = "not_achieved", "achieved"
    motors = [(leg, name, m) for leg, ms in legs.items() for name, m in ms.items()]
    worst_leg, worst_motor, worst = max(motors, key=lambda x: badness(x[2]))
    scheduled_swing = (~sig.stance[win]).sum(0)
    seed_peak = max(seed_analysis[m]["peak_torque_Nm"] for m in MOTORS)
    summary = {
        "gait": scenario.gait.kind, "closure": scenario.closure.kind,
        "ran": {"gait": scenario.gait.fields(), "controller": scenario.controller.fields(),
                "closure": scenario.closure.fields(),
                "planned_events_s": {k: start + v for k, v in
                                     scenario.gait.events(params.gait).items()}},
        "duration_s": t_end, "requested_duration_s": scenario.duration_s,
        "completed": completed, "interrupted": bool(record.interrupted),
        "error": record.error or (f"interrupted by {record.interrupted} at t = {t_end:.2f} s"
                                  if record.interrupted else ""),
        "cycles_in_window": cycles, "window_s": [start, end],
        "verdict": worst["verdict"] if sufficient else "insufficient",
        "deciding_check": worst["deciding_check"] if sufficient else None,
        "worst_motor": f"{worst_leg} {worst_motor}",
        "max_tilt_deg": max_tilt,
        "mean_forward_speed_m_s": speed,
        "gait_speed_m_s": gait_speed,
        "gait_frequency_hz": params.gait.frequency_hz,
        "periodic": scenario.gait.periodic, "cycle_s": cycle_s,
        "jump": maneuver["jump"] if maneuver else None,
        "landing": maneuver["landing"] if maneuver else None,
        "phases": maneuver["phases"] if maneuver else None,
        "force_capability": {k: v for k, v in maneuver["force_capability"].items()
                             if k != "phases"} if maneuver and maneuver["force_capability"]
        else None,
        "payload_kg": scenario.payload_kg, "slope_deg": scenario.slope_deg,
        "swing_clear_fraction": {leg: float(1 - sig.swing_contact[win, i].sum()
                                            / max(scheduled_swing[i], 1))
                                 for i, leg in enumerate(leg_names)},
        "swing_drag_fraction": {leg: _drag(sig, win, i) for i, leg in enumerate(leg_names)},
        "body_height_m": {"min": float(sig.body_p[:, 2].min()), "max": float(sig.body_p[:, 2].max())}
        if len(sig.t) else None,
        "vertical_support": vertical_support(sig, record, win),
        "max_loop_gap_m": float(np.max(sig.gap)) if len(sig.t) else math.nan,
        "max_loop_gap_per_leg_m": {leg: float(np.max(sig.gap[:, i])) if len(sig.t) else math.nan
                                   for i, leg in enumerate(leg_names)},
        "time_step_s": design.time_step_s,
        "log_period_s": scenario.log_period_s,
        "real_time_factor": t_end / record.wall_s if record.wall_s > 0 else math.nan,
        "wall_time_s": record.wall_s,
        "bushing": None if design.bushing is None else {
            "stiffness_N_m": design.bushing.stiffness_N_m,
            "damping_N_s_m": design.bushing.damping_N_s_m},
        "knee_effective_mass_kg": design.m_eff_kg, "design_loop_force_N": design.loop_force_N,
        "controller_gains": None if record.gains is None else {
            k: np.asarray(v).tolist() for k, v in record.gains._asdict().items()},
        "seed_peak_torque_Nm": seed_peak,
        "seed_load_model": seed_analysis_load(params),
        "motor_peak_torque_Nm": params.motor.peak_torque_Nm,
        "motor": {"model": params.motor.model, "gear_ratio": params.motor.gear_ratio,
                  "peak_torque_Nm": params.motor.peak_torque_Nm,
                  "braking_peak_torque_Nm": params.motor.braking_peak_torque_Nm,
                  "no_load_speed_rad_s": params.motor.no_load_speed_rad_s,
                  "continuous_torque_Nm": params.motor.continuous_torque_Nm},
        "step_check": None,
        "limits": limit_report(sig, params, leg_names),
        "legs": legs,
    }
    summary["answer"] = answer(summary, params)
    return summary


def vertical_support(sig: Signals, record: SimulationRecord, win) -> dict | None:
    """A gait's delivered vertical ground force over the window against the robot's weight
    (interval means of every plant step's contact forces): its least share (the dip at a
    touchdown or lift-off) and its largest (the overshoot), and when; None for a one-shot
    maneuver (its landing has its own figures) or an empty window."""
    if not record.scenario.gait.periodic or not win.any():
        return None
    share = sig.ground_force[win, 2] / (record.layout.mass_kg
                                        * -record.layout.gravity_m_s2[2])
    t = sig.t[win]
    return {"least_share": float(share.min()), "least_at_s": float(t[np.argmin(share)]),
            "largest_share": float(share.max()), "largest_at_s": float(t[np.argmax(share)])}


def seed_analysis_load(params: Params) -> str:
    """The seed's load model in words (its figure is on the seed's own path)."""
    return (f"the seed's model on the seed's ellipse: G(q) with its weight share "
            f"{params.robot.weight_share_kg:.3f} kg at every foot all cycle, swing included")


def achievement(params: Params, speed: float, gait_speed: float, max_tilt: float,
                goal: str = "speed", end_height: float = math.nan,
                standing_m: float = math.nan, maneuver: dict | None = None) -> str:
    """Why the run did not do its motion ("" if it did), by the foot path's goal: "speed" (a
    gait): the mean forward speed against checks.achieved_speed_fraction of the gait's; "stand"
    (a stand-up, a drop): the body ends within checks.achieved_height_tolerance_m of its
    standing height standing_m (m); "jump": all feet left the ground, and it ends standing;
    a landing whose legs gave way (maneuver_figures.phase_figures); always the tilt against
    achieved_max_tilt_deg."""
    c, why = params.checks, []
    if goal == "jump" and (maneuver is None or maneuver["jump"] is None):
        why.append("no foot left the ground" + (f" ({maneuver['why_grounded']})"
                                                if maneuver else ""))
    if goal in ("stand", "jump") and not abs(end_height - standing_m) <= \
            c.achieved_height_tolerance_m:
        why.append(f"it ended with the body at {end_height * 1e3:.0f} mm, not within "
                   f"{c.achieved_height_tolerance_m * 1e3:g} mm of its standing height "
                   f"{standing_m * 1e3:.0f} mm")
    if goal == "speed" and gait_speed > 0 and not speed >= c.achieved_speed_fraction * gait_speed:
        why.append(f"it walked {speed:.3f} m/s, less than {c.achieved_speed_fraction:.0%} of the "
                   f"gait's {gait_speed:.3f} m/s")
    landing = ((maneuver or {}).get("phases") or {}).get("landing")
    if landing and landing["gives_way"]:
        why.append(f"the legs gave way at the landing: the motors were asked to brake beyond "
                   f"their braking limit for {landing['braking_beyond_limit_s'] * 1e3:.0f} ms")
    if not max_tilt <= c.achieved_max_tilt_deg:
        why.append(f"the body tilted {max_tilt:.1f} deg, beyond {c.achieved_max_tilt_deg:g} deg")
    return "; ".join(why)


def motor_achieved(params: Params, m: dict, run_why: str) -> dict:
    """The motor's achieved check: the run followed its gait (run_why == "") and the motor sat
    at its limits (either quadrant, torque or voltage) at most
    checks.achieved_max_limit_fraction of the time."""
    why = [run_why] if run_why else []
    limit = params.checks.achieved_max_limit_fraction
    if m["saturated_fraction"] > limit:
        why.append(f"the motor sat at {limit_shares_text(m['limit_shares'])} ("
                   f"{m['saturated_fraction']:.1%} in all, more than {limit:.0%})")
    return {"verdict": "not_achieved" if why else "pass", "why": "; ".join(why),
            "at_limit_fraction": m["saturated_fraction"]}


def badness(m: dict) -> tuple:
    """Order of motors, worst last: not achieved; then by verdict; among equal verdicts the
    deciding check (torque before speed before thermal), then its figure (the lower the safety
    factor, then the longer at the motor's limits; the larger the share outside the envelope or
    the lower its margin, the worse)."""
    if m["checks"] is None:
        return (-1,)
    if m["verdict"] == "not_achieved":
        return (3, 0, m["saturated_fraction"], 0.0)
    c, deciding = m["checks"], m["deciding_check"]
    big = math.inf
    figure = {"torque": (-(c["torque"]["sf"] or big), c["torque"].get("at_limit_fraction", 0.0)),
              "speed": (c["speed"]["outside_fraction"], -(c["speed"]["least_margin"] or big)),
              "thermal": (0.0, -(c["thermal"]["margin"] or big))}[deciding]
    return (SEVERITY[m["verdict"]], -CHECK_ORDER.index(deciding), *figure)


def answer(s: dict, params: Params) -> str:
    """The plain sentence that answers 'how much torque does the gait need?' for this run,
    naming the check that decided the verdict; the static torque on the same poses with the
    same load schedule beside it, and the seed's own figure separately with its load model."""
    if s["verdict"] == "insufficient":
        if not s["completed"] and not s["interrupted"]:
            return (f"No verdict: the run stopped early ({s['error']}): the gait, the "
                    "controller or the motors could not carry the robot through it.")
        why = (f"the run stopped early ({s['error']})" if not s["completed"] else
               f"it covered {s['cycles_in_window']} whole gait cycles after the ramp, fewer than "
               f"{MIN_CYCLES}")
        return (f"No verdict: {why}; run at least {MIN_CYCLES} whole cycles after the "
                f"{s['window_s'][0]:g} s of standing and ramp.")
    leg, name = s["worst_motor"].split()
    m = s["legs"][leg][name]
    c = m["checks"]
    head = (f"At {s['gait_frequency_hz']:g} Hz with the {s['gait']} gait" if s["periodic"] else
            f"For the {s['gait']} maneuver")
    seed = (f"Separately, {seed_analysis_load(params)}, gives {s['seed_peak_torque_Nm']:.2f} N·m "
            "(its peak).")
    if s["verdict"] == "not_achieved":
        why = c["achieved"]["why"]
        if m["saturated_fraction"] > params.checks.achieved_max_limit_fraction:
            need = (f"the motors need more than they give (worst motor {leg} {name}, at "
                    f"{limit_shares_text(m['limit_shares'])}; below its limits its demand p99 is "
                    f"{m['unsaturated_demand_p99_Nm']:.2f} N·m)")
        else:
            need = (f"its demand p99 of {m['demand_p99_Nm']:.2f} N·m (worst motor {leg} {name}) "
                    "is not a need")
        return (f"{head} the motion was NOT ACHIEVED ({why}): {need}; the saturated demand is "
                f"the controller's error growing, not what the gait takes. {seed}")
    checks = "; ".join(check_text(k, c[k]) for k in CHECK_ORDER)
    verdict_text = (f"{s['verdict'].upper()}, decided by the {s['deciding_check']} check"
                    if s["verdict"] != "marginal" else
                    f"MARGINAL: {s['step_check']['why']} (step check at half the plant step)")
    static = m["static_trot_Nm"]
    over = f"over {s['cycles_in_window']} {'cycles' if s['periodic'] else 'maneuver'}"
    limited = demand_unmet(c)
    figure = m["p99_torque_Nm"] if limited else m["demand_p99_Nm"]
    t = c["torque"]
    if limited:
        need = (f"the motors worked at their limits (worst motor {leg} {name}, at "
                f"{limit_shares_text(limited['limits'])}, {over}): they delivered "
                f"{m['p99_torque_Nm']:.2f} N·m ({PERCENTILE:g}th percentile; against each "
                f"sample's own quadrant {t['share_of_limit']:.0%} of the {t['quadrant']} limit, "
                f"{t['limit_Nm']:.2f} N·m), and what the controller asked beyond the limit was "
                "not needed: the motion was achieved without it (the demand's "
                f"{PERCENTILE:g}th percentile: {m['demand_p99_Nm']:.2f} N·m)")
    else:
        reached = ("it never reached a limit" if not m["saturated_fraction"] else
                   f"it sat at {limit_shares_text(m['limit_shares'])}")
        need = (f"the motors need {m['demand_p99_Nm']:.2f} N·m ({PERCENTILE:g}th percentile "
                f"of the demand {over}, worst motor {leg} {name}; against each sample's own "
                f"quadrant {t['share_of_limit']:.0%} of the {t['quadrant']} limit, "
                f"{t['limit_Nm']:.2f} N·m; {reached})")
    return (f"{head} {need}. "
            f"Verdict {verdict_text}. Checks: {checks}. On the same poses with the same load schedule "
            f"(the robot's weight shared by the feet in stance) the static torque is "
            f"{static:.2f} N·m: the dynamics add {figure / static - 1:+.0%}. {seed}")


def check_text(name: str, c: dict) -> str:
    limit = f" ({c['why']})" if "at_limit_fraction" in c else ""
    if name == "torque":
        if c["sf"] is None:
            return f"torque: no demand, {c['verdict']}"
        what = " on what it delivered" if "demand_sf" in c else ""
        return (f"torque: safety factor {c['sf']:.2f}{what} ({c['quadrant']}, against its "
                f"{c['limit_Nm']:.2f} N·m limit), {c['verdict']}{limit}")
    if name == "speed":
        least = "none driving" if c["least_margin"] is None else f"{c['least_margin']:.2f}"
        return (f"speed: least margin {least}, {c['outside_fraction']:.1%} of the time beyond "
                f"the envelope, {c['verdict']}{limit}")
    if c["margin"] is None:
        return f"thermal: {c.get('why', 'no model')}"
    return (f"thermal: continuous / RMS current {c['margin']:.2f}, {c['verdict']}")


STEP_ORDER = 1   # the discrete plant's time stepping is first order in the step: a figure's
#                  error at step h is about (f(h) - f(h/2)) / (2^p - 1) (measured on the default
#                  trot's worst SF: 1.505, 1.457, 1.416, 1.405 at 2, 1, 0.5, 0.25 ms)


def extrapolated(at_step: float, at_half: float) -> tuple[float, float]:
    """Richardson's estimate of a figure at step 0 from its values at steps h and h/2 (order
    STEP_ORDER) and its error: (f(h/2) + d, |d|), d = (f(h/2) - f(h)) / (2^p - 1)."""
    d = (at_half - at_step) / (2.0 ** STEP_ORDER - 1.0)
    return at_half + d, abs(d)


def apply_step_check(summary: dict, half: dict, params: Params) -> dict:
    """Put the step check into the summary (summary["step_check"]) from the summary of the same
    run at half the plant step: per motor the relative change of the demand p99 and RMS, the
    safety factor at half the step and its converged estimate with its error (extrapolated);
    the worst motor's converged safety factor decides: the verdict becomes "marginal" (and the
    answer says so) when its error band reaches a threshold (checks.sf_pass, sf_warn) or its
    torque verdict differs from the run's, where the torque check decides the verdict or would
    make it worse; or when the verdict at half the step differs. A maneuver's event figures
    (jump, landing) get their value at half the step and their converged estimate too."""
    motors, worst = {}, None
    for leg, ms in summary["legs"].items():
        for name, m in ms.items():
            h = half["legs"][leg][name]
            estimate, error = extrapolated(m["safety_factor"], h["safety_factor"])
            motors[f"{leg} {name}"] = {
                "demand_p99_change": _ratio(h["demand_p99_Nm"], m["demand_p99_Nm"]) - 1.0,
                "rms_change": _ratio(h["rms_torque_Nm"], m["rms_torque_Nm"]) - 1.0,
                "sf_change": h["safety_factor"] - m["safety_factor"],
                "sf_at_half_step": h["safety_factor"], "sf_converged": estimate,
                "sf_error": error, "verdict_at_half_step": h["verdict"]}
            if math.isfinite(estimate) and (worst is None or estimate < worst[1]):
                worst = (f"{leg} {name}", estimate, error)
    events = {}
    for group in ("jump", "landing"):
        if summary.get(group) and half.get(group):
            events[group] = {key: dict(zip(("at_half_step", "converged", "error"),
                                           (half[group][key],
                                            *extrapolated(value, half[group][key]))))
                             for key, value in summary[group].items()
                             if isinstance(value, float) and isinstance(half[group].get(key),
                                                                        float)}
    thresholds = (params.checks.sf_pass, params.checks.sf_warn)
    near = [t for t in thresholds if worst and abs(worst[1] - t) <= worst[2]]
    converged = verdict(params.checks, worst[1]) if worst else None
    torque_now = verdict(params.checks, min(m["safety_factor"] for ms in summary["legs"].values()
                                            for m in ms.values()))
    moved = converged is not None and converged != torque_now
    changed = half["verdict"] != summary["verdict"]
    # the torque figure's step error matters where the torque check decides, or would
    if not (summary.get("deciding_check") == "torque" or converged is not None and
            SEVERITY.get(converged, 0) > SEVERITY.get(summary["verdict"], 0)):
        near, moved = [], False
    check = {"time_step_s": summary["time_step_s"], "half_time_step_s": half["time_step_s"],
             "order": STEP_ORDER, "motors": motors,
             "worst_sf_change": max((abs(v["sf_change"]) for v in motors.values()
                                     if math.isfinite(v["sf_change"])), default=0.0),
             "worst_demand_p99_change": max((abs(v["demand_p99_change"]) for v in
                                             motors.values()), default=math.nan),
             "converged_worst_motor": worst[0] if worst else None,
             "converged_sf": worst[1] if worst else None,
             "converged_sf_error": worst[2] if worst else None,
             "torque_verdict_converged": converged, "events": events,
             "verdict_at_half_step": half["verdict"],
             "marginal": bool(near or changed or moved),
             "why": (f"the converged worst safety factor {worst[1]:.3f} ± {worst[2]:.3f} "
                     f"({worst[0]}) reaches {near[0]:g}" if near else
                     f"the converged worst safety factor {worst[1]:.3f} ({worst[0]}) gives "
                     f"{converged}, the run {torque_now}" if moved else
                     f"the verdict at half the step is {half['verdict']}" if changed else "")}
    summary["step_check"] = check
    if check["marginal"] and summary["verdict"] not in ("insufficient", "not_achieved"):
        summary["verdict"] = "marginal"
    summary["answer"] = answer(summary, params)
    return check


def markdown(s: dict, params: Params) -> str:
    lines = [
        f"# Simulated {s['gait']} gait: dynamic vs static motor torque", "", s["answer"], "",
        f"Simulated {s['duration_s']:.2f} s (requested {s['requested_duration_s']:g} s), "
        f"{s['closure']} closure, time step {s['time_step_s'] * 1e3:.3f} ms, "
        f"{s['real_time_factor']:.2f}x real time. Statistics over {s['cycles_in_window']} whole "
        f"gait cycles, t = {s['window_s'][0]:.2f} .. {s['window_s'][1]:.2f} s; every value is a "
        f"mean over {s['log_period_s'] * 1e3:g} ms of plant steps.",
    ]
    lines += ["", "Ran: " + "; ".join(
        f"{what} {v['kind']} (" + ", ".join(f"{k} = {x!r}" for k, x in v.items() if k != "kind")
        + ")" for what, v in ((w, s["ran"][w]) for w in ("gait", "controller", "closure")))
        + (", planned events " + ", ".join(f"{k} {x:.3f} s" for k, x in
                                          s["ran"]["planned_events_s"].items())
           if s["ran"]["planned_events_s"] else "") + "."]
    if s["error"]:
        lines += ["", f"**The run stopped early:** {s['error']}"]
    clear = min(s["swing_clear_fraction"].values())
    drag = max(s["swing_drag_fraction"].values())
    lines += [
        "", f"- walking: {s['mean_forward_speed_m_s']:.3f} m/s against the gait's "
        f"{s['gait_speed_m_s']:.3f} m/s; largest tilt {s['max_tilt_deg']:.1f} deg; swing feet "
        f"clear of the ground {clear * 100:.0f} % of scheduled swing, on it {drag * 100:.0f} % of "
        f"mid-swing (worst legs; the rest is early touchdown); worst loop gap "
        f"{s['max_loop_gap_m'] * 1e3:.4f} mm", f"- {limits_text(s['limits'])}",
        *([f"- vertical ground force (every plant step, {s['log_period_s'] * 1e3:g} ms means) "
           f"between {s['vertical_support']['least_share']:.2f} (t = "
           f"{s['vertical_support']['least_at_s']:.3f} s) and "
           f"{s['vertical_support']['largest_share']:.2f} (t = "
           f"{s['vertical_support']['largest_at_s']:.3f} s) of the weight"]
          if s.get("vertical_support") else []),
        "", "| leg | motor | demand p99 | demand peak | applied p99 | RMS | seed static | "
        "trot static | J^T F peak | dyn/seed | dyn/trot | SF | verdict | clipped | p99 speed "
        "(rad/s) |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for leg, motors in s["legs"].items():
        for name, m in motors.items():
            lines.append(
                f"| {leg} | {name} | {m['demand_p99_Nm']:.2f} | {m['demand_peak_Nm']:.2f} | "
                f"{m['p99_torque_Nm']:.2f} | {m['rms_torque_Nm']:.2f} | {m['static_seed_Nm']:.2f} | "
                f"{m['static_trot_Nm']:.2f} | {m['static_contact_Nm']:.2f} | "
                f"{m['dynamic_to_seed_static']:.2f}x | {m['dynamic_to_trot_static']:.2f}x | "
                f"{m['safety_factor']:.2f} ({_quadrant(m)}) | {m['verdict'].upper()} | "
                f"{_clipped(m)} | {m['p99_speed_rad_s']:.2f} |")
    lines += ["", "Torque split (RMS over the window, N·m): contact -J^T F, links M q'' + c + G, "
              "rotor N^2 J q'', friction; residual = applied - their sum.", "",
              "| leg | motor | contact | links | rotor | friction | residual |",
              "|---|---|---|---|---|---|---|"]
    for leg, motors in s["legs"].items():
        for name, m in motors.items():
            d = m["decomposition_rms_Nm"]
            lines.append(f"| {leg} | {name} | {d['contact']:.3f} | {d['links']:.3f} | "
                         f"{d['rotor']:.3f} | {d['friction']:.3f} | {d['residual']:.3f} |")
    motor = params.motor
    lines += ["", f"Units N·m unless stated. Motor limits at the output: "
              f"{motor.peak_torque_Nm:.2f} N·m driving (torque and speed of one sign), "
              f"{motor.braking_peak_torque_Nm:.2f} braking (opposite signs), both at the peak "
              f"current, the driving torque falling beyond its corner to zero at the no-load speed "
              f"{motor.no_load_speed_rad_s:.2f} rad/s, beyond which the back-EMF forces braking. "
              "Demand = the controller's command before saturation; SF = 1 / the "
              f"{PERCENTILE:g}th percentile of the demand over the limit of each sample's own "
              "quadrant (the quadrant of that percentile in brackets), or of the applied torque "
              f"where the motor sat at its limits more than {100 - PERCENTILE:g} % of the time "
              "(clipped, with the limit it sat at most: its demand p99 was not met, and is not a "
              f"need). Seed static: the seed's G(q) with {params.robot.weight_share_kg:.3f} kg at "
              "the foot. Per-cycle spreads are in summary.json."]
    return "\n".join(lines) + "\n"


def _quadrant(m: dict) -> str:
    """The quadrant of a motor's torque figure (summary table)."""
    c = m["checks"]
    return c["torque"]["quadrant"] or "—" if c else "—"


def _clipped(m: dict) -> str:
    """The share of the time a motor was clipped, with the limit it sat at most."""
    if not m["saturated_fraction"]:
        return "0.0 %"
    most = max(m["limit_shares"], key=lambda k: m["limit_shares"][k]).replace("_", " ")
    return f"{m['saturated_fraction'] * 100:.1f} % ({most} most)"


def write_summary(summary: dict, params: Params, out_dir: Path) -> list[Path]:
    """Write SUMMARY_FILES into out_dir, each atomically, summary.json last: call it after every
    other output of the run is written, so a summary.json always describes complete files."""
    texts = (markdown(summary, params),
             json.dumps(json_ready(summary), indent=2, allow_nan=False) + "\n")
    out_dir.mkdir(parents=True, exist_ok=True)
    return [write_atomic(out_dir / name, text) for name, text in zip(SUMMARY_FILES, texts)]
