"""The text of the ball-screw leg's jobs: the analysis's report.md and report.json, the squat's
summary.md and summary.json, and the lines the command line prints about each."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from fivebar_drake.core.files import write_atomic
from fivebar_drake.mechanisms.ballscrew_leg import EFFICIENCY_READINGS, RATIO_READINGS
from fivebar_drake.studies.ballscrew_leg.analysis import (REPRODUCED_WITHIN, Analysis,
                                                          lever_summary, ratio_crossings)
from fivebar_drake.studies.ballscrew_leg.plots import ANALYSIS_FIGURES
from fivebar_drake.studies.base import claims_answer
from fivebar_drake.studies.ballscrew_leg.simulation import STANDING_SETTLE_S

ANALYSIS_FILES = ("report.md", "report.json")          # report.json last
SIMULATION_FILES = ("summary.md", "summary.json")      # summary.json last
TABLE_Q1_DEG = (10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0)

GEOMETRY = (
    "Reading of the seed's geometry:", "",
    "- O is the hip, OA = l1 the thigh, AP = l2 the shank, P the foot.",
    "- The lever DA = s1 is the shank's extension beyond the knee (D, A, P on one line), so the "
    "angle OAD equals the knee's bend -q2.",
    "- The screw OD of length q2l sets the knee by the seed's law of cosines "
    "q2 = -acos((l1^2 + s1^2 - q2l^2) / (2 l1 s1)).",
    "- The screw pushes at D along OD; its moment arm about the knee is s1 sin(ODA) = "
    "l1 s1 sin(-q2) / q2l, largest where the angle ODP (= ODA) is 90 deg.",
)
SEED_TEXT_NOTES = (
    "The seed's screw Jacobian prints `q2` (and `q_2s`) where its own derivation needs the screw "
    "length q2l (the derivative of acos brings q2l down); read as q2l, it matches finite "
    "differences (tests/mechanisms/ballscrew_leg).",
    "The seed's geared Jacobian J_s has l1 sin(q1 + q2) in its (2, 2) entry; the derivative is "
    "l2 sin(q1 + q2). With l1 = l2 = 0.2 m the numbers are the same.",
    "The seed gives the screw one efficiency, 90 %; it is used here both ways: forward (motor "
    "drives the screw, raising the body) and back-driven (the load drives the motor, lowering). "
    "The geared knee's 100 % makes its motor torque the same either way.",
    "\"The geared joint motor's output torque over the screw motor's torque\": read as the geared "
    "knee's output (joint) torque, which is what the seed's 56:1 needs, and as the geared motor's "
    "own torque before its 10:1 gear (ten times smaller).",
    "The seed gives no q1 range; the analysed squat is the parameter file's. The minimum ratio "
    "is set by where that range starts (near the straight leg the screw is near its dead "
    "centre).",
)


def _json(a: Analysis) -> dict:
    p = a.params
    return {
        "mechanism": "ballscrew_leg",
        "parameters": dataclasses.asdict(p),
        "readings": {"ratio": RATIO_READINGS, "efficiency": EFFICIENCY_READINGS},
        "reproduced_within": REPRODUCED_WITHIN,
        "seed_claims": a.claims,
        "levers": {f"{s:g}": lever_summary(p, a.statics[s], a.strokes[s]) for s in a.statics},
        "drake_check": {f"{s:g}": v for s, v in a.drake.items()},
    }


def _claims_table(a: Analysis) -> list[str]:
    lines = ["| id | seed | computed | unit | reproduced | reading |", "|---|---|---|---|---|---|"]
    for c in a.claims:
        verdict = "reproduced" if c["reproduced"] else "**not reproduced**"
        lines.append(f"| `{c['id']}` | {c['seed_value']} | {c['computed_value']:.4g} | "
                     f"{c['unit']} | {verdict} | {c['reading']} |")
    return lines


def _why_not(a: Analysis) -> list[str]:
    """Why the claims that fail, fail (computed from the analysis)."""
    s = a.statics
    fw = {lever: float(np.max(st.ratio["joint", "forward"])) for lever, st in s.items()}
    lead, eta = a.params.screw.lead_m, a.params.screw.efficiency
    out = []
    if 0.02 in s:
        cross = ratio_crossings(s[0.02], ("joint", "forward"))
        ideal = 2 * np.pi * 0.02 / lead
        out.append(
            f"- **20:1 at s1 = 0.02 m**: at the peak the moment arm is s1, so the ratio is "
            f"2 pi eta s1 / lead = {fw[0.02]:.2f} (forward), {ideal:.2f} (eta = 1), "
            f"{ideal / eta:.2f} (back-driven): none is within {REPRODUCED_WITHIN:.0%} of 20 "
            f"(20 would need eta = {20 / ideal:.3f}); as a lower bound (\"can reach 20:1\") it "
            "holds. The geared motor's own torque reading gives a tenth of these.")
        out.append(
            f"- **1:1 at s1 = 0.02 m**: the ratio falls to 0 at the straight leg (screw at its "
            f"dead centre) and at the folded knee; it crosses 1:1 at q1 = "
            f"{', '.join(f'{q:.2f}' for q in cross)} deg (joint reading, forward), so the "
            "seed's minimum is the value at the end of its (unstated) plotted range; the "
            f"file's range starts at {a.params.squat.q1_min_deg:g} deg.")
    if 0.05 in s:
        gear = a.params.geared_knee.gear_ratio * a.params.geared_knee.efficiency
        cross = ratio_crossings(s[0.05], ("joint", "forward"), gear)
        out.append(
            f"- **screw motor below the geared motor at s1 = 0.05 m**: wherever the ratio beats "
            f"{gear:g}:1; it crosses {gear:g}:1 at q1 = {', '.join(f'{q:.2f}' for q in cross)} "
            "deg (forward): near the straight leg (the screw near its dead centre) and near the "
            "folded knee the screw motor needs more torque than the geared motor.")
    if 0.07 in s and 0.05 in s:
        out.append(
            f"- **0.07 m worse than 0.05 m**: the ratio at a given knee angle grows with s1 "
            f"(d/ds1 of s1 / q2l is l1 (l1 - s1 cos q2) / q2l^3 > 0 for s1 < l1), so 0.07 m "
            f"gives more at every q1 (peak {fw[0.07]:.1f} against {fw[0.05]:.1f}) and the screw "
            "motor needs less torque everywhere. What 0.07 m does cost is stroke: see the knee "
            "range below.")
    return out


def _markdown(a: Analysis) -> str:
    p = a.params
    lines = [
        "# Ball-screw knee against the geared knee (seed 001)", "",
        claims_answer(a.claims, "claims"), "",
        f"Serial two-link leg, l1 = {p.leg.thigh_m:g} m, l2 = {p.leg.shank_m:g} m; vertical squat "
        f"q2 = -2 q1 (foot below the hip), ground force {p.load.foot_force_N:g} N up on the foot; "
        f"geared knee {p.geared_knee.gear_ratio:g}:1 at {p.geared_knee.efficiency:.0%}; ball "
        f"screw lead {p.screw.lead_m * 1e3:g} mm at {p.screw.efficiency:.0%}; levers s1 = "
        f"{', '.join(f'{s * 1e3:g}' for s in p.screw.lever_lengths_m)} mm; q1 from "
        f"{p.squat.q1_min_deg:g} to {p.squat.q1_max_deg:g} deg ({p.squat.samples} samples).", "",
        *GEOMETRY, "",
        "Torques hold the pose at rest (static, massless links, as in the seed). The hip torque "
        "is 0 in this squat for both designs (the foot is straight below the hip).", "",
        "## Readings of the seed's text", "",
        *[f"- {n}" for n in SEED_TEXT_NOTES], "",
        "## Seed claims", "",
        f"Reproduced: within {REPRODUCED_WITHIN:.0%} of the seed's value (the 0.07 m claim: a "
        "comparison, see its reading).", "",
        *_claims_table(a), "",
        "Why the claims that are not reproduced are not:", "",
        *_why_not(a), "",
        "## Equivalent reduction ratio per lever (joint reading)", "",
        "| s1 (mm) | efficiency | max | at q1 (deg) | peak from the geometry, q1 (deg) | min | at "
        "q1 (deg) | crosses 1:1 at q1 (deg) |", "|---|---|---|---|---|---|---|---|"]
    for s, st in a.statics.items():
        summary = lever_summary(p, st, a.strokes[s])
        for e in EFFICIENCY_READINGS:
            r = summary[f"ratio_joint_{e}"]
            lines.append(f"| {s * 1e3:g} | {e} | {r['max']:.2f} | {r['max_at_q1_deg']:.2f} | "
                         f"{summary['peak_q1_geometry_deg']:.2f} | {r['min']:.3f} | "
                         f"{r['min_at_q1_deg']:.2f} | "
                         f"{', '.join(f'{q:.2f}' for q in r['crosses_1_at_q1_deg']) or '-'} |")
    lines += ["", "## Motor torques (N·m) at some hip angles", "",
              "| q1 (deg) | knee joint | geared motor | "
              + " | ".join(f"screw motor s1 = {s * 1e3:g} mm (fwd / back)" for s in a.statics)
              + " |", "|---" * (3 + len(a.statics)) + "|"]
    for q in TABLE_Q1_DEG:
        if not p.squat.q1_min_deg <= q <= p.squat.q1_max_deg:
            continue
        first = next(iter(a.statics.values()))
        i = int(np.argmin(np.abs(np.degrees(first.q1) - q)))
        cells = [f"{abs(st.screw_motor_Nm['forward'][i]):.3f} / "
                 f"{abs(st.screw_motor_Nm['back-driven'][i]):.3f}" for st in a.statics.values()]
        lines.append(f"| {np.degrees(first.q1[i]):.1f} | {abs(first.knee_Nm[i]):.2f} | "
                     f"{abs(first.geared_motor_Nm[i]):.3f} | " + " | ".join(cells) + " |")
    lines += ["", f"## Knee range within the stroke ({p.screw.stroke_m * 1e3:g} mm, retracted at "
              f"q1 = {p.screw.retracted_at_q1_deg:g} deg; assumptions)", "",
              "| s1 (mm) | screw length (mm) | knee bend (deg) | squat q1 (deg) | stroke the "
              "analysed squat needs (mm) |", "|---|---|---|---|---|"]
    for s, r in a.strokes.items():
        lines.append(f"| {s * 1e3:g} | {r.screw_m[0] * 1e3:.1f} .. {r.screw_m[1] * 1e3:.1f} | "
                     f"{np.degrees(r.bend_rad[0]):.1f} .. {np.degrees(r.bend_rad[1]):.1f} | "
                     f"{np.degrees(r.q1_rad[0]):.1f} .. {np.degrees(r.q1_rad[1]):.1f} | "
                     f"{r.needed_stroke_m * 1e3:.1f} |")
    lines += ["", "A longer lever gives a larger ratio but needs more stroke per degree of knee "
              "(the screw moves s1 sin(ODA) per radian): the stroke limits the knee's range, the "
              "seed's point 3; the geared knee has no such limit.", "",
              "## Drake model check", "",
              "The Drake model (thigh, shank with the lever, screw housing pivoting at the hip, "
              "nut on a ScrewJoint, the loop closed at D by a SAP ball constraint; hip fixed, the "
              "foot load as an external force, no gravity): tree inverse dynamics projected on "
              "the loop's admissible velocities, against the closed form with a lossless screw.",
              "", "| s1 (mm) | poses | largest relative difference, screw motor | largest hip "
              "difference (N·m) |", "|---|---|---|---|"]
    for s, d in a.drake.items():
        lines.append(f"| {s * 1e3:g} | {d['poses']} | {d['max_rel_screw']:.2e} | "
                     f"{d['max_abs_hip_Nm']:.2e} |")
    lines += ["", "## Figures", "", *[f"- `{name}`" for name in ANALYSIS_FIGURES], ""]
    return "\n".join(lines)


def write_analysis(a: Analysis, out: Path) -> list[Path]:
    """report.md, then report.json (last)."""
    return [write_atomic(out / "report.md", _markdown(a)),
            write_atomic(out / "report.json", json.dumps(_json(a), indent=2) + "\n")]


def analysis_lines(a: Analysis) -> list[str]:
    """Each lever's ratio extremes and Drake check, and how many claims hold."""
    lines = []
    for s, st in a.statics.items():
        r = st.ratio["joint", "forward"]
        i = int(np.argmax(r))
        lines.append(f"s1 = {s * 1e3:g} mm: equivalent ratio max {r[i]:.2f} at q1 = "
                     f"{np.degrees(st.q1[i]):.2f} deg, min {np.min(r):.3f} (forward efficiency); "
                     f"Drake check {a.drake[s]['max_rel_screw']:.1e}")
    held = sum(c["reproduced"] for c in a.claims)
    lines.append(f"seed claims: {held} of {len(a.claims)} readings reproduced (report.md)")
    return lines


