"""The figures: of the analysis, the motor torques of both designs per lever, the equivalent
reduction ratio with its extremes marked and the knee range the screw's stroke allows; of the
simulation, the squat."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from fivebar_drake.core.files import save_figure
from fivebar_drake.mechanisms.ballscrew_leg import Params, ball_screw_leg
from fivebar_drake.studies.ballscrew_leg.analysis import Analysis
from fivebar_drake.studies.ballscrew_leg.simulation import Signals

ANALYSIS_FIGURES = ("motor_torques.png", "equivalent_ratio.png", "knee_range.png")
SIMULATION_FIGURES = ("squat.png",)


def motor_torques(a: Analysis, path: Path) -> Path:
    """Holding torque magnitudes against q1, one panel per lever."""
    levers = sorted(a.statics)
    fig, axes = plt.subplots(1, len(levers), figsize=(5 * len(levers), 4), squeeze=False)
    g = a.params.geared_knee
    for ax, s in zip(axes[0], levers):
        st = a.statics[s]
        deg = np.degrees(st.q1)
        ax.plot(deg, np.abs(st.geared_motor_Nm), label=f"geared knee motor ({g.gear_ratio:g}:1)")
        for e, style in (("forward", "-"), ("back-driven", "--")):
            ax.plot(deg, np.abs(st.screw_motor_Nm[e]), style, label=f"screw motor, {e}")
        top = 2.0 * np.max(np.abs(st.geared_motor_Nm))
        ax.set_ylim(0.0, top)
        ax.set_title(f"s1 = {s * 1e3:g} mm")
        ax.set_xlabel("q1 (deg)")
        ax.set_ylabel("motor torque (N·m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"Static motor torques, {a.params.load.foot_force_N:g} N on the foot, "
                 "vertical squat q2 = -2 q1")
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def equivalent_ratio(a: Analysis, path: Path) -> Path:
    """Knee torque / screw motor torque against q1 per lever, max and min marked."""
    fig, ax = plt.subplots(figsize=(8, 5))
    for k, s in enumerate(sorted(a.statics)):
        st = a.statics[s]
        deg = np.degrees(st.q1)
        for e, style in (("forward", "-"), ("back-driven", ":")):
            r = st.ratio["joint", e]
            color = f"C{k}"
            ax.plot(deg, r, style, color=color, label=f"s1 = {s * 1e3:g} mm, {e}")
            i, j = int(np.argmax(r)), int(np.argmin(r))
            ax.plot(deg[i], r[i], "^", color=color)
            ax.plot(deg[j], r[j], "v", color=color)
            if e == "forward":
                ax.annotate(f"max {r[i]:.1f}", (deg[i], r[i]), textcoords="offset points",
                            xytext=(4, 4), fontsize=8)
                ax.annotate(f"min {r[j]:.2f}", (deg[j], r[j]), textcoords="offset points",
                            xytext=(4, -10), fontsize=8)
    ax.axhline(a.params.geared_knee.gear_ratio, color="gray", lw=0.8,
               label=f"geared knee {a.params.geared_knee.gear_ratio:g}:1")
    ax.set_xlabel("q1 (deg)")
    ax.set_ylabel("equivalent reduction ratio (knee torque / screw motor torque)")
    ax.set_title("Ball screw's equivalent reduction ratio (^ max, v min)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2, loc="upper right")
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def knee_range(a: Analysis, path: Path) -> Path:
    """Knee bend against the screw's length per lever, the stroke's window marked."""
    fig, ax = plt.subplots(figsize=(8, 5))
    for s in sorted(a.strokes):
        leg, r = ball_screw_leg(a.params, s), a.strokes[s]
        lo, hi = leg.screw_range()
        length = np.linspace(lo, hi, 400)
        line, = ax.plot(length * 1e3, -np.degrees(leg.knee_from_screw(length)),
                        label=f"s1 = {s * 1e3:g} mm")
        window = np.linspace(*r.screw_m, 100)
        ax.plot(window * 1e3, -np.degrees(leg.knee_from_screw(window)), lw=6, alpha=0.35,
                color=line.get_color())
        ax.annotate(f"bend {np.degrees(r.bend_rad[0]):.0f}..{np.degrees(r.bend_rad[1]):.0f} deg",
                    (r.screw_m[1] * 1e3, np.degrees(r.bend_rad[1])), fontsize=8,
                    textcoords="offset points", xytext=(4, -4))
    ax.set_xlabel("screw length OD = q2l (mm)")
    ax.set_ylabel("knee bend -q2 (deg)")
    ax.set_title(f"Knee range within the screw's stroke ({a.params.screw.stroke_m * 1e3:g} mm, "
                 "thick)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def squat(sig: Signals, p: Params, path: Path) -> Path:
    """The simulated squat: q1 against its reference, the screw motor's torques, the loop gaps."""
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    axes[0].plot(sig.t, np.degrees(sig.q1_ref), "--", label="reference")
    axes[0].plot(sig.t, np.degrees(sig.q1), label="simulated")
    axes[0].set_ylabel("q1 (deg)")
    axes[1].plot(sig.t, sig.command, label="commanded")
    axes[1].plot(sig.t, sig.applied, label="applied")
    axes[1].plot(sig.t, sig.static, "--", label="closed-form static (700 N, lossless)")
    axes[1].axhline(-p.motor.peak_torque_Nm, color="gray", lw=0.8, label="motor limit")
    axes[1].set_ylabel("screw motor torque (N·m)")
    axes[2].semilogy(sig.t, np.maximum(sig.gap_d, 1e-12), label="at D")
    axes[2].semilogy(sig.t, np.maximum(sig.gap_foot, 1e-12), label="at the foot")
    axes[2].set_ylabel("loop gap (m)")
    axes[2].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def write_analysis(a: Analysis, out: Path) -> list[Path]:
    return [f(a, out / name) for f, name in zip((motor_torques, equivalent_ratio, knee_range),
                                                ANALYSIS_FIGURES)]


def write_simulation(sig: Signals, p: Params, out: Path) -> list[Path]:
    return [squat(sig, p, out / SIMULATION_FIGURES[0])]
