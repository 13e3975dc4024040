"""The verdict a designer acts on: thresholds (Checks) and the checks of one motor against its
actuator — torque (safety factor), speed (the operating points against the envelope), thermal
(RMS current against the continuous current) — and whether a simulated gait was achieved; the
worst check decides.

Verdicts, best first: pass, warn, fail; a run whose gait was not followed is not_achieved (its
demand is not a need), one whose worst safety factor lies within the step error of a threshold
is marginal; insufficient: no verdict (too short, stopped early)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fivebar_drake.core.motor import Motor
from fivebar_drake.core.validation import MAX_LENGTH_M, MAX_SAFETY_FACTOR, check_number, require

SEVERITY = {"pass": 0, "warn": 1, "fail": 2}
CHECK_ORDER = ("torque", "speed", "thermal")   # among equally bad checks, the first decides
MAX_TILT_DEG = 90.0


@dataclass(frozen=True)
class Checks:
    """Thresholds. Torque: SF >= sf_pass passes, SF >= sf_warn warns, else fails. Speed: more
    than speed_outside_fail of the time beyond the envelope fails, a least speed margin below
    speed_margin_warn warns. Thermal: continuous / RMS current below 1 fails, below
    thermal_margin_warn warns. Achieved (simulation): mean speed >= achieved_speed_fraction of
    the gait's, tilt <= achieved_max_tilt_deg, no motor at its torque limit more than
    achieved_max_limit_fraction of the time; a maneuver ends standing within
    achieved_height_tolerance_m (m) of the standing height."""

    sf_pass: float
    sf_warn: float
    speed_margin_warn: float = 1.1
    speed_outside_fail: float = 0.01
    thermal_margin_warn: float = 1.2
    achieved_speed_fraction: float = 0.7
    achieved_max_tilt_deg: float = 10.0
    achieved_max_limit_fraction: float = 0.05
    achieved_height_tolerance_m: float = 0.01

    def __post_init__(self):
        for name in ("sf_pass", "sf_warn", "speed_margin_warn", "thermal_margin_warn"):
            check_number(f"checks.{name}", getattr(self, name), 0.0, MAX_SAFETY_FACTOR,
                         low_open=True)
        require(self.sf_warn <= self.sf_pass, "checks.sf_warn", self.sf_warn,
                f"must be <= checks.sf_pass = {self.sf_pass}")
        for name in ("speed_outside_fail", "achieved_speed_fraction",
                     "achieved_max_limit_fraction"):
            check_number(f"checks.{name}", getattr(self, name), 0.0, 1.0)
        check_number("checks.achieved_max_tilt_deg", self.achieved_max_tilt_deg, 0.0,
                     MAX_TILT_DEG, low_open=True)
        check_number("checks.achieved_height_tolerance_m", self.achieved_height_tolerance_m, 0.0,
                     MAX_LENGTH_M, low_open=True)


def verdict(checks: Checks, safety_factor: float) -> str:
    """Torque: 'pass' (SF >= sf_pass), 'warn' (sf_warn <= SF < sf_pass) or 'fail'."""
    if safety_factor >= checks.sf_pass:
        return "pass"
    return "warn" if safety_factor >= checks.sf_warn else "fail"


def _finite(x) -> float | None:
    return float(x) if x is not None and math.isfinite(x) else None


def torque_check(checks: Checks, peak_Nm: float, demand_Nm: float) -> dict:
    """sf = the driving peak torque / the demand (p99 in a simulation, the peak in the
    analysis)."""
    sf = peak_Nm / demand_Nm if demand_Nm > 0 else math.inf
    return {"sf": _finite(sf), "verdict": verdict(checks, sf)}


def speed_check(checks: Checks, margins, outside) -> dict:
    """From Motor.speed_margins over the operating points (demand torque, speed): least_margin
    (None if no point is driving within the peak current), outside_fraction (share of the
    points beyond the envelope on its speed side)."""
    margins = np.asarray(margins, dtype=float)
    driving = margins[np.isfinite(margins)]
    least = float(driving.min()) if driving.size else None
    share = float(np.mean(outside)) if np.size(outside) else 0.0
    if share > checks.speed_outside_fail:
        result = "fail"
    elif share > 0.0 or (least is not None and least < checks.speed_margin_warn):
        result = "warn"
    else:
        result = "pass"
    return {"least_margin": least, "outside_fraction": share, "verdict": result}


def thermal_check(checks: Checks, continuous_A: float | None, rms_A: float,
                  steady_C: float | None = None) -> dict:
    """margin = continuous current / RMS current (None: no thermal model, verdict 'pass' with
    the reason); steady_C: the winding temperature if the motion repeats for ever."""
    if continuous_A is None:
        return {"margin": None, "verdict": "pass", "why": "no thermal model"}
    margin = continuous_A / rms_A if rms_A > 0 else math.inf
    result = "fail" if margin < 1.0 else "warn" if margin < checks.thermal_margin_warn else "pass"
    out = {"margin": _finite(margin), "rms_current_A": rms_A,
           "continuous_current_A": continuous_A, "verdict": result}
    if steady_C is not None:
        out["steady_state_C"] = steady_C
    return out


def worst_check(checks: dict) -> tuple[str, str]:
    """(verdict, deciding check) of a motor's torque, speed and thermal checks: the most severe,
    the first of CHECK_ORDER among equals."""
    name = max(CHECK_ORDER, key=lambda c: (SEVERITY[checks[c]["verdict"]], -CHECK_ORDER.index(c)))
    return checks[name]["verdict"], name


def motor_checks(motor: Motor, checks: Checks, demand_Nm, speed_rad_s, torque_figure_Nm: float,
                 delivered_Nm=None) -> dict:
    """The torque, speed and thermal checks of one motor from its samples evenly spaced in time
    (arrays of one shape): demand (N*m, the torque asked for) at joint speeds (rad/s); the
    torque check on torque_figure_Nm (the demand's p99 or peak); the thermal check on the RMS
    current of delivered_Nm (default: the demand). Returns the three checks, the worst verdict
    and the deciding check."""
    demand = np.asarray(demand_Nm, dtype=float)
    delivered = demand if delivered_Nm is None else np.asarray(delivered_Nm, dtype=float)
    margins, outside = motor.speed_margins(demand, speed_rad_s)
    rms = float(np.sqrt(np.mean(np.square(motor.currents(delivered, speed_rad_s)))))
    return checks_of(motor, checks, torque_figure_Nm, margins, outside, rms)


def at_limit(out: dict, checks: Checks, peak_Nm: float, delivered_Nm: float,
             torque_share: float, voltage_share: float, allowed_share: float) -> dict:
    """A motor's checks (motor_checks) when its commands were clipped more often than
    allowed_share of the time (the share above the percentile the torque figure takes): the
    demand's figure is then an ask the motor did not meet, not a need. The torque check takes
    what the motor gave instead (sf = the driving peak over delivered_Nm, that percentile of the
    delivered torque; demand_sf keeps the sf on the demand), and the check of the limit it sat at
    most often fails, with at_limit_fraction and why: torque (the peak current) or speed (the
    voltage at speed). Returns out, changed; unchanged below allowed_share."""
    share = torque_share + voltage_share
    if not share > allowed_share:
        return out
    out = {**out, "torque": {**out["torque"], **torque_check(checks, peak_Nm, delivered_Nm),
                             "demand_sf": out["torque"]["sf"]}}
    name = "torque" if torque_share >= voltage_share else "speed"
    what = ("its torque limit (the peak current)" if name == "torque" else
            "its voltage limit at speed (the back-EMF)")
    out[name] = dict(out[name], verdict="fail", at_limit_fraction=share,
                     why=f"at {what} {share:.1%} of the time (more than {allowed_share:.0%}): it "
                         "gave all it had, and the demand beyond it is the controller's ask, "
                         "not a need")
    out["verdict"], out["deciding_check"] = worst_check(out)
    return out


def demand_unmet(out: dict) -> dict | None:
    """The check that failed at the motor's limit (at_limit), None if the demand was met."""
    return next((out[k] for k in CHECK_ORDER if "at_limit_fraction" in out[k]), None)


def checks_of(motor: Motor, checks: Checks, torque_figure_Nm: float, margins, outside,
              rms_current_A: float) -> dict:
    """motor_checks from the figures already computed: the torque figure (N*m), the speed
    margins and outside flags of the operating points (Motor.speed_margins) and the RMS current
    (A, Motor.currents)."""
    out = {"torque": torque_check(checks, motor.peak_torque_Nm, torque_figure_Nm),
           "speed": speed_check(checks, margins, outside)}
    continuous = getattr(motor, "rated_continuous_current_A", None)
    if continuous is None:
        out["thermal"] = thermal_check(checks, None, 0.0)
    else:
        steady = (float(motor.steady_winding_C(rms_current_A)) if motor.has_thermal_model
                  else None)
        out["thermal"] = thermal_check(checks, continuous, rms_current_A, steady)
    out["verdict"], out["deciding_check"] = worst_check(out)
    return out
