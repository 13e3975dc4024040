"""report.md and report.json of the torque analysis: the seed's Tables 3-5 filled for each model."""

from __future__ import annotations

import json
import math
from pathlib import Path

from fivebar_drake.analysis.design_report import design_assumptions, design_lines
from fivebar_drake.analysis.torques import Analysis
from fivebar_drake.core.files import json_ready, write_atomic
from fivebar_drake.core.text import ANSWER_CHARS, figure
from fivebar_drake.gaits import foot_path
from fivebar_drake.actuators.motor import FRICTION_SMOOTHING_RAD_S
from fivebar_drake.mechanisms.fivebar import LINK_NAMES, MOTORS, physical_izz
from fivebar_drake.robots.quadruped.config import sampling_error


SIDE_BY_SIDE = ("seed", "full")
REPORT_FILES = ("report.md", "report.json")
FIGURE_NAMES = ("joint_angles", "joint_rates", "torque_components", "total_torque", "workspace",
                "force_capability", "force_margin", "torque_speed", "thermal", "joint_loads",
                "gear_ratio")
ANALYSIS_FILES = REPORT_FILES + tuple(f"{name}.png" for name in FIGURE_NAMES)  # what analyze writes


def assumptions(analysis: Analysis) -> list[str]:
    p = analysis.params
    izz = dict(zip(LINK_NAMES, physical_izz(p.leg, p.links)))
    return [
        f"Weight share m_leg = {p.robot.total_mass_kg:.2f} kg / {p.robot.legs} legs = "
        f"{p.robot.weight_share_kg:.4f} kg acts at the foot for the whole cycle, swing included "
        "(seed 000 eq. 8), in the `seed` and `full` models; `full_trot` is the trot reading.",
        "Static torque of a pose: the torque that holds it with q' = q'' = 0 under the same "
        "loads (link weights + foot load); its peak over the cycle is reported.",
        f"Izz values are about each link's COM, axis along the hinges. The seed's '~0' for AC is "
        f"0 in the `seed` model and the thin-rod estimate m L^2/12 = {izz['AC']:.3g} kg m^2 in "
        "the `full` models.",
        " ".join(motor_assumption(p.motor)),
        f"The motor's operating points are the joint's torque plus the output friction it "
        f"overcomes (Coulomb {p.motor.coulomb_friction_Nm:g} N·m, regularised over "
        f"{FRICTION_SMOOTHING_RAD_S:g} rad/s, and viscous {p.motor.viscous_friction_Nm_s:g} N·m "
        "s/rad: the law the simulation's motor model applies) at the joint speed; the checks "
        "take each against the envelope of its own quadrant (driving: torque and speed of one "
        "sign; braking: opposite signs). The seed's Tables 3-5 keep the joint torque alone.",
        "Joint rates and accelerations are periodic central differences over the N samples "
        "(seed 000 section 5); the IK mode follows seed 000 appendix B from the knees-out mode.",
        f"Safety factor (Table 5, the seed's) = {p.motor.peak_torque_Nm:g} N·m / the peak "
        "|dynamic torque|; the torque check's = 1 / the largest |operating torque| over the "
        "peak-current torque of its quadrant; verdict: SF >= "
        f"{p.checks.sf_pass:g} pass, {p.checks.sf_warn:g} <= SF < {p.checks.sf_pass:g} warn, "
        "else fail.",
        "The leg's limits ([limits] of the parameter file): " + (
            ", ".join(f"{k} = {v:g}" for k, v in p.limits.given.items())
            + "; the IK, the foot paths, the workspace and force-capability maps respect them (a "
            "pose past one counts as out of reach)" if p.limits.given else "none set"),
        *design_assumptions(p),
    ]