def _summary_markdown(summary: dict) -> str:
    s = summary
    return "\n".join([
        f"# Ball-screw leg: simulated squat (s1 = {s['lever_m'] * 1e3:g} mm)", "",
        f"- simulated {s['duration_s']:.3f} s in {s['wall_time_s']:.2f} s "
        f"({s['real_time_factor']:.2f}x real time)",
        f"- hip angle tracking error: RMS {s['q1_tracking_error_deg']['rms']:.3f} deg, max "
        f"{s['q1_tracking_error_deg']['max']:.3f} deg",
        f"- loop gaps: at D {s['max_loop_gap_m']['D'] * 1e6:.2f} um, at the foot "
        f"{s['max_loop_gap_m']['foot'] * 1e6:.2f} um",
        f"- screw motor: peak applied {s['peak_applied_torque_Nm']:.3f} N·m (closed-form static "
        f"peak {s['peak_static_closed_form_Nm']:.3f} N·m, lossless screw; with the 90 % screw "
        f"{s['peak_applied_with_screw_efficiency_Nm']['forward']:.3f} N·m forward), limit "
        f"{s['motor_peak_torque_Nm']:g} N·m; peak speed {s['peak_motor_speed_rad_s']:.1f} rad/s "
        f"of {s['motor_no_load_speed_rad_s']:g}; clipped {s['clipped_share']['peak']:.1%} at the "
        f"peak, {s['clipped_share']['torque_speed_line']:.1%} on the torque-speed line",
        f"- standing still (after {STANDING_SETTLE_S:g} s): applied torque / static torque - 1 "
        f"= {_pct(s['standing_applied_vs_static']['drake'])} against Drake's projected static "
        f"torque (links included), {_pct(s['standing_applied_vs_static']['closed_form'])} "
        "against the closed form (700 N only, no link weights)", ""])


def _pct(value) -> str:
    return "n/a (no standing samples)" if value is None else f"{value:+.2%}"


def write_simulation(summary: dict, out: Path) -> list[Path]:
    """summary.md, then summary.json (last)."""
    return [write_atomic(out / "summary.md", _summary_markdown(summary)),
            write_atomic(out / "summary.json", json.dumps(summary, indent=2) + "\n")]


def simulation_lines(summary: dict, recording: Path) -> list[str]:
    """summary.md's points, and how to open the recording."""
    return [line[2:] for line in _summary_markdown(summary).splitlines() if line.startswith("- ")
            ] + [f"open the recording with: rerun {recording}"]
