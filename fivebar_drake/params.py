"""Parameters of the leg, robot, gait and motor: typed, immutable, each section validated on
construction. Loading them from TOML and the checks that need the kinematics are in config.py.

All values are SI (m, kg, s, rad, N, N*m), and every key names its unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .compiled import jit

LINK_NAMES = ("AC", "BD", "CE", "DE")
LEGS_BUILT = 4   # the simulation builds a quadruped (sdf_model.LEGS): robot.legs must say so

# Bounds of the values of a parameter file (SI). Each lies far outside any design this tool is
# for (a ~7 kg quadruped with ~0.3 m legs) and is there to catch a slip, such as millimetres
# written as metres or grams as kilograms, before it turns into a result that looks valid.
MAX_LENGTH_M = 2.0              # any length or coordinate: "105" for 0.105 m is refused
MAX_MASS_KG = 500.0             # any mass: "6700" (grams) for the 6.7 kg robot is refused
MAX_GRAVITY_M_S2 = 30.0         # the largest surface gravity in the solar system is 24.8 (Jupiter)
MAX_GAIT_FREQUENCY_HZ = 10.0    # small quadrupeds trot at 1-5 Hz; no hip motor of the kind follows 10
MAX_SAMPLES = 10_000            # per cycle: central differences are exact to ~1e-7 of the peaks long
#                                 before; the IK mode tracking costs ~10 us per sample in Python
MAX_TORQUE_NM = 1000.0          # hip motors of legged robots this size give well under 100 N m
MAX_GEAR_RATIO = 1000.0         # the largest harmonic drives are ~160:1
MAX_SPEED_RAD_S = 10_000.0      # ~95 000 RPM at the output: beyond any motor
MAX_ROTOR_INERTIA_KG_M2 = 1.0   # a small outrunner's rotor is ~1e-6 kg m^2
MAX_FRICTION_COEFFICIENT = 5.0  # rubber on rough ground is 1-2
MAX_CONTACT_STIFFNESS_N_M = 1e9  # a steel ball on steel is ~1e8-1e9 N/m
MAX_RELAXATION_TIME_S = 1.0     # a foot pad still dissipating a second after touchdown is no foot
MAX_SAFETY_FACTOR = 100.0       # a verdict threshold beyond this can never pass


class ParameterError(ValueError):
    """Bad input: a parameter or scenario file, a command-line value or an output path that is
    malformed or describes something that cannot exist. Its text names the source (a file, the
    command line), the field (dotted path), the value and what is allowed."""

    def __init__(self, message: str, field: str = "", source: str = ""):
        super().__init__(message)
        self.message, self.field, self.source = message, field, source

    def __str__(self) -> str:
        return f"{self.source}: {self.message}" if self.source else self.message

    def located(self, source) -> "ParameterError":
        """The same error with its source (a file, "command line"), unless it has one."""
        return self if self.source else ParameterError(self.message, self.field, str(source))


def require(ok: bool, field: str, value, rule: str) -> None:
    """ParameterError "field = value: rule" unless ok."""
    if not ok:
        raise ParameterError(f"{field} = {value!r}: {rule}", field)


def check_number(field: str, value, low=-math.inf, high=math.inf, *, low_open=False,
                 high_open=False, integer=False, why: str = ""):
    """value as a float (an int if integer) if it is a finite number within low .. high (the
    ends included unless *_open); else ParameterError naming the field, the value and the
    allowed range (and why, if given). Booleans are not numbers."""
    numeric = isinstance(value, int) if integer else isinstance(value, (int, float))
    require(numeric and not isinstance(value, bool), field, value,
            "must be an integer" if integer else "must be a number")
    try:
        finite = math.isfinite(value)
    except OverflowError:          # an integer beyond any float
        finite = False
    inside = (finite and (value > low if low_open else value >= low)
              and (value < high if high_open else value <= high))
    if not inside:
        kind = "an integer " if integer else "" if finite else "a finite number "
        if low == high:
            kind, allowed = "", f"{low:g}"
        elif math.isfinite(low) and math.isfinite(high):
            allowed = (f"in {'(' if low_open else '['}{low:g}, {high:g}"
                       f"{')' if high_open else ']'}")
        elif math.isfinite(low):
            allowed = f"{'>' if low_open else '>='} {low:g}"
        elif math.isfinite(high):
            allowed = f"{'<' if high_open else '<='} {high:g}"
        else:
            kind, allowed = "a finite number", ""
        require(False, field, value, f"must be {kind}{allowed}".rstrip()
                + (f" ({why})" if why else ""))
    return int(value) if integer else float(value)


def _lengths(section: str, obj, names, low_open=True) -> None:
    for name in names:
        check_number(f"{section}.{name}", getattr(obj, name), 0.0, MAX_LENGTH_M, low_open=low_open)


def _point(field: str, point) -> None:
    require(isinstance(point, (tuple, list)) and len(point) == 2, field, point, "must be [x, y] in m")
    for i, v in enumerate(point):
        check_number(f"{field}[{i}]", v, -MAX_LENGTH_M, MAX_LENGTH_M)


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
        _lengths("leg", self, ("ac_m", "bd_m", "ce_m", "de_m"))
        _lengths("leg", self, ("ef_m",), low_open=False)
        for name in ("motor_a_m", "motor_b_m"):
            _point(f"leg.{name}", getattr(self, name))

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
        for name in ("battery_electronics_kg", "structure_kg", "motors_kg"):
            check_number(f"robot.{name}", getattr(self, name), 0.0, MAX_MASS_KG, low_open=True)
        check_number("robot.gravity_m_s2", self.gravity_m_s2, 0.0, MAX_GRAVITY_M_S2,
                     low_open=True)
        check_number("robot.legs", self.legs, LEGS_BUILT, LEGS_BUILT, integer=True,
                     why="the simulation builds a quadruped; the weight share is total / legs")

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
        _lengths("gait", self, ("a_m", "b_m"), low_open=False)
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
        for name, high in (("peak_torque_Nm", MAX_TORQUE_NM), ("gear_ratio", MAX_GEAR_RATIO),
                           ("no_load_speed_rad_s", MAX_SPEED_RAD_S)):
            check_number(f"motor.{name}", getattr(self, name), 0.0, high, low_open=True)
        check_number("motor.rotor_inertia_kg_m2", self.rotor_inertia_kg_m2, 0.0,
                     MAX_ROTOR_INERTIA_KG_M2)
        check_number("motor.coulomb_friction_Nm", self.coulomb_friction_Nm, 0.0, MAX_TORQUE_NM)
        check_number("motor.viscous_friction_Nm_s", self.viscous_friction_Nm_s, 0.0, MAX_TORQUE_NM)
        at_speed = self.coulomb_friction_Nm + self.viscous_friction_Nm_s * self.no_load_speed_rad_s
        require(at_speed < self.peak_torque_Nm, "motor.coulomb_friction_Nm",
                self.coulomb_friction_Nm, f"with viscous_friction_Nm_s the friction at the no-load "
                f"speed is {at_speed:g} N m, not below peak_torque_Nm = {self.peak_torque_Nm:g}: "
                "the motor could not turn")

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
        _lengths("body", self, ("length_m", "width_m", "height_m", "hip_x_m", "hip_y_m",
                                "link_width_m", "foot_radius_m"))
        check_number("body.hip_z_m", self.hip_z_m, -MAX_LENGTH_M, MAX_LENGTH_M)
        check_number("body.foot_friction", self.foot_friction, 0.0, MAX_FRICTION_COEFFICIENT,
                     low_open=True)
        check_number("body.foot_stiffness_N_m", self.foot_stiffness_N_m, 0.0,
                     MAX_CONTACT_STIFFNESS_N_M, low_open=True)
        check_number("body.foot_relaxation_time_s", self.foot_relaxation_time_s, 0.0,
                     MAX_RELAXATION_TIME_S, low_open=True)


@dataclass(frozen=True)
class Checks:
    """Safety-factor verdict thresholds: SF >= sf_pass passes, SF >= sf_warn warns, else fails."""

    sf_pass: float
    sf_warn: float

    def __post_init__(self):
        for name in ("sf_pass", "sf_warn"):
            check_number(f"checks.{name}", getattr(self, name), 0.0, MAX_SAFETY_FACTOR,
                         low_open=True)
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
            check_number(f"{field}.mass_kg", link.mass_kg, 0.0, MAX_MASS_KG, low_open=True)
            check_number(f"{field}.com_m", link.com_m, 0.0, length,
                         why="the COM lies on its link")
            # A body whose mass lies on the segment [0, L] with COM at c has Izz <= m c (L - c).
            bound = link.mass_kg * link.com_m * (length - link.com_m)
            check_number(f"{field}.izz_kg_m2", link.izz_kg_m2, 0.0, bound,
                         why="cannot be physical beyond m*c*(L-c), L the link's length, c its COM")
        links_kg = LEGS_BUILT * sum(link.mass_kg for link in self.links.values())
        carried = self.robot.battery_electronics_kg + self.robot.structure_kg
        require(links_kg < carried, "links.*.mass_kg", links_kg,
                f"the {LEGS_BUILT} legs' links ({links_kg:.3f} kg) must weigh less than "
                f"robot.battery_electronics_kg + robot.structure_kg = {carried:.3f} kg, which "
                "include them")
        self._check_start_pose()

    def _check_start_pose(self) -> None:
        """The robot starts standing on its feet: the foot path stays below the hips, and the
        body's underside is above the ground."""
        g, b = self.gait, self.body
        hips_y = min(self.leg.motor_a_m[1], self.leg.motor_b_m[1])
        require(g.y_home_m + g.b_m < hips_y, "gait.y_home_m", g.y_home_m,
                f"the feet must stay below the hips: y_home_m + b_m = {g.y_home_m + g.b_m:g} m "
                f"must be < {hips_y:g} m (the motors' height in the leg plane)")
        clearance = b.foot_radius_m - b.hip_z_m - g.y_home_m - b.height_m / 2
        require(clearance > 0, "body.hip_z_m", b.hip_z_m,
                f"the body starts {-clearance:.3g} m below the ground (standing on feet at "
                f"gait.y_home_m = {g.y_home_m:g} m, its underside is at body.foot_radius_m - "
                "hip_z_m - y_home_m - height_m/2): lower the feet or the hips")
