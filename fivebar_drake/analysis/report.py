"""report.md and report.json of the torque analysis: the seed's Tables 3-5 filled for each model."""

from __future__ import annotations

import json
import math
from pathlib import Path

from fivebar_drake.analysis.design_report import design_assumptions, design_lines
from fivebar_drake.analysis.torques import Analysis
from fivebar_drake.core.files import json_ready, write_atomic
from fivebar_drake.core.footpath import foot_path
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
        f"The {p.motor.peak_torque_Nm:g} N m motor torque is taken at the gearbox output "
        f"(gear {p.motor.gear_ratio:g}:1); {p.motor.no_load_speed_rad_s:.2f} rad/s "
        f"({p.motor.no_load_speed_rad_s * 60 / (2 * math.pi):.0f} RPM) is taken as the no-load "
        "output speed of a linear torque-speed line.",
        "Joint rates and accelerations are periodic central differences over the N samples "
        "(seed 000 section 5); the IK mode follows seed 000 appendix B from the knees-out mode.",
        "Safety factor = motor torque / peak dynamic torque; verdict: SF >= "
        f"{p.checks.sf_pass:g} pass, {p.checks.sf_warn:g} <= SF < {p.checks.sf_pass:g} warn, "
        "else fail.",
        "The leg's limits ([limits] of the parameter file): " + (
            ", ".join(f"{k} = {v:g}" for k, v in p.limits.given.items())
            + "; the IK, the foot paths, the workspace and force-capability maps respect them (a "
            "pose past one counts as out of reach)" if p.limits.given else "none set"),
        *design_assumptions(p),
    ]


def _where(at: dict) -> str:
    x, y = (v * 1e3 for v in at["foot_m"])
    return f"t = {at['time_s']:.3f} s (sample {at['sample']}), F = ({x:.1f}, {y:.1f}) mm"


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
        f"Foot path: {path.text(g)}, f = {g.frequency_hz:g} Hz, N = {g.samples} samples "
        f"(central differences: peak joint speed within {sampled['speed']:.1%}, peak "
        f"acceleration within {sampled['acceleration']:.1%} of {sampled['reference_samples']} "
        f"samples). Motor: {p.motor.peak_torque_Nm:g} N m, {p.motor.no_load_speed_rad_s:.2f} "
        "rad/s.",
        "",
        *([f"**Warning:** {sampled['warning']}.", ""] if sampled["warning"] else []),
        "Models, side by side (the seed's formulas as written and the physically consistent "
        "ones):",
        "",
    ]
    lines += [f"- **{name}**: {text}" for name, text in analysis.results["models"].items()]
    lines += ["", "## Table 3: peak dynamic torque", "",
              "| motor | model | peak torque (N m) | where in the cycle |", "|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE:
            m = r[model][motor]
            lines.append(f"| {motor} | {model} | {m['peak_torque_Nm']:.3f} | "
                         f"{_where(m['peak_at'])} |")
    lines += ["", "## Table 4: static vs dynamic torque", "",
              "| motor | model | static torque (N m) | peak dynamic torque (N m) | dynamic/static "
              "| static peak at |", "|---|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE:
            m = r[model][motor]
            lines.append(f"| {motor} | {model} | {m['static_torque_Nm']:.3f} | "
                         f"{m['peak_torque_Nm']:.3f} | {m['dynamic_to_static_ratio']:.4f}x | "
                         f"{_where(m['static_peak_at'])} |")
    lines += ["", f"## Table 5: safety factor against {p.motor.peak_torque_Nm:g} N m", "",
              "| motor | model | peak torque (N m) | safety factor | verdict |",
              "|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE:
            m = r[model][motor]
            lines.append(f"| {motor} | {model} | {m['peak_torque_Nm']:.3f} | "
                         f"{m['safety_factor']:.2f}x | {m['verdict'].upper()} |")
    lines += ["", f"## Speed check (limit {p.motor.no_load_speed_rad_s:.2f} rad/s)", "",
              "| motor | peak speed (rad/s) | where | within limit | peak accel (rad/s^2) "
              "| torque-speed margin (seed / full) |", "|---|---|---|---|---|---|"]
    for motor in MOTORS:
        m = r["full"][motor]
        lines.append(f"| {motor} | {m['peak_speed_rad_s']:.3f} | {_where(m['peak_speed_at'])} | "
                     f"{'yes' if m['speed_ok'] else 'NO'} | {m['peak_acceleration_rad_s2']:.2f} | "
                     f"{r['seed'][motor]['torque_speed_margin']:.2f}x / "
                     f"{m['torque_speed_margin']:.2f}x |")
    lines += ["", "Torque-speed margin: the least ratio, over the cycle, of the torque the motor "
              "can give at that sample's speed (the actuator's envelope, driving) to the torque "
              "needed.",
              "", "## Trot loading (the other reading of the weight share)", "",
              "| motor | peak torque (N m) | static (N m) | safety factor | verdict |",
              "|---|---|---|---|---|"]
    for motor in MOTORS:
        m = r["full_trot"][motor]
        lines.append(f"| {motor} | {m['peak_torque_Nm']:.3f} | {m['static_torque_Nm']:.3f} | "
                     f"{m['safety_factor']:.2f}x | {m['verdict'].upper()} |")
    mo = analysis.results["motor"]
    lines += ["", "## Verdict: the actuator's checks", "",
              f"The {mo['model']} actuator: peak {mo['peak_torque_Nm']:.3g} N m (driving, "
              f"{mo['braking_peak_torque_Nm']:.3g} braking), no-load "
              f"{mo['no_load_speed_rad_s']:.2f} rad/s, continuous "
              f"{_maybe(mo['continuous_torque_Nm'], '.3g')} N m at the output "
              "(report.json: motor.envelope). Torque: safety factor on the peak demand; speed: "
              "the least ratio of the speed at which the envelope still gives a sample's torque "
              "to its speed, and the share of the cycle beyond the envelope; thermal: continuous "
              "/ RMS current. The worst check decides.", "",
              "| motor | model | verdict | decided by | SF | speed margin | beyond envelope | "
              "current margin |", "|---|---|---|---|---|---|---|---|"]
    for motor in MOTORS:
        for model in SIDE_BY_SIDE + ("full_trot",):
            c = r[model][motor]["checks"]
            lines.append(f"| {motor} | {model} | {c['verdict'].upper()} | {c['deciding_check']} "
                         f"| {_maybe(c['torque']['sf'], '.2f')} | "
                         f"{_maybe(c['speed']['least_margin'], '.2f')} | "
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
    lines += [f"- {a}" for a in assumptions(analysis)]
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
