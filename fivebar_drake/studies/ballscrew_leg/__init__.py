"""Study of seed 001: the serial two-link leg with a ball-screw knee against the geared knee
(`fivebar-drake analyze|simulate --mechanism ballscrew_leg`), the Study contract of
studies/base.py."""

from __future__ import annotations

from pathlib import Path

from fivebar_drake.mechanisms.ballscrew_leg import Params, load_params
from fivebar_drake.studies import base
from fivebar_drake.studies.ballscrew_leg import analysis, plots, recording, report, simulation

NAME = "ballscrew_leg"
ANALYSIS_FILES = plots.ANALYSIS_FIGURES + report.ANALYSIS_FILES
SIMULATION_FILES = plots.SIMULATION_FIGURES + (recording.RECORDING_FILE,) + report.SIMULATION_FILES
OPTIONS = frozenset()

load_analysis = base.parameters_loader(NAME, load_params)
analyze = analysis.analyze
write_analysis = base.analysis_writer(plots, report)
load_simulation = base.simulation_loader(NAME, load_params, simulation.duration_limits)


def simulate(inputs: tuple[Params, float], progress: bool, stop) -> simulation.SquatRun:
    """The squat (no progress lines; a stop request ends it early)."""
    return simulation.run_squat(*inputs, stop=stop)


def write_simulation(run: simulation.SquatRun, out: Path) -> base.Written:
    """squat.png, run.rrd, summary.md and summary.json (last)."""
    sig = simulation.signals(run)
    summary = simulation.summarize(run, sig)
    path = out / recording.RECORDING_FILE
    return base.Written([*plots.write_simulation(sig, run.params, out),
                         recording.write_recording(sig, run.params, path),
                         *report.write_simulation(summary, out)],
                        report.simulation_lines(summary, path),
                        interrupted=base.stopped_early(run.interrupted, run.t))
