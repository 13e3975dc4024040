"""Foot paths in the leg plane, one evaluator for the analysis and the simulation.

A path is periodic with the gait period T = 1/f. The cycle phase of a leg is
u = (f t + phase / 2 pi) mod 1, u in [0, 1); u = 0 is lift-off at the back of the stride
(x = x_c + a; leg-plane x points backwards, so a stance foot moving to +x walks the robot forwards).

- ``seed_ellipse`` (seed 000 section 3): x = x_c + a cos(2 pi u), y = y_home + b sin(2 pi u);
  the upper half (u < 0.5) is swing, the lower half stance.
- ``trot``: a path made for walking. Stance (u >= 1 - beta, beta = gait.duty_factor) is a straight
  line on the ground y = y_home from x_c - a to x_c + a at the constant speed v = 2a / (beta T).
  Swing (u < 1 - beta) goes back to x_c - a over T_sw = (1 - beta) T: x is the quintic with
  x, x' and x'' matched to the stance at both ends (x' = v, x'' = 0), so the foot lifts off and
  touches down without slipping; y = y_home + b 64 s^3 (1 - s)^3 (s = swing fraction) lifts the foot
  by b with zero vertical speed and acceleration at lift-off and touchdown. Position, velocity and
  acceleration are continuous over the whole cycle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.validation import (MAX_GAIT_FREQUENCY_HZ, MAX_LENGTH_M, MAX_SAMPLES,
                                           check_lengths, check_number)


PATHS = ("seed_ellipse", "trot")

# Gait phase (rad) of the legs FL, FR, RL, RR: a trot, diagonal pairs in phase, pairs half a
# cycle apart.
TROT_PHASES_RAD = (0.0, math.pi, math.pi, 0.0)


def check_path(path: str) -> None:
    if path not in PATHS:
        raise ValueError(f"gait = {path!r}: allowed {list(PATHS)}")


@dataclass(frozen=True)
class PathPoints:
    """Foot targets (..., 2) in m, velocities (..., 2) in m/s, accelerations (..., 2) in m/s^2
    in the leg plane, and the scheduled stance flag (...)."""

    pos: np.ndarray
    vel: np.ndarray
    acc: np.ndarray
    stance: np.ndarray


def cycle_phase(gait: Gait, t, phase_rad=0.0) -> np.ndarray:
    """Cycle phase u in [0, 1) at times t (s) of a leg with gait phase phase_rad (rad)."""
    return np.asarray(phase_of(gait.frequency_hz, np.asarray(t, dtype=float),
                               np.asarray(phase_rad, dtype=float)))


@jit
def phase_of(frequency_hz, t, phase_rad):
    """Cycle phase in [0, 1) at times t (s) for gait phases phase_rad (rad), broadcast."""
    return np.mod(frequency_hz * t + phase_rad / (2.0 * np.pi), 1.0)


def stance_speed(gait: Gait, path: str) -> float:
    """Mean foot speed (m/s) relative to the hip in stance: the stride 2a over the stance time;
    the robot's kinematic walking speed."""
    check_path(path)
    beta = 0.5 if path == "seed_ellipse" else gait.duty_factor
    return 2.0 * gait.a_m / (beta * gait.period_s)


@jit
def ellipse_point(a, b, x_center, y_home, frequency, u):
    """Seed ellipse at cycle phase u: (x, y, vx, vy, ax, ay) in m, m/s, m/s^2 and the stance
    flag."""
    w = 2.0 * np.pi * frequency
    c, s = np.cos(2.0 * np.pi * u), np.sin(2.0 * np.pi * u)
    return (x_center + a * c, y_home + b * s, -a * w * s, b * w * c, -a * w * w * c,
            -b * w * w * s, s < 0.0)


@jit
def _quintic_h(r):
    """H (unit start slope, zero end slope, zero second derivative at both ends) and its first
    and second derivatives at r."""
    return (r - 6 * r**3 + 8 * r**4 - 3 * r**5, 1 - 18 * r**2 + 32 * r**3 - 15 * r**4,
            -36 * r + 96 * r**2 - 60 * r**3)


@jit
def trot_point(a, b, x_center, y_home, period, beta, u):
    """Trot path (module docstring) at cycle phase u: (x, y, vx, vy, ax, ay) in m, m/s, m/s^2
    and the stance flag. The swing's x is the min-jerk P (0 -> 1) with H and G
    (G(s) = -H(1 - s)) adding the matched end slopes."""
    v = 2.0 * a / (beta * period)
    if u >= 1.0 - beta:                     # stance: flat, at constant speed
        sigma = min(max((u - (1.0 - beta)) / beta, 0.0), 1.0)
        return (-a + 2 * a * sigma) + x_center, y_home, v, 0.0, 0.0, 0.0, True
    t_sw = (1.0 - beta) * period
    s = min(max(u / (1.0 - beta), 0.0), 1.0)
    p, dp, ddp = 10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4, \
        60 * s - 180 * s**2 + 120 * s**3
    h0, dh0, ddh0 = _quintic_h(s)
    h1, dh1, ddh1 = _quintic_h(1.0 - s)
    hg, dhg, ddhg = h0 - h1, dh0 + dh1, ddh0 - ddh1
    bump = 64 * s**3 * (1 - s) ** 3
    dbump = 192 * s**2 * (1 - s) ** 2 * (1 - 2 * s) / t_sw
    ddbump = 384 * s * (1 - s) * ((1 - 2 * s) ** 2 - s * (1 - s)) / t_sw**2
    return (a - 2 * a * p + v * t_sw * hg + x_center, y_home + b * bump,
            (-2 * a * dp + v * t_sw * dhg) / t_sw, b * dbump,
            (-2 * a * ddp + v * t_sw * ddhg) / t_sw**2, b * ddbump, False)


