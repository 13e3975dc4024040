"""The duty envelope's pictures: every maneuver's operating points over the motor's torque-speed
envelope (the actuator-sizing picture) and the windings' temperature over the duty cycle."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fivebar_drake.core.files import save_figure
from fivebar_drake.actuators.motor import Motor
from fivebar_drake.envelope.duty_cycle import DutyTemperature
from fivebar_drake.mechanisms.fivebar import MOTORS

OPERATING_POINTS_FILE, DUTY_CYCLE_FILE = "operating_points.png", "duty_cycle.png"
PLOT_FILES = (OPERATING_POINTS_FILE, DUTY_CYCLE_FILE)
MOTOR_COLOURS = {"A": "tab:blue", "B": "tab:orange"}


def plot_operating_points(motor: Motor, points: dict, path: Path) -> Path:
    """One panel per motor (A, B; every leg): the demand (N*m) at the joint speed (rad/s) of
    each maneuver (points: name -> (speed (2, n), demand (2, n)); one colour each) over the
    actuator's envelope in all four quadrants (actuators/motor.torque_limits: driving and braking)
    and the continuous torque."""
    import matplotlib.pyplot as plt

    w0 = motor.no_load_speed_rad_s
    fastest = max([w0] + [float(np.max(np.abs(s))) for s, _ in points.values() if s.size])
    speed = np.linspace(-1.1 * fastest, 1.1 * fastest, 801)
    upper, lower = motor.limits(speed)
    colours = plt.get_cmap("tab10" if len(points) <= 10 else "tab20")
    fig, axes = plt.subplots(1, len(MOTORS), figsize=(13, 5.5), sharey=True)
    for j, (ax, name) in enumerate(zip(axes, MOTORS)):
        ax.fill_between(speed, lower, upper, color="0.93", zorder=0)
        ax.plot(speed, upper, "k-", lw=1.3, label="envelope (driving and braking)")
        ax.plot(speed, lower, "k-", lw=1.3)
        if motor.continuous_torque_Nm is not None:
            for sign in (1, -1):
                ax.axhline(sign * motor.continuous_torque_Nm, color="0.45", ls="--", lw=0.9,
                           label="continuous torque" if sign > 0 else None)
        for k, (maneuver, (s, d)) in enumerate(points.items()):
            ax.scatter(s[j], d[j], s=4, alpha=0.5, color=colours(k % colours.N),
                       label=maneuver, rasterized=True)
        ax.axhline(0, color="0.6", lw=0.5)
        ax.axvline(0, color="0.6", lw=0.5)
        ax.set(title=f"motor {name} (all legs): demand at the joint speed",
               xlabel="joint speed (rad/s)", xlim=(speed[0], speed[-1]))
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
