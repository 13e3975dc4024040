"""One-shot maneuvers: segments of quintic Hermite curves in time (Maneuver), their segment
helpers, and what a landing takes (Landing)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from fivebar_drake.verdicts.checks import Checks
from fivebar_drake.core.compiled import jit
from fivebar_drake.core.validation import check_number, MAX_LENGTH_M, unit_of, UNIT_SUFFIXES
from fivebar_drake.gaits.base import FootPath, Gait, MAX_MANEUVER_S, Outcome


class ManeuverConstants(NamedTuple):
    """A one-shot maneuver's segments: span (s, their total); per segment (n,) its start and end
    times (n, 2) in s, x and y (n, 6): position, velocity, acceleration at its start, then at
    its end (m, m/s, m/s^2), and whether the feet are in stance (n,) 1 or 0."""

    span: float
    times: np.ndarray
    x: np.ndarray
    y: np.ndarray
    stance: np.ndarray


@jit
def hermite5(e, t0, t1, t):
    """The quintic Hermite curve over [t0, t1] (s) through e = (p0, v0, a0, p1, v1, a1) (position,
    velocity, acceleration at both ends): (value, first, second derivative) at t, clamped to the
    segment."""
    T = t1 - t0
    r = min(max((t - t0) / T, 0.0), 1.0)
    r2, r3, r4, r5 = r * r, r**3, r**4, r**5
    h = (1 - 10 * r3 + 15 * r4 - 6 * r5, r - 6 * r3 + 8 * r4 - 3 * r5,
         0.5 * (r2 - 3 * r3 + 3 * r4 - r5), 10 * r3 - 15 * r4 + 6 * r5, -4 * r3 + 7 * r4 - 3 * r5,
         0.5 * (r3 - 2 * r4 + r5))
    dh = (-30 * r2 + 60 * r3 - 30 * r4, 1 - 18 * r2 + 32 * r3 - 15 * r4,
          0.5 * (2 * r - 9 * r2 + 12 * r3 - 5 * r4), 30 * r2 - 60 * r3 + 30 * r4,
          -12 * r2 + 28 * r3 - 15 * r4, 0.5 * (3 * r2 - 8 * r3 + 5 * r4))
    ddh = (-60 * r + 180 * r2 - 120 * r3, -36 * r + 96 * r2 - 60 * r3,
           0.5 * (2 - 18 * r + 36 * r2 - 20 * r3), 60 * r - 180 * r2 + 120 * r3,
           -24 * r + 84 * r2 - 60 * r3, 0.5 * (6 * r - 24 * r2 + 20 * r3))
    c = (e[0], e[1] * T, e[2] * T * T, e[3], e[4] * T, e[5] * T * T)
    value, first, second = 0.0, 0.0, 0.0
    for k in range(6):
        value += h[k] * c[k]
        first += dh[k] * c[k]
        second += ddh[k] * c[k]
    return value, first / T, second / (T * T)


@jit
def maneuver_point(c, u):
    """A maneuver (ManeuverConstants c) at u = t / span: (x, y, vx, vy, ax, ay) in m, m/s,
    m/s^2 and the stance flag; before the first segment its start, after the last its end."""
    t = u * c.span
    k = 0
    while k < c.times.shape[0] - 1 and t >= c.times[k, 1]:
        k += 1
    x, vx, ax = hermite5(c.x[k], c.times[k, 0], c.times[k, 1], t)
    y, vy, ay = hermite5(c.y[k], c.times[k, 0], c.times[k, 1], t)
    return x, y, vx, vy, ax, ay, c.stance[k] > 0.5


REST = (0.0, 0.0)   # velocity and acceleration of a foot at rest


@dataclass(frozen=True)
class Maneuver(FootPath):
    """A one-shot maneuver (module docstring): all legs together, no ramp, its segments from
    `segments`; it starts after the scenario's standing time (stand_first) and its span is the
    statistics window. Subclasses give `segments`."""

    periodic: ClassVar[bool] = False
    point: ClassVar = staticmethod(maneuver_point)
    stand_first: ClassVar[bool] = True

    def shortfalls(self, gait: Gait, outcome: Outcome, checks: Checks) -> list[str]:
        """A maneuver ends standing: the body within checks.achieved_height_tolerance_m of its
        standing height."""
        tolerance = checks.achieved_height_tolerance_m
        if abs(outcome.end_height_m - outcome.standing_m) <= tolerance:
            return []
        return [f"it ended with the body at {outcome.end_height_m * 1e3:.0f} mm, not within "
                f"{tolerance * 1e3:g} mm of its standing height {outcome.standing_m * 1e3:.0f} mm"]

    def leg_phase(self, leg: str) -> float:
        return 0.0

    def gait_fields(self) -> tuple[str, ...]:
        """A maneuver starts from the gait's home point (x_center, y_home); no stride,
        frequency or duty factor."""
        return ("x_center_m", "y_home_m")

    def segments(self, gait: Gait) -> list[tuple]:
        """[(duration s, stance, x (p0, v0, a0, p1, v1, a1), y (the same)), ...] in m, m/s,
        m/s^2."""
        raise NotImplementedError

    def constants(self, gait: Gait) -> ManeuverConstants:
        segs = self.segments(gait)
        ends = np.cumsum([d for d, *_ in segs])
        return ManeuverConstants(
            float(ends[-1]), np.stack([np.concatenate([[0.0], ends[:-1]]), ends], -1),
            np.array([x for _, _, x, _ in segs], dtype=float),
            np.array([y for _, _, _, y in segs], dtype=float),
            np.array([float(st) for _, st, _, _ in segs]))

    def span_s(self, gait: Gait) -> float:
        return float(sum(d for d, *_ in self.segments(gait)))

    def clock(self, gait: Gait) -> tuple[float, float]:
        span = self.span_s(gait)
        return 1.0 / span, span

    def phase(self, gait: Gait, t, phase_rad=0.0) -> np.ndarray:
        return np.maximum(np.asarray(t, dtype=float), 0.0) / self.span_s(gait) + 0.0 * phase_rad

    def home(self, gait: Gait) -> np.ndarray:
        first = self.segments(gait)[0]
        return np.array([first[2][0], first[3][0]])

    def start_s(self, stand_s: float) -> float:
        return stand_s if self.stand_first else 0.0

    def stance_start(self, gait: Gait) -> float:
        return 0.0

    def stance_speed(self, gait: Gait) -> float:
        return 0.0

    def check(self, field: str) -> None:
        """Every field with a unit suffix within its unit's bounds (validation.unit_of: a speed
        "_m_s" as a speed, never as a time; a time at most MAX_MANEUVER_S); a field without one
        (a share, a count) is its class's to check."""
        for f in dataclasses.fields(self):
            unit = unit_of(f.name)
            if unit is not None:
                low, high, low_open = UNIT_SUFFIXES[unit]
                check_number(f"{field}.{f.name}", getattr(self, f.name), low,
                             MAX_MANEUVER_S if unit == "_s" else high, low_open=low_open)


