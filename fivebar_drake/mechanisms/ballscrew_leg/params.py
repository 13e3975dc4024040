"""Parameters of the ball-screw leg study (data/ballscrew_leg.toml), typed and validated on load:
every error names the file, the field, the value and what is allowed."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fivebar_drake.core.parameter_files import build_section, load_parameter_file, packaged
from fivebar_drake.actuators.motor import LineMotor, build_motor
from fivebar_drake.core.validation import (MIN_PLANT_STEP_S, MAX_GEAR_RATIO, MAX_GRAVITY_M_S2, MAX_LENGTH_M,
                                           MAX_MASS_KG, MAX_SAMPLES, check_lengths, check_number, require)
from fivebar_drake.mechanisms.ballscrew_leg.leg import BallScrewLeg

DEFAULT_PATH = packaged("ballscrew_leg.toml")
MAX_FOOT_FORCE_N = 1e5          # 10 t on one leg: a slip of units, not a design of this size
MAX_DURATION_S = 60.0           # a squat of a minute is no "short squat"
MAX_RATE_HZ = 1000.0


@dataclass(frozen=True)
class Leg:
    """Thigh OA = l1 and shank AP = l2 (m)."""

    thigh_m: float
    shank_m: float

    def __post_init__(self):
        check_lengths("leg", self, ("thigh_m", "shank_m"))


@dataclass(frozen=True)
class Screw:
    """The knee's ball screw: lead (m per turn), efficiency (forward and back-driven), the lever
    lengths s1 = DA studied (m), the nut's stroke (m) and the squat angle q1 (deg) at which the
    screw is fully retracted."""

    lead_m: float
    efficiency: float
    lever_lengths_m: tuple
    stroke_m: float
    retracted_at_q1_deg: float

    def __post_init__(self):
        check_number("screw.lead_m", self.lead_m, 0.0, 0.1, low_open=True,
                     why="a ball screw's lead is millimetres")
        check_number("screw.efficiency", self.efficiency, 0.0, 1.0, low_open=True)
        require(isinstance(self.lever_lengths_m, tuple) and len(self.lever_lengths_m) >= 1,
                "screw.lever_lengths_m", self.lever_lengths_m, "must be a list of lengths in m")
        for i, s in enumerate(self.lever_lengths_m):
            check_number(f"screw.lever_lengths_m[{i}]", s, 0.0, MAX_LENGTH_M, low_open=True)
        check_number("screw.stroke_m", self.stroke_m, 0.0, MAX_LENGTH_M, low_open=True)
        check_number("screw.retracted_at_q1_deg", self.retracted_at_q1_deg, 0.0, 90.0,
                     high_open=True)


@dataclass(frozen=True)
class GearedKnee:
    """The geared knee motor: reduction and efficiency."""

    gear_ratio: float
    efficiency: float

    def __post_init__(self):
        check_number("geared_knee.gear_ratio", self.gear_ratio, 0.0, MAX_GEAR_RATIO,
                     low_open=True)
        check_number("geared_knee.efficiency", self.efficiency, 0.0, 1.0, low_open=True)


@dataclass(frozen=True)
class Load:
    """The ground's vertical force on the foot (N, up)."""

    foot_force_N: float

    def __post_init__(self):
        check_number("load.foot_force_N", self.foot_force_N, 0.0, MAX_FOOT_FORCE_N,
                     low_open=True)


@dataclass(frozen=True)
class Squat:
    """The analysed vertical squat: q1 from q1_min_deg to q1_max_deg, q2 = -2 q1."""

    q1_min_deg: float
    q1_max_deg: float
    samples: int

    def __post_init__(self):
        check_number("squat.q1_min_deg", self.q1_min_deg, 0.0, 90.0, low_open=True,
                     high_open=True, why="at 0 (straight leg) the screw force is 0/0")
        check_number("squat.q1_max_deg", self.q1_max_deg, self.q1_min_deg, 90.0, low_open=True,
                     high_open=True, why="above q1_min_deg; at 90 deg the foot is at the hip")
        check_number("squat.samples", self.samples, 3, MAX_SAMPLES, integer=True)

    @property
    def q1_rad(self) -> np.ndarray:
        """The sampled hip angles (rad)."""
        return np.radians(np.linspace(self.q1_min_deg, self.q1_max_deg, self.samples))


