"""The text of the SCARA jobs: the analysis's report.md and report.json, the run's summary.md
and summary.json, and the lines the command line prints about each."""

from __future__ import annotations

import json
from pathlib import Path

from fivebar_drake.core.files import write_atomic
from fivebar_drake.studies.base import claims_answer
from fivebar_drake.studies.scara.analysis import Analysis
from fivebar_drake.studies.scara.plots import FIGURES, SIMULATION_FIGURES, UNITS
from fivebar_drake.studies.scara.recording import RECORDING_FILE

ANALYSIS_FILES = ("report.md", "report.json")          # report.json last
SIMULATION_FILES = ("summary.md", "summary.json")      # summary.json last


def _f(v, digits=4) -> str:
    return f"{v:.{digits}g}"


def markdown(data: dict) -> str:
    ws, tr = data["workspace"], data["trajectory"]
    lines = ["# SCARA arm (seed 002): kinematics, workspace, trajectory, dynamics, drive sizing",
             "", claims_answer(data["seed_claims"], "drive-sizing claims"), "",
             f"Parameters: `{data['source']}`.", "", "## Kinematics and workspace", "",
             "IK of A with both elbows (q1, q2 rad, q3 m): " + "; ".join(
                 f"elbow {e}: ({', '.join(_f(v) for v in q)})"
                 for e, q in data["kinematics"]["ik_at_A"].items()) + ".",
             f"Tool Cardan angles at A (alpha, beta, eta) rad: "
             f"{', '.join(_f(v) for v in data['kinematics']['cardan_at_A_rad'])}.", "",
             f"Horizontal reach {_f(ws['inner_radius_m'])} .. {_f(ws['outer_radius_m'])} m, tool "
             f"height {_f(ws['z_range_m'][0])} .. {_f(ws['z_range_m'][1])} m; the exact boundary "
             f"under the joint limits has {ws['boundary_pieces']} arcs (workspace.png); the "
             f"trajectory is {'inside' if ws['trajectory_inside'] else 'NOT inside'} it.", "",
             "## Trajectory (section 2.2.2)", "",
             f"{_f(tr['duration_s'])} s, {tr['samples']} samples; peak joint speeds "
             f"{', '.join(_f(v) for v in tr['peak_joint_speed'])} (rad/s, rad/s, m/s), peak "
             f"accelerations {', '.join(_f(v) for v in tr['peak_joint_acceleration'])}; peak "
             f"tool speed {_f(tr['peak_tool_speed_m_s'])} m/s.", "",
             "## Joint forces along the trajectory (Lagrange) and the drive demand", "",
             "| payload (kg) | joint | peak | at t (s) | RMS | peak speed | peak power (W) "
             "| input power at mu (W) |", "|---|---|---|---|---|---|---|---|"]
    for d in data["demand"]:
        for j in range(3):
            lines.append(f"| {d['payload_kg']:g} | {j + 1} | {_f(d['peak'][j])} {UNITS[j]} | "
                         f"{d['peak_time_s'][j]:.3f} | {_f(d['rms'][j])} | "
                         f"{_f(d['peak_speed'][j])} | {_f(d['peak_power_W'][j])} | "
                         f"{_f(d['input_power_W'][j])} |")
    elbow = data["parameters"]["kinematics"]["elbow"]
    lines += ["", f"With the payload, by elbow (the trajectory's is {elbow:+d}): "
              + "; ".join(f"elbow {e['elbow']:+d}: peak speeds "
                          f"{', '.join(_f(v) for v in e['peak_joint_speed'])}, peak forces "
                          f"{', '.join(_f(v) for v in e['peak_force'])}" if e["reachable"]
                          else f"elbow {e['elbow']:+d}: {e['why']}" for e in data["elbows"]) + "."]
    lines += ["", "Lagrange model against Drake's MultibodyPlant of the same arm (generated SDF):"]
    for c in data["drake_check"]:
        lines.append(f"- payload {c['payload_kg']:g} kg, {c['samples']} samples: inverse "
                     f"dynamics within {max(c['max_relative_difference']):.2e} of the peaks, "
                     f"M within {c['mass_matrix_max_abs']:.1e}, C qd within "
                     f"{c['bias_max_abs']:.1e}, G within {c['gravity_max_abs']:.1e} "
                     f"({'agrees' if c['agrees'] else 'DISAGREES'} within 0.1 %)")
    lines += ["", "## Drive sizing: the seed's numbers beside the computed ones", "",
              "| id | seed | computed | unit | reading | verdict |", "|---|---|---|---|---|---|"]
    for c in data["seed_claims"]:
        verdict = ("reproduced" if c["reproduced"] else
                   f"not reproduced — because this reading gives {_f(c['computed_value'])} "
                   f"({c['deviation']:+.1%})")
        lines.append(f"| {c['id']} | {_f(c['seed_value'])} | {_f(c['computed_value'])} | "
                     f"{c['unit']} | {c['reading'].replace('|', '/')} | {verdict} |")
    lines += ["", "## Where the seed's text is inconsistent", ""]
    lines += [f"- {n}" for n in data["seed_notes"]]
    lines += ["", "## Assumptions", ""] + [f"- {a}" for a in data["assumptions"]]
    lines += ["", "## Plots", ""] + [f"![{n}]({n}.png)" for n in FIGURES]
    return "\n".join(lines) + "\n"


