"""Seed 004's 4-DOF parallel manipulator after Pierrot as a study (`fivebar-drake
analyze|simulate --mechanism parallel4`), the Study contract of studies/base.py: the analysis
(report and plots) and the Drake model's platform moved along the configured path, recorded to
Rerun."""

from __future__ import annotations

from pathlib import Path

from fivebar_drake.core.parameter_files import load_parameter_file
from fivebar_drake.mechanisms.parallel4.params import Params, params_from_dict
from fivebar_drake.studies.base import (Plan, Written, checked_duration, parameters_line,
                                        parameters_loader)
from fivebar_drake.studies.parallel4 import plots, recording, report
from fivebar_drake.studies.parallel4.analysis import Analysis, analyze
from fivebar_drake.studies.parallel4.simulation import Run, run_summary, simulate as run

NAME = "parallel4"
PACKAGED = "parallel4.toml"
ANALYSIS_FILES = plots.ANALYSIS_FIGURES + report.ANALYSIS_FILES
SIMULATION_FILES = (recording.RECORDING_FILE,) + report.SIMULATION_FILES
ANALYSIS_OUT, SIMULATION_OUT = f"out/{NAME}", f"out/simulation/{NAME}"
OPTIONS = frozenset()

__all__ = ["ANALYSIS_FILES", "ANALYSIS_OUT", "OPTIONS", "SIMULATION_FILES", "SIMULATION_OUT",
           "analyze", "load_analysis", "load_params", "load_simulation", "simulate",
           "write_analysis", "write_simulation"]


def load_params(config: str | Path | None) -> Params:
    """The validated parameters of `config` (None: the packaged file); ParameterError naming the
    file and field."""
    return load_parameter_file(config, PACKAGED, params_from_dict)


load_analysis = parameters_loader(NAME, load_params)


def write_analysis(a: Analysis, out: Path) -> Written:
    return Written(plots.write_analysis(a, out) + report.write_analysis(a, out),
                   report.analysis_lines(a))


def load_simulation(config: str | Path | None, duration_s: float | None) -> Plan:
    """The parameters and the run's duration (default: the file's)."""
    params = load_params(config)
    return Plan((params, checked_duration(duration_s, params.simulation.duration_s)),
                parameters_line(NAME, config))


def simulate(inputs: tuple[Params, float], progress: bool, stop) -> tuple[Params, Run]:
    """The run (about a second: neither progress lines nor an early stop)."""
    params, duration = inputs
    return params, run(params, duration)


def write_simulation(record: tuple[Params, Run], out: Path) -> Written:
    """run.rrd, then summary.json (last)."""
    params, r = record
    summary = run_summary(r)
    path = recording.write_recording(out / recording.RECORDING_FILE, params, r)
    return Written([path, *report.write_simulation(summary, out)],
                   report.simulation_lines(summary, path))
