"""The verdict policy of a simulated run, beside the checks of one motor (checks.py): whether the
run did its motion (achievement) and each motor its part (motor_achieved, judge), which motor
decides the run's verdict and in what order motors rank (badness, run_verdict), and the step
check: the run against itself at half the plant step (extrapolated, step_check,
step_checked_verdict). Plain data in and out (the summary's dictionaries: summary_schema), no
pydrake, no simulation: simulation/summary.py applies it to a run's statistics."""

from __future__ import annotations

import math

from fivebar_drake.verdicts.checks import (CHECK_ORDER, SEVERITY, Checks, limit_shares_text,
                                       verdict)
from fivebar_drake.verdicts.summary_schema import (AchievedCheck, ContactCheck, MotorSummary,
                                               StepCheck, StepCheckMotor, Summary)

STEP_ORDER = 1   # the discrete plant's time stepping is first order in the step: a figure's
#                  error at step h is about (f(h) - f(h/2)) / (2^p - 1) (measured on the default
#                  trot's worst SF: 1.505, 1.457, 1.416, 1.405 at 2, 1, 0.5, 0.25 ms)
NO_STEP_CHECK_VERDICTS = ("insufficient", "not_achieved")   # the step check leaves these
ACHIEVED_VERDICTS = ("pass", "warn", "fail")   # a run that did its motion, whatever the torque


def achievement(checks: Checks, missed: list[str], max_tilt: float,
                maneuver: dict | None = None) -> str:
    """Why the run did not do its motion ("" if it did): what its path says it missed
    (FootPath.shortfalls: a gait's speed, a maneuver's end pose, a jump's flight), a landing
    whose legs gave way (maneuver: maneuver_figures' dictionary, its phase_figures), and the
    tilt against checks.achieved_max_tilt_deg."""
    why = list(missed)
    landing = ((maneuver or {}).get("phases") or {}).get("landing")
    if landing and landing["gives_way"]:
        why.append(f"the legs gave way at the landing: the motors were asked to brake beyond "
                   f"their braking limit for {landing['braking_beyond_limit_s'] * 1e3:.0f} ms")
    if not max_tilt <= checks.achieved_max_tilt_deg:
        why.append(f"the body tilted {max_tilt:.1f} deg, beyond {checks.achieved_max_tilt_deg:g} "
                   "deg")
    return "; ".join(why)


def motor_achieved(checks: Checks, m: MotorSummary, run_why: str) -> AchievedCheck:
    """The motor's achieved check: the run followed its gait (run_why == "") and the motor sat
    at its limits (either quadrant, torque or voltage) at most
    checks.achieved_max_limit_fraction of the time."""
    why = [run_why] if run_why else []
    limit = checks.achieved_max_limit_fraction
    if m["saturated_fraction"] > limit:
        why.append(f"the motor sat at {limit_shares_text(m['limit_shares'])} ("
                   f"{m['saturated_fraction']:.1%} in all, more than {limit:.0%})")
    return {"verdict": "not_achieved" if why else "pass", "why": "; ".join(why),
            "at_limit_fraction": m["saturated_fraction"]}


def judge(legs: dict[str, dict[str, MotorSummary]], checks: Checks, run_why: str) -> None:
    """Give every motor with checks its achieved check (motor_achieved; run_why: achievement);
    a motor whose motion was not achieved gets the verdict not_achieved, decided by it."""
    for ms in legs.values():
        for m in ms.values():
            if m["checks"] is not None:
                m["checks"]["achieved"] = motor_achieved(checks, m, run_why)
                if m["checks"]["achieved"]["verdict"] == "not_achieved":
                    m["verdict"], m["deciding_check"] = "not_achieved", "achieved"


