"""Parameter files: the packaged ``data/default.toml`` is the one source of truth, a user may
pass their own with the same layout. Loading builds the typed sections of params.py and checks
what needs the kinematics: every foot path must stay in the workspace."""

from __future__ import annotations

import dataclasses
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

from .footpath import PATHS, evaluate
from .kinematics import KNEES_OUT, UnreachableError, inverse
from .params import (Body, Checks, Gait, LegGeometry, LinkInertia, Motor, ParameterError, Params,
                     Robot, require)


def _build(cls, table: dict, section: str):
    names = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(set(table) - set(names))
    missing = sorted(set(names) - set(table))
    if unknown:
        raise ParameterError(f"[{section}] has unknown key(s) {unknown}; allowed: {sorted(names)}")
    if missing:
        raise ParameterError(f"[{section}] is missing key(s) {missing}")
    values = {}
    for key, value in table.items():
        kind = names[key].type
        if kind == "int":
            require(isinstance(value, int) and not isinstance(value, bool), f"{section}.{key}",
                     value, "must be an integer")
        elif kind == "float":
            require(isinstance(value, (int, float)) and not isinstance(value, bool),
                     f"{section}.{key}", value, "must be a number")
            value = float(value)
        else:  # a point [x, y]
            require(isinstance(value, list) and len(value) == 2
                     and all(isinstance(v, (int, float)) for v in value), f"{section}.{key}",
                     value, "must be [x, y] in m")
            value = (float(value[0]), float(value[1]))
        values[key] = value
    return cls(**values)


def params_from_dict(data: dict) -> Params:
    """Build and validate Params from the nested dict of a parameter file."""
    sections = {"leg", "links", "robot", "gait", "motor", "checks", "body"}
    unknown, missing = sorted(set(data) - sections), sorted(sections - set(data))
    if unknown or missing:
        raise ParameterError(f"parameter file sections: unknown {unknown}, missing {missing}; "
                             f"expected {sorted(sections)}")
    params = Params(
        leg=_build(LegGeometry, data["leg"], "leg"),
        links={name: _build(LinkInertia, table, f"links.{name}")
               for name, table in data["links"].items()},
        robot=_build(Robot, data["robot"], "robot"),
        gait=_build(Gait, data["gait"], "gait"),
        motor=_build(Motor, data["motor"], "motor"),
        checks=_build(Checks, data["checks"], "checks"),
        body=_build(Body, data["body"], "body"),
    )
    check_gait_reachable(params)
    return params


def check_gait_reachable(params: Params) -> None:
    """Raise ParameterError if a sample of either foot path lies outside the knees-out
    workspace."""
    for path in PATHS:
        foot = evaluate(params.gait, path, np.linspace(0.0, params.gait.period_s, 241)).pos
        try:
            inverse(params.leg, foot, KNEES_OUT)
        except UnreachableError as err:
            raise ParameterError(f"gait leaves the workspace ({path} path): {err}") from None


def with_gait(params: Params, **changes) -> Params:
    """A copy with some gait fields changed (validated like a loaded file)."""
    params = dataclasses.replace(params, gait=dataclasses.replace(params.gait, **changes))
    check_gait_reachable(params)
    return params


DEFAULT_PATH = resources.files("fivebar_drake") / "data" / "default.toml"


def load_params(path: str | Path | None = None) -> Params:
    """Load and validate a parameter file (TOML); None loads the packaged default."""
    source = DEFAULT_PATH if path is None else Path(path)
    try:
        text = source.read_text()
    except FileNotFoundError:
        raise ParameterError(f"parameter file not found: {path}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ParameterError(f"{source}: not valid TOML: {err}") from None
    return params_from_dict(data)
