"""The co-design's predictions, two levels below simulation, each honest about what it covers:

(a) screening, closed form: the full model's torque analysis over one cycle of the trot path
    under trot loading (analysis/design_points.evaluate_designs, vectorised over the designs
    that share a leg) for each trot maneuver of the requirements, with that maneuver's gait:
    each motor's safety factor, speed and thermal checks;
(b) the optimal-maneuver floors, for the designs that pass (a): for each jump and drop
    (optimal/vertical_jump.py), the least peak motor torque any controller needs for its
    push-off and its landing on the maneuver's own strokes; for each walk, bound and pronk
    (optimal/gait_floor.py: the body free to surge, heave and pitch, cached per process by the
    design without its motor), the least peak stance torque of the gait at its speed, period
    and payload, and the worst motor's RMS current on that motion. The predicted safety factor
    is the motors' peak over the floor, the thermal margin the continuous current over that RMS
    current: upper bounds on the simulated (no controller does better, the package's asks
    more; the floor neglects the swing legs and the links' inertia).

With requirements.actuator_mass, a design's actuator mass (motor and gearbox, as designed: no
prediction) must lie within the band: its margin is the band's half-width over the design's
relative distance from the reference mass (capped at MASS_MARGIN_CAP).
With requirements.top_speed_m_s, each gait's top speed for any controller (optimal/top_speed.py,
on the first maneuver's parameters; for the designs that pass (a)) over the least required:
predicted only, the simulated finalists are not run at it.
The duty cycle's thermal margin is predicted as the least closed-form thermal margin of its
maneuvers (duty_cycle). The stand-up has no prediction here: the simulation alone judges it.
A requirement's margin is the figure over what the accepted verdict needs (>= 1 meets it): the safety factor over checks.sf_pass (sf_warn when warn is accepted), the
least speed margin over checks.speed_margin_warn (1), the thermal current margin over
checks.thermal_margin_warn (1).
"""

from __future__ import annotations

import math

import numpy as np

from fivebar_drake.analysis.design_points import evaluate_designs
from fivebar_drake.codesign.designs import actuator_mass, design_name, design_params
from fivebar_drake.codesign.spec import (GAITS, MASS, ON_GAIT, ON_MANEUVER, TOP_SPEED,
                                         CodesignSpec)
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.envelope.spec import Maneuver
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.optimal import gait_floor, top_speed, vertical_jump
from fivebar_drake.optimal.needs import NEEDS, needs_of
from fivebar_drake.robots.quadruped.params import Params

SCREENED = ("trot",)              # gait kinds level (a) predicts
FLOORED = tuple(k for k in gait_floor.KINDS if k not in SCREENED)   # and level (b)'s
DUTY = "duty cycle"               # its row beside the maneuvers (no maneuver name has a space)
CHECKS = ("torque", "speed", "thermal")
MASS_MARGIN_CAP = 10.0            # the mass band's margin of a design at (or near) its reference


def needs(params: Params, accept: tuple[str, ...]) -> dict[str, float]:
    """What each check's figure must reach for the accepted verdicts."""
    c, warn = params.checks, "warn" in accept
    return {"torque": c.sf_warn if warn else c.sf_pass,
            "speed": 1.0 if warn else c.speed_margin_warn,
            "thermal": 1.0 if warn else c.thermal_margin_warn}


def closed_form(maneuver: Maneuver, designs: list[Params], accept) -> list[dict]:
    """Level (a) of a trot maneuver for many designs (its gait, each design's parameters): per
    design the worst motor's safety factor, its verdict, each check's margin, or an error."""
    out = []
    for params, row in zip(designs, evaluate_designs(designs, "trot", "full_trot")):
        if "error" in row:
            out.append({"level": "closed form", "error": row["error"], "margins": {}})
            continue
        need = needs(params, accept)
        figures = {"torque": min(row[m]["safety_factor"] for m in MOTORS),
                   "speed": min(row[m]["speed_margin"] for m in MOTORS),
                   "thermal": min(row[m]["thermal_current_margin"] for m in MOTORS)}
        worst = min(MOTORS, key=lambda m: row[m]["safety_factor"])
        out.append({"level": "closed form", "safety_factor": figures["torque"],
                    "verdict": max((row[m]["verdict"] for m in MOTORS), key=_severity),
                    "deciding_check": row[worst]["deciding_check"],
                    "margins": {c: figures[c] / need[c] for c in CHECKS}})
    return out


