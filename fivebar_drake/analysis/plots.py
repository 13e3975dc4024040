"""The seed's plots (seed 000 section 9.3), a workspace map and the design metrics' plots
(design_plots.py), as PNG files."""

from __future__ import annotations

from pathlib import Path
import matplotlib.pyplot as plt
import numpy as np

from fivebar_drake.analysis import design_plots
from fivebar_drake.analysis.force_capability import workspace_grid
from fivebar_drake.analysis.report import FIGURE_NAMES
from fivebar_drake.analysis.torques import Analysis
from fivebar_drake.core.files import save_figure
from fivebar_drake.mechanisms.fivebar import MOTORS, workspace


MODEL_STYLE = {"seed": "--", "full": "-", "full_trot": ":"}
COMPONENTS = (("inertial", "inertial M q''"), ("coriolis", "Coriolis c(q, q')"),
              ("link_weight", "link weights"), ("foot_load", "foot load m_leg g"),
              ("total", "total"))


def joint_angles(an: Analysis) -> plt.Figure:
    fig, ax = plt.subplots(figsize=(8, 4))
    for j, motor in enumerate(MOTORS):
        ax.plot(an.samples.t, np.degrees(an.samples.pose.q[:, j]), "o-", ms=3,
                label=f"theta_{motor}")
    ax.set(xlabel="time (s)", ylabel="motor angle (deg)", title="Joint angles over one gait cycle")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def joint_rates(an: Analysis) -> plt.Figure:
    fig, (av, aa) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    limit = an.params.motor.no_load_speed_rad_s
    for j, motor in enumerate(MOTORS):
        av.plot(an.samples.t, an.samples.qd[:, j], label=f"theta_{motor}'")
        aa.plot(an.samples.t, an.samples.qdd[:, j], label=f"theta_{motor}''")
    for sign in (1, -1):
        av.axhline(sign * limit, color="r", ls="--", label="speed limit" if sign > 0 else None)
    av.set(ylabel="joint speed (rad/s)", title="Joint speeds and accelerations")
    aa.set(xlabel="time (s)", ylabel="joint acceleration (rad/s²)")
    for ax in (av, aa):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig


def torque_components(an: Analysis) -> plt.Figure:
    names = ("seed", "full")
    fig, axes = plt.subplots(2, len(names), figsize=(11, 7), sharex=True, sharey="row")
    for col, name in enumerate(names):
        tb = an.torques[name]
        for row, motor in enumerate(MOTORS):
            ax = axes[row, col]
            for attr, label in COMPONENTS:
                values = getattr(tb, attr)[:, row]
                ax.plot(an.samples.t, values, lw=2.2 if attr == "total" else 1.2, label=label)
            ax.set(title=f"motor {motor}, {name} model", ylabel="torque (N·m)")
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes[0, -1].legend(fontsize=8, loc="best")
    fig.suptitle("Torque components: inertial vs gravity")
    fig.tight_layout()
    return fig


def total_torque(an: Analysis) -> plt.Figure:
    p = an.params
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    limit = p.motor.peak_torque_Nm
    for j, (ax, motor) in enumerate(zip(axes, MOTORS)):
        for name, tb in an.torques.items():
            line, = ax.plot(an.samples.t, tb.total[:, j], MODEL_STYLE[name], lw=1.8,
                            label=f"{name}: dynamic")
            ax.plot(an.samples.t, tb.static[:, j], MODEL_STYLE[name], lw=0.8,
                    color=line.get_color(), alpha=0.6, label=f"{name}: static")
        braking = p.motor.braking_peak_torque_Nm
        for sign in (1, -1):
            ax.axhline(sign * limit, color="r", lw=1.5,
                       label=f"driving limit ±{limit:.2f} N·m" if sign > 0 else None)
            if braking > limit:
                ax.axhline(sign * braking, color="r", ls="-.", lw=1.0,
                           label=f"braking limit ±{braking:.2f} N·m (torque against the "
                                 "motion)" if sign > 0 else None)
            ax.axhline(sign * limit / p.checks.sf_pass, color="orange", ls="--", lw=1,
                       label=f"SF = {p.checks.sf_pass:g} (driving)" if sign > 0 else None)
        ax.set(title=f"motor {motor}", xlabel="time (s)", ylabel="torque (N·m)")
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.suptitle("Total motor torque with the motor's limits in each quadrant")
    fig.tight_layout()
    return fig


def workspace_map(an: Analysis) -> plt.Figure:
    leg = an.params.leg
    ws = workspace(leg, *workspace_grid(leg))
    fig, ax = plt.subplots(figsize=(8, 7.5))
    mesh = ax.pcolormesh(ws.x * 1e3, ws.y * 1e3, np.log10(ws.measures.cond_jf), cmap="viridis",
                         shading="auto", vmax=2.0)
    fig.colorbar(mesh, ax=ax, label="log10 cond(J_F)  (0 = isotropic, high = near singular)")
    ax.plot(an.samples.foot[:, 0] * 1e3, an.samples.foot[:, 1] * 1e3, "r-", lw=2,
            label="gait path")
    pose = an.samples.pose
    for k, alpha in ((0, 1.0), (len(an.samples.t) // 4, 0.5)):
        chain = np.array([leg.a, pose.c[k], pose.e[k], pose.f[k], pose.e[k], pose.d[k], leg.b])
        ax.plot(chain[:, 0] * 1e3, chain[:, 1] * 1e3, "wo-", lw=2, ms=4, alpha=alpha,
                label="leg at t = 0 and T/4" if k == 0 else None)
    limited = design_plots.draw_limits(ax, leg, ws.x, ws.y)
    ax.set(xlabel="x (mm)", ylabel="y (mm)", aspect="equal",
           title="Foot workspace (knees-out mode) " + ("within the leg's limits " if limited
                                                       else "") + "and conditioning")
    if not limited:
        ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig


def write_plots(an: Analysis, out_dir: Path) -> list[Path]:
    """Write every plot of the analysis into out_dir as PNG (atomically); returns the paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    return [save_figure(figure(an), out_dir / f"{name}.png", dpi=120)
            for name, figure in FIGURES.items()]

# the report names the figures (report.FIGURE_NAMES, without importing matplotlib); in its order
FIGURES = dict(zip(FIGURE_NAMES, (joint_angles, joint_rates, torque_components, total_torque,
                                  workspace_map))) | design_plots.FIGURES
