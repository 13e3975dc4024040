"""Study of seed 001: the serial two-link leg with a ball-screw knee against the geared knee
(`fivebar-drake analyze|simulate --mechanism ballscrew_leg`), the Study contract of
studies/base.py."""

from __future__ import annotations

from pathlib import Path

from fivebar_drake.mechanisms.ballscrew_leg import Params, load_params
from fivebar_drake.studies.ballscrew_leg import plots, recording, report
from fivebar_drake.studies.ballscrew_leg.analysis import Analysis, analyze
from fivebar_drake.studies.ballscrew_leg.simulation import (MAX_DURATION_S, SquatRun, run_squat,
                                                            signals, summarize)
from fivebar_drake.studies.base import (Plan, Written, checked_duration, parameters_line,
                                        parameters_loader)

NAME = "ballscrew_leg"
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
    """The parameters and the squat's duration (at most MAX_DURATION_S)."""
    params = load_params(config)
    return Plan((params, checked_duration(duration_s, params.simulation.duration_s,
                                          high=MAX_DURATION_S)), parameters_line(NAME, config))


def simulate(inputs: tuple[Params, float], progress: bool, stop) -> SquatRun:
    """The squat (in one piece: neither progress lines nor an early stop)."""
    return run_squat(*inputs)


def write_simulation(run: SquatRun, out: Path) -> Written:
    """squat.png, run.rrd, summary.md and summary.json (last)."""
    sig = signals(run)
    summary = summarize(run, sig)
    path = out / recording.RECORDING_FILE
    return Written([*plots.write_simulation(sig, run.params, out),
                    recording.write_recording(sig, run.params, path),
                    *report.write_simulation(summary, out)],
                   report.simulation_lines(summary, path))