def _severity(verdict: str) -> int:
    return ("pass", "warn", "fail").index(verdict) if verdict in ("pass", "warn", "fail") else 3


def floors(maneuver: Maneuver, params: Params, accept) -> dict:
    """Level (b) of a maneuver whose kind has a need (optimal/needs.needs_of: a jump's push-off
    and landing, a drop's landing; their floors, N*m), the motors' safety factor on them (each
    phase's limit in its quadrant, driving or braking, over its floor: the least), the torque
    margin. A phase beyond the bound by another method is a margin of 0 with why; a phase
    between the model's optimum and its bound has no prediction (undecided: margin None, left to
    the simulation), as pipeline.any_controller splits a run."""
    needs_ = needs_of(params, maneuver.scenario.gait, maneuver.scenario.payload_kg)
    phases = {name: need.floor_Nm for name, (need, _) in needs_.items()}
    why = "; ".join(need.why for need, _ in needs_.values() if need.why)
    statuses = {need.status for need, _ in needs_.values()}
    if "beyond bound" in statuses:
        return {"level": "floor", "phases": phases, "safety_factor": 0.0, "verdict": "fail",
                "why": why, "margins": {"torque": 0.0}}
    if statuses - {"floor"}:
        return {"level": "floor", "phases": phases, "safety_factor": None,
                "verdict": "undecided", "why": why, "margins": {}}
    sf = min(limit / need.floor_Nm for need, limit in needs_.values())
    return {"level": "floor", "phases": phases, "safety_factor": sf,
            "margins": {"torque": sf / needs(params, accept)["torque"]}}


def gait_floors(maneuver: Maneuver, params: Params, accept) -> dict:
    """Level (b) of a walk, bound or pronk (module docstring): the floor (N*m), the motors'
    safety factor on it and its torque margin, the thermal margin where the motor has a
    continuous rating; a gait no motion of the floor's model carries is a margin of 0 with
    why."""
    try:
        floor = gait_floor.gait_floor(params, maneuver.scenario.gait, maneuver.scenario.payload_kg)
    except ParameterError as err:
        return {"level": "floor", "safety_factor": 0.0, "verdict": "fail", "why": err.message,
                "margins": {"torque": 0.0}}
    need = needs(params, accept)
    sf = params.motor.peak_torque_Nm / floor.floor_Nm
    out = {"level": "floor", "floor_Nm": floor.floor_Nm, "safety_factor": sf,
           "margins": {"torque": sf / need["torque"]}}
    continuous = getattr(params.motor, "rated_continuous_current_A", None)
    if continuous and math.isfinite(floor.rms_current_A) and floor.rms_current_A > 0:
        out["margins"]["thermal"] = continuous / floor.rms_current_A / need["thermal"]
    return out


def duty_cycle(spec: CodesignSpec, entry: dict) -> dict | None:
    """The duty cycle's thermal margin, predicted as the least closed-form thermal margin of its
    maneuvers that have one (a steady trot's winding: the cycle's hottest part when it runs
    long against the winding's time constant); None without a duty cycle or such a maneuver."""
    steps = {s.maneuver for s in spec.envelope.duty_cycle}
    margins = [entry["maneuvers"][name]["margins"]["thermal"] for name in steps
               if entry["maneuvers"].get(name, {}).get("level") == "closed form"
               and "thermal" in entry["maneuvers"][name]["margins"]]
    if not margins:
        return None
    return {"level": "closed form (its maneuvers' steady state)",
            "margins": {"thermal": min(margins)}}


