"""What the command line says about the 5-bar leg's jobs (their files are written by
fivebar_drake.pipeline: analysis/report.py, simulation/summary_text.py)."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

from fivebar_drake.verdicts.summary_schema import Summary
from fivebar_drake.pipeline import AnalysisRecord
from fivebar_drake.robots.quadruped.config import sampling_error
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.summary_text import contact_text, limits_text


def analysis_lines(record: AnalysisRecord) -> list[str]:
    """Every reading (model, motor), the lowest safety factor first."""
    readings = [(model, motor, m) for model, motors in record.results.items()
                for motor, m in motors.items()]
    lines = [f"foot path: {record.analysis.results['path']['gait']}; every reading, the lowest "
             "safety factor first:"]
    for model, motor, m in sorted(readings, key=lambda r: r[2]["safety_factor"]):
        torque = m["checks"]["torque"]
        lines.append(
            f"  {model:>9} motor {motor}: peak {m['peak_torque_Nm']:.3f} N·m, "
            f"static {m['static_torque_Nm']:.3f} N·m, seed's SF {m['safety_factor']:.2f} "
            f"({m['verdict'].upper()}), peak speed {m['peak_speed_rad_s']:.2f} rad/s; torque "
            f"check SF {torque['sf']:.2f} ({torque['quadrant']}); verdict "
            f"{m['checks']['verdict'].upper()} ({m['checks']['deciding_check']} check)")
    return lines


def simulation_lines(summary: Summary) -> list[str]:
    """The run in one line, each leg's motors, the verdict, the step check, the answer."""
    s = summary
    lines = [f"{s['gait']} gait, {s['closure']} closure: {s['duration_s']:.2f} s simulated, "
             f"{s['real_time_factor']:.2f}x real time, worst loop gap "
             f"{s['max_loop_gap_m'] * 1e3:.4f} mm, {s['cycles_in_window']} whole cycles, walking "
             f"{s['mean_forward_speed_m_s']:.3f} m/s (gait {s['gait_speed_m_s']:.3f} m/s), "
             f"largest tilt {s['max_tilt_deg']:.1f} deg"]
    if "timing" in s:
        t = s["timing"]
        lines.append(f"wall time: stepping {t['simulate_s']:.2f} s, output files "
                     f"{t['outputs_s']:.2f} s ({t['outputs_share']:.0%} of both)")
    for leg, motors in s["legs"].items():
        lines.append("  " + leg + ": " + ", ".join(
            f"{m} demand p99 {v['demand_p99_Nm']:.2f} N·m (RMS {v['rms_torque_Nm']:.2f}, "
            f"SF {v['safety_factor']:.2f}, {v['verdict']}"
            + (f" by {v['checks']['deciding_check']}" if v.get("checks") else "") + ")"
            for m, v in motors.items()))
    lines.append(limits_text(s["limits"]))
    lines.append(f"verdict: {s['verdict'].upper()}" + (
        f" (worst motor {s['worst_motor']}, decided by the {s['deciding_check']} check)"
        if s["deciding_check"] else " (no verdict: see the answer below)"))
    if s["step_check"]:
        sc = s["step_check"]
        lines.append(f"step check at {sc['half_time_step_s']:g} s: worst demand p99 change "
                     f"{sc['worst_demand_p99_change']:+.2%}, worst SF change "
                     f"{sc['worst_sf_change']:.3f}; converged worst SF "
                     f"{sc['converged_sf']:.3f} ± {sc['converged_sf_error']:.3f} "
                     f"({sc['converged_worst_motor']})" + (f"; MARGINAL: {sc['why']}"
                                                           if sc["marginal"] else ""))
    if s["contact_check"]:
        lines.append(contact_text(s["contact_check"]))
    return lines + [s["answer"]]


def recording_line(path: Path) -> str:
    """How to open the recording: the rerun viewer installed beside this Python (the venv's,
    which works without activating it), else `rerun` on the PATH."""
    beside = Path(sys.executable).parent / "rerun"
    viewer = shlex.quote(str(beside)) if beside.exists() else "rerun"
    return f"open the recording with: {viewer} {shlex.quote(str(path))}"


def simulation_warnings(params: Params) -> list[str]:
    """The sampling error of the seed's reference figures every summary compares with."""
    warning = sampling_error(params, "seed_ellipse")["warning"]
    return [f"warning: the seed's reference figures: {warning}"] if warning else []


def failure(record: SimulationRecord, summary: Summary) -> str:
    """Why the run failed (exit 1), or "": it stopped early, has no verdict or did not achieve
    its motion."""
    if record.error:
        return f"error: the run stopped early: {record.error}"
    if summary["verdict"] == "insufficient":
        return f"error: no verdict: {summary['answer'].removeprefix('No verdict: ')}"
    if summary["verdict"] == "not_achieved":
        return ("error: the motion was not achieved: "
                + summary["answer"].removeprefix("NOT ACHIEVED, "))
    return ""
