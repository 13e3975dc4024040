"""The mechanisms the command line knows, by name, and the study module of each.

`fivebar_leg` is the quadruped's 5-bar leg (pipeline.py); every other name is a package under
`fivebar_drake.studies`, imported only when asked for, that offers:

    ANALYSIS_FILES: tuple[str, ...]          the files write_analysis writes (the last one last)
    load_params(config: str | Path | None)   its validated parameters (ParameterError naming the
                                             file and field), None for the packaged file
    write_analysis(params, out: Path) -> (lines: list[str], written: list[Path])
        the analysis, its report and plots written into out; lines: what the command line
        prints about it (the headline numbers)
and, if it can be simulated:
    SIMULATION_FILES: tuple[str, ...]
    write_simulation(params, out: Path, duration_s: float | None, progress: bool)
        -> (lines, written)
"""

from __future__ import annotations

import importlib
from types import ModuleType

FIVEBAR = "fivebar_leg"
STUDIES = {
    "ballscrew_leg": "fivebar_drake.studies.ballscrew_leg",
    "scara": "fivebar_drake.studies.scara",
    "parallel4": "fivebar_drake.studies.parallel4",
}
MECHANISMS = (FIVEBAR, *STUDIES)


def study(name: str) -> ModuleType:
    """The study module of a mechanism other than the 5-bar leg (KeyError names the choices)."""
    if name not in STUDIES:
        raise KeyError(f"no study for mechanism {name!r}; known: {list(STUDIES)}")
    return importlib.import_module(STUDIES[name])


def can_simulate(name: str) -> bool:
    """Whether `simulate --mechanism name` exists."""
    return name == FIVEBAR or hasattr(study(name), "write_simulation")
