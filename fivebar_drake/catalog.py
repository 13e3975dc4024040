"""The mechanisms the command line knows, by name, and the study of each: a module keeping the
Study contract (studies/base.py), imported only when asked for. A mechanism here is a folder
under mechanisms/, one under studies/ and its entry in STUDIES; another package's registers its
study module with register_study from a module named by an entry point (core/plugins.py)."""

from __future__ import annotations

import importlib
from types import ModuleType

from fivebar_drake.core import plugins

FIVEBAR = "fivebar_leg"          # the default: the quadruped's 5-bar leg
STUDIES = {name: f"fivebar_drake.studies.{name}"    # mechanism -> the module of its study
           for name in (FIVEBAR, "ballscrew_leg", "scara", "parallel4")}


def register_study(name: str, module: str, replaces: bool = False) -> None:
    """Make `--mechanism name` run the study in `module` (a module path keeping the Study
    contract, imported when asked for); a name another study has is refused unless replaces
    (plugins.claim)."""
    plugins.claim("mechanism", name, STUDIES.get(name), module, replaces)
    STUDIES[name] = module


def mechanisms() -> tuple[str, ...]:
    """Every mechanism's name, this package's and the plugins' (core/plugins.py)."""
    plugins.load()
    return tuple(STUDIES)


def study(name: str) -> ModuleType:
    """The study of a mechanism, a module keeping studies/base.py's Study contract (KeyError
    names the choices)."""
    if name not in mechanisms():
        raise KeyError(f"no study for mechanism {name!r}; known: {list(STUDIES)}")
    return importlib.import_module(STUDIES[name])


def default_out(name: str, command: str) -> str:
    """The output folder of `command` (analyze, simulate) when --out is not given: out/analysis
    and out/simulation for the default mechanism, out/NAME and out/simulation/NAME for another."""
    if name == FIVEBAR:
        return "out/analysis" if command == "analyze" else "out/simulation"
    return f"out/{name}" if command == "analyze" else f"out/simulation/{name}"


def can_simulate(name: str) -> bool:
    """Whether `simulate --mechanism name` exists."""
    return bool(study(name).SIMULATION_FILES)