def write_analysis(a: Analysis, out: Path) -> list[Path]:
    """report.md, then report.json (last)."""
    return [write_atomic(out / "report.md", markdown(a.data)),
            write_atomic(out / "report.json", json.dumps(a.data, indent=2, allow_nan=False)
                         + "\n")]


def analysis_lines(a: Analysis) -> list[str]:
    """The trajectory's peaks with the payload, the Drake check, how many claims hold."""
    claims, loaded = a.data["seed_claims"], a.data["demand"][1]
    return [f"trajectory peaks with {loaded['payload_kg']:g} kg: tau1 "
            f"{loaded['peak'][0]:.3g} N·m, tau2 {loaded['peak'][1]:.3g} N·m, F3 "
            f"{loaded['peak'][2]:.4g} N; Lagrange vs Drake within "
            f"{max(max(c['max_relative_difference']) for c in a.data['drake_check']):.1e}",
            f"seed claims: {sum(c['reproduced'] for c in claims)} of {len(claims)} readings "
            f"reproduce the seed's number (report.md, drive sizing)"]


def summary_markdown(summary: dict) -> str:
    tr = summary["tracking"]
    lines = [f"# SCARA simulation: {summary['verdict']}", "",
             f"The arm carried {summary['payload_kg']:g} kg along the seed's trajectory for "
             f"{summary['duration_s']:g} s (plant step {summary['time_step_s']:g} s, "
             f"{summary['controller']['kind']}, kp = {summary['controller']['kp']:g} 1/s^2, "
             f"kd = {summary['controller']['kd']:g} 1/s). The tool stayed within "
             f"{tr['max_error_m'] * 1e3:.3f} mm of the path (worst at t = {tr['at_s']:.3f} s, "
             f"RMS {tr['rms_error_m'] * 1e3:.3f} mm; tolerance {tr['tolerance_m'] * 1e3:g} mm).",
             "", "| joint | peak applied | Lagrange peak | RMS | sized limit | peak / limit | "
             "peak speed | clipped (peak, line) |", "|---|---|---|---|---|---|---|---|"]
    for j in summary["joints"]:
        lines.append(f"| {j['joint']} | {j['peak_applied']:.4g} {j['unit']} | "
                     f"{j['lagrange_peak']:.4g} | {j['rms_applied']:.4g} | {j['limit']:.4g} | "
                     f"{j['peak_over_limit']:.1%} | "
                     f"{j['peak_speed']:.3g} | {j['clipped_by_peak_fraction']:.1%}, "
                     f"{j['clipped_by_line_fraction']:.1%} |")
    lines += ["", "Units: joints 1, 2 in N·m and rad/s, joint 3 in N and m/s. Lagrange peak: "
              "M qdd + C qd + G of the desired motion (the analysis's model). The limit of "
              "joint 3 is the chosen servo's peak torque through the 1:2 belt and the ball "
              "screw (eq. 2.86).", "", f"![tracking]({SIMULATION_FIGURES[0]})", "",
              f"Recording: `{RECORDING_FILE}` (open with `rerun {RECORDING_FILE}`)."]
    return "\n".join(lines) + "\n"


def write_simulation(summary: dict, out: Path) -> list[Path]:
    """summary.md, then summary.json (last)."""
    return [write_atomic(out / "summary.md", summary_markdown(summary)),
            write_atomic(out / "summary.json",
                         json.dumps(summary, indent=2, allow_nan=False) + "\n")]


def simulation_lines(summary: dict, recording: Path) -> list[str]:
    """The verdict, the tracking error and the peak forces; how to open the recording."""
    tr = summary["tracking"]
    return [f"{summary['verdict']}: the tool stayed within {tr['max_error_m'] * 1e3:.3f} mm of "
            f"the seed's path (tolerance {tr['tolerance_m'] * 1e3:g} mm) with "
            f"{summary['payload_kg']:g} kg; peak forces "
            + ", ".join(f"{j['joint']} {j['peak_applied']:.3g} {j['unit']} "
                        f"({j['peak_over_limit']:.1%} of the sized motor)"
                        for j in summary["joints"]),
            f"open the recording: rerun '{recording}'"]
