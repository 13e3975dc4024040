"""Plots of a simulated run: motor torques against the static predictions and the motor limit,
loop gap and body motion (PNG).

Drawn for speed (they are written after every run, and matplotlib's fixed costs dominate): the
curves at most PLOT_POINTS per axes, keeping each bucket's extremes (no peak is lost); few
axes (both motors of a leg in one, in two hues), x tick labels on the bottom axes only (the
others get grid lines, not Tick objects), no titles (the y labels say what and in which unit),
plain-text labels (no mathtext), fast PNG compression."""

from __future__ import annotations

from pathlib import Path
import matplotlib.pyplot as plt
from matplotlib.ticker import FixedLocator, MaxNLocator, NullLocator
import numpy as np

from fivebar_drake.core.files import save_figure
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.summary import MOTORS, Signals

PLOT_POINTS = 1500       # points per curve at most (~ the axes' width in pixels)
STYLE = {"font.size": 8}


def extremes(t: np.ndarray, values: np.ndarray, points: int = PLOT_POINTS):
    """(t, values) reduced to about `points` samples: the minimum and the maximum of each of
    points / 2 buckets of equal rows (the last one shorter), in time order; unchanged when
    already short enough."""
    n = len(t)
    if n <= points:
        return t, values
    size = -(-n // (points // 2))                                   # rows per bucket
    padded = np.concatenate([values, np.full(-n % size, values[-1])]).reshape(-1, size)
    base = np.arange(0, padded.size, size)
    low, high = base + padded.argmin(1), base + padded.argmax(1)
    rows = np.minimum(np.column_stack([np.minimum(low, high), np.maximum(low, high)]).ravel(),
                      n - 1)
    return t[rows], values[rows]


def _axes(fig, rows: int, span) -> list:
    """rows axes stacked over one time span (s): tick labels on the bottom one only (an axes
    without x ticks makes no Tick objects; its vertical grid lines are drawn directly)."""
    axes = fig.subplots(rows, 1)
    xs = MaxNLocator(6).tick_values(*span)
    for k, ax in enumerate(axes):
        ax.set_xlim(*span)
        ax.yaxis.set_major_locator(MaxNLocator(4))
        ax.grid(alpha=0.3, axis="y")
        if k < rows - 1:
            ax.xaxis.set_major_locator(NullLocator())
            ax.vlines(xs, 0, 1, transform=ax.get_xaxis_transform(), color="0.9", lw=0.8,
                      zorder=0)
        else:
            ax.xaxis.set_major_locator(FixedLocator(xs))
            ax.grid(alpha=0.3, axis="x")
            ax.set_xlabel("time (s)")
    return axes


def _span(sig: Signals) -> tuple[float, float]:
    return (0.0, float(sig.t[-1])) if len(sig.t) else (0.0, 1.0)


# per torque series: the signal, its label, line style; the motor's colour (A blue, B orange)
# in its shade: applied full, demand light, the static estimates dark
TORQUE_LINES = (("command", "demand (command)", dict(lw=0.8, alpha=0.45)),
                ("applied", "applied (motor output)", dict(lw=1.3)),
                ("static_trot", "static: trot load", dict(lw=1.0, ls=":", color_dark=True)),
                ("static_seed", "static: seed G(q)", dict(lw=0.9, ls="--", color_dark=True)))
MOTOR_COLORS = {"A": ("#1f6fd1", "#0b2f6b"), "B": ("#ef6c0f", "#7a3000")}


def torque_figure(sig: Signals, legs, params: Params, window) -> plt.Figure:
    """Per leg, both motors' demand, applied torque and static estimates over time, the motor
    limit and the statistics window (shaded)."""
    limit = params.motor.peak_torque_Nm
    with plt.rc_context(STYLE):
        fig = plt.figure(figsize=(12, 1.9 * len(legs) + 0.9))
        axes = _axes(fig, len(legs), _span(sig))
        for i, (leg, ax) in enumerate(zip(legs, axes)):
            ax.axvspan(*window, color="0.94", zorder=0)
            for j, motor in enumerate(MOTORS):
                full, dark = MOTOR_COLORS[motor]
                for name, label, style in TORQUE_LINES:
                    style = dict(style)
                    color = dark if style.pop("color_dark", False) else full
                    ax.plot(*extremes(sig.t, getattr(sig, name)[:, i, j]), color=color,
                            label=f"{motor} {label}", **style)
            for sign in (1, -1):
                ax.axhline(sign * limit, color="r", lw=1.0,
                           label=f"limit ±{limit:g} N·m" if sign > 0 else None)
            ax.set_ylim(-1.12 * limit, 1.12 * limit)
            ax.set_ylabel(f"{leg} torque (N·m)")
        fig.legend(*axes[0].get_legend_handles_labels(), loc="upper left", ncol=5,
                   fontsize=7.5, frameon=False, bbox_to_anchor=(0.06, 0.995))
        fig.subplots_adjust(left=0.06, right=0.99, bottom=0.6 / fig.get_figheight(),
                            top=1 - 0.75 / fig.get_figheight(), hspace=0.08)
    return fig


def motion_figure(sig: Signals, legs, gait_speed: float) -> plt.Figure:
    """Loop gap per leg (µm), body height (mm), tilt (deg) and forward speed (m/s): one unit
    per axes."""
    with plt.rc_context(STYLE):
        fig = plt.figure(figsize=(10, 7.5))
        ag, ah, at, av = _axes(fig, 4, _span(sig))
        for i, leg in enumerate(legs):
            ag.plot(*extremes(sig.t, sig.gap[:, i] * 1e6), lw=0.8, label=leg)
        ag.set_ylabel("loop gap (µm)\nworst per interval")
        ag.legend(fontsize=7.5, ncol=len(legs), loc="upper right")
        ah.plot(*extremes(sig.t, sig.body_p[:, 2] * 1e3))
        ah.set_ylabel("body height (mm)")
        at.plot(*extremes(sig.t, sig.tilt_deg))
        at.set_ylabel("tilt (deg)")
        av.plot(*extremes(sig.t, sig.body_v[:, 0]), label="body")
        av.axhline(gait_speed, color="k", ls="--", lw=1, label="gait speed")
        av.set_ylabel("forward speed (m/s)")
        av.legend(fontsize=7.5, loc="lower right")
        fig.subplots_adjust(left=0.09, right=0.98, bottom=0.07, top=0.98, hspace=0.08)
    return fig


SIM_PLOT_FILES = ("sim_torques.png", "sim_motion.png")


def write_sim_plots(sig: Signals, legs, params: Params, summary: dict,
                    out_dir: Path) -> list[Path]:
    """Write SIM_PLOT_FILES into out_dir (atomically); returns their paths."""
    figures = (torque_figure(sig, legs, params, summary["window_s"]),
               motion_figure(sig, legs, summary["gait_speed_m_s"]))
    return [save_figure(fig, out_dir / name, dpi=90, compress_level=1)
            for name, fig in zip(SIM_PLOT_FILES, figures)]