def motor_assumption(motor) -> list[str]:
    """The actuator model, with its output figures: its opening sentence, then (a brushless
    motor) each part of its envelope; report.md lists the parts under the opening, report.json
    joins them into one assumption."""
    if motor.model != "bldc":
        return [f"The {motor.peak_torque_Nm:g} N·m motor torque is taken at the gearbox output "
                f"(gear {motor.gear_ratio:g}:1, model = \"{motor.model}\"): a linear "
                f"torque-speed line from it to the no-load speed {motor.no_load_speed_rad_s:.2f} "
                f"rad/s ({motor.no_load_speed_rad_s * 60 / (2 * math.pi):.0f} RPM), braking held "
                f"at {motor.braking_peak_torque_Nm:.3g} N·m up to it; beyond it the line goes on "
                "into braking (as a DC motor's)."]
    law = motor.law
    corner = (law.phase_voltage - law.resistance * law.peak_current) / (law.back_emf * law.gear)
    return [
        f"The actuator is a brushless motor behind a {motor.gear_ratio:g}:1 gearbox "
        f"(efficiency {motor.gear_efficiency:g}), from motor-side data ([motor]: k_t = "
        f"{motor.torque_constant_Nm_per_A:.4g} N·m per A of q-axis current, R = "
        f"{motor.winding_resistance_ohm:g} ohm, V_bus = {motor.bus_voltage_V:g} V, I_peak = "
        f"{motor.peak_current_A:.4g} A), the winding's inductance neglected:",
        "|i| <= I_peak and the voltage equation R i + (k_t / 1.5) N w within +-V_bus / sqrt(3) "
        "(the phase amplitude of space-vector modulation);",
        "output torque N eta k_t i driving and N k_t i / eta braking;",
        f"driving: flat at {motor.peak_torque_Nm:.3g} N·m up to the corner {corner:.2f} rad/s, "
        f"then falling to zero at the no-load speed {motor.no_load_speed_rad_s:.2f} rad/s "
        f"({motor.no_load_speed_rad_s * 60 / (2 * math.pi):.0f} RPM); braking "
        f"{motor.braking_peak_torque_Nm:.3g} N·m;",
        "beyond the no-load speed the back-EMF exceeds the phase voltage and forces regenerative "
        "braking ((k_t / 1.5) N w - V_bus / sqrt(3)) / R amperes at least: the motor cannot coast "
        "there (README \"The actuator\").",
    ]


def _where(at: dict) -> str:
    x, y = (v * 1e3 for v in at["foot_m"])
    return f"t = {at['time_s']:.3f} s (sample {at['sample']}), F = ({x:.1f}, {y:.1f}) mm"


ANSWER_MODELS = (("full_trot", "the physically consistent model with the trot's loading"),
                 ("seed", "the seed's model as written"))


def answer(analysis: Analysis) -> str:
    """report.md's first line (at most ANSWER_CHARS): each motor's verdict and its torque
    check's safety factor, for the physically consistent model under the trot's loading (what
    the robot's legs carry) and for the seed's model as written. The check that decided a
    verdict is named at the first motor and wherever it changes; if that runs over
    ANSWER_CHARS, only where it is not the torque check (the SF is the torque check's), then in
    one word, then nowhere: answer_details names every one."""
    r = analysis.results["results"]

    def line(name) -> str:
        groups, last = [], None
        for model, label in ANSWER_MODELS:
            parts = []
            for m in MOTORS:
                c = r[model][m]["checks"]
                by = name(c["deciding_check"], last)
                last = c["deciding_check"]
                parts.append(f"{m} {c['verdict'].upper()}{by} (SF {figure(c['torque']['sf'])})")
            groups.append(f"{label}: {', '.join(parts)}")
        return f"**Answer:** {'; '.join(groups)}."

    namings = (lambda check, last: f" by the {check} check" if check != last else "",
               lambda check, last: f" by the {check} check" if check != "torque" else "",
               lambda check, last: f" by {check}" if check != "torque" else "",
               lambda check, last: "")
    lines = [line(name) for name in namings]
    return next((text for text in lines if len(text) <= ANSWER_CHARS), lines[-1])


def answer_details(analysis: Analysis) -> list[str]:
    """The list under the answer: what the figures are (the seed's estimate, against which
    motors), the models' names, the check that decided each verdict and the thresholds."""
    r, c, motor = analysis.results["results"], analysis.params.checks, analysis.params.motor
    decided = {(model, m): r[model][m]["checks"]["deciding_check"]
               for model, _ in ANSWER_MODELS for m in MOTORS}
    if len(set(decided.values())) == 1:
        checks = (f"each verdict above is the {next(iter(decided.values()))} check's (the worst "
                  "check decides)")
    else:
        checks = "the check that decided each verdict above: " + "; ".join(
            f"`{model}` " + ", ".join(f"{m} {decided[model, m]}" for m in MOTORS)
            for model, _ in ANSWER_MODELS)
    return [
        "- The seed's estimate (a model on the prescribed foot path, not a verdict on the "
        f"simulated robot), against the {motor.peak_torque_Nm:.2f} N·m, "
        f"{motor.no_load_speed_rad_s:.2f} rad/s motors.",
        "- Models: " + ", ".join(f"{label} is `{model}`" for model, label in ANSWER_MODELS)
        + " (both defined below).",
        f"- Checks: {checks}; the speed and thermal checks below.",
        f"- Thresholds: SF ≥ {c.sf_pass:g} pass, ≥ {c.sf_warn:g} warn, else fail.",
    ]


