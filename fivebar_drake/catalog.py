"""The mechanisms the command line knows, by name, and the study of each: a package under
`fivebar_drake.studies` keeping the Study contract (studies/base.py), imported only when asked
for. A new mechanism is a folder under mechanisms/, one under studies/ and an entry here."""

from __future__ import annotations

import importlib
from types import ModuleType

FIVEBAR = "fivebar_leg"          # the default: the quadruped's 5-bar leg
MECHANISMS = (FIVEBAR, "ballscrew_leg", "scara", "parallel4")


def study(name: str) -> ModuleType:
    """The study of a mechanism, a module keeping studies/base.py's Study contract (KeyError
    names the choices)."""
    if name not in MECHANISMS:
        raise KeyError(f"no study for mechanism {name!r}; known: {list(MECHANISMS)}")
    return importlib.import_module(f"fivebar_drake.studies.{name}")


def default_out(name: str, command: str) -> str:
    """The output folder of `command` (analyze, simulate) when --out is not given: out/analysis
    and out/simulation for the default mechanism, out/NAME and out/simulation/NAME for another."""
    if name == FIVEBAR:
        return "out/analysis" if command == "analyze" else "out/simulation"
    return f"out/{name}" if command == "analyze" else f"out/simulation/{name}"


def can_simulate(name: str) -> bool:
    """Whether `simulate --mechanism name` exists."""
    return bool(study(name).SIMULATION_FILES)
