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

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar, NamedTuple, Optional
import numpy as np

from fivebar_drake.core.checks import Checks
from fivebar_drake.core.compiled import jit, jit_uncached
from fivebar_drake.core.validation import (MAX_GAIT_FREQUENCY_HZ, MAX_GRAVITY_M_S2,
                                           MAX_LENGTH_M, MAX_SAMPLES, UNIT_SUFFIXES,
                                           check_lengths, check_number, unit_of)
from fivebar_drake.core.variants import Variant, by_kind, registrar


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
        """Why a run did not do this path's motion (none if it did; core/verdicts.achievement
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


class EllipseConstants(NamedTuple):
    """The seed ellipse's semi-axes a, b and centre (x_center, y_home) in m, frequency in Hz."""

    a: float
    b: float
    x_center: float
    y_home: float
    frequency: float


@jit
def ellipse_point(c, u):
    """Seed ellipse (EllipseConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in m, m/s,
    m/s^2 and the stance flag."""
    w = 2.0 * np.pi * c.frequency
    cu, su = np.cos(2.0 * np.pi * u), np.sin(2.0 * np.pi * u)
    return (c.x_center + c.a * cu, c.y_home + c.b * su, -c.a * w * su, c.b * w * cu,
            -c.a * w * w * cu, -c.b * w * w * su, su < 0.0)


@register_path
@dataclass(frozen=True)
class SeedEllipse(FootPath):
    """The seed's ellipse (module docstring): the lower half is the stance."""

    kind: ClassVar[str] = "seed_ellipse"
    point: ClassVar = staticmethod(ellipse_point)
    title: ClassVar[str] = "seed's elliptical gait"

    def text(self, gait: Gait) -> str:
        g = gait
        return (f"the seed's ellipse x = {g.x_center_m * 1e3:g} + {g.a_m * 1e3:g} cos(wt) mm, "
                f"y = {g.y_home_m * 1e3:g} + {g.b_m * 1e3:g} sin(wt) mm")

    def constants(self, gait: Gait) -> EllipseConstants:
        return EllipseConstants(gait.a_m, gait.b_m, gait.x_center_m, gait.y_home_m,
                                gait.frequency_hz)

    def stance_start(self, gait: Gait) -> float:
        return 0.5


@jit
def _quintic_h(r):
    """H (unit start slope, zero end slope, zero second derivative at both ends) and its first
    and second derivatives at r."""
    return (r - 6 * r**3 + 8 * r**4 - 3 * r**5, 1 - 18 * r**2 + 32 * r**3 - 15 * r**4,
            -36 * r + 96 * r**2 - 60 * r**3)


class TrotConstants(NamedTuple):
    """The trot path's stride half-length a, lift b and centre (x_center, y_home) in m, period
    in s, duty factor beta and stance dip (m; the pronk's, 0 for a flat stance)."""

    a: float
    b: float
    x_center: float
    y_home: float
    period: float
    beta: float
    dip: float = 0.0


@jit
def trot_point(c, u):
    """Trot path (module docstring; TrotConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in
    m, m/s, m/s^2 and the stance flag. The swing's x is the min-jerk P (0 -> 1) with H and G
    (G(s) = -H(1 - s)) adding the matched end slopes."""
    a, b, x_center, y_home, period, beta = c.a, c.b, c.x_center, c.y_home, c.period, c.beta
    v = 2.0 * a / (beta * period)
    w = np.pi / (beta * period)             # the dip's rate: A sin(w t) over the stance
    if u >= 1.0 - beta:                     # stance: flat (or dipping), at constant speed
        sigma = min(max((u - (1.0 - beta)) / beta, 0.0), 1.0)
        sn, cs = np.sin(np.pi * sigma), np.cos(np.pi * sigma)
        return ((-a + 2 * a * sigma) + x_center, y_home + c.dip * sn, v, c.dip * w * cs, 0.0,
                -c.dip * w * w * sn, True)
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
    # the dip's vertical speed -A w at lift-off and +A w at touchdown, matched by H and G
    vd = -c.dip * w * t_sw
    return (a - 2 * a * p + v * t_sw * hg + x_center, y_home + b * bump + vd * (h0 + h1),
            (-2 * a * dp + v * t_sw * dhg) / t_sw, b * dbump + vd * (dh0 - dh1) / t_sw,
            (-2 * a * ddp + v * t_sw * ddhg) / t_sw**2, b * ddbump + vd * (ddh0 + ddh1) / t_sw**2,
            False)


