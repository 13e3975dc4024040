"""The duty envelope's pictures: every maneuver's operating points over the motor's torque-speed
envelope (the actuator-sizing picture; its points kept in a file beside it) and the windings'
temperature over the duty cycle."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from fivebar_drake.core.files import save_figure, write_atomic
from fivebar_drake.actuators.motor import Motor
from fivebar_drake.envelope.duty_cycle import DutyTemperature
from fivebar_drake.mechanisms.fivebar import MOTORS

OPERATING_POINTS_FILE, DUTY_CYCLE_FILE = "operating_points.png", "duty_cycle.png"
POINTS_FILE = "operating_points.npz"       # the points operating_points.png draws
PLOT_FILES = (OPERATING_POINTS_FILE, POINTS_FILE, DUTY_CYCLE_FILE)
MOTOR_COLOURS = {"A": "tab:blue", "B": "tab:orange"}
DESIGN_COLOURS = ("0.35", "tab:blue", "tab:green")     # designs side by side: the first grey


def save_points(points: dict, path: Path) -> Path:
    """POINTS_FILE: the operating points plot_operating_points draws (name -> (speed (2, n) rad/s,
    demand (2, n) N*m)), so that a later picture can set two designs side by side."""
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **{f"{name}/{key}": array for name, pair in points.items()
                                   for key, array in zip(("speed", "demand"), pair)})
    return write_atomic(path, buffer.getvalue())


def load_points(path: Path) -> dict:
    """save_points' file read back: name -> (speed, demand), in the order saved."""
    with np.load(path) as data:
        names = list(dict.fromkeys(key.rsplit("/", 1)[0] for key in data.files))
        return {n: (data[f"{n}/speed"], data[f"{n}/demand"]) for n in names}


def plot_operating_points(designs: dict[str, tuple[Motor, dict]], path: Path) -> Path:
    """One panel per motor (A, B; every leg): the demand (N*m) at the joint speed (rad/s) of
    each maneuver over the actuator's envelope in all four quadrants (actuators/motor.limits:
    driving and braking) and the continuous torque. designs: label -> (motor, points: name ->
    (speed (2, n), demand (2, n))). One design: a colour per maneuver, the envelope in black;
    several (the dossier's default beside the recommended): a colour per design, its envelope
    and its points alike."""
    import matplotlib.pyplot as plt

    motors = [m for m, _ in designs.values()]
    fastest = max([min(m.no_load_speed_rad_s for m in motors)]
                  + [float(np.max(np.abs(s))) for _, points in designs.values()
                     for s, _ in points.values() if s.size])
    strongest = max([max(m.peak_torque_Nm, m.braking_peak_torque_Nm) for m in motors]
                    + [float(np.max(np.abs(t))) for _, points in designs.values()
                       for _, t in points.values() if t.size])
    speed = np.linspace(-1.1 * fastest, 1.1 * fastest, 801)
    single = len(designs) == 1
    fig, axes = plt.subplots(1, len(MOTORS), figsize=(13, 5.5), sharey=True)
    for j, (ax, name) in enumerate(zip(axes, MOTORS)):
        for d, (design, (motor, points)) in enumerate(designs.items()):
            colour = "k" if single else DESIGN_COLOURS[d % len(DESIGN_COLOURS)]
            upper, lower = motor.limits(speed)
            named = "" if single else f"{design}: "
            if d == 0:
                ax.fill_between(speed, lower, upper, color="0.93", zorder=0)
            ax.plot(speed, upper, "-", color=colour, lw=1.3,
                    label=f"{named}envelope (driving and braking)")
            ax.plot(speed, lower, "-", color=colour, lw=1.3)
            if motor.continuous_torque_Nm is not None:
                for sign in (1, -1):
                    ax.axhline(sign * motor.continuous_torque_Nm, color=colour, ls="--",
                               lw=0.9, alpha=0.6,
                               label=f"{named}continuous torque" if sign > 0 else None)
            cmap = plt.get_cmap("tab10" if len(points) <= 10 else "tab20")
            for k, (maneuver, (s, t)) in enumerate(points.items()):
                ax.scatter(s[j], t[j], s=4, alpha=0.5, rasterized=True,
                           color=cmap(k % cmap.N) if single else colour,
                           label=maneuver if single else (f"{design}: operating points"
                                                          if k == 0 else None))
        ax.axhline(0, color="0.6", lw=0.5)
        ax.axvline(0, color="0.6", lw=0.5)
        ax.set(title=f"motor {name} (all legs): demand at the joint speed",
               xlabel="joint speed (rad/s)", xlim=(speed[0], speed[-1]),
               ylim=(-1.2 * strongest, 1.2 * strongest))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("torque (N·m)")
    axes[-1].legend(loc="upper right", fontsize=8, markerscale=3)
    fig.tight_layout()
    return save_figure(fig, path)