def hold(duration_s: float, stance: bool, foot) -> tuple:
    """A segment (Maneuver.segments) holding the foot (2,) m at rest."""
    return (duration_s, stance, (foot[0], *REST, foot[0], *REST), (foot[1], *REST, foot[1], *REST))


def move(duration_s: float, stance: bool, start, end, vy=(0.0, 0.0)) -> tuple:
    """A segment from foot point start to end (m; at rest along x, y at the vertical speeds
    vy = (start, end) m/s, no acceleration at either end)."""
    return (duration_s, stance, (start[0], *REST, end[0], *REST),
            (start[1], vy[0], 0.0, end[1], vy[1], 0.0))


@dataclass(frozen=True)
class Landing(Maneuver):
    """What a landing takes: the feet land extension_m below the standing line y_home; from
    touchdown the stance takes the body's speed v_td to rest over landing_stroke_m (the foot's
    quintic from speed v_td to rest: peak deceleration 0.75 v_td^2 / stroke), then recovers to
    standing over recovery_s and holds it settle_s."""

    lands: ClassVar[bool] = True
    extension_m: float = 0.03
    landing_stroke_m: float = 0.06
    recovery_s: float = 0.5
    settle_s: float = 0.4

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.landing_stroke_m", self.landing_stroke_m, 0.0, MAX_LENGTH_M,
                     low_open=True, why="the landing stops the body over this stroke: none "
                                        "would take an infinite force")

    def touchdown_speed(self, gait: Gait) -> float:
        """The planned touchdown speed (m/s, > 0) of the body."""
        raise NotImplementedError

    def landing(self, gait: Gait, v_td: float) -> list[tuple]:
        """The segments from touchdown at speed v_td (m/s, > 0) to standing."""
        x, y_land = gait.x_center_m, gait.y_home_m - self.extension_m
        low = (x, y_land + self.landing_stroke_m)
        return [move(2.0 * self.landing_stroke_m / v_td, True, (x, y_land), low, (v_td, 0.0)),
                move(self.recovery_s, True, low, (x, gait.y_home_m)),
                hold(self.settle_s, True, (x, gait.y_home_m))]