@register_path
@dataclass(frozen=True)
class Trot(FootPath):
    """The trot path (module docstring); duty_factor: its fraction of the cycle in stance
    (None: the parameter file's gait.duty_factor)."""

    kind: ClassVar[str] = "trot"
    point: ClassVar = staticmethod(trot_point)
    title: ClassVar[str] = "trot foot path"
    duty_factor: Optional[float] = None

    def text(self, gait: Gait) -> str:
        g = gait
        return (f"the trot path (core/footpath.py): stance flat at y = {g.y_home_m * 1e3:g} mm "
                f"over the stride 2a = {2 * g.a_m * 1e3:g} mm at {self.stance_speed(g):.3f} m/s, "
                f"duty factor {self.beta(g):g} (stance fraction of the cycle), swing lifting the "
                f"foot by b = {g.b_m * 1e3:g} mm with matched touchdown speed")

    def beta(self, gait: Gait) -> float:
        """The duty factor: this path's, or the parameter file's."""
        return gait.duty_factor if self.duty_factor is None else self.duty_factor

    def gait_fields(self) -> tuple[str, ...]:
        """The periodic path's, and gait.duty_factor unless the path has its own."""
        return super().gait_fields() + (("duty_factor",) if self.duty_factor is None else ())

    def check(self, field: str) -> None:
        if self.duty_factor is not None:
            check_number(f"{field}.duty_factor", self.duty_factor, 0.0, 1.0, low_open=True,
                         high_open=True)

    def constants(self, gait: Gait) -> TrotConstants:
        return TrotConstants(gait.a_m, gait.b_m, gait.x_center_m, gait.y_home_m, gait.period_s,
                             self.beta(gait))

    def stance_start(self, gait: Gait) -> float:
        return 1.0 - self.beta(gait)

    def stance_speed(self, gait: Gait) -> float:
        return 2.0 * gait.a_m / (self.beta(gait) * gait.period_s)


@register_path
@dataclass(frozen=True)
class Walk(Trot):
    """A statically stable crawl: the trot path, one leg at a time (rear left, front left, rear
    right, front right, a quarter cycle apart), duty factor >= 0.75 so three or four feet are
    always down."""

    kind: ClassVar[str] = "walk"
    title: ClassVar[str] = "crawl (one leg at a time)"
    gait_defaults: ClassVar[dict] = {"frequency_hz": 0.5}
    order: ClassVar[tuple] = ("RL", "FL", "RR", "FR")   # each lifts off at f t = 1 - phase / 2 pi
    duty_factor: Optional[float] = 0.8

    def leg_phase(self, leg: str) -> float:
        return float(np.mod(-2.0 * math.pi * self.order.index(leg) / 4.0, 2.0 * math.pi))

    def check(self, field: str) -> None:
        check_number(f"{field}.duty_factor", self.duty_factor, MIN_CRAWL_DUTY, 1.0,
                     high_open=True, why="a crawl keeps three feet down: one leg swings at a time")


@register_path
@dataclass(frozen=True)
class Bound(Trot):
    """A bound: the trot path with the front pair and the rear pair half a cycle apart."""

    kind: ClassVar[str] = "bound"
    title: ClassVar[str] = "bound (front pair, rear pair)"
    gait_defaults: ClassVar[dict] = {"frequency_hz": 2.0, "a_m": 0.03}
    duty_factor: Optional[float] = 0.75

    def leg_phase(self, leg: str) -> float:
        return 0.0 if leg[0] == "F" else math.pi