def verdict_temperatures(motor, checks) -> dict[str, float]:
    """The winding temperatures (deg C) where the duty cycle's thermal check turns (its margin
    sqrt(allowed rise / rise) at 1 and at checks.thermal_margin_warn, envelope.duty_cycle's
    duty_verdict): "fail" above the steady temperature of the continuous rating, "warn" above
    that of the rating over thermal_margin_warn; none without a rating or a thermal model."""
    rated = motor.rated_continuous_current_A
    if rated is None or not motor.has_thermal_model:
        return {}
    rise = motor.copper_loss_W(1.0) * motor.thermal_resistance_K_W
    return {"fail": motor.ambient_C + rise * rated ** 2,
            "warn": motor.ambient_C + rise * (rated / checks.thermal_margin_warn) ** 2}


def plot_duty_cycle(motor, checks, duty: DutyTemperature, steps, legs, path: Path) -> Path:
    """The winding temperature (deg C) of every motor over the duty cycle (time in min, in s for
    a cycle under 10 min), A and B in their colours (one line per leg), the winding's limit,
    the temperatures where the thermal check (checks' thresholds) fails and warns
    (verdict_temperatures), the steps shaded and named."""
    import matplotlib.pyplot as plt

    scale, unit = (60.0, "min") if duty.t[-1] >= 600.0 else (1.0, "s")
    times = duty.t / scale
    fig, ax = plt.subplots(figsize=(12, 5))
    for k, step in enumerate(steps):
        lo, hi = duty.starts[k] / scale, duty.starts[k + 1] / scale
        if k % 2:
            ax.axvspan(lo, hi, color="0.93", zorder=0)
        ax.text((lo + hi) / 2, 1.0, step.maneuver, transform=ax.get_xaxis_transform(),
                ha="center", va="bottom", fontsize=8, rotation=30 if len(steps) > 6 else 0)
    for j, name in enumerate(MOTORS):
        for i, leg in enumerate(legs):
            ax.plot(times, duty.temperature[:, i, j], color=MOTOR_COLOURS[name], lw=1.2,
                    alpha=0.85, label=f"motor {name}" if i == 0 else None)
    ax.axhline(motor.winding_limit_C, color="tab:red", ls="--", lw=1.2,
               label=f"winding limit {motor.winding_limit_C:g} °C")
    turns = verdict_temperatures(motor, checks)
    for name, colour in (("fail", "tab:red"), ("warn", "tab:orange")):
        if name in turns:
            ax.axhline(turns[name], color=colour, ls="-.", lw=1.0,
                       label=f"thermal check {name.upper()} above {turns[name]:.0f} °C "
                             "(continuous rating" + ("" if name == "fail" else
                                                     f" / {checks.thermal_margin_warn:g}") + ")")
    ax.axhline(motor.ambient_C, color="0.5", ls=":", lw=1, label="ambient")
    ax.set(xlabel=f"time ({unit})", ylabel="winding temperature (°C)", xlim=(0, times[-1]))
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)
