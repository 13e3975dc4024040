"""The winding temperature over a duty cycle: maneuvers one after the other, each repeated for
its time, every winding driven by its maneuver's instantaneous copper loss.

Each step repeats its maneuver's motor currents (the rows of its verdict: whole gait cycles,
so the repetition is seamless) for the step's duration; the copper loss 1.5 R i^2 of every
sample drives the first-order winding model of actuators/thermal.py, solved exactly for a loss held
over each interval (thermal.winding_rise). A long cycle is solved over bins of whole samples
(at most MAX_BINS over the cycle) holding each bin's mean loss: the energy is exact, and what
the bins smooth is the temperature ripple within a bin, a fraction ~ bin / tau_th of the rise
(module docstring of actuators/thermal.py). The cycle starts at ambient."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fivebar_drake.verdicts.checks import SEVERITY, Checks, thermal_check
from fivebar_drake.actuators.motor import BldcMotor
from fivebar_drake.actuators.thermal import winding_rise

MAX_BINS = 20_000


@dataclass(frozen=True)
class DutyTemperature:
    """The duty cycle's winding temperatures: t (bins + 1,) s from the start, temperature
    (bins + 1, legs, 2) deg C at those times (the start at ambient, then the end of each bin),
    the steps' start times (steps + 1,) s (the last: the end of the cycle)."""

    t: np.ndarray
    temperature: np.ndarray
    starts: np.ndarray


def segment_loss(loss: np.ndarray, dt_s: float, duration_s: float,
                 bin_s: float) -> tuple[np.ndarray, np.ndarray]:
    """A maneuver's loss samples (n, ...) W, each held dt_s, repeated for duration_s (a whole
    number of samples, the nearest), as bins of whole samples about bin_s long (at least one
    sample, the last bin shorter): (bin lengths (bins,) s, mean loss (bins, ...) W). The mean
    of a bin is its energy over its length, from the cumulative energy of the repetition."""
    n = loss.shape[0]
    samples = max(1, round(duration_s / dt_s))
    per_bin = max(1, int(bin_s / dt_s))
    edges = np.unique(np.append(np.arange(0, samples, per_bin), samples))
    cum = np.concatenate([np.zeros((1,) + loss.shape[1:]), np.cumsum(loss, axis=0)])
    energy = (edges // n)[(...,) + (None,) * (loss.ndim - 1)] * cum[-1] + cum[edges % n]
    counts = np.diff(edges)
    return counts * dt_s, np.diff(energy, axis=0) / counts[(...,) + (None,) * (loss.ndim - 1)]


def duty_temperature(motor: BldcMotor, steps, currents: dict[str, tuple[np.ndarray, float]],
                     max_bins: int = MAX_BINS) -> DutyTemperature:
    """The windings' temperature over the steps (DutyStep: maneuver, duration_s) from each
    maneuver's currents (name -> (currents (rows, legs, 2) A, the interval of a row s)); the
    module docstring says how."""
    total = sum(s.duration_s for s in steps)
    bin_s = total / max_bins
    widths, losses, starts = [], [], [0.0]
    for step in steps:
        current, dt = currents[step.maneuver]
        w, p = segment_loss(motor.copper_loss_W(current), dt, step.duration_s, bin_s)
        widths.append(w)
        losses.append(p)
        starts.append(starts[-1] + float(w.sum()))
    width, loss = np.concatenate(widths), np.concatenate(losses)
    rise = winding_rise(motor, loss, width)
    temperature = motor.ambient_C + np.concatenate([np.zeros((1,) + rise.shape[1:]), rise])
    return DutyTemperature(t=np.concatenate([[0.0], np.cumsum(width)]), temperature=temperature,
                           starts=np.array(starts))


def duty_verdict(motor: BldcMotor, checks: Checks, duty: DutyTemperature, legs,
                 motors) -> dict:
    """Per motor (A, B), the hottest winding of the duty cycle: its peak temperature (deg C),
    leg, time (s), and the thermal check (verdicts/checks.thermal_check) of the constant current
    that would hold the winding at that peak for ever (equivalent_current_A) against the
    motor's one continuous rating (Motor.rated_continuous_current_A, never above the thermal
    model's: a winding above its limit always fails): margin = sqrt(allowed rise / peak rise), fail below 1 (beyond the
    winding's limit), warn below checks.thermal_margin_warn. The worst verdict of
    the two motors with the motor that decides it."""
    out = {}
    for j, name in enumerate(motors):
        temp = duty.temperature[:, :, j]
        row, leg = np.unravel_index(int(np.argmax(temp)), temp.shape)
        peak = float(temp[row, leg])
        rise = peak - motor.ambient_C
        equivalent = (math.sqrt(rise / (motor.copper_loss_W(1.0) * motor.thermal_resistance_K_W))
                      if rise > 0 else 0.0)
        check = thermal_check(checks, motor.rated_continuous_current_A, equivalent)
        out[name] = {"peak_C": peak, "leg": legs[leg], "at_s": float(duty.t[row]),
                     "end_C": float(temp[-1].max()), "equivalent_current_A": equivalent,
                     "margin": check["margin"], "verdict": check["verdict"]}
    worst = max(motors, key=lambda m: (SEVERITY[out[m]["verdict"]], out[m]["peak_C"]))
    return {"motors": out, "verdict": out[worst]["verdict"], "worst_motor": worst,
            "winding_limit_C": motor.winding_limit_C, "ambient_C": motor.ambient_C}
