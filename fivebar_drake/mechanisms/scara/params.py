"""The SCARA arm's parameters (data/scara.toml): typed sections, each value checked on load, and
the loader whose errors name the file, the field, the value and the allowed range."""

from __future__ import annotations

import math
from dataclasses import dataclass

from fivebar_drake.core.parameter_files import build_section, check_keys
from fivebar_drake.core.validation import (MIN_PLANT_STEP_S, MAX_GRAVITY_M_S2, MAX_LENGTH_M, MAX_MASS_KG,
                                           MAX_SAMPLES, MAX_SPEED_RAD_S, MAX_TORQUE_NM,
                                           check_number, require)

MAX_DURATION_S = 600.0          # a trajectory segment of ten minutes is no pick-and-place move
MAX_ACCELERATION_M_S2 = 1000.0  # ~100 g: beyond any arm's joint
MAX_SPEED_RPM = 100_000.0
MAX_FORCE_N = 1.0e6
MAX_STRESS_PA = 5.0e9           # above the strongest steels' ultimate strength
MAX_INERTIA_KG_M2 = 100.0
MAX_GAIN_RAD_S = 1000.0         # the plant step must resolve the closed loop


def _positive(field, value, high, **kw):
    return check_number(field, value, 0.0, high, low_open=True, **kw)


def _range(field, pair, low, high, unit):
    require(isinstance(pair, (tuple, list)) and len(pair) == 2, field, pair,
            f"must be [lower, upper] in {unit}")
    lo = check_number(f"{field}[0]", pair[0], low, high)
    hi = check_number(f"{field}[1]", pair[1], low, high)
    require(lo < hi, field, pair, "the lower limit must be below the upper one")
    return lo, hi


def _point(field, point):
    require(isinstance(point, (tuple, list)) and len(point) == 3, field, point,
            "must be [x, y, z] in m")
    return tuple(check_number(f"{field}[{i}]", v, -MAX_LENGTH_M, MAX_LENGTH_M)
                 for i, v in enumerate(point))


@dataclass(frozen=True)
class Kinematics:
    """DH geometry (m) and joint limits: q1, q2 in deg, q3 in m; q3_direction +1 (tool up with
    q3, eq. 2.20 as written) or -1 (tool down); elbow +1 or -1 (sign of q2); the step (deg) of
    the seed's workspace grid."""

    a1_m: float
    a2_m: float
    d1_m: float
    d2_m: float
    q1_limits_deg: tuple
    q2_limits_deg: tuple
    q3_limits_m: tuple
    q3_direction: int
    elbow: int
    seed_grid_step_deg: float

    def __post_init__(self):
        for name in ("a1_m", "a2_m"):
            _positive(f"kinematics.{name}", getattr(self, name), MAX_LENGTH_M)
        for name in ("d1_m", "d2_m"):
            check_number(f"kinematics.{name}", getattr(self, name), -MAX_LENGTH_M, MAX_LENGTH_M)
        _range("kinematics.q1_limits_deg", self.q1_limits_deg, -180.0, 180.0, "deg")
        _range("kinematics.q2_limits_deg", self.q2_limits_deg, -180.0, 180.0, "deg")
        _range("kinematics.q3_limits_m", self.q3_limits_m, -MAX_LENGTH_M, MAX_LENGTH_M, "m")
        _positive("kinematics.seed_grid_step_deg", self.seed_grid_step_deg, 90.0)
        for name in ("q3_direction", "elbow"):
            require(getattr(self, name) in (1, -1) and not isinstance(getattr(self, name), bool),
                    f"kinematics.{name}", getattr(self, name), "must be 1 or -1")


@dataclass(frozen=True)
class Links:
    """Masses (kg) carried by links 1, 2, 3 and the payload at the tool; centres of mass of
    links 1, 2 from their joint axes (m); the inputs of the seed's inertias; gravity (m/s^2)."""

    m1_kg: float
    m2_kg: float
    m3_kg: float
    payload_kg: float
    com1_m: float
    com2_m: float
    link1_body_kg: float
    link2_body_kg: float
    screw_kg: float
    screw_radius_m: float
    gravity_m_s2: float

    def __post_init__(self):
        for name in ("m1_kg", "m2_kg", "m3_kg", "link1_body_kg", "link2_body_kg", "screw_kg"):
            _positive(f"links.{name}", getattr(self, name), MAX_MASS_KG)
        check_number("links.payload_kg", self.payload_kg, 0.0, MAX_MASS_KG)
        for name in ("com1_m", "com2_m", "screw_radius_m"):
            check_number(f"links.{name}", getattr(self, name), 0.0, MAX_LENGTH_M)
        check_number("links.gravity_m_s2", self.gravity_m_s2, 0.0, MAX_GRAVITY_M_S2)
        for body, total in (("link1_body_kg", "m1_kg"), ("link2_body_kg", "m2_kg"),
                            ("screw_kg", "m3_kg")):
            require(getattr(self, body) <= getattr(self, total), f"links.{body}",
                    getattr(self, body), f"must not exceed links.{total} = {getattr(self, total)}")