def mass_band(spec: CodesignSpec, mass_kg: float) -> dict | None:
    """The mass band's row (module docstring), None without one."""
    if spec.mass_band is None:
        return None
    reference, within = spec.mass_band
    off = abs(mass_kg / reference - 1.0)
    return {"level": "design", "actuator_mass_kg": mass_kg, "reference_kg": reference,
            "within": within, "margins": {
                "within": MASS_MARGIN_CAP if off * MASS_MARGIN_CAP <= within else within / off}}


def top_speed_of(params: Params, gait: str) -> float:
    """A gait's top speed for any controller (m/s; optimal/top_speed.py), 0 where none."""
    speed = top_speed.top_speed(params, gait).speed_m_s
    return speed if math.isfinite(speed) else 0.0


def speed_objectives(spec: CodesignSpec, params: Params) -> dict[str, float]:
    """The top_speed_m_s:GAIT objectives of spec on the design's parameters."""
    return {o: top_speed_of(params, o.partition(":")[2]) for o in spec.objectives
            if o.partition(":")[0] in ON_GAIT}


def speed_requirements(spec: CodesignSpec, params: Params) -> dict[str, dict]:
    """A row per required top speed (TOP_SPEED by gait): the top speed against the least
    required, its margin their ratio (any controller: predicted, not simulated)."""
    rows = {}
    for gait, required in spec.top_speeds:
        speed = top_speed_of(params, gait)
        rows[TOP_SPEED.format(gait)] = {"level": "any controller", "top_speed_m_s": speed,
                                        "required_m_s": required,
                                        "margins": {"speed": speed / required}}
    return rows


def max_jump_height(params: Params) -> float:
    """The highest vertical jump the legs and motors allow (m above standing, any controller:
    the ceiling over the leg's whole reach, optimal/vertical_jump.push)."""
    jump = ceiling(params)
    return 0.0 if jump is None else jump.body_apex_above_standing_m


def ceiling(params: Params):
    """The highest jump over the leg's reach (vertical_jump.Jump), None where there is none (no
    push reaches takeoff, or no hip height within the limits)."""
    try:
        low, high = vertical_jump.reach(params)
    except ParameterError:
        return None
    return vertical_jump.push(vertical_jump.stroke(params, low, high), -params.gait.y_home_m)


def power_maneuvers(spec: CodesignSpec, objective: str) -> list[Maneuver]:
    """The maneuvers a power objective is on: the one it names (NAME:MANEUVER), else every
    gait maneuver of the envelope."""
    name = objective.partition(":")[2]
    return [m for m in spec.envelope.maneuvers
            if (m.name == name if name else m.scenario.gait.kind in GAITS)]


def floor_power(maneuver: Maneuver, params: Params) -> dict:
    """The robot's electrical power over the gait floor's motion of a gait maneuver (its
    stance legs' torques and speeds; the swing legs draw nothing in the floor's model): the
    peak (W, over the period's knots, summed over the motors: what the battery gives) and the
    cost of transport (the period's positive electrical energy over m g times the distance:
    the gait's stance speed times the period); nan where the motor has no electrical model or
    no floor is found."""
    power = getattr(params.motor, "electrical_power_W", None)
    try:
        floor = gait_floor.gait_floor(params, maneuver.scenario.gait,
                                      maneuver.scenario.payload_kg)
    except ParameterError:
        floor = None
    if power is None or floor is None:
        return {"peak_W": math.nan, "cost_of_transport": math.nan}
    robot = power(floor.torque_Nm, floor.speed_rad_s).sum(axis=(0, 2))
    period = params.gait.period_s
    energy = float(np.clip(robot, 0.0, None).mean() * period)
    distance = maneuver.scenario.gait.stance_speed(params.gait) * period
    weight = floor.mass_kg * params.robot.gravity_m_s2
    return {"peak_W": float(robot.max()),
            "cost_of_transport": energy / (weight * distance) if distance > 0 else math.nan}


