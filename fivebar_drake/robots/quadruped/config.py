"""Parameter files: the packaged ``data/default.toml`` is the one source of truth, a user may
pass their own with the same layout. Loading builds the typed sections of params.py and checks
what needs the kinematics: every foot path and the home point must stay in the workspace and
within the leg's limits."""

from __future__ import annotations

import dataclasses
from pathlib import Path
import numpy as np

from fivebar_drake.verdicts.checks import Checks
from fivebar_drake.gaits import FootPath, Gait, evaluate, foot_path
from fivebar_drake.actuators.motor import build_motor
from fivebar_drake.core.parameter_files import build_section, load_parameter_file, packaged
from fivebar_drake.core.validation import MAX_SAMPLES, ParameterError, require
from fivebar_drake.mechanisms.fivebar import (KNEES_OUT, LegGeometry, LegLimits, LinkInertia,
                                              UnreachableError, inverse, path_poses, sample_gait)
from fivebar_drake.robots.quadruped.params import Body, Params, Robot
from fivebar_drake.robots.quadruped.published import published_from


# Central differences over N samples per cycle: the peak joint speed and acceleration are
# compared with those over REFERENCE_REFINEMENT * N samples (an O(h^2) error shrinks 64 times;
# at most params.MAX_SAMPLES); a difference above SAMPLING_ERROR_WARN of the peak is reported
# with the analysis.
REFERENCE_REFINEMENT = 8
SAMPLING_ERROR_WARN = 0.05   # the speed check and safety factors move visibly beyond this
# the file's sections; an optional one may be left out (absent [limits]: no limit)
SECTIONS = ("leg", "links", "robot", "gait", "motor", "checks", "body", "limits", "published")
OPTIONAL_SECTIONS = ("limits", "published")
EDITABLE_SECTIONS = SECTIONS[:-1]   # [published] holds figures to compare with, not parameters
PATH_CHECK_SAMPLES = 241    # samples of each foot path checked against the workspace and limits


def params_from_dict(data: dict) -> Params:
    """Build and validate Params from the nested dict of a parameter file."""
    unknown = sorted(set(data) - set(SECTIONS))
    missing = sorted(set(SECTIONS) - set(OPTIONAL_SECTIONS) - set(data))
    if unknown or missing:
        raise ParameterError(f"parameter file sections: unknown {unknown}, missing {missing}; "
                             f"expected {sorted(SECTIONS)} ({list(OPTIONAL_SECTIONS)} optional)")
    require(isinstance(data["links"], dict), "[links]", data["links"], "must hold [links.AC] ...")
    leg = build_section(LegGeometry, data["leg"], "leg")
    robot = build_section(Robot, data["robot"], "robot")
    params = Params(
        leg=dataclasses.replace(leg, limits=build_section(LegLimits, data.get("limits", {}),
                                                          "limits")),
        links={name: build_section(LinkInertia, table, f"links.{name}")
               for name, table in data["links"].items()},
        robot=robot,
        gait=dataclasses.replace(build_section(Gait, data["gait"], "gait"),
                                 gravity_m_s2=robot.gravity_m_s2),
        motor=build_motor(data["motor"]),
        checks=build_section(Checks, data["checks"], "checks"),
        body=build_section(Body, data["body"], "body"),
        published=published_from(data.get("published", {})),
    )
    check_gait_reachable(params)
    return params


SECTION_PATHS = ("seed_ellipse", "trot")   # the paths the file's [gait] section describes


def check_gait_reachable(params: Params) -> None:
    """Raise ParameterError if the home point or a sample of the paths the parameter file's
    [gait] section describes (SECTION_PATHS) lies outside the knees-out workspace or past one of
    the leg's limits (check_path). Any other path (a registered gait with its own defaults, a
    maneuver with its scenario fields) is checked by the command that runs it: analyze, simulate,
    a sweep, an envelope; registering a gait never makes a parameter file fail to load."""
    for path in SECTION_PATHS:
        check_path(params, path)
    g = params.gait
    try:
        inverse(params.leg, np.array([g.x_center_m, g.y_home_m]), KNEES_OUT)
    except UnreachableError as err:
        field = f"limits.{err.field}" if err.field else "gait.y_home_m"
        raise ParameterError(f"the home point (gait.x_center_m, gait.y_home_m), where the robot "
                             f"stands, is unreachable: {err}", field) from None


def check_path(params: Params, path: FootPath | str) -> None:
    """Raise ParameterError if a sample of the foot path (a FootPath or its kind), sampled
    PATH_CHECK_SAMPLES times over its span (a cycle, or a maneuver from start to end), lies
    outside the workspace or past a limit, naming the sample (index, time, foot target), the
    limit and the fields that place the path."""
    g = params.gait
    t = np.linspace(0.0, foot_path(path).span_s(g), PATH_CHECK_SAMPLES)
    points = evaluate(g, path, t)              # a path of numbers (a plugin's may not be)
    bad = ~(np.isfinite(points.pos).all(-1) & np.isfinite(points.vel).all(-1)
            & np.isfinite(points.acc).all(-1))
    if bad.any():
        k = int(np.argmax(bad))
        raise ParameterError(f"the {foot_path(path).kind} path gives a value that is not a "
                             f"number at t = {t[k]:.4g} s (foot {points.pos[k].tolist()} m, "
                             f"velocity {points.vel[k].tolist()} m/s, acceleration "
                             f"{points.acc[k].tolist()} m/s^2): its point function is broken",
                             "gait")
    try:
        path_poses(params.leg, g, path, t)
    except UnreachableError as err:
        where = (f"the path spans x = gait.x_center_m +- gait.a_m = {g.x_center_m:g} +- "
                 f"{g.a_m:g} m and y = gait.y_home_m .. + gait.b_m = {g.y_home_m:g} .. "
                 f"{g.y_home_m + g.b_m:g} m: move or shrink it")
        if err.field:
            raise ParameterError(f"the foot path leaves the leg's limits ({err.where}): "
                                 f"{err.reason}; {where}, or change limits.{err.field}",
                                 f"limits.{err.field}") from None
        raise ParameterError(f"the foot path leaves the workspace ({err.where}): {err.reason}; "
                             f"{where}, or change the link lengths leg.*",
                             "gait.y_home_m") from None


