"""Plots of a simulated run: motor torques against the static predictions and the motor limit,
loop gap and body motion, the operating points over the motor's torque–speed envelope (PNG).

Each figure is a strip chart: one matplotlib axes holding stacked bands that share the time
axis, each band with its own quantity, unit and scale (its grid lines labelled in that unit).
They are written after every run, and matplotlib's fixed costs per axes (its Tick objects,
axes set-up and drawing) were most of the output files' time: one axes per figure instead of
four. The curves are reduced to at most PLOT_POINTS, keeping each bucket's extremes (no peak is
lost); keys in words, not legends (their line samples and layout cost a tenth of a figure);
plain-text labels (no mathtext); fast PNG compression."""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple
import matplotlib.pyplot as plt
from matplotlib.patches import Rectangle
from matplotlib.ticker import MaxNLocator
import numpy as np

from fivebar_drake.core.files import save_figure
from fivebar_drake.verdicts.summary_schema import Summary
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.simulation.maneuver_figures import capability_along
from fivebar_drake.simulation.run_statistics import window_rows
from fivebar_drake.simulation.signals import Signals, StepSignals

COINCIDE = 0.02          # capability curves within this share of the panel's scale: one curve
PLOT_POINTS = 1500       # points per curve at most (~ the plot's width in pixels)
BAND_FILL = 0.86         # the share of its band a strip's range takes (the rest: a gap)
# hinting off: glyphs drawn as outlined (a sixth less drawing time, no visible change at 90 dpi)
STYLE = {"font.size": 8, "text.hinting": "none"}
# per torque series: the signal, its label, line style; the motor's colour (A blue, B orange)
# in its shade: applied full, demand light, the static estimates dark
TORQUE_LINES = (("command", "demand (command)", dict(lw=0.8, alpha=0.45)),
                ("applied", "applied (motor output)", dict(lw=1.3)),
                ("static_trot", "static: same loads", dict(lw=1.0, ls=":", color_dark=True)),
                ("static_seed", "static: seed G(q)", dict(lw=0.9, ls="--", color_dark=True)))
MOTOR_COLORS = {"A": ("#1f6fd1", "#0b2f6b"), "B": ("#ef6c0f", "#7a3000")}
LEG_COLORS = ("C0", "C1", "C2", "C3")
LEG_COLOR_NAMES = ("blue", "orange", "green", "red")


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


class Band(NamedTuple):
    """One strip of a strip chart: its y label (quantity and unit) and the range of values it
    shows, bottom to top."""

    label: str
    low: float
    high: float


def band_of(label: str, *series, margin: float = 0.08) -> Band:
    """A band spanning the values of the series with a margin (a share of their range)."""
    low = min(float(np.nanmin(s)) for s in series)
    high = max(float(np.nanmax(s)) for s in series)
    pad = margin * (high - low) if high > low else max(abs(high), 1.0) * 0.1
    return Band(label, low - pad, high + pad)


class StripChart:
    """One axes holding bands stacked top to bottom over the time span (s): put(k, v) maps values
    of band k into the axes' y coordinates (band k takes [K-1-k, K-k))."""

    def __init__(self, fig, span, bands: list[Band]):
        self.ax, self.bands, self.span = fig.add_subplot(), bands, span
        self.ax.set_xlim(*span)
        self.ax.set_ylim(0.0, len(bands))
        self.ax.set_axis_off()

    def put(self, k: int, values):
        band = self.bands[k]
        gap = (1.0 - BAND_FILL) / 2
        scale = BAND_FILL / (band.high - band.low)
        return len(self.bands) - 1 - k + gap + (np.asarray(values, dtype=float) - band.low) * scale

    def plot(self, k: int, t, values, **style):
        t, values = extremes(t, values)
        return self.ax.plot(t, self.put(k, values), **style)

    def hline(self, k: int, value: float, **style):
        y = float(self.put(k, value))
        return self.ax.hlines(y, *self.span, **style)

    def finish(self, x_label: str = "time (s)") -> None:
        """Frames, grid lines and their labels in each band's unit, the band labels and the
        time axis under the bottom band."""
        ax, (t0, t1), gap = self.ax, self.span, (1.0 - BAND_FILL) / 2
        xs = MaxNLocator(6).tick_values(t0, t1)
        xs = xs[(xs >= t0) & (xs <= t1)]
        grid = dict(color="0.88", lw=0.7, zorder=0)
        for k, band in enumerate(self.bands):
            bottom = len(self.bands) - 1 - k + gap / 2
            top = bottom + BAND_FILL + gap
            ax.add_patch(Rectangle((t0, bottom), t1 - t0, top - bottom, fill=False, lw=0.8,
                                   zorder=3))
            ax.vlines(xs, bottom, top, **grid)
            ys = MaxNLocator(4).tick_values(band.low, band.high)
            ys = ys[(ys >= band.low) & (ys <= band.high)]
            ax.hlines(self.put(k, ys), t0, t1, **grid)
            for y in ys:
                ax.text(t0 - 0.005 * (t1 - t0), self.put(k, y), f"{y:g}", ha="right",
                        va="center")
            ax.text(t0 - 0.06 * (t1 - t0), (bottom + top) / 2, band.label, rotation=90,
                    ha="center", va="center")
        bottom = gap / 2
        for x in xs:
            ax.text(x, bottom - 0.03, f"{x:g}", ha="center", va="top")
        ax.text((t0 + t1) / 2, bottom - 0.16, x_label, ha="center", va="top")


