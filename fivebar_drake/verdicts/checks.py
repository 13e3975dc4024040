"""The verdict a designer acts on: thresholds (Checks) and the checks of one motor against its
actuator — torque (safety factor: each sample against the peak-current torque of its own
quadrant, driving or braking), speed (the operating points against the envelope), thermal (RMS
current against the continuous current) — the worst check deciding. A motor clipped beyond the
allowed share is judged on what it delivered (at_limit), and every statement of a limit names its
quadrant and kind (limit_shares). A simulated run's verdict policy (achieved or not, the worst
motor deciding, the step check) is beside this, in verdicts.py.

Verdicts, best first: pass, warn, fail; a run whose gait was not followed is not_achieved (its
demand is not a need), one whose worst safety factor lies within the step error of a threshold
is marginal; insufficient: no verdict (too short, stopped early)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fivebar_drake.actuators.motor import Motor
from fivebar_drake.core.validation import MAX_LENGTH_M, MAX_SAFETY_FACTOR, check_number, require

SEVERITY = {"pass": 0, "warn": 1, "fail": 2}
CHECK_ORDER = ("torque", "speed", "thermal")   # among equally bad checks, the first decides
MAX_TILT_DEG = 90.0
QUADRANTS = ("driving", "braking")   # torque and speed of one sign (or standing); opposite signs
LIMIT_KINDS = ("torque", "voltage")  # the peak current; the back-EMF against the bus voltage
LIMIT_WORDS = {"torque": "torque limit (the peak current)",
               "voltage": "voltage limit (the back-EMF at speed)"}


@dataclass(frozen=True)
class Checks:
    """Thresholds. Torque: SF >= sf_pass passes, SF >= sf_warn warns, else fails. Speed: more
    than speed_outside_fail of the time beyond the envelope fails, a least speed margin below
    speed_margin_warn warns. Thermal: continuous / RMS current below 1 fails, below
    thermal_margin_warn warns. Achieved (simulation): mean speed >= achieved_speed_fraction of
    the gait's, tilt <= achieved_max_tilt_deg, no motor at its torque limit more than
    achieved_max_limit_fraction of the time; a maneuver ends standing within
    achieved_height_tolerance_m (m) of the standing height; a jump's apex rises at least
    achieved_height_fraction of its planned height. Claims for any controller (verdicts.fails_for):
    a floor (an optimum of a reduced model) is beyond the motors only when floor (1 -
    floor_margin) is."""

    sf_pass: float
    sf_warn: float
    speed_margin_warn: float = 1.1
    speed_outside_fail: float = 0.01
    thermal_margin_warn: float = 1.2
    achieved_speed_fraction: float = 0.7
    achieved_max_tilt_deg: float = 10.0
    achieved_max_limit_fraction: float = 0.05
    achieved_height_tolerance_m: float = 0.01
    achieved_height_fraction: float = 0.85
    floor_margin: float = 0.05

    def __post_init__(self):
        for name in ("sf_pass", "sf_warn", "speed_margin_warn", "thermal_margin_warn"):
            check_number(f"checks.{name}", getattr(self, name), 0.0, MAX_SAFETY_FACTOR,
                         low_open=True)
        require(self.sf_warn <= self.sf_pass, "checks.sf_warn", self.sf_warn,
                f"must be <= checks.sf_pass = {self.sf_pass}")
        for name in ("speed_outside_fail", "achieved_speed_fraction",
                     "achieved_max_limit_fraction", "achieved_height_fraction",
                     "floor_margin"):
            check_number(f"checks.{name}", getattr(self, name), 0.0, 1.0)
        check_number("checks.achieved_max_tilt_deg", self.achieved_max_tilt_deg, 0.0,
                     MAX_TILT_DEG, low_open=True)
        check_number("checks.achieved_height_tolerance_m", self.achieved_height_tolerance_m, 0.0,
                     MAX_LENGTH_M, low_open=True)


def thresholds_text(checks: Checks) -> str:
    """The thresholds of the verdict, written beside every verdict a report gives."""
    return (f"Thresholds: SF ≥ {checks.sf_pass:g} pass, ≥ {checks.sf_warn:g} warn, else fail; "
            f"speed: beyond the torque–speed envelope more than "
            f"{checks.speed_outside_fail * 100:g} % of the time fails, a least margin below "
            f"{checks.speed_margin_warn:g} warns; thermal: continuous / RMS current below 1 fails, "
            f"below {checks.thermal_margin_warn:g} warns.")


def verdict(checks: Checks, safety_factor: float) -> str:
    """Torque: 'pass' (SF >= sf_pass), 'warn' (sf_warn <= SF < sf_pass) or 'fail'."""
    if safety_factor >= checks.sf_pass:
        return "pass"
    return "warn" if safety_factor >= checks.sf_warn else "fail"


def check_badness(name: str, c: dict) -> tuple:
    """How bad one motor's check is (name: torque, speed or thermal), to find the motor where
    it is worst (the largest): torque the lowest safety factor; speed the worst verdict, then
    the largest share beyond the envelope, then the least margin; thermal the worst verdict,
    then the least margin (a missing figure counts as an infinite one)."""
    def inf(x):
        return math.inf if x is None else x

    if name == "torque":
        return (-inf(c["sf"]),)
    if name == "speed":
        return (SEVERITY[c["verdict"]], c["outside_fraction"], -inf(c["least_margin"]))
    return (SEVERITY[c["verdict"]], -inf(c.get("margin")))


def _finite(x) -> float | None:
    return float(x) if x is not None and math.isfinite(x) else None


def torque_check(checks: Checks, motor: Motor, torque_Nm, speed_rad_s,
                 percentile: float | None = None) -> dict:
    """Each sample (torques N*m at joint speeds rad/s, arrays of one shape) against the
    peak-current torque of its own quadrant (Motor.quadrant_loads; driving: torque and speed of
    one sign, or standing; braking: opposite signs, where the gearbox's losses help and the
    motor holds more): its load |torque| / that peak. sf = 1 / the load's percentile
    (percentile, e.g. 99 in a simulation; None: its largest, the analysis's peak), so a
    delivered torque, which never exceeds its quadrant's limit, has sf >= 1. Also the quadrant
    of the sample at that figure, its limit_Nm (that quadrant's peak), the torque_Nm it stands
    for (share_of_limit x limit_Nm) and share_of_limit = 1 / sf."""
    load, braking = motor.quadrant_loads(torque_Nm, speed_rad_s)
    load, braking = load.ravel(), braking.ravel()
    if not load.size:
        return {"sf": None, "verdict": "pass", "quadrant": None, "limit_Nm": None,
                "torque_Nm": None, "share_of_limit": None}
    figure = float(np.percentile(load, percentile) if percentile is not None else load.max())
    at = int(np.argmin(np.where(load >= figure * (1.0 - 1e-12), load, np.inf)))
    quadrant = QUADRANTS[int(braking[at])]
    limit = motor.braking_peak_torque_Nm if braking[at] else motor.peak_torque_Nm
    sf = 1.0 / figure if figure > 0 else math.inf
    return {"sf": _finite(sf), "verdict": verdict(checks, sf), "quadrant": quadrant,
            "limit_Nm": limit, "torque_Nm": figure * limit, "share_of_limit": figure}


def speed_check(checks: Checks, margins, outside) -> dict:
    """From Motor.speed_margins over the operating points (demand torque, speed): least_margin
    (None if no point moves within its quadrant's peak current), outside_fraction (share of the
    points beyond the envelope: driving beyond what the back-EMF leaves, or braking less than it
    forces beyond the no-load speed)."""
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


def motor_checks(motor: Motor, checks: Checks, demand_Nm, speed_rad_s,
                 percentile: float | None = None, delivered_Nm=None) -> dict:
    """The torque, speed and thermal checks of one motor from its samples evenly spaced in time
    (arrays of one shape): demand (N*m, the torque asked of the motor) at joint speeds (rad/s);
    the torque check (torque_check) on the demand's percentile (None: its peak), each sample
    against its own quadrant's limit; the thermal check on the RMS current of delivered_Nm
    (default: the demand). Returns the three checks, the worst verdict and the deciding
    check."""
    demand = np.asarray(demand_Nm, dtype=float)
    delivered = demand if delivered_Nm is None else np.asarray(delivered_Nm, dtype=float)
    margins, outside = motor.speed_margins(demand, speed_rad_s)
    rms = float(np.sqrt(np.mean(np.square(motor.currents(delivered, speed_rad_s)))))
    return checks_of(motor, checks, torque_check(checks, motor, demand, speed_rad_s, percentile),
                     margins, outside, rms)


def limit_shares(clipped_torque, clipped_voltage, braking) -> dict:
    """The share of the samples (arrays of one shape: fractions of each sample clipped by the
    peak current and by the voltage, and whether the sample brakes) at each of the motor's
    limits: {"<quadrant>_<kind>": share} over QUADRANTS x LIMIT_KINDS."""
    braking = np.asarray(braking, dtype=bool)
    out = {}
    for quadrant, mask in zip(QUADRANTS, (~braking, braking)):
        for kind, clipped in zip(LIMIT_KINDS, (clipped_torque, clipped_voltage)):
            clipped = np.asarray(clipped, dtype=float)
            out[f"{quadrant}_{kind}"] = float(np.mean(clipped * mask)) if clipped.size else 0.0
    return out


def limit_shares_text(shares: dict) -> str:
    """The limits a motor sat at (limit_shares), largest first, each with its quadrant: 'its
    braking torque limit (the peak current) 3.0 % of the time, its driving voltage limit (...)
    0.2 %'; 'no limit' if none."""
    parts = [(v, k) for k, v in shares.items() if v > 0.0]
    if not parts:
        return "no limit"
    words = []
    for v, k in sorted(parts, reverse=True):
        quadrant, kind = k.split("_")
        words.append(f"its {quadrant} {LIMIT_WORDS[kind]} "
                     + (f"{v:.1%}" if v >= 0.0005 else "under 0.1%"))
    return ", ".join(words) + " of the time"


def at_limit(out: dict, checks: Checks, motor: Motor, delivered_Nm, speed_rad_s,
             shares: dict, allowed_share: float, percentile: float | None = None) -> dict:
    """A motor's checks (motor_checks) when its commands were clipped more often than
    allowed_share of the time in all (shares: limit_shares, the share at each quadrant's torque
    and voltage limit; allowed_share: the share above the percentile the torque figure takes):
    the demand's figure is then an ask the motor did not meet, not a need. The torque check
    takes what the motor gave instead (torque_check on delivered_Nm at joint speeds speed_rad_s:
    each sample against its own quadrant's limit, so sf >= 1: at the limit it is 1; demand_sf
    and demand_quadrant keep the demand's), and the check of the kind of limit it sat at most
    (over both quadrants) fails (torque: the peak current; speed: the voltage), with
    at_limit_fraction (all limits), limit (the "<quadrant>_<kind>" of that kind sat at most),
    limits (every share) and why, naming each limit's quadrant. Returns out, changed; unchanged
    below allowed_share."""
    share = float(sum(shares.values()))
    if not share > allowed_share:
        return out
    given = torque_check(checks, motor, delivered_Nm, speed_rad_s, percentile)
    out = {**out, "torque": {**out["torque"], **given, "demand_sf": out["torque"]["sf"],
                             "demand_quadrant": out["torque"]["quadrant"]}}
    by_kind = {kind: sum(v for k, v in shares.items() if k.endswith("_" + kind))
               for kind in LIMIT_KINDS}
    kind = "torque" if by_kind["torque"] >= by_kind["voltage"] else "voltage"
    most = max((k for k in shares if k.endswith("_" + kind)), key=lambda k: shares[k])
    name = "torque" if kind == "torque" else "speed"
    out[name] = dict(out[name], verdict="fail", at_limit_fraction=share, limit=most,
                     limits=dict(shares),
                     why=f"at {limit_shares_text(shares)} (in all {share:.1%}, more than "
                         f"{allowed_share:.0%}): it gave all it had, and the demand beyond it is "
                         "the controller's ask, not a need")
    out["verdict"], out["deciding_check"] = worst_check(out)
    return out


def demand_unmet(out: dict) -> dict | None:
    """The check that failed at the motor's limit (at_limit), None if the demand was met."""
    return next((out[k] for k in CHECK_ORDER if "at_limit_fraction" in out[k]), None)


def checks_of(motor: Motor, checks: Checks, torque: dict, margins, outside,
              rms_current_A: float) -> dict:
    """motor_checks from the figures already computed: the torque check (torque_check), the
    speed margins and outside flags of the operating points (Motor.speed_margins) and the RMS
    current (A, Motor.currents)."""
    out = {"torque": torque,
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