def with_gait(params: Params, **changes) -> Params:
    """A copy with some gait fields changed (validated like a loaded file)."""
    gait = dataclasses.replace(params.gait, **changes)
    params = dataclasses.replace(params, gait=gait)
    check_gait_reachable(params)
    return params


def with_path_defaults(params: Params, path: FootPath | str, **overrides) -> Params:
    """The parameters a foot path runs with, the same for analyze, simulate and a sweep: the
    path's own gait fields (FootPath.gait_defaults, e.g. the bound's 2 Hz and a = 30 mm) over the
    parameter file's, and overrides (gait field -> value) over both; validated (with_gait)."""
    changes = {**foot_path(path).gait_defaults, **overrides}
    return with_gait(params, **changes) if changes else params


def with_changes(params: Params, changes: dict) -> Params:
    """The parameters with fields changed by dotted path (section.field, or links.NAME.field),
    validated as a parameter file is (ParameterError naming the field). The motor is given by
    its motor-side data, so changing motor.gear_ratio keeps the motor and changes the gearbox
    (actuators/motor.py): the same physics as a parameter file with that ratio."""
    sections = {}
    for path, value in changes.items():
        parts = path.split(".")
        if parts[0] not in EDITABLE_SECTIONS or len(parts) != (3 if parts[0] == "links" else 2):
            raise ParameterError(f"{path}: not a parameter; use section.field with a section of "
                                 f"{list(EDITABLE_SECTIONS)} (links.NAME.field for a link)", path)
        sections.setdefault(parts[0], {})[".".join(parts[1:])] = value
    new = {}
    for section, fields in sections.items():
        old = getattr(params, section)
        if section == "links":
            links = dict(old)
            for key, value in fields.items():
                name, field = key.split(".")
                if name not in links:
                    raise ParameterError(f"links.{name}: no such link; links are {list(links)}",
                                         f"links.{name}")
                links[name] = _replace(links[name], f"links.{name}", {field: value})
            new[section] = links
        else:
            new[section] = _replace(old, section, fields)
    if "limits" in new:                    # the leg's limits: [limits] of the file
        new["leg"] = dataclasses.replace(new.get("leg", params.leg), limits=new.pop("limits"))
    if "robot" in new:                  # the gait's gravity is the robot's
        new["gait"] = dataclasses.replace(new.get("gait", params.gait),
                                          gravity_m_s2=new["robot"].gravity_m_s2)
    return dataclasses.replace(params, **new)


def _replace(obj, section: str, fields: dict):
    known = {f.name: f for f in dataclasses.fields(obj)}
    for name in fields:
        if name not in known:
            raise ParameterError(f"{section}.{name}: no such field; {section} has "
                                 f"{sorted(known)}", f"{section}.{name}")
    values = {k: float(v) if known[k].type in ("float", "float | None") and isinstance(v, int)
              and not isinstance(v, bool) else v for k, v in fields.items()}
    try:
        return dataclasses.replace(obj, **values)
    except TypeError as err:
        raise ParameterError(f"{section}: {err}", section) from None


def sampling_error(params: Params, path: str) -> dict:
    """How far the central differences over gait.samples samples per cycle are from converged:
    the relative shortfall of the peak joint speed and acceleration (worst motor) against
    REFERENCE_REFINEMENT times as many samples (at most MAX_SAMPLES), that reference count, and
    a warning if either is above SAMPLING_ERROR_WARN ("" otherwise)."""
    fine = dataclasses.replace(params.gait, samples=min(params.gait.samples * REFERENCE_REFINEMENT,
                                                        MAX_SAMPLES))
    coarse, ref = sample_gait(params.leg, params.gait, path), sample_gait(params.leg, fine, path)
    err = {"reference_samples": fine.samples}
    for key, name in (("speed", "qd"), ("acceleration", "qdd")):
        peak, ref_peak = (np.max(np.abs(getattr(s, name)), axis=0) for s in (coarse, ref))
        err[key] = float(np.max(np.abs(peak - ref_peak) / np.maximum(ref_peak, 1e-12)))
    err["warning"] = "" if max(err["speed"], err["acceleration"]) <= SAMPLING_ERROR_WARN else (
        f"gait.samples = {params.gait.samples}: the central differences over so few samples per "
        f"cycle are off by {err['speed']:.0%} in the peak joint speed and "
        f"{err['acceleration']:.0%} in the peak joint acceleration (against {fine.samples} "
        f"samples); raise gait.samples for figures within {SAMPLING_ERROR_WARN:.0%}")
    return err

DEFAULT_PATH = packaged("default.toml")


def load_params(path: str | Path | None = None) -> Params:
    """Load and validate a parameter file (TOML); None loads the packaged default. Errors name
    the file (ParameterError.source)."""
    return load_parameter_file(path, "default.toml", params_from_dict)
