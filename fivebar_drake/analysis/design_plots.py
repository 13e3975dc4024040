"""Plots of the design metrics (design_metrics.py): force capability maps and margin along the
gait, torque-speed envelope, winding temperature, hinge loads and the gear-ratio trade."""

from __future__ import annotations

import dataclasses

import matplotlib.pyplot as plt
from matplotlib.colors import LogNorm
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
import numpy as np

from fivebar_drake.analysis.design_metrics import GEAR_MODEL, PHYSICAL
from fivebar_drake.analysis.force_capability import CAPABILITY_KEYS, capability_map, workspace_grid
from fivebar_drake.analysis.gear_ratio import EFFECTS, safety_factors
from fivebar_drake.analysis.joint_loads import JOINT_NAMES
from fivebar_drake.analysis.torques import Analysis
from fivebar_drake.actuators.thermal import winding_temperature
from fivebar_drake.mechanisms.fivebar import (ALL_MODES, KNEES_OUT, MOTORS, LegGeometry, LegLimits,
                                              inverse, limit_tests, mode_name, past_any)


MODEL_STYLE = {"full": "-", "full_trot": "--"}
# the gear-ratio readings overlap where an effect is small: styles that stay visible
EFFECT_STYLE = {"peak only": dict(ls=":", lw=2.5), "torque-speed line": dict(lw=4, alpha=0.4),
                "reflected inertia": dict(ls="--", lw=1.5), "both": dict(lw=1.5, color="r")}
CAPABILITY_TITLES = dict(zip(CAPABILITY_KEYS, ("largest vertical force", "largest horizontal "
                                               "force", "force available in every direction")))


def draw_limits(ax, leg: LegGeometry, x, y, mode=KNEES_OUT) -> bool:
    """Draw on ax (mm) where the leg's limits cut the mode's geometric reach on the grid x by y
    (m): the cut region filled grey and each limit's boundary (limits.py) dashed, with legend
    entries; False if the leg has no limits."""
    free = dataclasses.replace(leg, limits=LegLimits())
    foot = np.stack(np.meshgrid(x, y), axis=-1)
    pose = inverse(free, foot, mode, strict=False)
    tests = limit_tests(leg, pose)
    if not tests:
        return False
    reach = ~np.isnan(pose.q).any(axis=-1)
    cut = reach & past_any(tests, reach.shape)
    xm, ym = np.asarray(x) * 1e3, np.asarray(y) * 1e3
    ax.contourf(xm, ym, cut.astype(float), levels=[0.5, 1.5], colors=["0.55"], alpha=0.55)
    handles = [Patch(color="0.55", alpha=0.55, label="reachable, cut by the limits")]
    colors = plt.get_cmap("tab10").colors
    for k, test in enumerate(tests):
        excess = np.where(reach, test.excess, np.nan)
        if np.nanmin(excess) < 0 < np.nanmax(excess):
            color = colors[k % len(colors)]
            ax.contour(xm, ym, excess, levels=[0.0], colors=[color], linewidths=1.2,
                       linestyles="--")
            sign = ">=" if test.side < 0 else "<="
            handles.append(Line2D([], [], color=color, ls="--", label=f"{test.name} {sign} "
                                  f"{test.bound * test.scale:.4g} {test.unit}"))
    ax.legend(handles=ax.get_legend_handles_labels()[0] + handles, fontsize=7, ncol=3,
              loc="upper center", bbox_to_anchor=(0.5, -0.1))
    return True


