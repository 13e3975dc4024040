"""Seed 004's 4-DOF parallel manipulator after Pierrot as a study (`fivebar-drake
analyze|simulate --mechanism parallel4`), the Study contract of studies/base.py: the analysis
(report and plots) and the Drake model's platform moved along the configured path, recorded to
Rerun."""

from __future__ import annotations

from pathlib import Path

from fivebar_drake.core.parameter_files import load_parameter_file
from fivebar_drake.mechanisms.parallel4.params import Params, params_from_dict
from fivebar_drake.studies import base
from fivebar_drake.studies.parallel4 import analysis, plots, recording, report, simulation

NAME = "parallel4"
PACKAGED = "parallel4.toml"
ANALYSIS_FILES = plots.ANALYSIS_FIGURES + report.ANALYSIS_FILES
SIMULATION_FILES = (recording.RECORDING_FILE,) + report.SIMULATION_FILES
OPTIONS = frozenset()


def load_params(config: str | Path | None) -> Params:
    """The validated parameters of `config` (None: the packaged file); ParameterError naming the
    file and field."""
    return load_parameter_file(config, PACKAGED, params_from_dict)


load_analysis = base.parameters_loader(NAME, load_params)
analyze = analysis.analyze
write_analysis = base.analysis_writer(plots, report)
load_simulation = base.simulation_loader(NAME, load_params, simulation.duration_limits)


def simulate(inputs: tuple[Params, float], progress: bool,
             stop) -> tuple[Params, simulation.Run]:
    """The run (about a second: no progress lines; a stop request ends it early)."""
    params, duration = inputs
    return params, simulation.simulate(params, duration, stop)


def write_simulation(record: tuple[Params, simulation.Run], out: Path) -> base.Written:
    """run.rrd, then summary.json (last)."""
    params, run = record
    summary = simulation.run_summary(run)
    path = recording.write_recording(out / recording.RECORDING_FILE, params, run)
    return base.Written([path, *report.write_simulation(summary, out)],
                        report.simulation_lines(summary, path),
                        interrupted=base.stopped_early(run.interrupted, run.t))
