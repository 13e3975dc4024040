"""Plots of a simulated run: motor torques against the static predictions and the motor limit,
loop gap and body motion (PNG)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt

from .params import Params
from .summary import MOTORS, Signals


def torque_figure(sig: Signals, legs, params: Params) -> plt.Figure:
    limit = params.motor.peak_torque_Nm
    fig, axes = plt.subplots(len(legs), 2, figsize=(13, 2.6 * len(legs)), sharex=True, sharey=True)
    for i, leg in enumerate(legs):
        for j, motor in enumerate(MOTORS):
            ax = axes[i, j]
            ax.plot(sig.t_log, sig.command[:, i, j], color="0.7", lw=0.8, label="commanded")
            ax.plot(sig.t_log, sig.applied[:, i, j], lw=1.2, label="applied (simulated)")
            ax.plot(sig.t_log, sig.static_contact[:, i, j], lw=1.0, label="static: $-J_F^T F$")
            ax.plot(sig.t_log, sig.static_seed[:, i, j], "--", lw=1.0, label="static: seed G(q)")
            for sign in (1, -1):
                ax.axhline(sign * limit, color="r", lw=1.2,
                           label=f"limit ±{limit:g} N·m" if sign > 0 else None)
            ax.set(title=f"{leg} motor {motor}", ylabel="torque (N·m)")
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes[0, 1].legend(fontsize=7, loc="upper right")
    fig.suptitle("Motor torques in the simulated trot vs static predictions")
    fig.tight_layout()
    return fig


def motion_figure(sig: Signals, legs) -> plt.Figure:
    fig, (ag, ah, av) = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
    for i, leg in enumerate(legs):
        ag.plot(sig.t_state, sig.gap[i] * 1e3, lw=0.8, label=leg)
    ag.axhline(0.1, color="r", ls="--", lw=1, label="0.1 mm")
    ag.set(ylabel="loop gap (mm)", title="Loop closure gap per leg")
    ah.plot(sig.t_state, sig.body_p[:, 2] * 1e3)
    ah.set(ylabel="body height (mm)")
    av.plot(sig.t_state, sig.body_v[:, 0])
    av.set(ylabel="forward speed (m/s)", xlabel="time (s)")
    for ax in (ag, ah, av):
        ax.grid(alpha=0.3)
    ag.legend(fontsize=8, ncol=5)
    fig.tight_layout()
    return fig


def write_sim_plots(sig: Signals, legs, params: Params, out_dir: Path) -> list[Path]:
    paths = []
    for name, fig in (("sim_torques.png", torque_figure(sig, legs, params)),
                      ("sim_motion.png", motion_figure(sig, legs))):
        fig.savefig(out_dir / name, dpi=110)
        plt.close(fig)
        paths.append(out_dir / name)
    return paths
