"""Parameters of the leg, robot, gait and motor: typed, immutable, each section validated on
construction. Loading them from TOML and the checks that need the kinematics are in config.py.

All values are SI (m, kg, s, rad, N, N*m), and every key names its unit.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .compiled import jit

LINK_NAMES = ("AC", "BD", "CE", "DE")


class ParameterError(ValueError):
    """A parameter file is malformed or describes something that cannot exist."""


def require(ok: bool, field: str, value, rule: str) -> None:
    if not ok:
        raise ParameterError(f"{field} = {value!r}: {rule}")


def _positive(section: str, obj) -> None:
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, float):
            require(math.isfinite(value) and value > 0, f"{section}.{f.name}", value, "must be > 0")


@dataclass(frozen=True)
class LegGeometry:
    """5-bar leg in its plane (x right, y up, origin between the motors); lengths in m."""

    motor_a_m: tuple[float, float]
    motor_b_m: tuple[float, float]
    ac_m: float
    bd_m: float
    ce_m: float
    de_m: float
    ef_m: float

    def __post_init__(self):
        for name in ("ac_m", "bd_m", "ce_m", "de_m"):
            value = getattr(self, name)
            require(math.isfinite(value) and value > 0, f"leg.{name}", value, "must be > 0")
        require(math.isfinite(self.ef_m) and self.ef_m >= 0, "leg.ef_m", self.ef_m, "must be >= 0")
        for name in ("motor_a_m", "motor_b_m"):
            p = getattr(self, name)
            require(len(p) == 2 and all(math.isfinite(v) for v in p), f"leg.{name}", p,
                     "must be two finite numbers [x, y]")

    @property
    def a(self) -> np.ndarray:
        return np.asarray(self.motor_a_m, dtype=float)

    @property
    def b(self) -> np.ndarray:
        return np.asarray(self.motor_b_m, dtype=float)

    @property
    def core(self) -> tuple[float, ...]:
        """(x_A, y_A, x_B, y_B, AC, BD, CE, DE, EF) in m: the geometry as the compiled kernels
        take it."""
        return tuple(float(v) for v in (*self.motor_a_m, *self.motor_b_m, self.ac_m, self.bd_m,
                                         self.ce_m, self.de_m, self.ef_m))

    def link_length(self, link: str) -> float:
        """Length of a link's rigid body in m; DE carries the foot, so it reaches F."""
        return {"AC": self.ac_m, "BD": self.bd_m, "CE": self.ce_m, "DE": self.de_m + self.ef_m}[link]


@dataclass(frozen=True)
class LinkInertia:
    """Mass (kg), COM distance from the link's first joint along the link (m), Izz about the COM
    with the axis along the hinges (kg*m^2)."""

    mass_kg: float
    com_m: float
    izz_kg_m2: float


@dataclass(frozen=True)
class Robot:
    """Whole-robot masses (kg); the seed's weight share per leg is total/legs."""

    battery_electronics_kg: float
    structure_kg: float
    motors_kg: float
    legs: int
    gravity_m_s2: float

    def __post_init__(self):
        _positive("robot", self)
        require(isinstance(self.legs, int) and self.legs >= 1, "robot.legs", self.legs,
                 "must be an integer >= 1")

    @property
    def total_mass_kg(self) -> float:
        return self.battery_electronics_kg + self.structure_kg + self.motors_kg

    @property
    def weight_share_kg(self) -> float:
        return self.total_mass_kg / self.legs


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
        for name in ("a_m", "b_m"):
            value = getattr(self, name)
            require(math.isfinite(value) and value >= 0, f"gait.{name}", value, "must be >= 0")
        for name in ("x_center_m", "y_home_m"):
            value = getattr(self, name)
            require(math.isfinite(value), f"gait.{name}", value, "must be finite")
        require(math.isfinite(self.frequency_hz) and self.frequency_hz > 0, "gait.frequency_hz",
                 self.frequency_hz, "must be > 0")
        require(isinstance(self.samples, int) and self.samples >= 3, "gait.samples", self.samples,
                 "must be an integer >= 3 (central differences need neighbours)")
        require(math.isfinite(self.duty_factor) and 0.0 < self.duty_factor < 1.0,
                 "gait.duty_factor", self.duty_factor, "must be in (0, 1)")

    @property
    def period_s(self) -> float:
        return 1.0 / self.frequency_hz


