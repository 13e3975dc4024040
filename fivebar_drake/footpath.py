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

from .params import Gait

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
    return np.mod(gait.frequency_hz * np.asarray(t, dtype=float)
                  + np.asarray(phase_rad, dtype=float) / (2.0 * np.pi), 1.0)


def stance_speed(gait: Gait, path: str) -> float:
    """Mean foot speed (m/s) relative to the hip in stance: the stride 2a over the stance time;
    the robot's kinematic walking speed."""
    check_path(path)
    beta = 0.5 if path == "seed_ellipse" else gait.duty_factor
    return 2.0 * gait.a_m / (beta * gait.period_s)


def _ellipse(gait: Gait, u):
    w = 2.0 * np.pi * gait.frequency_hz
    c, s = np.cos(2.0 * np.pi * u), np.sin(2.0 * np.pi * u)
    a, b = gait.a_m, gait.b_m
    pos = np.stack([gait.x_center_m + a * c, gait.y_home_m + b * s], -1)
    vel = np.stack([-a * w * s, b * w * c], -1)
    acc = np.stack([-a * w * w * c, -b * w * w * s], -1)
    return PathPoints(pos=pos, vel=vel, acc=acc, stance=s < 0.0)


def _quintic_parts(s):
    """min-jerk P (0 -> 1), H (unit start slope) and G (unit end slope) with their first and
    second derivatives in s; all with zero second derivative at both ends."""
    p = (10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4,
         60 * s - 180 * s**2 + 120 * s**3)
    h = lambda r: (r - 6 * r**3 + 8 * r**4 - 3 * r**5, 1 - 18 * r**2 + 32 * r**3 - 15 * r**4,  # noqa: E731
                   -36 * r + 96 * r**2 - 60 * r**3)
    h0, h1 = h(s), h(1.0 - s)
    hg = (h0[0] - h1[0], h0[1] + h1[1], h0[2] - h1[2])    # H(s) + G(s), G(s) = -H(1 - s)
    return p, hg


def _trot(gait: Gait, u):
    beta, period, a = gait.duty_factor, gait.period_s, gait.a_m
    v = 2.0 * a / (beta * period)
    t_sw = (1.0 - beta) * period
    swing = u < 1.0 - beta
    s = np.clip(u / (1.0 - beta), 0.0, 1.0)
    (p, dp, ddp), (hg, dhg, ddhg) = _quintic_parts(s)
    sw_x = (a - 2 * a * p + v * t_sw * hg, (-2 * a * dp + v * t_sw * dhg) / t_sw,
            (-2 * a * ddp + v * t_sw * ddhg) / t_sw**2)
    bump = (64 * s**3 * (1 - s) ** 3, 192 * s**2 * (1 - s) ** 2 * (1 - 2 * s) / t_sw,
            384 * s * (1 - s) * ((1 - 2 * s) ** 2 - s * (1 - s)) / t_sw**2)
    sigma = np.clip((u - (1.0 - beta)) / beta, 0.0, 1.0)
    st_x = -a + 2 * a * sigma
    x = np.where(swing, sw_x[0], st_x) + gait.x_center_m
    y = gait.y_home_m + np.where(swing, gait.b_m * bump[0], 0.0)
    vx = np.where(swing, sw_x[1], v)
    vy = np.where(swing, gait.b_m * bump[1], 0.0)
    ax = np.where(swing, sw_x[2], 0.0)
    ay = np.where(swing, gait.b_m * bump[2], 0.0)
    return PathPoints(pos=np.stack([x, y], -1), vel=np.stack([vx, vy], -1),
                      acc=np.stack([ax, ay], -1), stance=~swing)


def evaluate(gait: Gait, path: str, t, phase_rad=0.0) -> PathPoints:
    """The path at times t (s) for a leg with gait phase phase_rad (rad); t and phase_rad
    broadcast against each other."""
    check_path(path)
    u = cycle_phase(gait, t, phase_rad)
    return _ellipse(gait, u) if path == "seed_ellipse" else _trot(gait, u)


def stance_start(gait: Gait, path: str) -> float:
    """Cycle phase u at which the path's stance begins (it ends at u = 1)."""
    check_path(path)
    return 0.5 if path == "seed_ellipse" else 1.0 - gait.duty_factor


def stance_weight(gait: Gait, path: str, t, phase_rad, transfer_s: float) -> np.ndarray:
    """Scheduled share of a foot in the support (0 swing, 1 stance) at times t (s), rising and
    falling smoothly (smoothstep) over transfer_s (s) after touchdown and before lift-off, so
    the load passes from foot to foot without a step."""
    u = cycle_phase(gait, t, phase_rad)
    u0 = stance_start(gait, path)
    edge = np.minimum(u - u0, 1.0 - u) * gait.period_s           # s from the nearer stance end
    x = np.clip(edge / transfer_s, 0.0, 1.0) if transfer_s > 0 else (edge >= 0).astype(float)
    return np.where(u >= u0, x * x * (3.0 - 2.0 * x), 0.0)


def cycle_times(gait: Gait) -> np.ndarray:
    """The N sample times t_k = k T / N (s) of one cycle."""
    return np.arange(gait.samples) * (gait.period_s / gait.samples)


def stance_loads(gait: Gait, path: str, t, phases_rad, weight_N: float) -> np.ndarray:
    """Scheduled ground load (N) on each foot at times t: the weight shared equally by the feet
    the schedule has in stance (none in a flight phase). Shape (legs, *t.shape)."""
    stance = np.stack([evaluate(gait, path, t, ph).stance for ph in phases_rad])
    return stance * weight_N / np.maximum(stance.sum(0), 1)