@register_path
@dataclass(frozen=True)
class Pronk(Trot):
    """A pronk: all four legs together; in stance the foot rises
    by dip_m sin(pi sigma) towards the hip (the body dips and is pushed back up), leaving at the
    vertical speed pi dip_m / T_stance, so the body flies 2 pi dip_m / (g T_stance) s: the
    default dip, 36 mm, gives the 0.1 s flight of the default 3 Hz, duty 0.7 (g = 9.81 m/s^2);
    choose dip_m = g (1 - beta) beta T^2 / (2 pi) for another."""

    kind: ClassVar[str] = "pronk"
    title: ClassVar[str] = "pronk (all four legs together)"
    # all four land together: a pair down before its schedule is the body's pitch, not an
    # early step, and freezing it made the gait flip between two patterns with the plant step
    # (issue 39: the heavy-rotor designs' pronk not achieved at 1 ms, achieved at 0.5 ms)
    early_touchdown: ClassVar[bool] = False
    gait_defaults: ClassVar[dict] = {"frequency_hz": 3.0, "a_m": 0.03, "b_m": 0.015}
    duty_factor: Optional[float] = 0.7
    dip_m: float = 0.0364

    def leg_phase(self, leg: str) -> float:
        return 0.0

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.dip_m", self.dip_m, 0.0, MAX_LENGTH_M)

    def constants(self, gait: Gait) -> TrotConstants:
        return super().constants(gait)._replace(dip=self.dip_m)


class DoggoConstants(NamedTuple):
    """The Doggo-style path's stride half-length a, flight height h, stance depth d and centre
    (x_center, y_home) in m, frequency in Hz and flight share (fraction of the cycle)."""

    a: float
    h: float
    d: float
    x_center: float
    y_home: float
    frequency: float
    flight: float


@jit
def doggo_point(c, u):
    """Doggo-style path (DoggoConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in m, m/s,
    m/s^2 and the stance flag. Flight (u < flight): x from x_c + a to x_c - a at constant speed,
    y = y_home + h sin(pi s); stance: back from x_c - a to x_c + a, y = y_home - d sin(pi s)
    (s: the fraction of the flight or the stance), as Stanford Doggo's sinusoidal gait; the
    foot's speed jumps at lift-off and touchdown."""
    if u < c.flight:
        rate = c.frequency / c.flight                   # ds/dt
        s = u / c.flight
        sn, cs = np.sin(np.pi * s), np.cos(np.pi * s)
        return (c.x_center + c.a - 2.0 * c.a * s, c.y_home + c.h * sn, -2.0 * c.a * rate,
                c.h * np.pi * cs * rate, 0.0, -c.h * np.pi**2 * sn * rate**2, False)
    rate = c.frequency / (1.0 - c.flight)
    s = (u - c.flight) / (1.0 - c.flight)
    sn, cs = np.sin(np.pi * s), np.cos(np.pi * s)
    return (c.x_center - c.a + 2.0 * c.a * s, c.y_home - c.d * sn, 2.0 * c.a * rate,
            -c.d * np.pi * cs * rate, 0.0, c.d * np.pi**2 * sn * rate**2, True)


@register_path
@dataclass(frozen=True)
class Doggo(FootPath):
    """Stanford Doggo's sinusoidal foot path (its firmware's trajectory, in this package's
    frame): a half sine up in flight, a half sine down in stance, straight at constant speed
    along x in each. flight_height_m (None: gait.b_m), stance_depth_m (m, the foot pressed below
    the ground line mid-stance; 0: flat), flight_share (None: 1 - gait.duty_factor)."""

    kind: ClassVar[str] = "doggo"
    point: ClassVar = staticmethod(doggo_point)
    title: ClassVar[str] = "Doggo-style sinusoidal foot path"
    flight_height_m: Optional[float] = None
    stance_depth_m: float = 0.0
    flight_share: Optional[float] = None

    def text(self, gait: Gait) -> str:
        return (f"a Doggo-style path: flight {self.share(gait):.0%} of the cycle lifting the foot "
                f"{self.height(gait) * 1e3:g} mm (half sine), stance pressing it "
                f"{self.stance_depth_m * 1e3:g} mm below y = {gait.y_home_m * 1e3:g} mm (half "
                f"sine), stride 2a = {2 * gait.a_m * 1e3:g} mm at {self.stance_speed(gait):.3f} "
                "m/s in stance")

    def height(self, gait: Gait) -> float:
        return gait.b_m if self.flight_height_m is None else self.flight_height_m

    def share(self, gait: Gait) -> float:
        return 1.0 - gait.duty_factor if self.flight_share is None else self.flight_share

    def check(self, field: str) -> None:
        for name in ("flight_height_m", "stance_depth_m"):
            if getattr(self, name) is not None:
                check_number(f"{field}.{name}", getattr(self, name), 0.0, MAX_LENGTH_M)
        if self.flight_share is not None:
            check_number(f"{field}.flight_share", self.flight_share, 0.0, 1.0, low_open=True,
                         high_open=True)

    def gait_fields(self) -> tuple[str, ...]:
        return super().gait_fields() + (("duty_factor",) if self.flight_share is None else ())

    def constants(self, gait: Gait) -> DoggoConstants:
        return DoggoConstants(gait.a_m, self.height(gait), self.stance_depth_m, gait.x_center_m,
                              gait.y_home_m, gait.frequency_hz, self.share(gait))

    def stance_start(self, gait: Gait) -> float:
        return self.share(gait)


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