def _span(sig: Signals) -> tuple[float, float]:
    return (0.0, float(sig.t[-1])) if len(sig.t) else (0.0, 1.0)


def torque_figure(sig: Signals, legs, params: Params, window) -> plt.Figure:
    """Per leg, both motors' demand, applied torque and static estimates over time, the motor
    limit and the statistics window (shaded)."""
    limit, braking = params.motor.peak_torque_Nm, params.motor.braking_peak_torque_Nm
    top = 1.1 * max(limit, braking)
    fig = plt.figure(figsize=(12, 1.9 * len(legs) + 0.9))
    chart = StripChart(fig, _span(sig), [Band(f"{leg} torque (N·m)", -top, top) for leg in legs])
    chart.ax.axvspan(*window, color="0.94", zorder=0)
    for i, leg in enumerate(legs):
        for j, motor in enumerate(MOTORS):
            full, dark = MOTOR_COLORS[motor]
            for name, label, style in TORQUE_LINES:
                style = dict(style)
                color = dark if style.pop("color_dark", False) else full
                chart.plot(i, sig.t, getattr(sig, name)[:, i, j], color=color, **style)
        for sign in (1, -1):
            chart.hline(i, sign * limit, color="r", lw=1.0)
            chart.hline(i, sign * braking, color="r", ls="-.", lw=0.8)
    chart.finish()
    fig.text(0.07, 1 - 0.06 / fig.get_figheight(),
             f"motor A blue, motor B orange; red: the driving limit ±{limit:.2f} N·m (torque "
             f"along the motion), dash-dot: the braking limit ±{braking:.2f} N·m (against it); "
             "shaded: the statistics window\n" + "; ".join(
                 f"{what}: {label}" for what, (_, label, _) in zip(
                     ("light", "bold", "dotted, dark", "dashed, dark"), TORQUE_LINES)),
             va="top")
    fig.subplots_adjust(left=0.07, right=0.99, bottom=0.45 / fig.get_figheight(),
                        top=1 - 0.45 / fig.get_figheight())
    return fig


def motion_figure(sig: Signals, legs, gait_speed: float) -> plt.Figure:
    """Loop gap per leg (µm, worst per interval), body height (mm), tilt (deg) and forward
    speed (m/s) against the gait's: one unit per band."""
    gap, height = sig.gap * 1e6, sig.body_p[:, 2] * 1e3
    fig = plt.figure(figsize=(10, 7.5))
    chart = StripChart(fig, _span(sig), [
        band_of("loop gap (µm)", gap), band_of("body height (mm)", height),
        band_of("tilt (deg)", sig.tilt_deg),
        band_of("forward speed (m/s)", sig.body_v[:, 0], [gait_speed])])
    for i, leg in enumerate(legs):
        chart.plot(0, sig.t, gap[:, i], lw=0.8, color=LEG_COLORS[i])
    chart.plot(1, sig.t, height, color="C0")
    chart.plot(2, sig.t, sig.tilt_deg, color="C0")
    chart.plot(3, sig.t, sig.body_v[:, 0], color="C0")
    chart.hline(3, gait_speed, color="k", ls="--", lw=1)
    chart.finish()
    fig.text(0.98, 0.985, "loop gap: " + ", ".join(f"{leg} {name}" for leg, name in zip(
        legs, LEG_COLOR_NAMES)) + "; dashed: the gait's speed", ha="right", va="top")
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.06, top=0.96)
    return fig