def badness(m: MotorSummary) -> tuple:
    """Order of motors, worst last: not achieved; then by verdict; among equal verdicts the
    deciding check (torque before speed before thermal), then its figure (the lower the safety
    factor, then the longer at the motor's limits; the larger the share outside the envelope or
    the lower its margin, the worse). m: a motor's summary, or any dictionary with its checks,
    verdict, deciding_check and saturated_fraction (an envelope's motor row)."""
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


def run_verdict(legs: dict[str, dict[str, MotorSummary]], sufficient: bool) -> dict:
    """The run's verdict, deciding_check and worst_motor ("<leg> <motor>", the last in badness
    order): the worst motor's verdict and check; "insufficient" and None where the run is not
    sufficient (too few whole cycles, or it stopped early)."""
    leg, name, worst = max(((leg, name, m) for leg, ms in legs.items() for name, m in ms.items()),
                           key=lambda x: badness(x[2]))
    return {"verdict": worst["verdict"] if sufficient else "insufficient",
            "deciding_check": worst["deciding_check"] if sufficient else None,
            "worst_motor": f"{leg} {name}"}


def extrapolated(at_step: float, at_half: float) -> tuple[float, float]:
    """Richardson's estimate of a figure at step 0 from its values at steps h and h/2 (order
    STEP_ORDER) and its error: (f(h/2) + d, |d|), d = (f(h/2) - f(h)) / (2^p - 1)."""
    d = (at_half - at_step) / (2.0 ** STEP_ORDER - 1.0)
    return at_half + d, abs(d)


def _change(new: float, old: float) -> float:
    """The relative change from old to new (NaN from 0)."""
    return (new / old if old else math.nan) - 1.0


def _step_motors(summary: Summary, half: Summary) -> dict[str, StepCheckMotor]:
    """Per motor ("<leg> <motor>") the change at half the step and its converged safety
    factor (extrapolated) with its error."""
    motors = {}
    for leg, ms in summary["legs"].items():
        for name, m in ms.items():
            h = half["legs"][leg][name]
            estimate, error = extrapolated(m["safety_factor"], h["safety_factor"])
            motors[f"{leg} {name}"] = {
                "demand_p99_change": _change(h["demand_p99_Nm"], m["demand_p99_Nm"]),
                "rms_change": _change(h["rms_torque_Nm"], m["rms_torque_Nm"]),
                "sf_change": h["safety_factor"] - m["safety_factor"],
                "sf_at_half_step": h["safety_factor"], "sf_converged": estimate,
                "sf_error": error, "verdict_at_half_step": h["verdict"]}
    return motors


def _step_events(summary: Summary, half: Summary) -> dict:
    """A maneuver's event figures (jump, landing: every float) at half the step and their
    converged estimates (extrapolated)."""
    events = {}
    for group in ("jump", "landing"):
        if summary.get(group) and half.get(group):
            events[group] = {key: dict(zip(("at_half_step", "converged", "error"),
                                           (half[group][key],
                                            *extrapolated(value, half[group][key]))))
                             for key, value in summary[group].items()
                             if isinstance(value, float) and isinstance(half[group].get(key),
                                                                        float)}
    return events