@register_path
@dataclass(frozen=True)
class Jump(Landing):
    """A vertical jump of all four legs: crouch crouch_m above the standing line over crouch_s,
    hold hold_s, push off (the foot's quintic from rest to the takeoff speed at extension_m below
    the standing line over push_share of 2 stroke / v: at 1, peak acceleration 0.75 v^2 /
    stroke; an optimal push, which the tracking controller follows, is shorter), fly (the legs'
    extension stopped
    within EXTENSION_STOP_S, the feet tucked retract_m and reaching down at 0.1 m/s to land),
    land (Landing). The takeoff speed puts the body's apex
    height_m above its standing height: v = sqrt(2 g (height_m - extension_m))."""

    pushes: ClassVar[bool] = True
    kind: ClassVar[str] = "jump"
    title: ClassVar[str] = "vertical jump"
    height_m: float = 0.06
    crouch_m: float = 0.06
    crouch_s: float = 0.4
    hold_s: float = 0.2
    retract_m: float = 0.02
    push_share: float = 1.0

    def shortfalls(self, gait: Gait, outcome: Outcome, checks: Checks) -> list[str]:
        """A jump leaves the ground with every foot, its body's apex rises at least
        checks.achieved_height_fraction of height_m above standing, and it ends standing
        (Maneuver)."""
        m = outcome.maneuver
        jump = None if m is None else m["jump"]
        if jump is None:
            missed = ["no foot left the ground" + (f" ({m['why_grounded']})" if m else "")]
        elif not jump["height_m"] >= checks.achieved_height_fraction * self.height_m:
            missed = [f"it rose {jump['height_m'] * 1e3:.1f} mm, less than "
                      f"{checks.achieved_height_fraction:.0%} of the planned "
                      f"{self.height_m * 1e3:.1f} mm"]
        else:
            missed = []
        return missed + super().shortfalls(gait, outcome, checks)

    def takeoff_speed(self, gait: Gait) -> float:
        """Planned takeoff speed (m/s) of the body."""
        return math.sqrt(2.0 * gait.gravity_m_s2 * max(self.height_m - self.extension_m, 0.0))

    def touchdown_speed(self, gait: Gait) -> float:
        """The body lands at its takeoff height, at its takeoff speed (m/s)."""
        return self.takeoff_speed(gait)

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.crouch_m", self.crouch_m, 0.0 - self.extension_m, MAX_LENGTH_M,
                     low_open=True, why="the push-off's stroke is crouch_m + extension_m: none "
                                        "would push in no distance")
        check_number(f"{field}.height_m", self.height_m, self.extension_m, MAX_LENGTH_M,
                     low_open=True, why=f"the apex lies above the takeoff height "
                                        f"(extension_m = {self.extension_m:g} m)")
        check_number(f"{field}.push_share", self.push_share, *PUSH_SHARES, low_open=True,
                     why="the push's time over 2 stroke / takeoff speed: at 0.5 the whole "
                         "stroke at the takeoff speed; beyond 1.25 the foot's quintic "
                         "reverses")

    def timing(self, gait: Gait) -> tuple[float, float, float]:
        """(push-off s, flight s, takeoff speed m/s) of the plan: the body lands at its takeoff
        height."""
        v = self.takeoff_speed(gait)
        return (2.0 * self.push_share * (self.crouch_m + self.extension_m) / v,
                2.0 * v / gait.gravity_m_s2, v)

    def segments(self, gait: Gait) -> list[tuple]:
        x, y0 = gait.x_center_m, gait.y_home_m
        push, flight, v = self.timing(gait)
        crouch, takeoff = (x, y0 + self.crouch_m), (x, y0 - self.extension_m)
        tucked = (x, takeoff[1] + self.retract_m)
        stopped = (x, takeoff[1] - v * EXTENSION_STOP_S / 2)     # the extension, stopped
        return [move(self.crouch_s, True, (x, y0), crouch), hold(self.hold_s, True, crouch),
                (push, True, (x, *REST, x, *REST),
                 (crouch[1], 0.0, 0.0, takeoff[1], -v, 0.0)),
                move(EXTENSION_STOP_S, False, takeoff, stopped, (-v, 0.0)),
                move(flight / 2 - EXTENSION_STOP_S, False, stopped, tucked),
                move(flight / 2, False, tucked, takeoff, (0.0, -REACH_SPEED_M_S)),
                ] + self.landing(gait, v)

    def events(self, gait: Gait) -> Events:
        push, flight, _ = self.timing(gait)
        onset = self.crouch_s + self.hold_s
        return Events(onset=onset, takeoff=onset + push, touchdown=onset + push + flight)


