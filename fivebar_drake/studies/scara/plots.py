"""The SCARA figures: of the analysis, the workspace with the trajectory, the joint motion and
the joint forces along the trajectory; of the simulation, the tracking error and the joint
forces against the sized motors."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from fivebar_drake.core.files import save_figure
from fivebar_drake.mechanisms.scara import Dynamics, Scara, ScaraParams, seed_inertia
from fivebar_drake.studies.scara.analysis import Analysis, Motion
from fivebar_drake.studies.scara.simulation import Run

FIGURES = ("workspace", "joint_motion", "joint_forces")
ANALYSIS_FIGURES = tuple(f"{name}.png" for name in FIGURES)
SIMULATION_FIGURES = ("sim_tracking.png",)
UNITS = ("N·m", "N·m", "N")


def plot_workspace(params: ScaraParams, motion: Motion) -> plt.Figure:
    scara = Scara(params.kinematics)
    fig, (top, side) = plt.subplots(1, 2, figsize=(12, 5.5), width_ratios=[1.4, 1])
    grid = scara.seed_grid()
    top.plot(grid[:, 0], grid[:, 1], ".", color="0.7", ms=2, label="the seed's grid (Fig. 2.4)")
    for k, piece in enumerate(scara.workspace_boundary()):
        top.plot(piece[:, 0], piece[:, 1], "k-", lw=1.2, label="boundary" if k == 0 else None)
    top.plot(motion.p[:, 0], motion.p[:, 1], "r-", lw=2, label="trajectory")
    top.plot(0, 0, "ko")
    top.set(aspect="equal", xlabel="x (m)", ylabel="y (m)",
            title="workspace under the joint limits (top view)")
    top.legend(loc="lower left")
    radius = np.linalg.norm(motion.p[:, :2], axis=1)
    inner, outer = scara.radial_extent()
    z = sorted(scara.z0 + params.kinematics.q3_direction * np.array(params.kinematics.q3_limits_m))
    side.fill_between([inner, outer], z[0], z[1], color="0.85", label="reach x height")
    side.plot(radius, motion.p[:, 2], "r-", lw=2, label="trajectory")
    side.set(xlabel="horizontal distance from axis 1 (m)", ylabel="z (m)", title="side view")
    side.legend()
    fig.tight_layout()
    return fig


def plot_joint_motion(motion: Motion) -> plt.Figure:
    fig, axes = plt.subplots(3, 3, figsize=(12, 8), sharex=True)
    units = (("rad", "rad/s", "rad/s^2"), ("rad", "rad/s", "rad/s^2"), ("m", "m/s", "m/s^2"))
    for j in range(3):
        for r, (values, name) in enumerate(((motion.q, "q"), (motion.qd, "qd"),
                                           (motion.qdd, "qdd"))):
            axes[r, j].plot(motion.t, values[:, j])
            axes[r, j].set_ylabel(f"{name}{j + 1} ({units[j][r]})")
            axes[r, j].grid(alpha=0.3)
        axes[2, j].set_xlabel("t (s)")
    fig.suptitle("joint positions, speeds and accelerations along the seed's trajectory")
    fig.tight_layout()
    return fig


def plot_joint_forces(params: ScaraParams, motion: Motion) -> plt.Figure:
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    for payload, style in ((0.0, "-"), (params.links.payload_kg, "--")):
        dyn = Dynamics(params.kinematics, seed_inertia(params.links, payload))
        tau = dyn.torques(motion.q, motion.qd, motion.qdd)["total"]
        for j, ax in enumerate(axes):
            k = int(np.argmax(np.abs(tau[:, j])))
            line, = ax.plot(motion.t, tau[:, j], style, label=f"payload {payload:g} kg")
            ax.plot(motion.t[k], tau[k, j], "o", color=line.get_color())
            ax.annotate(f"peak {tau[k, j]:.3g}", (motion.t[k], tau[k, j]),
                        textcoords="offset points", xytext=(5, 5))
            ax.set_ylabel(f"tau{j + 1} ({UNITS[j]})")
            ax.grid(alpha=0.3)
    axes[0].legend()
    axes[-1].set_xlabel("t (s)")
    fig.suptitle("joint forces along the trajectory (Lagrange: M qdd + C qd + G)")
    fig.tight_layout()
    return fig


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


def write_analysis(a: Analysis, out: Path) -> list[Path]:
    figures = (plot_workspace(a.params, a.motion), plot_joint_motion(a.motion),
               plot_joint_forces(a.params, a.motion))
    return [save_figure(fig, out / name) for fig, name in zip(figures, ANALYSIS_FIGURES)]


def write_simulation(r: Run, summary: dict, error_m, out: Path) -> list[Path]:
    return [save_figure(plot_run(r, summary, error_m), out / SIMULATION_FIGURES[0])]