@dataclass(frozen=True)
class Trajectory:
    """The seed's path: points A, B and circle centre I (m), segment durations (s), samples."""

    a_m: tuple
    b_m: tuple
    center_m: tuple
    line_s: float
    circle_s: float
    return_s: float
    samples_per_s: int

    def __post_init__(self):
        for name in ("a_m", "b_m", "center_m"):
            _point(f"trajectory.{name}", getattr(self, name))
        for name in ("line_s", "circle_s", "return_s"):
            _positive(f"trajectory.{name}", getattr(self, name), MAX_DURATION_S)
        check_number("trajectory.samples_per_s", self.samples_per_s, 10, MAX_SAMPLES,
                     integer=True)
        require(abs(self.b_m[2] - self.center_m[2]) < 1e-12, "trajectory.center_m",
                self.center_m, f"must lie at the height of b_m (z = {self.b_m[2]}): the circle "
                "is horizontal and starts at B")
        require(math.dist(self.b_m, self.center_m) > 0, "trajectory.center_m", self.center_m,
                "must differ from b_m (the circle's radius is |B - I|)")

    @property
    def radius_m(self) -> float:
        return math.dist(self.b_m, self.center_m)

    @property
    def duration_s(self) -> float:
        return self.line_s + self.circle_s + self.return_s


@dataclass(frozen=True)
class Sizing:
    """The seed's drive-sizing inputs (section 2.3.2); units in the names."""

    qd1_rad_s: tuple
    qd2_rad_s: float
    qdd1_rad_s2: float
    qdd2_rad_s2: float
    t_q2_s: float
    n1_rpm: float
    n2_rpm: float
    reducer_efficiency: float
    power_constant: float
    qdd3_m_s2: float
    v3_m_s: float
    screw_starts: int
    screw_lead_m: float
    friction_angle_deg: float
    allowable_stress_Pa: float
    core_diameter_m: float
    ball_diameter_m: float
    groove_radius_m: float
    contact_angle_deg: float
    working_turns: float
    rolling_friction_m: float
    screw_efficiency_factor: float

    def __post_init__(self):
        require(isinstance(self.qd1_rad_s, (tuple, list)) and len(self.qd1_rad_s) > 0,
                "sizing.qd1_rad_s", self.qd1_rad_s, "must be a list of speeds in rad/s")
        for i, v in enumerate(self.qd1_rad_s):
            _positive(f"sizing.qd1_rad_s[{i}]", v, MAX_SPEED_RAD_S)
        _positive("sizing.qd2_rad_s", self.qd2_rad_s, MAX_SPEED_RAD_S)
        for name in ("qdd1_rad_s2", "qdd2_rad_s2", "qdd3_m_s2"):
            _positive(f"sizing.{name}", getattr(self, name), MAX_ACCELERATION_M_S2)
        _positive("sizing.t_q2_s", self.t_q2_s, MAX_DURATION_S)
        for name in ("n1_rpm", "n2_rpm"):
            _positive(f"sizing.{name}", getattr(self, name), MAX_SPEED_RPM)
        for name in ("reducer_efficiency", "screw_efficiency_factor"):
            _positive(f"sizing.{name}", getattr(self, name), 1.0)
        _positive("sizing.power_constant", self.power_constant, 1e6)
        _positive("sizing.v3_m_s", self.v3_m_s, 100.0)
        check_number("sizing.screw_starts", self.screw_starts, 1, 10, integer=True)
        for name in ("screw_lead_m", "core_diameter_m", "ball_diameter_m", "groove_radius_m",
                     "rolling_friction_m"):
            _positive(f"sizing.{name}", getattr(self, name), MAX_LENGTH_M)
        check_number("sizing.friction_angle_deg", self.friction_angle_deg, 0.0, 45.0)
        _positive("sizing.contact_angle_deg", self.contact_angle_deg, 90.0, high_open=True)
        _positive("sizing.allowable_stress_Pa", self.allowable_stress_Pa, MAX_STRESS_PA)
        _positive("sizing.working_turns", self.working_turns, 100.0)
        require(self.groove_radius_m >= self.ball_diameter_m / 2, "sizing.groove_radius_m",
                self.groove_radius_m, f"must be at least half sizing.ball_diameter_m = "
                f"{self.ball_diameter_m} (the ball must fit its groove)")


