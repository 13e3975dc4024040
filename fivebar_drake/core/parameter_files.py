"""Parameter files (TOML) of every mechanism: reading one with its errors located, and building
its typed sections (dataclasses) with unknown and missing keys named."""

from __future__ import annotations

import dataclasses
import tomllib
from importlib import resources
from pathlib import Path

from fivebar_drake.core.files import read_input_text
from fivebar_drake.core.validation import ParameterError, require

FLOAT_TYPES = ("float", "float | None")


def read_toml(path: str | Path) -> dict:
    """The tables of a TOML file (ParameterError naming the file if it cannot be read or is
    not TOML)."""
    text = read_input_text(path, "parameter file")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ParameterError(f"not valid TOML: {err}", source=str(path)) from None


def check_keys(table, section: str, allowed, required=None) -> dict:
    """The table, if it is one whose keys are among `allowed` and include `required` (default:
    all of allowed); else ParameterError naming the section and the keys."""
    require(isinstance(table, dict), f"[{section}]", table, "must be a table of keys")
    required = set(allowed) if required is None else set(required)
    unknown, missing = sorted(set(table) - set(allowed)), sorted(required - set(table))
    if unknown:
        raise ParameterError(f"{section}.{unknown[0]}: [{section}] has unknown key(s) "
                             f"{unknown}; allowed: {sorted(allowed)}", f"{section}.{unknown[0]}")
    if missing:
        raise ParameterError(f"{section}.{missing[0]}: [{section}] is missing key(s) {missing}",
                             f"{section}.{missing[0]}")
    return table


def build_section(cls, table, section: str):
    """cls (a dataclass, which validates its values) from a TOML table: every field without a
    default is required (check_keys); where the field is a float, the value must be a number (a
    TOML integer becomes a float); a list becomes a tuple."""
    fields = {f.name: f for f in dataclasses.fields(cls)}
    required = [n for n, f in fields.items()
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    check_keys(table, section, fields, required)
    values = {}
    for key, value in table.items():
        if fields[key].type in FLOAT_TYPES:
            require(isinstance(value, (int, float)) and not isinstance(value, bool),
                    f"{section}.{key}", value, "must be a number")
            value = float(value)
        elif isinstance(value, list):
            value = tuple(value)
        values[key] = value
    return cls(**values)


def packaged(name: str) -> Path:
    """The path of a parameter file packaged in fivebar_drake/data/."""
    return Path(str(resources.files("fivebar_drake") / "data" / name))


def load_parameter_file(path: str | Path | None, default: str, build):
    """build(the file's tables) for the TOML file at path (None: the packaged file `default`);
    a ParameterError of either names the file."""
    source = packaged(default) if path is None else Path(path)
    data = read_toml(source)
    try:
        return build(data)
    except ParameterError as err:
        raise err.located(source) from None
