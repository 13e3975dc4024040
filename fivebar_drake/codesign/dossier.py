"""The recommended design's dossier (OUT/dossier/): what a designer takes away from a co-design.

    spec_sheet.md   the design in one page: its actuator (motor, gearbox, ratio, mass, peak
                    torque in both quadrants, no-load speed, continuous torque), what its legs
                    allow for any controller (the highest jump, each gait's top speed), and per
                    motor the requirements to send to a vendor: the largest torque any maneuver
                    asked (its quadrant, its speed margin) and the largest RMS current, over its
                    simulated envelope (OUT/finalists/KEY/envelope.json), beside what the motor
                    gives
    quadruped.sdf   the design's Drake model (closed by the explicit bushing, as sdf/)
    quadruped.xml   the design's MuJoCo model (robots/quadruped/mjcf.py)
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from fivebar_drake.codesign.designs import design_params
from fivebar_drake.codesign.predict import ceiling
from fivebar_drake.codesign.spec import CodesignSpec
from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.text import figure as _f
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.optimal.top_speed import GAITS, top_speed
from fivebar_drake.robots.quadruped.closure import ExplicitBushing
from fivebar_drake.robots.quadruped.mjcf import MJCF_FILE, quadruped_mjcf
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.sdf import quadruped_sdf
from fivebar_drake.simulation.builder import closure_design
from fivebar_drake.simulation.scenario import load_scenario

DOSSIER_DIR = "dossier"
SHEET_FILE = "spec_sheet.md"
SHEET_GAITS = GAITS           # the gaits whose top speed the sheet gives
DOSSIER_FILES = ("quadruped.sdf", MJCF_FILE, SHEET_FILE)


def requirements(envelope: dict) -> dict[str, dict]:
    """Per motor (MOTORS) of a simulated envelope (envelope.json's dictionary): the largest
    torque asked (demand p99 over the maneuvers, N*m) with its quadrant, maneuver and the
    motor's limit there, the least speed margin, and the largest RMS current (A) with the
    duty cycle's equivalent current where there is one."""
    out = {}
    for motor in MOTORS:
        rows = [(name, m["motors"][motor]["checks"]) for name, m in envelope["maneuvers"].items()
                if m.get("motors") and motor in m["motors"]]
        torque = max(rows, key=lambda r: r[1]["torque"]["torque_Nm"])
        speed = min(rows, key=lambda r: r[1]["speed"]["least_margin"] or math.inf)
        current = max(rows, key=lambda r: r[1]["thermal"]["rms_current_A"] or 0.0)
        duty = ((envelope.get("duty_cycle") or {}).get("motors") or {}).get(motor) or {}
        out[motor] = {"torque_Nm": torque[1]["torque"]["torque_Nm"],
                      "quadrant": torque[1]["torque"]["quadrant"], "torque_maneuver": torque[0],
                      "limit_Nm": torque[1]["torque"]["limit_Nm"],
                      "speed_margin": speed[1]["speed"]["least_margin"],
                      "speed_maneuver": speed[0],
                      "rms_current_A": current[1]["thermal"]["rms_current_A"],
                      "current_maneuver": current[0],
                      "continuous_current_A": current[1]["thermal"].get("continuous_current_A"),
                      "duty_cycle_current_A": duty.get("equivalent_current_A")}
    return out


def capabilities(params: Params) -> dict:
    """What the design's legs allow for any controller: the highest jump (m above standing,
    vertical_jump's ceiling; None where none) and each SHEET_GAITS gait's top speed (m/s, nan
    where none) with what limits it."""
    jump = ceiling(params)
    speeds = {kind: top_speed(params, kind) for kind in SHEET_GAITS}
    return {"jump_m": None if jump is None else jump.body_apex_above_standing_m,
            "top_speed": {k: {"speed_m_s": t.speed_m_s, "limited_by": t.limited_by,
                              "bound_m_s": t.bound_m_s} for k, t in speeds.items()}}


def sheet(report: dict, params: Params, needs: dict, allows: dict) -> str:
    """spec_sheet.md of the recommended design (design.json's recommended entry)."""
    r, m = report["recommended"], params.motor
    design = r["design"]
    speeds = {k: t["speed_m_s"] for k, t in allows["top_speed"].items()
              if math.isfinite(t["speed_m_s"])}
    fastest = max(speeds, key=speeds.get) if speeds else None
    asked = max(needs.values(), key=lambda n: n["torque_Nm"] / n["limit_Nm"])
    lines = [f"# Spec sheet: {r['name']}", "",
             f"**Answer:** Recommended: {r['name']} ({r['key']}), PASS on every maneuver of its "
             f"simulated envelope, no motor asked more than {asked['torque_Nm']:.2f} N·m of its "
             f"{asked['limit_Nm']:.2f} N·m; for any controller its legs allow "
             + ("no jump" if allows["jump_m"] is None else
                f"a {allows['jump_m'] * 1e3:.0f} mm jump")
             + ("" if fastest is None else f" and a {fastest} at {speeds[fastest]:.2f} m/s")
             + ". Below: its actuator, what its legs allow, and per motor what its maneuvers "
               "asked (the requirements to send to a vendor).", "",
             "## Actuator", "",
             "| figure | value |", "|---|---|",
             f"| motor | {design['motor']} |",
             f"| gearbox | {design.get('gearbox', '')} at {m.gear_ratio:.2f}:1 |",
             f"| actuator mass (kg) | {r['objectives']['actuator_mass_kg']:.3f} |",
             f"| peak torque, driving / braking (N·m) | {m.peak_torque_Nm:.2f} / "
             f"{m.braking_peak_torque_Nm:.2f} |",
             f"| no-load speed (rad/s) | {m.no_load_speed_rad_s:.2f} |",
             f"| continuous current (A) | {_f(m.rated_continuous_current_A)} |",
             f"| reflected rotor inertia (kg·m^2) | {m.reflected_inertia_kg_m2:.3g} |", "",
             "## What the legs allow (any controller)", "",
             "| figure | value | limited by |", "|---|---|---|",
             "| highest jump above standing (mm) | "
             + ("none" if allows["jump_m"] is None else f"{allows['jump_m'] * 1e3:.0f}")
             + " | the one-leg model's ceiling (optimal/vertical_jump.py) |"]
    for kind, t in allows["top_speed"].items():
        lines.append(f"| {kind} top speed (m/s) | {_f(t['speed_m_s'])} | {t['limited_by']} "
                     f"(no-load bound {t['bound_m_s']:.2f} m/s) |")
    lines += ["", "## Requirements per motor (its simulated envelope)", "",
              "| motor | largest torque asked (N·m) | quadrant | in | limit (N·m) | "
              "least speed margin | in | largest RMS current (A) | in | duty cycle (A RMS) | "
              "continuous current (A) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for motor, n in needs.items():
        lines.append(f"| {motor} | {n['torque_Nm']:.2f} | {n['quadrant']} | "
                     f"{n['torque_maneuver']} | {n['limit_Nm']:.2f} | {_f(n['speed_margin'])} | "
                     f"{n['speed_maneuver']} | {_f(n['rms_current_A'])} | "
                     f"{n['current_maneuver']} | {_f(n['duty_cycle_current_A'])} | "
                     f"{_f(n['continuous_current_A'])} |")
    lines += ["", f"Models: `quadruped.sdf` (Drake), `{MJCF_FILE}` (MuJoCo), `../design.toml` "
                  "(the parameter file: `fivebar-drake optimal --config ../design.toml`, "
                  "`simulate --config ../design.toml`)."]
    return "\n".join(lines) + "\n"


def write_dossier(spec: CodesignSpec, report: dict, out: Path, finalists: Path) -> list[Path]:
    """Write OUT/dossier/ for the recommended design (module docstring; its envelope in
    finalists/KEY/); [] without one, and an earlier run's dossier removed."""
    folder = out / DOSSIER_DIR
    for name in DOSSIER_FILES:
        (folder / name).unlink(missing_ok=True)
    r = report["recommended"]
    if r is None:
        return []
    params = design_params(spec.envelope.maneuvers[0].params, r["design"])
    envelope = json.loads((finalists / r["key"] / "envelope.json").read_text())
    folder.mkdir(parents=True, exist_ok=True)
    bushing = closure_design(load_scenario(closure="bushing_rpy"), params).bushing
    return [write_atomic(folder / DOSSIER_FILES[0], quadruped_sdf(params, ExplicitBushing(),
                                                                 bushing)),
            write_atomic(folder / MJCF_FILE, quadruped_mjcf(params)),
            write_atomic(folder / SHEET_FILE, sheet(report, params, requirements(envelope),
                                                    capabilities(params)))]