def force_capability_maps(an: Analysis) -> plt.Figure:
    p = an.params
    x, y = workspace_grid(p.leg, 161, 107)
    maps = [capability_map(p.leg, p.motor.peak_torque_Nm, x, y, mode) for mode in ALL_MODES]
    weight = p.robot.weight_share_kg * p.robot.gravity_m_s2
    trot = float(np.max(an.metrics.support["full_trot"].needed))
    fig, axes = plt.subplots(len(CAPABILITY_KEYS), len(maps), figsize=(15, 9), sharex=True,
                             sharey=True, layout="constrained")
    norm = LogNorm(vmin=weight / 4, vmax=weight * 20)
    for row, key in enumerate(CAPABILITY_KEYS):
        for col, cmap in enumerate(maps):
            ax = axes[row, col]
            mesh = ax.pcolormesh(x * 1e3, y * 1e3, cmap.forces[key], norm=norm, cmap="magma",
                                 shading="auto")
            ax.contour(x * 1e3, y * 1e3, cmap.forces[key], levels=[weight, trot],
                       colors=["w", "c"], linewidths=1)   # trot peak: half the robot's weight
            ax.plot(an.samples.foot[:, 0] * 1e3, an.samples.foot[:, 1] * 1e3, "g-", lw=1.5)
            ax.plot(p.gait.x_center_m * 1e3, p.gait.y_home_m * 1e3, "g+", ms=10)
            ax.set(aspect="equal", title=f"{mode_name(cmap.mode)}: {CAPABILITY_TITLES[key]}")
            ax.title.set_fontsize(9)
    for ax in axes[-1]:
        ax.set_xlabel("x (mm)")
    for ax in axes[:, 0]:
        ax.set_ylabel("y (mm)")
    fig.colorbar(mesh, ax=axes, shrink=0.6, label="foot force (N), torque box through J_F^-T")
    limited = " (blank: out of reach or past the leg's limits)" if p.limits.given else ""
    fig.suptitle("Static foot-force capability per assembly mode (motors "
                 f"±{p.motor.peak_torque_Nm:.2f} N·m)\ncontours: weight share {weight:.1f} N "
                 f"(white), trot peak {trot:.1f} N (cyan); green: gait path and home point"
                 + limited, wrap=True)
    return fig


def force_margin(an: Analysis) -> plt.Figure:
    fig, (af, am) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    t = an.samples.t
    for name in PHYSICAL:
        s = an.metrics.support[name]
        style = MODEL_STYLE[name]
        af.plot(t, s.needed, style, color="k", label=f"{name}: needed (foot load)")
        af.plot(t, s.moving, style, color="tab:blue", label=f"{name}: available while moving")
        with np.errstate(divide="ignore", invalid="ignore"):
            am.plot(t, np.where(s.needed > 0, s.moving / s.needed, np.nan), style,
                    color="tab:blue", label=f"{name}: moving")
            am.plot(t, np.where(s.needed > 0, s.at_rest / s.needed, np.nan), style,
                    color="tab:orange", label=f"{name}: at rest")
    af.plot(t, an.metrics.support["full"].at_rest, color="tab:orange",
            label="available at rest (torque box)")
    af.set(ylabel="vertical foot force (N)", title="Support force along the gait")
    am.axhline(1.0, color="r", lw=1)
    am.set(xlabel="time (s)", ylabel="available / needed",
           title="Margin (swing of the trot: no load, no margin)")
    for ax in (af, am):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return fig


def torque_speed(an: Analysis) -> plt.Figure:
    """The motors' operating points (the torque each delivers: joint torque + output friction,
    Motor.delivered_torque) over the envelope of both quadrants, folded onto positive speeds:
    torque in the direction of the motion (driving > 0, braking < 0) against |joint speed|."""
    m = an.params.motor
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6), sharey=True)
    fastest = max(float(np.max(np.abs(an.samples.qd))), m.no_load_speed_rad_s)
    w = np.linspace(0.0, 1.1 * fastest, 300)
    up, lo = m.limits(w)
    bottom = min(float(lo.min()), float(up.min()))
    for j, (ax, motor) in enumerate(zip(axes, MOTORS)):
        ax.plot(w, up, "r-", lw=1.5, label="envelope, driving side (beyond the no-load speed "
                "the back-EMF\nforces braking)")
        ax.plot(w, lo, "r-.", lw=1.2, label=f"envelope, braking side ({m.braking_peak_torque_Nm:.2f}"
                " N·m)")
        if m.continuous_torque_Nm is not None:
            ax.plot(w, np.clip(up, None, m.continuous_torque_Nm), "r--", lw=1,
                    label=f"continuous rating {m.continuous_torque_Nm:.2f} N·m")
        ax.axhline(0.0, color="grey", lw=0.6)
        for name in PHYSICAL:
            speed = an.samples.qd[:, j]
            demand = m.delivered_torque(an.torques[name].total[:, j], speed)
            along = np.where(speed >= 0.0, demand, -demand)
            dots = ax.plot(np.abs(speed), along, "o" if name == "full" else "x", ms=4,
                           label=f"{name} (joint torque + friction)")[0]
            r = an.results["results"][name][motor]
            k = r["torque_speed_margin_at"]["sample"]
            ax.plot(abs(speed[k]), along[k], "s", mfc="none", ms=10, color=dots.get_color(),
                    label=f"{name}: least margin {r['torque_speed_margin']:.2f}x")
        ax.set(title=f"motor {motor}", xlabel="|joint speed| (rad/s)",
               ylabel="torque along the motion (N·m): driving > 0, braking < 0",
               xlim=(0, w[-1]), ylim=(1.05 * bottom, 1.05 * m.peak_torque_Nm))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6.5, loc="lower right", bbox_to_anchor=(1.0, 0.08))
    fig.suptitle("Operating points over the gait on the torque-speed plane, both quadrants")
    fig.tight_layout()
    return fig