@dataclass(frozen=True)
class Simulation:
    """The simulated squat: lever, squat angles (deg), timing (s), controller, link masses (kg),
    recording rate and gravity."""

    lever_m: float
    q1_top_deg: float
    q1_bottom_deg: float
    hold_s: float
    down_s: float
    time_step_s: float
    motor_period_s: float
    pd_bandwidth_hz: float
    pd_damping_ratio: float
    thigh_mass_kg: float
    shank_mass_kg: float
    screw_mass_kg: float
    nut_mass_kg: float
    pose_rate_hz: float
    gravity_m_s2: float

    def __post_init__(self):
        check_number("simulation.lever_m", self.lever_m, 0.0, MAX_LENGTH_M, low_open=True)
        check_number("simulation.q1_top_deg", self.q1_top_deg, 0.0, 90.0, low_open=True,
                     high_open=True)
        check_number("simulation.q1_bottom_deg", self.q1_bottom_deg, self.q1_top_deg, 90.0,
                     low_open=True, high_open=True, why="deeper than q1_top_deg")
        check_number("simulation.hold_s", self.hold_s, 0.0, MAX_DURATION_S)
        check_number("simulation.down_s", self.down_s, 0.0, MAX_DURATION_S, low_open=True)
        check_number("simulation.time_step_s", self.time_step_s, MIN_PLANT_STEP_S, 0.01)
        check_number("simulation.motor_period_s", self.motor_period_s, self.time_step_s, 0.1,
                     why="at least one plant step")
        check_number("simulation.pd_bandwidth_hz", self.pd_bandwidth_hz, 0.0,
                     0.1 / self.time_step_s, low_open=True, why="a tenth of the plant's rate")
        check_number("simulation.pd_damping_ratio", self.pd_damping_ratio, 0.0, 10.0,
                     low_open=True)
        for name in ("thigh_mass_kg", "shank_mass_kg", "screw_mass_kg", "nut_mass_kg"):
            check_number(f"simulation.{name}", getattr(self, name), 0.0, MAX_MASS_KG,
                         low_open=True)
        check_number("simulation.pose_rate_hz", self.pose_rate_hz, 0.0, MAX_RATE_HZ,
                     low_open=True)
        check_number("simulation.gravity_m_s2", self.gravity_m_s2, 0.0, MAX_GRAVITY_M_S2,
                     low_open=True)

    @property
    def duration_s(self) -> float:
        """Hold, down, up, hold."""
        return 2.0 * (self.hold_s + self.down_s)


@dataclass(frozen=True)
class Params:
    """Everything the study reads from its parameter file."""

    leg: Leg
    screw: Screw
    geared_knee: GearedKnee
    load: Load
    squat: Squat
    simulation: Simulation
    motor: LineMotor


SECTIONS = {"leg": Leg, "screw": Screw, "geared_knee": GearedKnee, "load": Load,
            "squat": Squat, "simulation": Simulation, "motor": build_motor}


def params_from_dict(data: dict) -> Params:
    """Params from a parameter file's tables, validated (ParameterError without the source)."""
    require(isinstance(data, dict) and set(data) == set(SECTIONS), "sections",
            sorted(data) if isinstance(data, dict) else data, f"must be {sorted(SECTIONS)}")
    params = Params(**{name: build_motor(data[name]) if cls is build_motor else
                       build_section(cls, data[name], name) for name, cls in SECTIONS.items()})
    s = params.simulation
    require(s.lever_m in params.screw.lever_lengths_m, "simulation.lever_m", s.lever_m,
            f"must be one of screw.lever_lengths_m = {list(params.screw.lever_lengths_m)}")
    for i, lever in enumerate(params.screw.lever_lengths_m):
        require(lever < params.leg.thigh_m, f"screw.lever_lengths_m[{i}]", lever,
                f"must be shorter than leg.thigh_m = {params.leg.thigh_m:g} (else the screw "
                "length cannot set every knee angle)")
    require(math.isclose(params.leg.thigh_m, params.leg.shank_m), "leg.shank_m",
            params.leg.shank_m, f"must equal leg.thigh_m = {params.leg.thigh_m:g}: the squat "
            "q2 = -2 q1 keeps the foot below the hip only for equal links")
    leg = BallScrewLeg(params.leg.thigh_m, params.leg.shank_m, s.lever_m, params.screw.lead_m)
    _, bends = leg.stroke_window(params.screw.stroke_m,
                                 2.0 * math.radians(params.screw.retracted_at_q1_deg))
    lo, hi = (math.degrees(b / 2.0) for b in bends)
    for name in ("q1_top_deg", "q1_bottom_deg"):
        value = getattr(s, name)
        require(lo - 1e-9 <= value <= hi + 1e-9, f"simulation.{name}", value,
                f"must lie within the q1 range {lo:.2f} .. {hi:.2f} deg the screw's stroke "
                f"(screw.stroke_m = {params.screw.stroke_m:g}) allows the lever {s.lever_m:g} m")
    return params


def load_params(path: str | Path | None = None) -> Params:
    """Load and validate a parameter file (TOML); None: the packaged one. Errors name the file."""
    return load_parameter_file(path, "ballscrew_leg.toml", params_from_dict)
