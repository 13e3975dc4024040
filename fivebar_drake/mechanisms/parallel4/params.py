"""All parameters of the parallel4 study, as typed sections built and validated from the nested
dict of its TOML file (fivebar_drake/data/parallel4.toml). Errors name the field; the loader
adds the file."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from fivebar_drake.core.parameter_files import check_keys
from fivebar_drake.core.validation import (MIN_PLANT_STEP_S, MAX_LENGTH_M, MAX_MASS_KG, ParameterError,
                                           check_number, require)
from fivebar_drake.mechanisms.parallel4.geometry import Geometry
from fivebar_drake.mechanisms.parallel4.statics import in_workspace

MAX_ACTUATOR_STIFFNESS_N_M = 1e10   # a steel ball screw is ~1e8 N/m
MAX_GAIN_N_M = 1e9
MAX_GRID_POINTS = 2_000_000         # a cross-section grid; ~1 s per 10^6 poses here
MAX_DURATION_S = 600.0


def _variant_a_minus_b(g: Geometry, v: float) -> Geometry:
    return dataclasses.replace(g, a=g.b + v)


def _variant_c_equals_d(g: Geometry, v: float) -> Geometry:
    return dataclasses.replace(g, c=v, d=v)


def _variant_c_over_d(g: Geometry, v: float) -> Geometry:
    return dataclasses.replace(g, d=g.c / v)


def _variant_R(g: Geometry, v: float) -> Geometry:
    return dataclasses.replace(g, R=v)


VARIED = {"a_minus_b": _variant_a_minus_b, "c_equals_d": _variant_c_equals_d,
          "c_over_d": _variant_c_over_d, "R": _variant_R}


@dataclass(frozen=True)
class Grid:
    """The yz grid of the cross-sections and maps: |y| <= half_width, z_low <= z <= z_high, m."""

    half_width: float
    z_low: float
    z_high: float
    step: float


@dataclass(frozen=True)
class Study:
    """One workspace study (a seed figure): `varied` takes `values` on the geometry `base`
    (the file's [geometry] with `set` overriding), at the platform angles theta_deg."""

    name: str
    figure: str
    varied: str
    values: tuple[float, ...]
    theta_deg: tuple[float, ...]
    base: Geometry

    def geometries(self) -> list[Geometry]:
        return [VARIED[self.varied](self.base, v) for v in self.values]


@dataclass(frozen=True)
class Stiffness:
    """Actuator stiffnesses (N/m), the seed's point (y, z) in m, the wide-base readings of
    a - b and R, the narrow base a - b, and the map angles (deg)."""

    actuator_N_m: tuple[float, ...]
    point_y: float
    point_z: float
    wide_a_minus_b: tuple[float, ...]
    R_readings: tuple[float, ...]
    narrow_a_minus_b: float
    wide_theta_deg: tuple[float, ...]
    narrow_theta_deg: tuple[float, ...]


@dataclass(frozen=True)
class Model:
    """Masses (kg) and sizes (m) of the Drake model."""

    platform_mass_kg: float
    guide_mass_kg: float
    slider_mass_kg: float
    leg_mass_kg: float
    leg_radius_m: float
    gravity_m_s2: float


@dataclass(frozen=True)
class Simulation:
    """The platform path pose(t) = center + amplitude * (sin, sin, cos, sin)(2 pi t / period)
    (m, m, m, deg), the actuators' PD gains, the plant step and the run length (s)."""

    center: tuple[float, ...]
    amplitude: tuple[float, ...]
    period_s: float
    kp_N_m: float
    kd_N_s_m: float
    time_step_s: float
    duration_s: float
    record_hz: float

    def poses(self, t) -> np.ndarray:
        """Path poses (..., 4) (m, rad) at times t (s)."""
        w = 2 * np.pi * np.asarray(t, dtype=float)[..., None] / self.period_s
        shape = np.concatenate([np.sin(w), np.sin(w), np.cos(w), np.sin(w)], axis=-1)
        pose = np.asarray(self.center) + np.asarray(self.amplitude) * shape
        return pose * np.array([1, 1, 1, np.pi / 180])


@dataclass(frozen=True)
class Params:
    geometry: Geometry
    grid: Grid
    studies: tuple[Study, ...]
    stiffness: Stiffness
    model: Model
    simulation: Simulation


def _numbers(field: str, values, low, high, n=None, **kw) -> tuple[float, ...]:
    require(isinstance(values, list) and len(values) > 0 and (n is None or len(values) == n),
            field, values, f"must be a list of {n or 'one or more'} numbers")
    return tuple(check_number(f"{field}[{i}]", v, low, high, **kw) for i, v in enumerate(values))


def _fields(cls, data: dict, section: str, bounds: dict) -> dict:
    names = [f.name for f in dataclasses.fields(cls)]
    data = check_keys(data, section, names)
    return {n: check_number(f"{section}.{n}", data[n], *bounds[n][:2], **bounds[n][2])
            for n in names if n in bounds}


def _geometry(data, section: str) -> Geometry:
    names = [f.name for f in dataclasses.fields(Geometry)]
    data = check_keys(data, section, names)
    for n in names:
        require(isinstance(data[n], (int, float)) and not isinstance(data[n], bool),
                f"{section}.{n}", data[n], "must be a number")
    return Geometry(**{n: float(data[n]) for n in names}).check(section)


def _study(data, i: int, geometry: Geometry) -> Study:
    section = f"workspace.studies[{i}]"
    data = check_keys(data, section, ["name", "figure", "varied", "values", "theta_deg", "set"])
    for key in ("name", "figure"):
        require(isinstance(data[key], str) and data[key], f"{section}.{key}", data[key],
                "must be a non-empty string")
    require(data["varied"] in VARIED, f"{section}.varied", data["varied"],
            f"must be one of {sorted(VARIED)}")
    require(isinstance(data["set"], dict) and set(data["set"]) <= {"a", "b", "c", "d", "R"},
            f"{section}.set", data["set"], "must be a table of a, b, c, d, R (m)")
    base = dataclasses.replace(geometry, **{k: check_number(f"{section}.set.{k}", v, 0.0,
                                                            MAX_LENGTH_M, low_open=True)
                                            for k, v in data["set"].items()})
    study = Study(data["name"], data["figure"], data["varied"],
                  _numbers(f"{section}.values", data["values"], 0.0, 10.0, low_open=True),
                  _numbers(f"{section}.theta_deg", data["theta_deg"], -89.0, 89.0), base)
    for k, g in enumerate(study.geometries()):
        try:
            g.check(f"{section} with values[{k}]")
        except ParameterError as err:
            raise ParameterError(err.message, f"{section}.values[{k}]") from None
    return study


def params_from_dict(data: dict) -> Params:
    """Params built from the nested dict of a parameter file; ParameterError naming the field."""
    data = check_keys(data, "file", ["geometry", "workspace", "stiffness", "model", "simulation"])
    geometry = _geometry(data["geometry"], "geometry")
    ws = check_keys(data["workspace"], "workspace", ["half_width", "z_low", "z_high", "step",
                                                 "studies"])
    grid = Grid(**{n: check_number(f"workspace.{n}", ws[n], -MAX_LENGTH_M, MAX_LENGTH_M)
                   for n in ("half_width", "z_low", "z_high", "step")})
    require(grid.half_width > 0 and grid.z_low < grid.z_high and grid.step > 0,
            "workspace.step", grid, "needs half_width > 0, z_low < z_high, step > 0")
    points = (2 * grid.half_width / grid.step) * ((grid.z_high - grid.z_low) / grid.step)
    require(points <= MAX_GRID_POINTS, "workspace.step", grid.step,
            f"gives {points:.3g} grid points, at most {MAX_GRID_POINTS:g}")
    require(isinstance(ws["studies"], list) and ws["studies"], "workspace.studies",
            ws["studies"], "must be a list of [[workspace.studies]] tables")
    studies = tuple(_study(s, i, geometry) for i, s in enumerate(ws["studies"]))

    st = check_keys(data["stiffness"], "stiffness", [f.name for f in dataclasses.fields(Stiffness)])
    stiffness = Stiffness(
        _numbers("stiffness.actuator_N_m", st["actuator_N_m"], 0.0, MAX_ACTUATOR_STIFFNESS_N_M,
                 n=4, low_open=True),
        check_number("stiffness.point_y", st["point_y"], -MAX_LENGTH_M, MAX_LENGTH_M),
        check_number("stiffness.point_z", st["point_z"], -MAX_LENGTH_M, MAX_LENGTH_M),
        _numbers("stiffness.wide_a_minus_b", st["wide_a_minus_b"], 0.0, MAX_LENGTH_M,
                 low_open=True),
        _numbers("stiffness.R_readings", st["R_readings"], 0.0, MAX_LENGTH_M, low_open=True),
        check_number("stiffness.narrow_a_minus_b", st["narrow_a_minus_b"], 0.0, MAX_LENGTH_M,
                     low_open=True),
        _numbers("stiffness.wide_theta_deg", st["wide_theta_deg"], -89.0, 89.0),
        _numbers("stiffness.narrow_theta_deg", st["narrow_theta_deg"], -89.0, 89.0))

    mass = (0.0, MAX_MASS_KG, {"low_open": True})
    model = Model(**_fields(Model, data["model"], "model", {
        "platform_mass_kg": mass, "guide_mass_kg": mass, "slider_mass_kg": mass,
        "leg_mass_kg": mass, "leg_radius_m": (0.0, 0.1, {"low_open": True}),
        "gravity_m_s2": (0.0, 30.0, {})}))

    sim = data["simulation"]
    scalars = _fields(Simulation, sim, "simulation", {
        "period_s": (0.0, MAX_DURATION_S, {"low_open": True}),
        "kp_N_m": (0.0, MAX_GAIN_N_M, {"low_open": True}),
        "kd_N_s_m": (0.0, MAX_GAIN_N_M, {}),
        "time_step_s": (MIN_PLANT_STEP_S, 0.01, {}),
        "duration_s": (0.0, MAX_DURATION_S, {"low_open": True}),
        "record_hz": (1.0, 1000.0, {})})
    simulation = Simulation(_numbers("simulation.center", sim["center"], -89.0, 89.0, n=4),
                            _numbers("simulation.amplitude", sim["amplitude"], 0.0, 89.0, n=4),
                            **scalars)
    check_path(geometry, simulation)
    return Params(geometry, grid, studies, stiffness, model, simulation)


def check_path(g: Geometry, sim: Simulation, samples: int = 721) -> None:
    """ParameterError naming simulation.center / amplitude unless the whole path lies in the
    workspace (reachable, within the stroke, on the seed's forward branch)."""
    t = np.linspace(0.0, sim.period_s, samples)
    inside = in_workspace(g, sim.poses(t))
    if not inside.all():
        pose = sim.poses(t[~inside][0])
        raise ParameterError(
            f"simulation.center/amplitude: the path leaves the workspace at t = "
            f"{t[~inside][0]:.4g} s, pose (x, y, z, theta) = ({pose[0]:.4g} m, {pose[1]:.4g} m, "
            f"{pose[2]:.4g} m, {math.degrees(pose[3]):.4g} deg): out of reach, outside the "
            f"stroke [d_min, d_max] or across the type-2 singularity", "simulation.center")