def thermal(an: Analysis) -> plt.Figure:
    m = an.params.motor
    t = np.linspace(0.0, 5.0 * m.thermal_time_constant_s, 300)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name in PHYSICAL:
        th = an.results["thermal"]["models"][name]
        for motor in MOTORS:
            i, tau = th[motor]["rms_current_A"], th[motor]["rms_torque_Nm"]
            ax.plot(t / 60.0, winding_temperature(m, i, t), MODEL_STYLE[name],
                    label=f"{name}, motor {motor}: RMS {tau:.2f} N·m, {i:.2f} A")
    ax.axhline(m.winding_limit_C, color="r", label=f"winding limit {m.winding_limit_C:g} °C")
    ax.axhline(m.ambient_C, color="grey", lw=0.8, label=f"ambient {m.ambient_C:g} °C")
    ax.set(xlabel="time walking (min)", ylabel="winding temperature (°C)",
           title=f"First-order winding temperature (R_th {m.thermal_resistance_K_W:g} K/W, "
                 f"tau {m.thermal_time_constant_s:g} s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    return fig


def joint_loads(an: Analysis) -> plt.Figure:
    fig, (at, ah) = plt.subplots(1, 2, figsize=(13, 5), gridspec_kw={"width_ratios": [3, 2]})
    colors = dict(zip(JOINT_NAMES, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    for name in PHYSICAL:
        forces = an.metrics.loads[name].forces
        for j, joint in enumerate(JOINT_NAMES):
            at.plot(an.samples.t, np.linalg.norm(forces[:, j], axis=-1), MODEL_STYLE[name],
                    color=colors[joint], label=f"{joint} ({name})")
            ah.plot(*np.vstack([forces[:, j], forces[:1, j]]).T, MODEL_STYLE[name],
                    color=colors[joint], label=f"{joint} ({name})" if name == "full" else None)
    at.set(xlabel="time (s)", ylabel="|hinge force| (N)", title="Hinge force magnitude")
    ah.set(xlabel="Fx (N)", ylabel="Fy (N)", aspect="equal",
           title="Hinge force on the downstream link (leg plane)")
    for ax in (at, ah):
        ax.grid(alpha=0.3)
    at.legend(fontsize=7, ncol=2)
    ah.legend(fontsize=7)
    fig.tight_layout()
    return fig


def gear_ratio(an: Analysis) -> plt.Figure:
    g, p = an.metrics.gear, an.params
    tb = an.torques[GEAR_MODEL]
    fig, ax = plt.subplots(figsize=(8, 5))
    for name, flags in EFFECTS.items():
        sf = safety_factors(p.motor, tb.joint, an.samples.qd, an.samples.qdd, g.ratios, *flags)
        ax.plot(g.ratios, np.min(sf, axis=1), label=f"{name} (worst motor)",
                **EFFECT_STYLE[name])
    ax.axvline(p.motor.gear_ratio, color="k", ls=":",
               label=f"current {p.motor.gear_ratio:g}:1, SF {g.current_safety:.2f}")
    ax.plot(g.best_ratio, g.best_safety, "r*", ms=12,
            label=f"best {g.best_ratio:.2f}:1, SF {g.best_safety:.2f}")
    for level, color in ((p.checks.sf_pass, "g"), (p.checks.sf_warn, "orange")):
        ax.axhline(level, color=color, ls="--", lw=0.8)
    ax.set(xscale="log", xlabel="gear ratio N", ylabel="safety factor",
           ylim=(0, 1.3 * max(g.best_safety, 1.0)),
           title=f"Gear-ratio trade on the {GEAR_MODEL} model (the answer's): the same motor, "
                 "peak tau_m N, no-load w_m0 / N, rotor N² J_r")
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


FIGURES = {"force_capability": force_capability_maps, "force_margin": force_margin,
           "torque_speed": torque_speed, "thermal": thermal, "joint_loads": joint_loads,
           "gear_ratio": gear_ratio}
