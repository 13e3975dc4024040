"""The recommended design's dossier (OUT/dossier/): what a designer takes away from a co-design.

    spec_sheet.md   the design in one page: its actuator (motor, gearbox, ratio, mass, peak
                    torque in both quadrants, no-load speed, continuous torque), what its legs
                    allow for any controller (the highest jump, each gait's top speed), and per
                    motor the requirements to send to a vendor: the largest torque any maneuver
                    asked (its quadrant, its speed margin) and the largest RMS current, over its
                    simulated envelope (OUT/finalists/KEY/envelope.json), beside what the motor
                    gives
    operating_points.png  the default design's operating points and envelope beside the
                    recommended design's (each finalist's simulated envelope)
    quadruped.sdf   the design's Drake model (closed by the explicit bushing, as sdf/)
    quadruped.xml   the design's MuJoCo model (robots/quadruped/mjcf.py)
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import numpy as np

from fivebar_drake.codesign.designs import design_params
from fivebar_drake.codesign.predict import ceiling
from fivebar_drake.codesign.report import DEFAULT
from fivebar_drake.codesign.spec import CodesignSpec
from fivebar_drake.core.files import save_figure, write_atomic
from fivebar_drake.core.text import ANSWER_CHARS
from fivebar_drake.core.text import figure as _f
from fivebar_drake.envelope.plots import (OPERATING_POINTS_FILE, POINTS_FILE, load_points,
                                          plot_operating_points)
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
MARGINS_FILE = "margins.png"
OVERLAY_FILE = OPERATING_POINTS_FILE
REQUIREMENTS_FILE = "requirements.csv"
SHEET_GAITS = GAITS           # the gaits whose top speed the sheet gives
DOSSIER_FILES = ("quadruped.sdf", MJCF_FILE, REQUIREMENTS_FILE, MARGINS_FILE, OVERLAY_FILE,
                 SHEET_FILE)
# the simulated figures the margins picture sets side by side: (key, label, where it fails
# below, and where it warns below or passes from: a Checks field or a number)
MARGIN_CHECKS = (("torque", "torque: SF", "sf_warn", ("pass from", "sf_pass")),
                 ("speed", "speed: least margin", 1.0, ("warn below", "speed_margin_warn")),
                 ("thermal", "thermal: continuous / RMS current", 1.0,
                  ("warn below", "thermal_margin_warn")))


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


def _sheet_answer(r: dict, asked: dict, allows: dict, fastest, speeds: dict) -> str:
    """The spec sheet's first line (at most ANSWER_CHARS where the design's name allows)."""
    head = (f"**Answer:** Recommended: {r['name']}: PASS on its simulated envelope, at most "
            f"{asked['torque_Nm']:.2f} of {asked['limit_Nm']:.2f} N·m asked")
    legs = ("; for any controller its legs allow "
            + ("no jump" if allows["jump_m"] is None else
               f"a {allows['jump_m'] * 1e3:.0f} mm jump")
            + ("" if fastest is None else f" and a {fastest} at {speeds[fastest]:.2f} m/s"))
    return head + (legs if len(head + legs) < ANSWER_CHARS else "") + "."


def sheet(report: dict, params: Params, needs: dict, allows: dict, overlay: bool) -> str:
    """spec_sheet.md of the recommended design (design.json's recommended entry); overlay: with
    OVERLAY_FILE's picture."""
    r, m = report["recommended"], params.motor
    design = r["design"]
    speeds = {k: t["speed_m_s"] for k, t in allows["top_speed"].items()
              if math.isfinite(t["speed_m_s"])}
    fastest = max(speeds, key=speeds.get) if speeds else None
    asked = max(needs.values(), key=lambda n: n["torque_Nm"] / n["limit_Nm"])
    lines = [f"# Spec sheet: {r['name']}", "",
             _sheet_answer(r, asked, allows, fastest, speeds), "",
             "Below: its actuator, what its legs allow, and per motor what its maneuvers asked "
             f"(the requirements to send to a vendor, also as `{REQUIREMENTS_FILE}`).", "",
             f"![Simulated figures: default and recommended]({MARGINS_FILE})", "",
             *([f"![Operating points over each design's envelope: default and recommended]"
                f"({OVERLAY_FILE})", ""] if overlay else []),
             "## Actuator", "",
             "| figure | value |", "|---|---|",
             f"| motor | {design['motor']} |",
             f"| gearbox | {design.get('gearbox', '')} at {m.gear_ratio:.2f}:1 |",
             f"| actuator mass (kg) | {r['objectives']['actuator_mass_kg']:.3f} |",
             f"| peak torque, driving / braking (N·m) | {m.peak_torque_Nm:.2f} / "
             f"{m.braking_peak_torque_Nm:.2f} |",
             f"| no-load speed (rad/s) | {m.no_load_speed_rad_s:.2f} |",
             f"| continuous current (A) | {_f(m.rated_continuous_current_A)} |",
             f"| continuous torque (N·m) | {_f(m.continuous_torque_Nm)} |",
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


def requirements_csv(needs: dict, params: Params, allows: dict) -> str:
    """requirements.csv: one row per motor for a vendor (requirements' figures), with the
    continuous torque the rating gives (N*m at the output) and the fastest top speed the legs
    allow (m/s, for any controller)."""
    m = params.motor
    speeds = [t["speed_m_s"] for t in allows["top_speed"].values()
              if math.isfinite(t["speed_m_s"])]
    columns = ("motor", "peak_torque_asked_Nm", "quadrant", "in_maneuver", "peak_torque_limit_Nm",
               "least_speed_margin", "largest_rms_current_A", "duty_cycle_rms_current_A",
               "continuous_current_A", "continuous_torque_Nm", "no_load_speed_rad_s",
               "top_speed_m_s")
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for motor, n in needs.items():
        writer.writerow([motor, f"{n['torque_Nm']:.4g}", n["quadrant"], n["torque_maneuver"],
                         f"{n['limit_Nm']:.4g}", _g(n["speed_margin"]), _g(n["rms_current_A"]),
                         _g(n["duty_cycle_current_A"]), _g(n["continuous_current_A"]),
                         _g(m.continuous_torque_Nm), f"{m.no_load_speed_rad_s:.4g}",
                         _g(max(speeds) if speeds else None)])
    return buffer.getvalue()


def _g(x) -> str:
    """A CSV figure to 4 significant digits; empty where there is none."""
    return "" if x is None or not math.isfinite(x) else f"{x:.4g}"


def plot_margins(report: dict, checks, path: Path) -> Path:
    """margins.png: per check (MARGIN_CHECKS) and maneuver, the default design's simulated
    figure beside the recommended design's (design.json's, the worst motor's), with the
    thresholds where the check warns and fails."""
    import matplotlib.pyplot as plt

    designs = {"default design": report["default"]["simulated"],
               "recommended": report["recommended"]["simulated"]}
    names = [n for n in designs["recommended"]["maneuvers"]
             if designs["recommended"]["maneuvers"][n].get("figures")]
    fig, axes = plt.subplots(1, len(MARGIN_CHECKS), figsize=(13, 4.2))
    x = np.arange(len(names))
    for ax, (key, label, fails, turns) in zip(axes, MARGIN_CHECKS):
        top = 1.0
        for k, (design, colour) in enumerate(zip(designs, ("0.6", "tab:blue"))):
            runs = (designs[design] or {}).get("maneuvers") or {}
            values = [((runs.get(n) or {}).get("figures") or {}).get(key) for n in names]
            values = [np.nan if v is None else v for v in values]
            bars = ax.bar(x + (k - 0.5) * 0.38, values, 0.38, color=colour, label=design)
            ax.bar_label(bars, fmt="%.2f", fontsize=7)
            top = max(top, np.nanmax(values, initial=0.0))
        fail = getattr(checks, fails) if isinstance(fails, str) else fails
        word, other = turns
        ax.axhline(fail, color="tab:red", ls="--", lw=1, label=f"fail below {fail:g}")
        ax.axhline(getattr(checks, other), color="tab:orange" if word.startswith("warn") else
                   "tab:green", ls=":", lw=1.2, label=f"{word} {getattr(checks, other):g}")
        ax.set(title=label, xticks=x, xticklabels=names, ylim=(0.0, 1.5 * top))
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", ncol=2)      # above the bars
    fig.suptitle("Simulated figures, the worst motor per maneuver: default and recommended")
    fig.tight_layout()
    return save_figure(fig, path)


def plot_overlay(report: dict, spec: CodesignSpec, finalists: Path, path: Path) -> Path | None:
    """OVERLAY_FILE: the default design's and the recommended design's operating points, each over
    its own motor's envelope (their envelopes' POINTS_FILE); None where either has none."""
    base, r = spec.envelope.maneuvers[0].params, report["recommended"]
    designs = {"default design": (base.motor, finalists / DEFAULT / POINTS_FILE),
               "recommended": (design_params(base, r["design"]).motor,
                               finalists / r["key"] / POINTS_FILE)}
    if not all(points.is_file() for _, points in designs.values()):
        return None
    return plot_operating_points({label: (motor, load_points(points))
                                  for label, (motor, points) in designs.items()}, path)


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
    needs, allows = requirements(envelope), capabilities(params)
    return [write_atomic(folder / DOSSIER_FILES[0], quadruped_sdf(params, ExplicitBushing(),
                                                                 bushing)),
            write_atomic(folder / MJCF_FILE, quadruped_mjcf(params)),
            write_atomic(folder / REQUIREMENTS_FILE, requirements_csv(needs, params, allows)),
            plot_margins(report, params.checks, folder / MARGINS_FILE),
            *filter(None, [plot_overlay(report, spec, finalists, folder / OVERLAY_FILE)]),
            write_atomic(folder / SHEET_FILE, sheet(report, params, needs, allows,
                                                    (folder / OVERLAY_FILE).is_file()))]