def step_check(summary: Summary, half: Summary, checks: Checks) -> StepCheck:
    """The step check of a run (its summary) from the summary of the same run at half the
    plant step: per motor the relative change of the demand p99 and RMS, the safety factor at
    half the step and its converged estimate with its error (extrapolated); the worst motor's
    converged safety factor decides: the run is marginal when its error band reaches a
    threshold (checks.sf_pass, sf_warn) or its torque verdict differs from the run's, where the
    torque check decides the verdict or would make it worse; or when the verdict at half the
    step differs (step_checked_verdict); or whom a failing verdict blames (any_controller's
    fails_for: any controller or this one) does. A maneuver's event figures (jump, landing) get
    their value at half the step and their converged estimate too."""
    motors = _step_motors(summary, half)
    worst = min(((k, v["sf_converged"], v["sf_error"]) for k, v in motors.items()
                 if math.isfinite(v["sf_converged"])), key=lambda x: x[1], default=None)
    thresholds = (checks.sf_pass, checks.sf_warn)
    near = [t for t in thresholds if worst and abs(worst[1] - t) <= worst[2]]
    converged = verdict(checks, worst[1]) if worst else None
    torque_now = verdict(checks, min(m["safety_factor"] for ms in summary["legs"].values()
                                     for m in ms.values()))
    moved = converged is not None and converged != torque_now
    changed = half["verdict"] != summary["verdict"]
    achieved, achieved_half = (s["verdict"] not in NO_STEP_CHECK_VERDICTS for s in (summary, half))
    split, split_half = (((s.get("any_controller") or {}).get("fails_for"))
                         for s in (summary, half))
    blamed = split != split_half
    # the torque figure's step error matters where the torque check decides, or would
    if not (summary.get("deciding_check") == "torque" or converged is not None and
            SEVERITY.get(converged, 0) > SEVERITY.get(summary["verdict"], 0)):
        near, moved = [], False
    return {"time_step_s": summary["time_step_s"], "half_time_step_s": half["time_step_s"],
            "order": STEP_ORDER, "motors": motors,
            "worst_sf_change": max((abs(v["sf_change"]) for v in motors.values()
                                    if math.isfinite(v["sf_change"])), default=0.0),
            "worst_demand_p99_change": max((abs(v["demand_p99_change"]) for v in
                                            motors.values()), default=math.nan),
            "converged_worst_motor": worst[0] if worst else None,
            "converged_sf": worst[1] if worst else None,
            "converged_sf_error": worst[2] if worst else None,
            "torque_verdict_converged": converged, "events": _step_events(summary, half),
            "verdict_at_half_step": half["verdict"], "fails_for_at_half_step": split_half,
            "achieved": achieved, "achieved_at_half_step": achieved_half,
            "marginal": bool(near or changed or moved or blamed),
            "why": (f"the motion is {'' if achieved else 'not '}achieved at the plant step and "
                    f"{'' if achieved_half else 'not '}at half of it"
                    if achieved != achieved_half else
                    f"the converged worst safety factor {worst[1]:.3f} ± {worst[2]:.3f} "
                    f"({worst[0]}) reaches {near[0]:g}" if near else
                    f"the converged worst safety factor {worst[1]:.3f} ({worst[0]}) gives "
                    f"{converged}, the run {torque_now}" if moved else
                    f"the verdict at half the step is {half['verdict']}" if changed else
                    f"at half the step the verdict fails for {split_half or 'nobody'}, not "
                    f"for {split or 'nobody'}" if blamed else "")}


def _worst_sf(summary: Summary) -> float:
    """The least finite safety factor of a run's motors (nan: none)."""
    return min((m["safety_factor"] for ms in summary["legs"].values() for m in ms.values()
                if math.isfinite(m["safety_factor"])), default=math.nan)