@register_path
@dataclass(frozen=True)
class Drop(Landing):
    """A drop: the robot starts at rest with its feet height_m above the ground, legs extended
    extension_m below the standing line, falls and lands (Landing) at sqrt(2 g height_m)."""

    kind: ClassVar[str] = "drop"
    title: ClassVar[str] = "drop onto the feet"
    stand_first: ClassVar[bool] = False
    height_m: float = 0.1
    extension_m: float = 0.04
    landing_stroke_m: float = 0.08

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.height_m", self.height_m, 0.0, MAX_LENGTH_M, low_open=True,
                     why="a drop from no height is no landing (and its touchdown speed, 0, "
                         "divides the landing's time)")

    def lift_m(self, gait: Gait) -> float:
        return self.height_m

    def touchdown_speed(self, gait: Gait) -> float:
        """sqrt(2 g height_m) (m/s)."""
        return math.sqrt(2.0 * gait.gravity_m_s2 * self.height_m)

    def segments(self, gait: Gait) -> list[tuple]:
        g = gait.gravity_m_s2
        foot = (gait.x_center_m, gait.y_home_m - self.extension_m)
        return ([hold(math.sqrt(2.0 * self.height_m / g), False, foot)]
                + self.landing(gait, self.touchdown_speed(gait)))

    def events(self, gait: Gait) -> Events:
        return Events(touchdown=math.sqrt(2.0 * self.height_m / gait.gravity_m_s2))


@register_path
@dataclass(frozen=True)
class StandUp(Maneuver):
    """Standing up from lying on the belly: the feet start folded at (fold_x_m, fold_y_m) (the
    default: 150 mm behind the hips, 28 mm below them, on the ground when the default body lies
    on its belly) and move in a straight line to the standing point over rise_s, all in stance,
    then hold it settle_s."""

    kind: ClassVar[str] = "stand_up"
    title: ClassVar[str] = "stand up from lying"
    fold_x_m: float = 0.15
    fold_y_m: float = -0.028
    rise_s: float = 1.5
    settle_s: float = 0.5

    def check(self, field: str) -> None:
        check_number(f"{field}.fold_x_m", self.fold_x_m, -MAX_LENGTH_M, MAX_LENGTH_M)
        check_number(f"{field}.fold_y_m", self.fold_y_m, -MAX_LENGTH_M, MAX_LENGTH_M)
        for name in ("rise_s", "settle_s"):
            check_number(f"{field}.{name}", getattr(self, name), 0.0, MAX_MANEUVER_S,
                         low_open=True)

    def segments(self, gait: Gait) -> list[tuple]:
        home = (gait.x_center_m, gait.y_home_m)
        return [move(self.rise_s, True, (self.fold_x_m, self.fold_y_m), home),
                hold(self.settle_s, True, home)]


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
    maneuvers' ballistic flights); see footpath.py for the paths."""

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
