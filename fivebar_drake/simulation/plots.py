"""Plots of a simulated run: motor torques against the static predictions and the motor limit,
loop gap and body motion (PNG). Fixed margins, not tight_layout: the layout pass measured every
tick label and cost half of the output files' time."""

from __future__ import annotations

from pathlib import Path
import matplotlib.pyplot as plt
import numpy as np

from fivebar_drake.core.files import save_figure
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.summary import MOTORS, Signals, capability_along


def torque_figure(sig: Signals, legs, params: Params, window) -> plt.Figure:
    limit = params.motor.peak_torque_Nm
    fig, axes = plt.subplots(len(legs), 2, figsize=(13, 2.6 * len(legs)), sharex=True, sharey=True)
    for i, leg in enumerate(legs):
        for j, motor in enumerate(MOTORS):
            ax = axes[i, j]
            ax.axvspan(*window, color="0.93", zorder=0,
                       label="statistics window" if i == j == 0 else None)
            ax.plot(sig.t, sig.command[:, i, j], color="0.6", lw=0.8, label="demand (command)")
            ax.plot(sig.t, sig.applied[:, i, j], lw=1.2, label="applied (motor output)")
            ax.plot(sig.t, sig.static_contact[:, i, j], lw=1.0, label="quasi-static: $-J^T F$")
            ax.plot(sig.t, sig.static_trot[:, i, j], ":", lw=1.2, label="static: trot load")
            ax.plot(sig.t, sig.static_seed[:, i, j], "--", lw=1.0, label="static: seed G(q)")
            for sign in (1, -1):
                ax.axhline(sign * limit, color="r", lw=1.2,
                           label=f"limit ±{limit:g} N·m" if sign > 0 else None)
            ax.set(title=f"{leg} motor {motor}", ylabel="torque (N·m)")
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes[0, 1].legend(fontsize=7, loc="upper right")
    fig.suptitle("Motor torques in the simulated trot vs static predictions")
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.05, top=0.93, hspace=0.3, wspace=0.05)
    return fig


def motion_figure(sig: Signals, legs, gait_speed: float) -> plt.Figure:
    fig, (ag, ah, at, av) = plt.subplots(4, 1, figsize=(10, 9), sharex=True)
    for i, leg in enumerate(legs):
        ag.plot(sig.t, sig.gap[:, i] * 1e3, lw=0.8, label=leg)
    ag.axhline(0.1, color="r", ls="--", lw=1, label="0.1 mm")
    ag.set(ylabel="loop gap (mm)", title="Loop closure gap per leg (worst per interval)")
    ah.plot(sig.t, sig.body_p[:, 2] * 1e3)
    ah.set(ylabel="body height (mm)")
    at.plot(sig.t, sig.tilt_deg)
    at.set(ylabel="tilt (deg)")
    av.plot(sig.t, sig.body_v[:, 0], label="body")
    av.axhline(gait_speed, color="k", ls="--", lw=1, label="gait speed")
    av.set(ylabel="forward speed (m/s)", xlabel="time (s)")
    av.legend(fontsize=8)
    for ax in (ag, ah, at, av):
        ax.grid(alpha=0.3)
    ag.legend(fontsize=8, ncol=5)
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.06, top=0.96, hspace=0.25)
    return fig

SIM_PLOT_FILES = ("sim_torques.png", "sim_motion.png")
CAPABILITY_FILE = "force_capability.png"    # jump and drop only


def write_sim_plots(sig: Signals, legs, params: Params, summary: dict,
                    out_dir: Path) -> list[Path]:
    """Write SIM_PLOT_FILES into out_dir (atomically), and CAPABILITY_FILE for a maneuver with
    a push-off or a landing; returns their paths."""
    figures = (torque_figure(sig, legs, params, summary["window_s"]),
               motion_figure(sig, legs, summary["gait_speed_m_s"]))
    written = [save_figure(fig, out_dir / name) for name, fig in zip(SIM_PLOT_FILES, figures)]
    if summary.get("force_capability"):
        written.append(save_figure(capability_figure(sig, legs, params, summary),
                                   out_dir / CAPABILITY_FILE))
    return written


def capability_figure(sig: Signals, legs, params: Params, summary: dict) -> plt.Figure:
    """Along the push-off and the landing (a panel each), per leg against its foot's height
    in the leg plane (the stroke): the measured ground force and the force the motors hold
    along it, within the torque box and within the envelope at the joint speeds
    (summary.capability_along)."""
    phases = {}
    if summary.get("jump"):
        j = summary["jump"]
        phases["push-off"] = (sig.t > j["onset_s"]) & (sig.t <= j["takeoff_s"])
    if summary.get("landing"):
        ld = summary["landing"]
        phases["landing"] = (sig.t > ld["touchdown_s"]) & (sig.t <= ld["end_s"])
    along = capability_along(sig, params, phases, legs)["phases"]
    fig, axes = plt.subplots(1, len(along), figsize=(6 * len(along), 4.5), squeeze=False)
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.12, top=0.88, wspace=0.2)
    for ax, (name, a) in zip(axes[0], along.items()):
        for i, leg in enumerate(legs):
            color = f"C{i}"
            y = a["foot_y_m"][:, i] * 1e3
            ax.plot(y, a["required_N"][:, i], color=color, lw=2, label=f"{leg} required")
            ax.plot(y, a["box_N"][:, i], color=color, ls="--", lw=1,
                    label="torque box" if i == 0 else None)
            ax.plot(y, a["envelope_N"][:, i], color=color, ls=":", lw=1,
                    label="envelope at the joint speeds" if i == 0 else None)
        ax.set_title(name)
        ax.set_xlabel("foot height in the leg plane y (mm)")
        ax.set_ylabel("ground force on the foot (N)")
        top = np.nanmax(a["required_N"]) if np.isfinite(a["required_N"]).any() else 1.0
        ax.set_ylim(0, 3 * top)
        ax.legend(fontsize=7)
    fc = summary["force_capability"]
    fig.suptitle(f"Force capability along the {summary['gait']}: least available / required "
                 f"{fc['least_ratio_box']:.2f} (torque box), {fc['least_ratio_envelope']:.2f} "
                 "(envelope)")
    return fig
