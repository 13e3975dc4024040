"""`simulate --mechanism scara`: run the Diagram, then write the plot, the Rerun recording,
summary.md and summary.json (last)."""

from __future__ import annotations

import json
from pathlib import Path
import matplotlib.pyplot as plt
import numpy as np

from fivebar_drake.core.files import write_atomic
from fivebar_drake.mechanisms.scara import ScaraParams
from fivebar_drake.core.files import save_figure
from fivebar_drake.studies.scara.recording import RECORDING_FILE, write_recording
from fivebar_drake.studies.scara.simulation import Run, run, summarize

SIMULATION_FILES = ("sim_tracking.png", RECORDING_FILE, "summary.md", "summary.json")


def plot_run(r: Run, summary: dict, error_m) -> plt.Figure:
    fig, axes = plt.subplots(4, 1, figsize=(10, 10), sharex=True)
    axes[0].plot(r.t, np.asarray(error_m) * 1e3)
    axes[0].axhline(summary["tracking"]["tolerance_m"] * 1e3, color="r", ls="--",
                    label="tolerance")
    axes[0].set_ylabel("tool error (mm)")
    axes[0].legend()
    for j, (ax, joint) in enumerate(zip(axes[1:], summary["joints"])):
        ax.plot(r.t, r.record[:, j, 0], label="commanded")
        ax.plot(r.t, r.record[:, j, 2], "--", label="applied")
        for sign in (1, -1):
            ax.axhline(sign * joint["limit"], color="r", ls=":", label="sized limit"
                       if sign > 0 else None)
        peak = joint["peak_applied"]
        ax.set_ylabel(f"{joint['joint']} ({joint['unit']})")
        ax.set_ylim(-1.3 * max(peak, 1e-9) * (3 if peak < 0.3 * joint["limit"] else 1),
                    1.3 * max(peak, 1e-9) * (3 if peak < 0.3 * joint["limit"] else 1))
        ax.set_title(f"peak {peak:.3g} {joint['unit']}, {joint['peak_over_limit']:.1%} of the "
                     f"sized {joint['limit']:.4g}", fontsize=9)
        ax.legend(fontsize=8)
    axes[-1].set_xlabel("t (s)")
    fig.suptitle("SCARA following the seed's trajectory (Drake, computed torque, sized motors)")
    fig.tight_layout()
    return fig


def markdown(summary: dict) -> str:
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
    lines += ["", "Units: joints 1, 2 in N*m and rad/s, joint 3 in N and m/s. Lagrange peak: "
              "M qdd + C qd + G of the desired motion (the analysis's model). The limit of "
              "joint 3 is the chosen servo's peak torque through the 1:2 belt and the ball "
              "screw (eq. 2.86).", "", "![tracking](sim_tracking.png)", "",
              f"Recording: `{RECORDING_FILE}` (open with `rerun {RECORDING_FILE}`)."]
    return "\n".join(lines) + "\n"


def write_simulation(params: ScaraParams, out: Path, duration_s: float | None,
                     progress: bool) -> tuple[list[str], list[Path]]:
    """Run and write SIMULATION_FILES into out (summary.json last)."""
    r = run(params, duration_s, progress)
    summary = summarize(params, r)
    error = summary.pop("error_series")
    written = [save_figure(plot_run(r, summary, error), out / "sim_tracking.png"),
               write_recording(out / RECORDING_FILE, params, r, error),
               write_atomic(out / "summary.md", markdown(summary)),
               write_atomic(out / "summary.json",
                            json.dumps(summary, indent=2, allow_nan=False) + "\n")]
    tr = summary["tracking"]
    lines = [f"{summary['verdict']}: the tool stayed within {tr['max_error_m'] * 1e3:.3f} mm of "
             f"the seed's path (tolerance {tr['tolerance_m'] * 1e3:g} mm) with "
             f"{summary['payload_kg']:g} kg; peak forces "
             + ", ".join(f"{j['joint']} {j['peak_applied']:.3g} {j['unit']} "
                         f"({j['peak_over_limit']:.1%} of the sized motor)"
                         for j in summary["joints"]),
             f"open the recording: rerun '{out / RECORDING_FILE}'"]
    return lines, written