def torque_speed_figure(sig: Signals, legs, params: Params, summary: Summary) -> plt.Figure:
    """The speed check's picture: per motor (A, B; each leg in its colour) the operating points
    of the statistics window, the demand at the joint speed folded onto positive speeds (torque
    along the motion: driving > 0, braking < 0), over the motor's envelope; the points beyond it
    crossed; each leg's verdict, deciding check and share beyond in the legend."""
    motor = params.motor
    win = window_rows(sig.t, summary["window_s"])
    speed, demand = sig.qd[win], sig.command[win]
    fastest = max(float(np.max(np.abs(speed), initial=0.0)), motor.no_load_speed_rad_s)
    w = np.linspace(0.0, 1.1 * fastest, 200)
    up, lo = motor.limits(w)
    fig, axes = plt.subplots(1, len(MOTORS), figsize=(12, 5), sharey=True)
    for j, (ax, name) in enumerate(zip(axes, MOTORS)):
        ax.plot(w, up, "r-", lw=1.5, label="envelope, driving (beyond the no-load speed the "
                "back-EMF forces braking)")
        ax.plot(w, lo, "r-.", lw=1.2, label="envelope, braking")
        ax.axhline(0.0, color="0.6", lw=0.6)
        for i, leg in enumerate(legs):
            along = np.where(speed[:, i, j] >= 0.0, demand[:, i, j], -demand[:, i, j])
            _, beyond = motor.speed_margins(demand[:, i, j], speed[:, i, j])
            m = summary["legs"][leg][name]
            check = (m.get("checks") or {}).get("speed") or {}
            ax.scatter(np.abs(speed[:, i, j]), along, s=4, color=LEG_COLORS[i], alpha=0.5,
                       rasterized=True, label=f"{leg} {name}: {m['verdict'].upper()} "
                       f"({m['deciding_check'] or 'no check'}), "
                       f"{check.get('outside_fraction', 0.0):.1%} beyond")
            ax.scatter(np.abs(speed[beyond, i, j]), along[beyond], s=30, marker="x",
                       color=LEG_COLORS[i], rasterized=True, zorder=3)
        ax.set(title=f"motor {name}", xlabel="|joint speed| (rad/s)", xlim=(0, w[-1]))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    axes[0].set_ylabel("demand along the motion (N·m): driving > 0, braking < 0")
    fig.suptitle(f"Verdict {summary['verdict'].upper()}, decided by the "
                 f"{summary.get('deciding_check') or 'no'} check (worst motor "
                 f"{summary.get('worst_motor') or 'none'}): the demand over the window "
                 f"{summary['window_s'][0]:.2f} .. {summary['window_s'][1]:.2f} s on the "
                 "torque–speed plane; x: beyond the envelope", fontsize=9)
    fig.subplots_adjust(left=0.07, right=0.99, bottom=0.1, top=0.91, wspace=0.04)
    return fig


SIM_PLOT_FILES = ("sim_torques.png", "sim_motion.png", "sim_torque_speed.png")
CAPABILITY_FILE = "force_capability.png"    # jump and drop only


def write_sim_plots(sig: Signals, legs, params: Params, summary: Summary,
                    out_dir: Path, steps: StepSignals | None = None) -> list[Path]:
    """Write SIM_PLOT_FILES into out_dir (atomically), and CAPABILITY_FILE for a maneuver with
    a push-off or a landing (from its plant steps); returns their paths."""
    with plt.rc_context(STYLE):               # drawn when saved: the style covers both
        figures = (torque_figure(sig, legs, params, summary["window_s"]),
                   motion_figure(sig, legs, summary["gait_speed_m_s"]),
                   torque_speed_figure(sig, legs, params, summary))
        written = [save_figure(fig, out_dir / name, dpi=90, compress_level=1)
                   for name, fig in zip(SIM_PLOT_FILES, figures)]
        if summary.get("force_capability"):
            written.append(save_figure(capability_figure(steps, legs, params, summary),
                                       out_dir / CAPABILITY_FILE, dpi=90, compress_level=1))
    return written