@jit
def path_point(trot, a, b, x_center, y_home, frequency, period, beta, u):
    """The trot path (trot True) or the seed ellipse at cycle phase u:
    (x, y, vx, vy, ax, ay, stance flag) (see trot_point, ellipse_point)."""
    if trot:
        return trot_point(a, b, x_center, y_home, period, beta, u)
    return ellipse_point(a, b, x_center, y_home, frequency, u)


@jit
def path_arrays(trot, a, b, x_center, y_home, frequency, period, beta, u):
    """path_point at cycle phases u (n,): six arrays (n,) and the stance flags (n,)."""
    out, stance = np.empty((6, u.shape[0])), np.empty(u.shape[0], dtype=np.bool_)
    for i in range(u.shape[0]):
        x, y, vx, vy, ax, ay, stance[i] = path_point(trot, a, b, x_center, y_home, frequency,
                                                     period, beta, u[i])
        out[0, i], out[1, i], out[2, i], out[3, i], out[4, i], out[5, i] = x, y, vx, vy, ax, ay
    return out[0], out[1], out[2], out[3], out[4], out[5], stance


def path_constants(gait: Gait, path: str) -> tuple:
    """The leading arguments of path_arrays for a path of footpath.PATHS."""
    check_path(path)
    return (path == "trot", gait.a_m, gait.b_m, gait.x_center_m, gait.y_home_m,
            gait.frequency_hz, gait.period_s, gait.duty_factor)


def evaluate(gait: Gait, path: str, t, phase_rad=0.0) -> PathPoints:
    """The path at times t (s) for a leg with gait phase phase_rad (rad); t and phase_rad
    broadcast against each other."""
    u = cycle_phase(gait, t, phase_rad)
    flat = np.ascontiguousarray(u, dtype=float).ravel()
    x, y, vx, vy, ax, ay, stance = (v.reshape(u.shape) for v in
                                    path_arrays(*path_constants(gait, path), flat))
    return PathPoints(pos=np.stack([x, y], -1), vel=np.stack([vx, vy], -1),
                      acc=np.stack([ax, ay], -1), stance=stance)


def stance_start(gait: Gait, path: str) -> float:
    """Cycle phase u at which the path's stance begins (it ends at u = 1)."""
    check_path(path)
    return 0.5 if path == "seed_ellipse" else 1.0 - gait.duty_factor


def stance_weight(gait: Gait, path: str, t, phase_rad, transfer_s: float) -> np.ndarray:
    """Scheduled share of a foot in the support (0 swing, 1 stance) at times t (s), rising and
    falling smoothly (smoothstep) over transfer_s (s) after touchdown and before lift-off, so
    the load passes from foot to foot without a step."""
    u = cycle_phase(gait, t, phase_rad)
    flat = np.ascontiguousarray(u, dtype=float).ravel()
    return stance_weight_arrays(flat, stance_start(gait, path), gait.period_s,
                                float(transfer_s)).reshape(u.shape)


@jit
def stance_weight_at(u, u0, period, transfer_s):
    """stance_weight at cycle phase u for a stance from u0 to 1 (period s)."""
    if u < u0:
        return 0.0
    edge = min(u - u0, 1.0 - u) * period           # s from the nearer stance end
    x = min(max(edge / transfer_s, 0.0), 1.0) if transfer_s > 0 else 1.0
    return x * x * (3.0 - 2.0 * x)


@jit
def stance_weight_arrays(u, u0, period, transfer_s):
    """stance_weight_at at cycle phases u (n,)."""
    out = np.empty(u.shape[0])
    for i in range(u.shape[0]):
        out[i] = stance_weight_at(u[i], u0, period, transfer_s)
    return out


def cycle_times(gait: Gait) -> np.ndarray:
    """The N sample times t_k = k T / N (s) of one cycle."""
    return np.arange(gait.samples) * (gait.period_s / gait.samples)


def stance_loads(gait: Gait, path: str, t, phases_rad, weight_N: float) -> np.ndarray:
    """Scheduled ground load (N) on each foot at times t: the weight shared equally by the feet
    the schedule has in stance (none in a flight phase). Shape (legs, *t.shape)."""
    stance = np.stack([evaluate(gait, path, t, ph).stance for ph in phases_rad])
    return stance * weight_N / np.maximum(stance.sum(0), 1)


@dataclass(frozen=True)
class Gait:
    """Foot path parameters in the leg plane (m): stride half-length a, step height b, centre
    (x_center, y_home), frequency (Hz), samples per cycle for the analysis, and the trot path's
    duty factor (fraction of the cycle in stance); see footpath.py for the paths."""

    a_m: float
    b_m: float
    x_center_m: float
    y_home_m: float
    frequency_hz: float
    samples: int
    duty_factor: float

    def __post_init__(self):
        check_lengths("gait", self, ("a_m", "b_m"), low_open=False)
        for name in ("x_center_m", "y_home_m"):
            check_number(f"gait.{name}", getattr(self, name), -MAX_LENGTH_M, MAX_LENGTH_M)
        check_number("gait.frequency_hz", self.frequency_hz, 0.0, MAX_GAIT_FREQUENCY_HZ,
                     low_open=True)
        check_number("gait.samples", self.samples, 3, MAX_SAMPLES, integer=True,
                     why="central differences need neighbours")
        check_number("gait.duty_factor", self.duty_factor, 0.0, 1.0, low_open=True,
                     high_open=True)

    @property
    def period_s(self) -> float:
        return 1.0 / self.frequency_hz