@jit
def torque_speed_line(peak_Nm, no_load_rad_s, speed_rad_s):
    """Largest motoring torque (N*m) at a joint speed (rad/s, a number or an array): the linear
    torque-speed line peak (1 - |w| / w_0), zero beyond the no-load speed w_0."""
    return peak_Nm * np.minimum(np.maximum(1.0 - np.abs(speed_rad_s) / no_load_rad_s, 0.0), 1.0)


@dataclass(frozen=True)
class Motor:
    """Geared hip motor, values at the gearbox output: torque N*m, speed rad/s."""

    peak_torque_Nm: float
    gear_ratio: float
    no_load_speed_rad_s: float
    rotor_inertia_kg_m2: float
    coulomb_friction_Nm: float
    viscous_friction_Nm_s: float

    def __post_init__(self):
        for f in ("peak_torque_Nm", "gear_ratio", "no_load_speed_rad_s"):
            value = getattr(self, f)
            require(math.isfinite(value) and value > 0, f"motor.{f}", value, "must be > 0")
        for f in ("rotor_inertia_kg_m2", "coulomb_friction_Nm", "viscous_friction_Nm_s"):
            value = getattr(self, f)
            require(math.isfinite(value) and value >= 0, f"motor.{f}", value, "must be >= 0")

    def torque_limit(self, speed_rad_s):
        """Largest motoring torque (N*m) at joint speeds (rad/s, array): torque_speed_line."""
        return torque_speed_line(self.peak_torque_Nm, self.no_load_speed_rad_s,
                                 np.asarray(speed_rad_s, dtype=float))

    @property
    def reflected_inertia_kg_m2(self) -> float:
        """Rotor inertia seen at the output, N^2 J_rotor."""
        return self.gear_ratio**2 * self.rotor_inertia_kg_m2


@dataclass(frozen=True)
class Body:
    """Body box (m), hip placement of the leg planes (m), link width (m), foot sphere radius (m),
    its friction coefficient, contact stiffness (N/m) and dissipation time scale (s).
    Assumptions: the seeds give no body dimensions."""

    length_m: float
    width_m: float
    height_m: float
    hip_x_m: float
    hip_y_m: float
    hip_z_m: float
    link_width_m: float
    foot_radius_m: float
    foot_friction: float
    foot_stiffness_N_m: float
    foot_relaxation_time_s: float

    def __post_init__(self):
        for f in dataclasses.fields(self):
            if f.name != "hip_z_m":
                value = getattr(self, f.name)
                require(math.isfinite(value) and value > 0, f"body.{f.name}", value, "must be > 0")


@dataclass(frozen=True)
class Checks:
    """Safety-factor verdict thresholds: SF >= sf_pass passes, SF >= sf_warn warns, else fails."""

    sf_pass: float
    sf_warn: float

    def __post_init__(self):
        _positive("checks", self)
        require(self.sf_warn <= self.sf_pass, "checks.sf_warn", self.sf_warn,
                 f"must be <= checks.sf_pass = {self.sf_pass}")


@dataclass(frozen=True)
class Params:
    leg: LegGeometry
    links: dict[str, LinkInertia]
    robot: Robot
    gait: Gait
    motor: Motor
    checks: Checks
    body: Body

    def __post_init__(self):
        require(sorted(self.links) == sorted(LINK_NAMES), "links", sorted(self.links),
                 f"must be exactly {list(LINK_NAMES)}")
        for name, link in self.links.items():
            length = self.leg.link_length(name)
            field = f"links.{name}"
            require(math.isfinite(link.mass_kg) and link.mass_kg > 0, f"{field}.mass_kg",
                     link.mass_kg, "must be > 0")
            require(0 <= link.com_m <= length, f"{field}.com_m", link.com_m,
                     f"COM outside its link: allowed 0 .. {length} m")
            # A body whose mass lies on the segment [0, L] with COM at c has Izz <= m c (L - c).
            bound = link.mass_kg * link.com_m * (length - link.com_m)
            require(math.isfinite(link.izz_kg_m2) and 0 <= link.izz_kg_m2 <= bound,
                     f"{field}.izz_kg_m2", link.izz_kg_m2,
                     f"cannot be physical: allowed 0 .. m*c*(L-c) = {bound:.3g} kg*m^2")
