"""The statistics of a simulated run from its signals (simulation/signals.py), the summary's
measured figures: the statistics window (the whole gait cycles after the ramp; a one-shot
maneuver: its span after standing), per leg and motor the torques, speeds and the applied
torque's parts over it against the static estimates (motor_summary, with the motor's checks:
checks.motor_checks), the body's motion and the swing feet (motion_statistics), the delivered
vertical support, and the leg's limits over the whole run (limit_report: which leg reached which
limit, when first, for how long, how far). No verdict and no prose: verdicts/rules.py judges
these figures, simulation/summary_text.py words them."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from fivebar_drake.verdicts.checks import at_limit, limit_shares, motor_checks
from fivebar_drake.verdicts.summary_schema import LimitReport, MotorSummary, VerticalSupport
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.scenario import Scenario
from fivebar_drake.simulation.signals import Signals

MIN_CYCLES = 3            # fewer whole cycles than this give no verdict
PERCENTILE = 99.0

# Mid-swing, where a foot on the ground drags: after lift-off and before the descent to an early
# touchdown (the trot path lifts a foot 1.4 mm by 10 % of its swing, 18 mm by 70 %).
MID_SWING = (0.1, 0.7)

# A limit counts as reached within this of its bound, in the field's unit: Drake's joint limits
# (the motor ranges and the least knee angle, sdf.py) stop a joint at its bound, so a stopped
# joint lies at it, not past it.
LIMIT_REACHED = {"deg": 0.1, "m": 1e-4}


class Window(NamedTuple):
    """The statistics window of a run: its start and end (s), the whole cycles in it (a
    maneuver: 1 if its span fits, else 0), the rows it holds (a mask over the signals' rows),
    each held row's cycle (0 .. cycles - 1), and the run's last row time t_end (s)."""

    start: float
    end: float
    cycles: int
    rows: np.ndarray
    cycle: np.ndarray
    t_end: float


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


def statistics_window(sig: Signals, scenario: Scenario, params: Params) -> Window:
    """The run's statistics window (cycle_window up to the end of its last recorded interval;
    its rows: window_rows)."""
    t_end = float(sig.t[-1]) if len(sig.t) else 0.0
    half_row = 0.5 * float(np.median(np.diff(sig.t))) if len(sig.t) > 1 else 0.0
    start, end, cycles = cycle_window(scenario, params, t_end + half_row)
    rows = window_rows(sig.t, (start, end))
    cycle_s = scenario.gait.span_s(params.gait)
    cycle = np.clip(np.floor((sig.t[rows] - start - half_row) / cycle_s), 0,
                    max(cycles - 1, 0)).astype(int)
    return Window(start, end, cycles, rows, cycle, t_end)


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


def motor_summary(sig: Signals, params: Params, win, cycle, cycles: int, i: int,
                  j: int) -> MotorSummary:
    """Statistics of motor j of leg i over the window rows `win` (cycle: each row's cycle) and
    its checks (checks.motor_checks; at its limits: checks.at_limit); its achieved check is the
    verdict policy's (verdicts.judge)."""
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


def leg_statistics(sig: Signals, params: Params, window: Window,
                   legs) -> dict[str, dict[str, MotorSummary]]:
    """motor_summary of every motor: leg name (legs, in the signals' order) -> motor -> its
    statistics."""
    return {leg: {name: motor_summary(sig, params, window.rows, window.cycle, window.cycles, i, j)
                  for j, name in enumerate(MOTORS)} for i, leg in enumerate(legs)}


def _drag(sig: Signals, win, i: int) -> float:
    """Fraction of the mid-swing samples (MID_SWING) of leg i in which its foot is loaded."""
    frac = sig.swing_fraction[win, i]
    mid = (frac >= MID_SWING[0]) & (frac <= MID_SWING[1])
    return float(np.mean(sig.swing_contact[win, i][mid])) if mid.any() else math.nan


def motion_statistics(sig: Signals, record: SimulationRecord, window: Window) -> dict:
    """The body's and the feet's figures (the Summary keys of the same names): the largest tilt
    (whole run), the mean forward speed over the window, per leg the share of its scheduled
    swing clear of the ground and of its mid-swing on it (the window), the body's height range
    and the loop gaps (whole run), the vertical support (the window)."""
    win, legs = window.rows, record.layout.legs
    p, tw = sig.body_p[win], sig.t[win]
    scheduled_swing = (~sig.stance[win]).sum(0)
    whole = len(sig.t) > 0
    return {
        "max_tilt_deg": float(np.max(sig.tilt_deg)) if whole else math.nan,
        "mean_forward_speed_m_s": float((p[-1, 0] - p[0, 0]) / (tw[-1] - tw[0]))
        if len(tw) > 1 else math.nan,
        "swing_clear_fraction": {leg: float(1 - sig.swing_contact[win, i].sum()
                                            / max(scheduled_swing[i], 1))
                                 for i, leg in enumerate(legs)},
        "swing_drag_fraction": {leg: _drag(sig, win, i) for i, leg in enumerate(legs)},
        "body_height_m": {"min": float(sig.body_p[:, 2].min()),
                          "max": float(sig.body_p[:, 2].max())} if whole else None,
        "vertical_support": vertical_support(sig, record, win),
        "max_loop_gap_m": float(np.max(sig.gap)) if whole else math.nan,
        "max_loop_gap_per_leg_m": {leg: float(np.max(sig.gap[:, i])) if whole else math.nan
                                   for i, leg in enumerate(legs)},
    }


def end_height(sig: Signals, window: Window) -> float:
    """The body's height (m) at the window's last row (NaN for an empty window)."""
    return float(sig.body_p[window.rows][-1, 2]) if window.rows.any() else math.nan


def vertical_support(sig: Signals, record: SimulationRecord, win) -> VerticalSupport | None:
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


def limit_report(sig: Signals, params: Params, legs) -> LimitReport:
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