def markdown(analysis: Analysis, sampled: dict | None = None) -> str:
    """report.md; sampled: config.sampling_error of the analysed path (computed if None)."""
    if sampled is None:
        sampled = sampling_error(analysis.params, analysis.samples.path)
    r = analysis.results["results"]
    p, path = analysis.params, foot_path(analysis.samples.path)
    g = p.gait
    lines = [
        f"# 5-bar leg: dynamic torque analysis over the {path.title}",
        "",
        answer(analysis),
        "",
        *answer_details(analysis),
        "",
        f"Foot path: {path.text(g)}, f = {g.frequency_hz:g} Hz, N = {g.samples} samples "
        f"(central differences: peak joint speed within {sampled['speed']:.1%}, peak "
        f"acceleration within {sampled['acceleration']:.1%} of {sampled['reference_samples']} "
        f"samples). Motor: {p.motor.peak_torque_Nm:g} N·m, {p.motor.no_load_speed_rad_s:.2f} "
        "rad/s.",
        "",
        *([f"**Warning:** {sampled['warning']}.", ""] if sampled["warning"] else []),
        "Models, side by side (the seed's formulas as written and the physically consistent "
        "ones):",
        "",
    ]
    lines += [f"- **{name}**: {text}" for name, text in analysis.results["models"].items()]
    lines += ["", "## Peak dynamic torque (the seed's Table 3)", "",
              "| motor | model | peak torque (N·m) | where in the cycle |", "|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE:
            m = r[model][motor]
            lines.append(f"| {motor} | {model} | {m['peak_torque_Nm']:.3f} | "
                         f"{_where(m['peak_at'])} |")
    lines += ["", "## Static against dynamic torque (the seed's Table 4)", "",
              "| motor | model | static torque (N·m) | peak dynamic torque (N·m) | dynamic/static "
              "| static peak at |", "|---|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE:
            m = r[model][motor]
            lines.append(f"| {motor} | {model} | {m['static_torque_Nm']:.3f} | "
                         f"{m['peak_torque_Nm']:.3f} | {m['dynamic_to_static_ratio']:.4f}x | "
                         f"{_where(m['static_peak_at'])} |")
    lines += ["", f"## Safety factor against {p.motor.peak_torque_Nm:g} N·m (the seed's Table 5)",
              "",
              f"The seed's: {p.motor.peak_torque_Nm:g} N·m over the peak |joint torque|, whatever "
              "its quadrant (the torque check below takes each sample against its own "
              "quadrant's limit).", "",
              "| motor | model | peak torque (N·m) | safety factor | verdict |",
              "|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE:
            m = r[model][motor]
            lines.append(f"| {motor} | {model} | {m['peak_torque_Nm']:.3f} | "
                         f"{m['safety_factor']:.2f}x | {m['verdict'].upper()} |")
    lines += ["", f"## Speed check (no-load speed {p.motor.no_load_speed_rad_s:.2f} rad/s)", "",
              "| motor | model | peak speed (rad/s) | where | beyond the no-load speed | peak accel "
              "(rad/s^2) | least speed margin | beyond the envelope | torque-speed margin | "
              "speed check |", "|---|---|---|---|---|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE + ("full_trot",):
            m = r[model][motor]
            c = m["checks"]["speed"]
            lines.append(f"| {motor} | {model} | {m['peak_speed_rad_s']:.3f} | "
                         f"{_where(m['peak_speed_at'])} | {'no' if m['speed_ok'] else 'YES'} | "
                         f"{m['peak_acceleration_rad_s2']:.2f} | "
                         f"{_maybe(c['least_margin'], '.3f')} | {c['outside_fraction']:.1%} | "
                         f"{m['torque_speed_margin']:.2f}x | {c['verdict'].upper()} |")
    lines += ["", "- Operating points: the torque the motor delivers (joint torque + output "
              "friction) at the joint speed, each in its own quadrant.",
              "- Least speed margin: the largest speed at which the envelope still gives a "
              "sample's torque in its quadrant over its speed (driving: the back-EMF may reach "
              "the phase voltage less R i; braking: exceed it by R i at most, beyond which it "
              "forces more braking than asked).",
              "- Beyond the envelope: the share of the cycle's samples outside it (the check "
              f"fails above {p.checks.speed_outside_fail:.0%}, warns for any or a margin below "
              f"{p.checks.speed_margin_warn:g}).",
              "- Torque-speed margin: the least ratio of the torque the envelope gives at a "
              "sample's speed in the direction of its torque to that torque (below 1 exactly "
              "outside).",
              "- A joint beyond the no-load speed lies within the envelope only while it brakes "
              "at least as much as the back-EMF forces.",
              "", "## Trot loading (the other reading of the weight share)", "",
              "The torque check's safety factor and the verdict of the actuator's checks (below), "
              "the one figure every output gives for this reading.", "",
              "| motor | peak torque (N·m) | static (N·m) | SF | quadrant | verdict |",
              "|---|---|---|---|---|---|"]
    for motor in MOTORS:
        m = r["full_trot"][motor]
        c = m["checks"]
        lines.append(f"| {motor} | {m['peak_torque_Nm']:.3f} | {m['static_torque_Nm']:.3f} | "
                     f"{_maybe(c['torque']['sf'], '.2f')} | {c['torque']['quadrant']} | "
                     f"{c['verdict'].upper()} |")
    mo = analysis.results["motor"]
    lines += ["", "## Verdict: the actuator's checks", "",
              f"The {mo['model']} actuator: peak {mo['peak_torque_Nm']:.3g} N·m (driving, "
              f"{mo['braking_peak_torque_Nm']:.3g} braking), no-load "
              f"{mo['no_load_speed_rad_s']:.2f} rad/s, continuous "
              f"{_maybe(mo['continuous_torque_Nm'], '.3g')} N·m at the output "
              "(report.json: motor.envelope). The worst check decides.", "",
              "- Operating points: the joint torque plus the output friction, at the joint "
              "speed.",
              "- Torque: the safety factor, 1 / the largest ratio of a sample's torque to the "
              "peak-current torque of its own quadrant (driving: torque and speed of one sign; "
              "braking: opposite signs), with the quadrant of that sample.",
              "- Speed: the least ratio of the speed at which the envelope still gives a "
              "sample's torque to its speed, and the share of the cycle beyond the envelope.",
              "- Thermal: continuous / RMS current.", "",
              "| motor | model | verdict | decided by | SF | quadrant | speed margin | "
              "beyond envelope | current margin |", "|---|---|---|---|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE + ("full_trot",):
            c = r[model][motor]["checks"]
            lines.append(f"| {motor} | {model} | {c['verdict'].upper()} | {c['deciding_check']} "
                         f"| {_maybe(c['torque']['sf'], '.2f')} | {c['torque']['quadrant']} | "
                         f"{_maybe(c['speed']['least_margin'], '.3f')} | "
                         f"{c['speed']['outside_fraction']:.1%} | "
                         f"{_maybe(c['thermal']['margin'], '.2f')} |")
    path = analysis.results["path"]
    angles = ", ".join(f"{j} {a:.1f} deg" for j, a in path["min_transmission_angle_deg"].items())
    lines += ["", "## Along the path", "",
              f"- assembly modes used: {', '.join(path['assembly_modes_used'])}",
              f"- smallest transmission angle from in-line: {angles}",
              f"- largest condition number of J_F: {path['max_cond_jf']:.2f}; smallest |det J_F|: "
              f"{path['min_abs_det_jf_m2']:.3e} m^2"]
    lines += design_lines(analysis.results, p)
    lines += published_lines(analysis.results["published"])
    lines += ["", "## Assumptions", ""]
    motor = motor_assumption(p.motor)
    for a in assumptions(analysis):
        if a == " ".join(motor):                  # the actuator's: its parts listed under it
            lines += [f"- {motor[0]}", *(f"  - {part}" for part in motor[1:])]
        else:
            lines.append(f"- {a}")
    lines += ["", "## Plots", ""]
    lines += [f"![{name}]({name}.png)" for name in FIGURE_NAMES]
    return "\n".join(lines) + "\n"


def published_lines(rows: list[dict]) -> list[str]:
    """The table of the parameter file's published figures beside the toolkit's (none: no
    lines)."""
    if not rows:
        return []
    def text(v):
        return " .. ".join(f"{x:.4g}" for x in v) if isinstance(v, list) else f"{v:.4g}"
    lines = ["", "## Published figures", "",
             "The robot's published figures ([published] of the parameter file) against the same "
             "figures computed from its data:", "",
             "| figure | published | computed | unit | difference | reproduced | source | note |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['what']} | {text(r['published'])} | {text(r['computed'])} | "
                     f"{r['unit']} | {r['relative_difference']:.1%} | "
                     f"{'yes' if r['reproduced'] else 'NO'} (within {r['tolerance']:.0%}) | "
                     f"{r['source']} | {r['note']} |")
    return lines


def _maybe(value, fmt: str) -> str:
    return "n/a" if value is None else format(value, fmt)


def write_report(analysis: Analysis, out_dir: Path, sampled: dict | None = None) -> list[Path]:
    """Write REPORT_FILES into out_dir, each atomically, both composed before either is
    written; sampled: config.sampling_error of the analysed path (computed if None). Returns
    their paths."""
    sampled = sampled or sampling_error(analysis.params, analysis.samples.path)
    data = dict(analysis.results, assumptions=assumptions(analysis), sampling_error=sampled)
    undefined = []
    data = json_ready(data, undefined)
    data["undefined"] = {path: "not defined for this design (a singular pose or a mode that "
                               "is no assembly): left null" for path in undefined}
    texts = (markdown(analysis, sampled), json.dumps(data, indent=2, allow_nan=False) + "\n")
    out_dir.mkdir(parents=True, exist_ok=True)
    return [write_atomic(out_dir / name, text) for name, text in zip(REPORT_FILES, texts)]