def contact_check(summary: Summary, verdict: str, runs: dict[str, Summary],
                  checks: Checks) -> ContactCheck:
    """The run (its summary, its verdict before any check: verdict) against itself with the
    foot contact varied (runs: label -> the same run's summary with another contact): the band
    (least, largest over the run and the variants) of the worst motor's safety factor and of
    every event figure (a jump's and a landing's floats), each run's verdict and whether it did
    its motion. Marginal where a verdict differs (achievement included), or where the torque
    check decides and the safety factor's band reaches a threshold (checks.sf_pass, sf_warn)."""
    every = {"nominal": summary, **runs}
    verdicts = {label: (verdict if label == "nominal" else s["verdict"])
                for label, s in every.items()}
    worst = {label: _worst_sf(s) for label, s in every.items()}
    finite = [v for v in worst.values() if math.isfinite(v)]
    band = [min(finite), max(finite)] if finite else None
    events = {}
    for group in ("jump", "landing"):
        if all(s.get(group) for s in every.values()):
            events[group] = {key: [min(s[group][key] for s in every.values()),
                                   max(s[group][key] for s in every.values())]
                             for key, value in summary[group].items()
                             if isinstance(value, float)}
    achieved = {label: v not in NO_STEP_CHECK_VERDICTS for label, v in verdicts.items()}
    near = ([t for t in (checks.sf_pass, checks.sf_warn) if band[0] < t <= band[1]]
            if band and summary.get("deciding_check") == "torque" else [])
    changed = len(set(verdicts.values())) > 1
    why = ("the motion is achieved with " + ", ".join(k for k, a in achieved.items() if a)
           + " contact and not with " + ", ".join(k for k, a in achieved.items() if not a)
           if len(set(achieved.values())) > 1 else
           "the verdict is " + ", ".join(f"{v} with the {k} contact" for k, v in verdicts.items())
           if changed else
           f"the worst safety factor's band {band[0]:.2f}–{band[1]:.2f} reaches {near[0]:g}"
           if near else "")
    return {"variants": {label: s["contact"] for label, s in runs.items()},
            "verdicts": verdicts, "achieved": achieved, "worst_sf": worst,
            "worst_sf_band": band, "events": events, "marginal": bool(changed or near),
            "why": why}


def contact_checked_verdict(current: str, check: ContactCheck) -> str:
    """The run's verdict (current) after its contact check: "marginal" where the check is
    marginal, unless the run has no verdict or did not do its motion with every contact."""
    if len(set(check["achieved"].values())) > 1 and current != "insufficient":
        return "marginal"
    return "marginal" if check["marginal"] and current not in NO_STEP_CHECK_VERDICTS else current


NEEDS = ("floor", "undecided", "beyond bound", "unknown")   # a phase's need (PhaseFloor.status)


def beyond_limit(floor_Nm: float, limit_Nm: float, margin: float) -> bool:
    """Whether a floor (N*m) is beyond a motor's limit (N*m) for any controller: the floor less
    the model's margin (checks.floor_margin), floor (1 - margin), above the limit."""
    return floor_Nm * (1.0 - margin) > limit_Nm


def fails_for(verdict: str, phases: dict, margin: float) -> str | None:
    """Whom a failing verdict blames: the one rule every output reads. phases: per phase its
    need (summary_schema.PhaseFloor: status in NEEDS, floor_Nm, limit_Nm: the motors' limit in
    the quadrant the phase acts, driving or braking); margin: the floors' model margin
    (checks.floor_margin). None where nothing failed (verdict neither fail nor not_achieved);
    "any controller" where the run did not achieve its motion and a phase's need is beyond the
    motors: beyond a bound by another method, or its floor less the margin, floor (1 - margin),
    beyond its limit (a run that achieved its motion is never called impossible); else
    "undecided" where a phase lies between its model's optimum and its bound, "unknown" where
    a phase has no floor; else "this controller" (the need within the motors, the demand not)."""
    if verdict not in ("fail", "not_achieved"):
        return None
    statuses = {p["status"] for p in phases.values()}
    beyond = "beyond bound" in statuses or any(
        p["status"] == "floor" and beyond_limit(p["floor_Nm"], p["limit_Nm"], margin)
        for p in phases.values())
    if beyond and verdict == "not_achieved":
        return "any controller"
    if "undecided" in statuses:
        return "undecided"
    if "unknown" in statuses:
        return "unknown"
    return "this controller"


def step_checked_verdict(current: str, check: StepCheck) -> str:
    """The run's verdict (current) after its step check: "marginal" where the check is
    marginal, unless the run has no verdict or did not do its motion (NO_STEP_CHECK_VERDICTS)
    at both steps: a motion achieved at one step and not at the other is marginal, never a clean
    pass or a clean not achieved."""
    flips = check["achieved"] != check["achieved_at_half_step"]
    if flips and current != "insufficient":
        return "marginal"
    return "marginal" if check["marginal"] and current not in NO_STEP_CHECK_VERDICTS else current