def power_objectives(spec: CodesignSpec, params: dict[str, Params]) -> dict[str, float]:
    """The power objectives of spec (peak_electrical_power_W[:MANEUVER],
    cost_of_transport:MANEUVER) predicted on the gait floors (floor_power) of a design's
    maneuvers' parameters: the peak the largest over its maneuvers."""
    out = {}
    for objective in spec.objectives:
        kind = objective.partition(":")[0]
        if kind not in ON_MANEUVER:
            continue
        figures = [floor_power(m, params[m.name]) for m in power_maneuvers(spec, objective)]
        out[objective] = (max(f["peak_W"] for f in figures) if kind == "peak_electrical_power_W"
                          else figures[0]["cost_of_transport"])
    return out


def predict(spec: CodesignSpec, designs: list[dict]) -> list[dict]:
    """Each design's prediction (JSON-ready): its name, objectives, per maneuver the level that
    judged it and its figures, the least margin and where (`short_of`), whether it meets every
    predicted requirement (`meets`), or `error` for a design that cannot be built."""
    maneuvers = spec.envelope.maneuvers
    out, built = [], []
    for design in designs:
        entry = {"design": design, "name": design_name(design), "error": "",
                 "objectives": {"actuator_mass_kg": actuator_mass(design)}, "maneuvers": {}}
        try:
            params = {m.name: design_params(m.params, design) for m in maneuvers}
        except ParameterError as err:
            entry["error"] = str(err)
            params = None
        out.append(entry)
        built.append(params)
    ok = [i for i, p in enumerate(built) if p is not None]
    for m in maneuvers:
        if m.scenario.gait.kind in SCREENED and ok:
            for i, result in zip(ok, closed_form(m, [built[i][m.name] for i in ok],
                                                 spec.accept)):
                out[i]["maneuvers"][m.name] = result
    for i in ok:
        entry = out[i]
        band = mass_band(spec, entry["objectives"]["actuator_mass_kg"])
        if band is not None:        # outside it, no floors
            entry["maneuvers"][MASS] = band
        screened = _least(entry)[0] >= 1.0
        for m in maneuvers:
            if m.scenario.gait.lands and m.scenario.gait.kind in NEEDS and screened:
                entry["maneuvers"][m.name] = floors(m, built[i][m.name], spec.accept)
            elif m.scenario.gait.kind in FLOORED and screened:
                entry["maneuvers"][m.name] = gait_floors(m, built[i][m.name], spec.accept)
        if "max_jump_height_m" in spec.objectives:
            entry["objectives"]["max_jump_height_m"] = max_jump_height(built[i][maneuvers[0].name])
        entry["objectives"].update(speed_objectives(spec, built[i][maneuvers[0].name]))
        if screened:
            entry["maneuvers"].update(speed_requirements(spec, built[i][maneuvers[0].name]))
        entry["objectives"].update({k: v for k, v in power_objectives(spec, built[i]).items()
                                    if math.isfinite(v)})
        duty = duty_cycle(spec, entry)
        if duty is not None:
            entry["maneuvers"][DUTY] = duty
        entry["margin"], entry["short_of"] = _least(entry)
        entry["meets"] = entry["margin"] >= 1.0 and not any(
            "error" in r for r in entry["maneuvers"].values())
    for i in set(range(len(designs))) - set(ok):
        out[i].update(margin=0.0, short_of="", meets=False)
    return out


def _least(entry: dict) -> tuple[float, str]:
    """(the least margin of the design's predicted requirements, "maneuver check" of it);
    (inf, "") with none predicted, (0, maneuver) where a maneuver has an error."""
    least, where = math.inf, ""
    for name, result in entry["maneuvers"].items():
        if "error" in result:
            return 0.0, name
        for check, margin in result["margins"].items():
            if margin < least:
                least, where = margin, f"{name} {check}"
    return least, where