def coinciding(curves, tolerances) -> list[list[int]]:
    """Groups of legs (column indices, in order) whose curves (arrays (steps, legs)) agree with
    the group's first leg within each curve's tolerance at every step (NaN where both are)."""
    groups: list[list[int]] = []
    for i in range(curves[0].shape[1]):
        group = next((g for g in groups if all(
            np.allclose(c[:, i], c[:, g[0]], rtol=0.0, atol=tol, equal_nan=True)
            for c, tol in zip(curves, tolerances))), None)
        if group is None:
            groups.append([i])
        else:
            group.append(i)
    return groups


def _least(ratio, at) -> str:
    if ratio is None:
        return "n/a (no foot loaded)"
    return f"{ratio:.2f}" + (f" ({at['leg']}, {at['phase']}, t = {at['t_s']:.2f} s)" if at else "")


def capability_figure(sig: StepSignals, legs, params: Params,
                      summary: Summary) -> plt.Figure:
    """Along the push-off and the landing (a panel each), per leg against its foot's height
    in the leg plane (the stroke): the measured ground force and the force the motors hold
    along it, within the torque box and within the envelope at the joint speeds, at every
    plant step (maneuver_figures.capability_along). Legs whose curves coincide (within
    COINCIDE of the panel's scale, 1 mm of height) are drawn once and named together; each panel
    is scaled to its curves."""
    phases = {}
    if summary.get("jump"):
        j = summary["jump"]
        phases["push-off"] = (sig.t > j["onset_s"]) & (sig.t <= j["takeoff_s"])
    if summary.get("landing"):
        ld = summary["landing"]
        phases["landing"] = (sig.t > ld["touchdown_s"]) & (sig.t <= ld["end_s"])
    along = capability_along(sig, params, phases, legs)["phases"]
    fig, axes = plt.subplots(1, len(along), figsize=(6 * len(along), 5), squeeze=False)
    for ax, (name, a) in zip(axes[0], along.items()):
        y = a["foot_y_m"] * 1e3
        curves = (a["required_N"], a["box_N"], a["envelope_N"])
        finite = np.concatenate([c[np.isfinite(c)] for c in curves])
        needed = a["required_N"][np.isfinite(a["required_N"])]
        top = min(3.0 * needed.max(), 1.1 * finite.max()) if needed.size else 1.0
        for group in coinciding((y, *curves), (1.0, *[COINCIDE * top] * 3)):
            i, color = group[0], f"C{group[0]}"
            who = ", ".join(legs[k] for k in group)
            if len(group) > 1:
                who += f" ({'all' if len(group) == len(legs) else len(group)} coincide: one curve)"
            ax.plot(y[:, i], a["required_N"][:, i], color=color, lw=2, label=f"{who}: required")
            ax.plot(y[:, i], a["box_N"][:, i], color=color, ls="--", lw=1)
            ax.plot(y[:, i], a["envelope_N"][:, i], color=color, ls=":", lw=1)
        ax.plot([], [], "k--", lw=1, label="held within the torque box")
        ax.plot([], [], "k:", lw=1, label="held within the envelope at the joint speeds")
        ax.set_title(name)
        ax.set_xlabel("foot height in the leg plane y (mm)")
        ax.set_ylabel("ground force on the foot (N)")
        ax.set_ylim(0, top)
        ax.legend(fontsize=7)
    fc = summary["force_capability"]
    fig.suptitle(
        f"Force capability along the {summary['gait']}: the ground force each foot needs (solid)"
        " and the force its two motors can hold in that direction, statically within their "
        "peak torques (the torque box, dashed) and at the joint speeds within the torque-speed "
        "envelope (dotted).\nThe least ratio held / needed over the legs and the stroke: "
        f"{_least(fc['least_ratio_box'], fc.get('least_box_at'))} in the torque box, "
        f"{_least(fc['least_ratio_envelope'], fc.get('least_envelope_at'))} in the envelope; "
        "below 1 the motors could not hold that force there.", wrap=True, fontsize=8)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.1, top=0.84, wspace=0.18)
    return fig
