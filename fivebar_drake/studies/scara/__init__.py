"""The SCARA arm of seed 002 as a study (`fivebar-drake analyze|simulate --mechanism scara`),
the Study contract of studies/base.py: the analysis (report.md, report.json, plots) and a Drake
Diagram following the seed's trajectory with the sized motors (summary, plot, Rerun)."""

from __future__ import annotations

from pathlib import Path

from fivebar_drake.mechanisms.scara import ScaraParams, load_params
from fivebar_drake.studies import base
from fivebar_drake.studies.scara import analysis, plots, recording, report, simulation

NAME = "scara"
ANALYSIS_FILES = plots.ANALYSIS_FIGURES + report.ANALYSIS_FILES
SIMULATION_FILES = plots.SIMULATION_FIGURES + (recording.RECORDING_FILE,) + report.SIMULATION_FILES
OPTIONS = frozenset()

load_analysis = base.parameters_loader(NAME, load_params)
analyze = analysis.analyze
write_analysis = base.analysis_writer(plots, report)
load_simulation = base.simulation_loader(NAME, load_params, simulation.duration_limits)


def simulate(inputs: tuple[ScaraParams, float], progress: bool,
             stop) -> tuple[ScaraParams, simulation.Run]:
    """The run, a progress line every simulated second; a stop request ends it early."""
    params, duration = inputs
    return params, simulation.run(params, duration, progress, stop)


def write_simulation(record: tuple[ScaraParams, simulation.Run], out: Path) -> base.Written:
    """sim_tracking.png, run.rrd, summary.md and summary.json (last)."""
    params, run = record
    summary = simulation.summarize(params, run)
    error = summary.pop("error_series")
    path = out / recording.RECORDING_FILE
    return base.Written([*plots.write_simulation(run, summary, error, out),
                         recording.write_recording(path, params, run, error),
                         *report.write_simulation(summary, out)],
                        report.simulation_lines(summary, path),
                        interrupted=base.stopped_early(run.interrupted, run.t))