@dataclass(frozen=True)
class Motors:
    """Sized drives: peak torques of joints 1, 2 (N*m) and the servo speed (rpm) their
    torque-speed lines end at; joint 3's servo (peak N*m, max rpm) and belt ratio (nut/motor)."""

    peak1_Nm: float
    peak2_Nm: float
    servo_max_rpm: float
    motor3_peak_Nm: float
    motor3_max_rpm: float
    belt_ratio: float

    def __post_init__(self):
        for name in ("peak1_Nm", "peak2_Nm", "motor3_peak_Nm"):
            _positive(f"motors.{name}", getattr(self, name), MAX_TORQUE_NM)
        for name in ("servo_max_rpm", "motor3_max_rpm"):
            _positive(f"motors.{name}", getattr(self, name), MAX_SPEED_RPM)
        _positive("motors.belt_ratio", self.belt_ratio, 100.0)


@dataclass(frozen=True)
class Simulation:
    """Drake run: plant step = motor period (s), computed-torque gains (natural frequency rad/s,
    damping ratio), payload carried (kg), tool tracking tolerance (m), pose rate (Hz)."""

    time_step_s: float
    natural_frequency_rad_s: float
    damping_ratio: float
    payload_kg: float
    tracking_tolerance_m: float
    pose_rate_hz: float

    def __post_init__(self):
        check_number("simulation.time_step_s", self.time_step_s, MIN_PLANT_STEP_S, 0.01,
                     why="the motor model samples at this period; nothing in the arm needs a "
                         "finer step")
        _positive("simulation.natural_frequency_rad_s", self.natural_frequency_rad_s,
                  MAX_GAIN_RAD_S)
        require(self.natural_frequency_rad_s * self.time_step_s <= 0.2,
                "simulation.natural_frequency_rad_s", self.natural_frequency_rad_s,
                f"times simulation.time_step_s = {self.time_step_s} must be at most 0.2 (the "
                "discrete loop must resolve the closed-loop response)")
        _positive("simulation.damping_ratio", self.damping_ratio, 10.0)
        check_number("simulation.payload_kg", self.payload_kg, 0.0, MAX_MASS_KG)
        _positive("simulation.tracking_tolerance_m", self.tracking_tolerance_m, MAX_LENGTH_M)
        _positive("simulation.pose_rate_hz", self.pose_rate_hz, 1000.0)


@dataclass(frozen=True)
class ScaraParams:
    kinematics: Kinematics
    links: Links
    trajectory: Trajectory
    sizing: Sizing
    seed_claims: dict
    motors: Motors
    simulation: Simulation
    source: str = "packaged scara.toml"


SECTIONS = {"kinematics": Kinematics, "links": Links, "trajectory": Trajectory,
            "sizing": Sizing, "motors": Motors, "simulation": Simulation}
SEED_CLAIMS = ("tau1_max_Nm", "W1_kW", "tau2_max_Nm", "W2_kW", "Fa_unloaded_N", "Fa_loaded_N",
               "T3_Nm", "n3_rpm", "W3_kW", "d1_min_mm", "Dtb_mm", "gamma_deg", "Zb", "phi_deg",
               "eta_p")


def params_from_dict(data: dict, source: str = "") -> ScaraParams:
    """Validated ScaraParams from the nested dict of a parameter file (ParameterError)."""
    check_keys(data, "file", {*SECTIONS, "seed_claims"})
    check_keys(data["seed_claims"], "seed_claims", SEED_CLAIMS)
    claims = {k: check_number(f"seed_claims.{k}", v, 0.0, MAX_FORCE_N, low_open=True)
              for k, v in data["seed_claims"].items()}
    built = {name: build_section(cls, data[name], name) for name, cls in SECTIONS.items()}
    return ScaraParams(seed_claims=claims, source=source or "packaged scara.toml", **built)
