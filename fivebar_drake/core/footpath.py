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

Each path is a FootPath registered by its kind in PATHS (register_path): its constants (a
NamedTuple, as the compiled code takes it), its compiled point function, where its stance starts;
GaitSource, the Diagram's block, evaluates any of them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple, Optional
import numpy as np
from pydrake.systems.framework import LeafSystem

from fivebar_drake.core.compiled import jit, jit_uncached
from fivebar_drake.core.validation import (MAX_GAIT_FREQUENCY_HZ, MAX_LENGTH_M, MAX_SAMPLES,
                                           check_lengths, check_number)
from fivebar_drake.core.variants import Variant, by_kind, registrar


PATHS: dict[str, type["FootPath"]] = {}   # the foot paths by kind, in registration order
register_path = registrar(PATHS)


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


@dataclass(frozen=True)
class FootPath(Variant):
    """A foot path of the gait parameters (Gait): subclasses set `kind`, `point` (a compiled
    function (constants, u) -> (x, y, vx, vy, ax, ay) in m, m/s, m/s^2 and the stance flag at
    cycle phase u) and `constants` (the NamedTuple `point` takes), and where the stance starts;
    register them with register_path."""

    point: ClassVar = None
    title: ClassVar[str] = ""          # the path in a few words, e.g. "trot foot path"

    def text(self, gait: Gait) -> str:
        """The path in words with its numbers (mm, m/s), for the analysis report."""
        return self.title

    def constants(self, gait: Gait) -> tuple:
        """The NamedTuple of constants `point` takes."""
        raise NotImplementedError

    def stance_start(self, gait: Gait) -> float:
        """Cycle phase u at which the stance begins (it ends at u = 1; 0: no swing)."""
        raise NotImplementedError

    def stance_speed(self, gait: Gait) -> float:
        """Mean foot speed (m/s) relative to the hip in stance: the stride 2a over the stance
        time; the robot's kinematic walking speed."""
        return 2.0 * gait.a_m / ((1.0 - self.stance_start(gait)) * gait.period_s)

    def add_to(self, builder, gait: Gait, phases_rad, start_s: float, ramp_s: float,
               transfer_s: float, period_s: float) -> GaitSource:
        """Add this path's GaitSource (named "gait_source") to the DiagramBuilder."""
        return builder.AddNamedSystem("gait_source", GaitSource(
            gait, self, phases_rad, start_s, ramp_s, transfer_s, period_s))


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
    in s and duty factor beta."""

    a: float
    b: float
    x_center: float
    y_home: float
    period: float
    beta: float


@jit
def trot_point(c, u):
    """Trot path (module docstring; TrotConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in
    m, m/s, m/s^2 and the stance flag. The swing's x is the min-jerk P (0 -> 1) with H and G
    (G(s) = -H(1 - s)) adding the matched end slopes."""
    a, b, x_center, y_home, period, beta = c.a, c.b, c.x_center, c.y_home, c.period, c.beta
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

    def constants(self, gait: Gait) -> DoggoConstants:
        return DoggoConstants(gait.a_m, self.height(gait), self.stance_depth_m, gait.x_center_m,
                              gait.y_home_m, gait.frequency_hz, self.share(gait))

    def stance_start(self, gait: Gait) -> float:
        return self.share(gait)


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
    u = cycle_phase(gait, t, phase_rad)
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
def stance_weight_at(u, u0, period, transfer_s):
    """stance_weight at cycle phase u for a stance from u0 to 1 (period s; u0 = 0: always in
    stance, no touchdown or lift-off)."""
    if u0 <= 0.0:
        return 1.0
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


def stance_loads(gait: Gait, path: FootPath | str, t, phases_rad, weight_N: float) -> np.ndarray:
    """Scheduled ground load (N) on each foot at times t: the weight shared equally by the feet
    the schedule has in stance (none in a flight phase). Shape (legs, *t.shape)."""
    stance = np.stack([evaluate(gait, path, t, ph).stance for ph in phases_rad])
    return stance * weight_N / np.maximum(stance.sum(0), 1)


@jit_uncached
def foot_references(point, constants, frequency, period, stance_start_u, transfer_s, home,
                    phases, start_s, ramp_s, t):
    """The foot references at time t (s) as one vector (7 legs / 2, GaitSource): targets,
    velocities and accelerations (legs x (x, y) each), then stance weights (legs); the path
    point(constants, u) (FootPath.point) at frequency (Hz) and period (s)."""
    n = phases.shape[0]
    out = np.zeros(7 * n)
    targets, vel, acc = (out[:2 * n].reshape(n, 2), out[2 * n:4 * n].reshape(n, 2),
                         out[4 * n:6 * n].reshape(n, 2))
    weights = out[6 * n:]
    weights[:] = 1.0
    tau = t - start_s
    if tau < 0.0:
        targets[:, 0], targets[:, 1] = home[0], home[1]
        return out
    s, ds = (tau / ramp_s, 1.0 / ramp_s) if ramp_s > 0 and tau < ramp_s else (1.0, 0.0)
    for i in range(n):
        u = phase_of(frequency, tau, phases[i])
        x, y, vx, vy, ax, ay, _ = point(constants, u)
        for j, (rel, v, a) in enumerate(((x - home[0], vx, ax), (y - home[1], vy, ay))):
            targets[i, j] = home[j] + s * rel
            vel[i, j] = ds * rel + s * v
            acc[i, j] = 2.0 * ds * v + s * a
        weights[i] = 1.0 - s * (1.0 - stance_weight_at(u, stance_start_u, period, transfer_s))
    return out


class GaitSource(LeafSystem):
    """Time (s) -> foot targets of all legs in their leg planes and the stance schedule,
    sampled every period_s (the controller's period).

    Output port "foot_references" (7 legs / 2): foot targets (legs x (x, y), m), velocities
    (m/s), accelerations (m/s^2), then the stance weights (legs, in [0, 1]).
    The foot path (FootPath.point) with gait time tau = t - start_s, each leg at its phase
    (rad), about the home point (x_c, y_home) scaled by s ramping 0 -> 1 over ramp_s; the
    stance weights blend from all-stance to the schedule with the same s. While standing
    (t < start_s) the feet rest at home, all in stance. The path is known ahead, so at each
    tick t the source stores the values of the next tick: a block sampling it at a tick reads
    the values at that tick, computed once, with no Python on the output port."""

    def __init__(self, gait: Gait, path: FootPath, phases, start_s: float, ramp_s: float,
                 transfer_s: float, period_s: float):
        super().__init__()
        self._args = (path.point, path.constants(gait), gait.frequency_hz, gait.period_s,
                      path.stance_start(gait), float(transfer_s),
                      np.array([gait.x_center_m, gait.y_home_m]),
                      np.asarray(phases, dtype=float), float(start_s), float(ramp_s))
        self._period = period_s
        self._group = self.DeclareDiscreteState(self.references(0.0))
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareStateOutputPort("foot_references", self._group)

    def references(self, t: float) -> np.ndarray:
        """The output port's value at time t (s)."""
        return foot_references(*self._args, float(t))

    def _update(self, context, discrete_state):
        discrete_state.set_value(self._group, self.references(context.get_time() + self._period))


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
