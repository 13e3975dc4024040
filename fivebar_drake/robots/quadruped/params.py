"""The quadruped's parameter file as typed, immutable, validated sections (SI units, every key names
its unit); loading it from TOML is in config.py."""

from __future__ import annotations

from dataclasses import dataclass, field

from fivebar_drake.verdicts.checks import Checks
from fivebar_drake.gaits import Gait
from fivebar_drake.actuators.motor import THERMAL_FIELDS, BldcMotor
from fivebar_drake.core.validation import (MAX_CONTACT_STIFFNESS_N_M, MAX_FRICTION_COEFFICIENT,
                                           MAX_GRAVITY_M_S2, MAX_LENGTH_M, MAX_MASS_KG,
                                           MAX_RELAXATION_TIME_S, check_lengths, check_number,
                                           require)
from fivebar_drake.mechanisms.fivebar import (LINK_NAMES, FiveBarLeg, LegGeometry, LegLimits,
                                              LinkInertia)
from fivebar_drake.robots.quadruped.legs import LEGS


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
        check_number("robot.legs", self.legs, len(LEGS), len(LEGS), integer=True,
                     why="the simulation builds a quadruped; the weight share is total / legs")

    @property
    def total_mass_kg(self) -> float:
        return self.battery_electronics_kg + self.structure_kg + self.motors_kg

    @property
    def weight_share_kg(self) -> float:
        return self.total_mass_kg / self.legs


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
        check_lengths("body", self, ("length_m", "width_m", "height_m", "hip_x_m", "hip_y_m",
                                "link_width_m", "foot_radius_m"))
        check_number("body.hip_z_m", self.hip_z_m, -MAX_LENGTH_M, MAX_LENGTH_M)
        check_number("body.foot_friction", self.foot_friction, 0.0, MAX_FRICTION_COEFFICIENT,
                     low_open=True)
        check_number("body.foot_stiffness_N_m", self.foot_stiffness_N_m, 0.0,
                     MAX_CONTACT_STIFFNESS_N_M, low_open=True)
        check_number("body.foot_relaxation_time_s", self.foot_relaxation_time_s, 0.0,
                     MAX_RELAXATION_TIME_S, low_open=True)


@dataclass(frozen=True)
class Params:
    """The quadruped's parameter file: each leg's geometry with its limits ([limits]) and link
    inertias, the robot's masses, the gait, the hip motors, the verdict thresholds and the
    body."""

    leg: LegGeometry
    links: dict[str, LinkInertia]
    robot: Robot
    gait: Gait
    motor: BldcMotor
    checks: Checks
    body: Body
    published: dict = field(default_factory=dict)   # [published]: robots/quadruped/published.py

    @property
    def limits(self) -> LegLimits:
        """The leg's mechanical limits ([limits] of the file; part of the leg's geometry)."""
        return self.leg.limits

    @property
    def fivebar_leg(self) -> FiveBarLeg:
        """Each leg: the 5-bar (every part of mechanisms/base.py and its torque breakdown)."""
        return FiveBarLeg(self.leg, self.links)

    def __post_init__(self):
        require(self.gait.gravity_m_s2 == self.robot.gravity_m_s2, "gait.gravity_m_s2",
                self.gait.gravity_m_s2, f"is the robot's robot.gravity_m_s2 = "
                                        f"{self.robot.gravity_m_s2:g} (set from it on loading)")
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
        links_kg = len(LEGS) * sum(link.mass_kg for link in self.links.values())
        carried = self.robot.battery_electronics_kg + self.robot.structure_kg
        require(links_kg < carried, "links.*.mass_kg", links_kg,
                f"the {len(LEGS)} legs' links ({links_kg:.3f} kg) must weigh less than "
                f"robot.battery_electronics_kg + robot.structure_kg = {carried:.3f} kg, which "
                "include them")
        require(isinstance(self.motor, BldcMotor) and self.motor.has_thermal_model, "motor.model",
                self.motor.model, f"the quadruped's verdict needs a BLDC motor (model = \"bldc\") "
                f"with its thermal model: give all of {list(THERMAL_FIELDS)}")
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
