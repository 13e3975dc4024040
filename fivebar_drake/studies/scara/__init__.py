"""The SCARA arm of seed 002 as a study (`fivebar-drake analyze|simulate --mechanism scara`),
the Study contract of studies/base.py: the analysis (report.md, report.json, plots) and a Drake
Diagram following the seed's trajectory with the sized motors (summary, plot, Rerun)."""

from __future__ import annotations

from pathlib import Path

from fivebar_drake.mechanisms.scara import ScaraParams, load_params
from fivebar_drake.studies.base import (Plan, Written, checked_duration, parameters_line,
                                        parameters_loader)
from fivebar_drake.studies.scara import plots, recording, report
from fivebar_drake.studies.scara.analysis import Analysis, analyze
from fivebar_drake.studies.scara.simulation import Run, duration_limits, run, summarize

NAME = "scara"
ANALYSIS_FILES = plots.ANALYSIS_FIGURES + report.ANALYSIS_FILES
SIMULATION_FILES = plots.SIMULATION_FIGURES + (recording.RECORDING_FILE,) + report.SIMULATION_FILES
ANALYSIS_OUT, SIMULATION_OUT = f"out/{NAME}", f"out/simulation/{NAME}"
OPTIONS = frozenset()
load_analysis = parameters_loader(NAME, load_params)

__all__ = ["ANALYSIS_FILES", "ANALYSIS_OUT", "OPTIONS", "SIMULATION_FILES", "SIMULATION_OUT",
           "analyze", "load_analysis", "load_params", "load_simulation", "simulate",
           "write_analysis", "write_simulation"]


def write_analysis(a: Analysis, out: Path) -> Written:
    return Written(plots.write_analysis(a, out) + report.write_analysis(a, out),
                   report.analysis_lines(a))


def load_simulation(config: str | Path | None, duration_s: float | None) -> Plan:
    """The parameters and the run's duration (default: the trajectory's)."""
    params = load_params(config)
    duration = checked_duration(duration_s, params.trajectory.duration_s,
                                **duration_limits(params))
    return Plan((params, duration), parameters_line(NAME, config))


def simulate(inputs: tuple[ScaraParams, float], progress: bool, stop) -> tuple[ScaraParams, Run]:
    """The run, a progress line every simulated second (it does not stop early)."""
    params, duration = inputs
    return params, run(params, duration, progress)


def write_simulation(record: tuple[ScaraParams, Run], out: Path) -> Written:
    """sim_tracking.png, run.rrd, summary.md and summary.json (last)."""
    params, r = record
    summary = summarize(params, r)
    error = summary.pop("error_series")
    path = out / recording.RECORDING_FILE
    return Written([*plots.write_simulation(r, summary, error, out),
                    recording.write_recording(path, params, r, error),
                    *report.write_simulation(summary, out)],
                   report.simulation_lines(summary, path))
