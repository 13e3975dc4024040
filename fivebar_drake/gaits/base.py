"""Foot paths in the leg plane, one evaluator for the analysis and the simulation: the machinery
every gait and maneuver module of this package shares.

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

- ``walk``, ``bound``, ``pronk``: the trot path with the legs' phases of a crawl (one leg at a
  time), a bound (front pair, rear pair) and a pronk (all four); the pronk's stance dips the body
  by A sin(pi sigma) (foot y = y_home + A sin(pi sigma)), so the feet push it into a flight.
- one-shot maneuvers (Maneuver: ``jump``, ``drop``, ``stand_up``): segments of quintic Hermite
  curves in time (position, velocity and acceleration given at both ends of each), each in stance
  or in flight; u = t / span, no repetition: after the span the last point holds.

Each path is a FootPath registered by its kind in PATHS (register_path): its constants (a
NamedTuple, as the compiled code takes it), its compiled point function, where its stance starts;
the Diagram's block simulation/gait_source.GaitSource evaluates any of them (references_kernel).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, NamedTuple, Optional

import numpy as np

from fivebar_drake.verdicts.checks import Checks
from fivebar_drake.core.compiled import jit, jit_uncached
from fivebar_drake.core.validation import (check_lengths, check_number, MAX_GAIT_FREQUENCY_HZ,
                                           MAX_GRAVITY_M_S2, MAX_LENGTH_M, MAX_SAMPLES)
from fivebar_drake.core.variants import by_kind, registrar, Variant


MAX_MANEUVER_S = 100.0   # a maneuver's times (s); its lengths (m) are held to MAX_LENGTH_M, which
#                          catches the common slip of units (100 for 100 mm)
REACH_SPEED_M_S = 0.1   # a landing foot reaches down at this speed at touchdown (early touchdown
#                         detection joins a descending foot to the support)
PUSH_SHARES = (0.5, 1.25)  # a jump's push time over 2 stroke / v: (the whole stroke at the
#                           takeoff speed, open; the foot's quintic still moving one way, closed)
EXTENSION_STOP_S = 0.02  # after takeoff a jump's legs stop extending within this (the foot sinks
#                          v t / 2 below the takeoff point: 8 mm at the packaged jump's 0.77 m/s;
#                          a light leg stops that fast, and it keeps the leg inside its reach)
MIN_CRAWL_DUTY = 0.75   # a crawl's duty factor: one leg in swing at a time, three feet down
PATHS: dict[str, type["FootPath"]] = {}   # the foot paths by kind, in registration order
register_path = registrar(PATHS, "gait")


def foot_path(path: "FootPath | str") -> "FootPath":
    """A foot path, or the registered one of that kind with its defaults."""
    return by_kind(PATHS, path, "gait")


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


class Events(NamedTuple):
    """A maneuver's planned key times (s from its start; nan: not in its plan): the push-off's
    onset, the takeoff and the touchdown (FootPath.events)."""

    onset: float = math.nan
    takeoff: float = math.nan
    touchdown: float = math.nan

    def planned(self) -> dict[str, float]:
        """The times the plan has, by name."""
        return {name: t for name, t in self._asdict().items() if not math.isnan(t)}


class Outcome(NamedTuple):
    """What a run did, as its path's achievement sees it (FootPath.shortfalls): the mean forward
    speed (m/s), the body's height at the end and standing (m), and a maneuver's figures
    (simulation/maneuver_figures' dictionary; None for a gait)."""

    speed_m_s: float
    end_height_m: float
    standing_m: float
    maneuver: Optional[dict]


@dataclass(frozen=True)
class FootPath(Variant):
    """A foot path of the gait parameters (Gait): subclasses set `kind`, `point` (a compiled
    function (constants, u) -> (x, y, vx, vy, ax, ay) in m, m/s, m/s^2 and the stance flag at
    cycle phase u) and `constants` (the NamedTuple `point` takes), and where the stance starts;
    register them with register_path."""

    point: ClassVar = None
    title: ClassVar[str] = ""          # the path in a few words, e.g. "trot foot path"
    periodic: ClassVar[bool] = True    # False: a one-shot maneuver (Maneuver)
    early_touchdown: ClassVar[bool] = True   # the controller's touchdown detection applies
    lands: ClassVar[bool] = False      # lands (Landing: landing_stroke_m, touchdown_speed)
    pushes: ClassVar[bool] = False     # pushes off first (Jump: height_m, crouch_m, ...)
    gait_defaults: ClassVar[dict] = {}  # gait fields (m, Hz) this path takes unless the scenario
    #                                     sets them (scenario.gait_*)

    def text(self, gait: Gait) -> str:
        """The path in words with its numbers (mm, m/s), for the analysis report."""
        return self.title

    def shortfalls(self, gait: Gait, outcome: Outcome, checks: Checks) -> list[str]:
        """Why a run did not do this path's motion (none if it did; verdicts/rules.achievement
        adds what every run is held to): a gait walks at least checks.achieved_speed_fraction
        of its stance speed (none asked: nothing to miss)."""
        asked = self.stance_speed(gait)
        if asked > 0 and not outcome.speed_m_s >= checks.achieved_speed_fraction * asked:
            return [f"it walked {outcome.speed_m_s:.3f} m/s, less than "
                    f"{checks.achieved_speed_fraction:.0%} of the gait's {asked:.3f} m/s"]
        return []

    def leg_phase(self, leg: str) -> float:
        """The gait phase (rad) of a quadruped leg named front/rear then left/right ("FL",
        "RR", ...): a trot's, diagonal pairs in phase, the pairs half a cycle apart."""
        return math.pi if (leg[0] == "F") != (leg[1] == "L") else 0.0

    def constants(self, gait: Gait) -> tuple:
        """The NamedTuple of constants `point` takes."""
        raise NotImplementedError

    def gait_fields(self) -> tuple[str, ...]:
        """The Gait fields this path reads (a scenario's override of another is refused: it
        would do nothing): a periodic path's stride, step height, centre, ground line and
        frequency."""
        return ("a_m", "b_m", "x_center_m", "y_home_m", "frequency_hz")

    def stance_start(self, gait: Gait) -> float:
        """Cycle phase u at which the stance begins (it ends at u = 1; 0: no swing)."""
        raise NotImplementedError

    def stance_speed(self, gait: Gait) -> float:
        """Mean foot speed (m/s) relative to the hip in stance: the stride 2a over the stance
        time; the robot's kinematic walking speed."""
        return 2.0 * gait.a_m / ((1.0 - self.stance_start(gait)) * gait.period_s)

    def clock(self, gait: Gait) -> tuple[float, float]:
        """(frequency Hz, period s) of the path's clock u = f t: the gait's."""
        return gait.frequency_hz, gait.period_s

    def phase(self, gait: Gait, t, phase_rad=0.0) -> np.ndarray:
        """The path's phase u at gait times t (s) of a leg with gait phase phase_rad (rad)."""
        return cycle_phase(gait, t, phase_rad)

    def home(self, gait: Gait) -> np.ndarray:
        """Foot point (2,) m where the feet rest before the path starts: (x_c, y_home)."""
        return np.array([gait.x_center_m, gait.y_home_m])

    def lift_m(self, gait: Gait) -> float:
        """Height (m) of the feet above the ground at t = 0 (a drop's)."""
        return 0.0

    def start_s(self, stand_s: float) -> float:
        """When the path starts (s): after the scenario's standing time."""
        return stand_s

    def events(self, gait: Gait) -> Events:
        """The plan's key times (s from the maneuver's start); none for a periodic path."""
        return Events()

    def span_s(self, gait: Gait) -> float:
        """Time (s) the path takes: a period."""
        return gait.period_s



@jit_uncached
def path_arrays(point, constants, u):
    """point(constants, .) (FootPath.point) at cycle phases u (n,): six arrays (n,) and the
    stance flags (n,)."""
    out, stance = np.empty((6, u.shape[0])), np.empty(u.shape[0], dtype=np.bool_)
    for i in range(u.shape[0]):
        x, y, vx, vy, ax, ay, stance[i] = point(constants, u[i])
        out[0, i], out[1, i], out[2, i], out[3, i], out[4, i], out[5, i] = x, y, vx, vy, ax, ay
    return out[0], out[1], out[2], out[3], out[4], out[5], stance


def evaluate(gait: Gait, path: FootPath | str, t, phase_rad=0.0) -> PathPoints:
    """The path (a FootPath or its kind) at times t (s) for a leg with gait phase phase_rad
    (rad); t and phase_rad broadcast against each other."""
    path = foot_path(path)
    u = path.phase(gait, t, phase_rad)
    flat = np.ascontiguousarray(u, dtype=float).ravel()
    x, y, vx, vy, ax, ay, stance = (v.reshape(u.shape) for v in
                                    path_arrays(path.point, path.constants(gait), flat))
    return PathPoints(pos=np.stack([x, y], -1), vel=np.stack([vx, vy], -1),
                      acc=np.stack([ax, ay], -1), stance=stance)


def stance_weight(gait: Gait, path: FootPath | str, t, phase_rad, transfer_s: float) -> np.ndarray:
    """Scheduled share of a foot in the support (0 swing, 1 stance) at times t (s), rising and
    falling smoothly (smoothstep) over transfer_s (s) after touchdown and before lift-off, so
    the load passes from foot to foot without a step."""
    u = cycle_phase(gait, t, phase_rad)
    flat = np.ascontiguousarray(u, dtype=float).ravel()
    return stance_weight_arrays(flat, foot_path(path).stance_start(gait), gait.period_s,
                                float(transfer_s)).reshape(u.shape)


@jit
def smoothstep(x):
    """0 at x <= 0, 1 at x >= 1, 3 x^2 - 2 x^3 in between (zero slope at both ends)."""
    x = min(max(x, 0.0), 1.0)
    return x * x * (3.0 - 2.0 * x)


@jit
def stance_weight_at(u, u0, period, transfer_s):
    """stance_weight at cycle phase u for a stance from u0 to 1 (period s; u0 = 0: always in
    stance, no touchdown or lift-off)."""
    if u0 <= 0.0:
        return 1.0
    if u < u0:
        return 0.0
    edge = min(u - u0, 1.0 - u) * period           # s from the nearer stance end
    return smoothstep(edge / transfer_s) if transfer_s > 0 else 1.0


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


def shared_loads(stance, weight_N: float, axis: int = 0) -> np.ndarray:
    """Ground load (N) on each foot: the weight shared equally by the feet in stance (stance
    flags, the legs along `axis`; none in a flight phase)."""
    return stance * weight_N / np.maximum(np.sum(stance, axis=axis, keepdims=True), 1)


def stance_loads(gait: Gait, path: FootPath | str, t, phases_rad, weight_N: float) -> np.ndarray:
    """Scheduled ground load (N) on each foot at times t: the weight shared equally by the feet
    the schedule has in stance (shared_loads). Shape (legs, *t.shape)."""
    return shared_loads(np.stack([evaluate(gait, path, t, ph).stance for ph in phases_rad]),
                        weight_N)


REFERENCES_PER_LEG = 7   # the foot references' layout: per leg a target, a velocity and an
#                          acceleration (x, y) each, then its stance weight (reference_parts)


@jit
def reference_parts(references):
    """The foot references (REFERENCES_PER_LEG x legs) as views: targets (legs, 2) m,
    velocities (legs, 2) m/s, accelerations (legs, 2) m/s^2 in the leg planes, stance weights
    (legs,) in [0, 1]."""
    n = references.shape[0] // REFERENCES_PER_LEG
    return (references[:2 * n].reshape(n, 2), references[2 * n:4 * n].reshape(n, 2),
            references[4 * n:6 * n].reshape(n, 2), references[6 * n:])


def references_kernel(point):
    """The compiled foot references of a path's point function (FootPath.point), compiled once
    per process and point function (0.2-0.6 s; not cached on disk, compiled_uncached: its index
    would name the point's module): references(constants, frequency, period, stance_start_u,
    transfer_s, home, phases, start_s, ramp_s, periodic, t) -> the foot references at time t (s)
    as one vector (reference_parts: targets, velocities and accelerations, stance weights of the
    legs); the path point(constants, u) at frequency (Hz) and period (s); not periodic (a
    maneuver): u = frequency t, the weights its stance flags. The point is a global of the
    kernel, not an argument: an argument typed as a function costs ~20 us of typing per call."""
    if point not in _KERNELS:
        _KERNELS[point] = jit_uncached(_references_of(point))
    return _KERNELS[point]


_KERNELS: dict = {}   # references_kernel's, by point function


def _references_of(point):
    """The references function (references_kernel) with `point` bound, uncompiled."""
    def references(constants, frequency, period, stance_start_u, transfer_s, home, phases,
                   start_s, ramp_s, periodic, t):
        n = phases.shape[0]
        out = np.zeros(REFERENCES_PER_LEG * n)
        targets, vel, acc, weights = reference_parts(out)
        weights[:] = 1.0
        tau = t - start_s
        if tau < 0.0:
            targets[:, 0], targets[:, 1] = home[0], home[1]
            return out
        s, ds = (tau / ramp_s, 1.0 / ramp_s) if ramp_s > 0 and tau < ramp_s else (1.0, 0.0)
        for i in range(n):
            u = phase_of(frequency, tau, phases[i]) if periodic else frequency * tau
            x, y, vx, vy, ax, ay, flag = point(constants, u)
            for j, (rel, v, a) in enumerate(((x - home[0], vx, ax), (y - home[1], vy, ay))):
                targets[i, j] = home[j] + s * rel
                vel[i, j] = ds * rel + s * v
                acc[i, j] = 2.0 * ds * v + s * a
            w = (stance_weight_at(u, stance_start_u, period, transfer_s) if periodic
                 else (1.0 if flag else 0.0))
            weights[i] = 1.0 - s * (1.0 - w)
        return out
    return references


@dataclass(frozen=True)
class Gait:
    """Foot path parameters in the leg plane (m): stride half-length a, step height b, centre
    (x_center, y_home), frequency (Hz), samples per cycle for the analysis, the trot path's
    duty factor (fraction of the cycle in stance) and gravity (m/s^2, the robot's, for the
    maneuvers' ballistic flights); see the package's modules for the paths."""

    a_m: float
    b_m: float
    x_center_m: float
    y_home_m: float
    frequency_hz: float
    samples: int
    duty_factor: float
    gravity_m_s2: float = 9.81   # the robot's (config sets robot.gravity_m_s2): ballistic plans

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
        check_number("gait.gravity_m_s2", self.gravity_m_s2, 0.0, MAX_GRAVITY_M_S2, low_open=True)

    @property
    def period_s(self) -> float:
        return 1.0 / self.frequency_hz
