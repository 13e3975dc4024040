"""The contract every study keeps: one mechanism end to end, analysed and simulated.

A study is a package `fivebar_drake/studies/<name>/` named in catalog.STUDIES. Its `__init__.py` is
the contract (the module satisfies `Study`); the work sits in files of the same names in every
study, each only where the study has it:

    model.py       the Drake model (SDF, plant)
    analysis.py    the analysis: parameters -> record (plain data)
    simulation.py  the Drake Diagram and its run: parameters -> record (plain data), its summary
    plots.py       the figures of both jobs (PNG)
    report.py      the text of both jobs: report.md and report.json, summary.md and summary.json,
                   the lines the command line prints
    recording.py   the run's Rerun recording (run.rrd)

The command line runs every mechanism the same way (cli.py): load (every input checked, exit 2
before anything is written), the output folder cleared of the job's files, the heading printed,
run, write, the lines printed.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, NamedTuple, Protocol, Sequence, runtime_checkable

from fivebar_drake.core.validation import MAX_PLANT_STEPS, ParameterError, check_number


class Plan(NamedTuple):
    """A job checked and ready to run: its inputs (of the study's own kind) and the lines the
    command line prints before it runs."""

    inputs: Any
    heading: Sequence[str] = ()


class Written(NamedTuple):
    """What a job wrote and what the command line says about it: the files in the order
    written; the lines printed before the list of files (the headline figures) and after it;
    the warnings (stderr); `failure`, why the job failed (stderr, exit 1: the run stopped early,
    has no verdict, ...); `interrupted`, what a run stopped by a signal wrote (stderr, exit 130 or
    143); `timed`: the list of files names the job's wall time (a simulation summary that gives
    its own real-time factor does not)."""

    files: Sequence[Path]
    lines: Sequence[str] = ()
    closing: Sequence[str] = ()
    warnings: Sequence[str] = ()
    failure: str = ""
    interrupted: str = ""
    timed: bool = True


@runtime_checkable
class Study(Protocol):
    """A study's `__init__.py`. `load_*` take the command line's --config (None: the packaged
    parameter file) and the study's own OPTIONS by their argparse names (`--step-check` as
    step_check, `--set` as sets); they raise ParameterError naming the file or the command line
    and the field. `stop` is polled by a simulation that can end early (a non-empty answer, a
    signal's name, ends it there); `progress` prints progress lines."""

    ANALYSIS_FILES: tuple[str, ...]     # the names write_analysis writes (report.json last)
    SIMULATION_FILES: tuple[str, ...]   # those write_simulation writes (summary.json last); ()
    #                                     without a simulation
    OPTIONS: frozenset[str]             # command-line options of its own (e.g. "--gait")

    def load_params(self, config: str | Path | None) -> Any: ...

    def load_analysis(self, config: str | Path | None, **options) -> Plan: ...

    def analyze(self, inputs) -> Any: ...

    def write_analysis(self, record, out: Path) -> Written: ...

    def load_simulation(self, config: str | Path | None, duration_s: float | None,
                        **options) -> Plan: ...

    def simulate(self, inputs, progress: bool, stop: Callable[[], str]) -> Any: ...

    def write_simulation(self, record, out: Path) -> Written: ...


MIN_RUN_STEPS = 10     # a run shorter than this many plant steps records next to nothing


def duration_limits(default: float, time_step_s: float, most_s: float = math.inf) -> dict:
    """checked_duration's limits of a study's run: its default, at least MIN_RUN_STEPS plant
    steps, at most most_s and core.validation.MAX_PLANT_STEPS steps."""
    high = min(most_s, MAX_PLANT_STEPS * time_step_s)
    return {"default": default, "low": MIN_RUN_STEPS * time_step_s, "high": high,
            "why": f"{MIN_RUN_STEPS} .. {MAX_PLANT_STEPS:g} plant steps of {time_step_s:g} s"
                   + (f", at most {most_s:g} s" if high == most_s else "")}


def stopped_early(interrupted: str, t) -> str:
    """Written.interrupted of a run a signal stopped early ("" if none did)."""
    end = float(t[-1]) if len(t) else 0.0
    return (f"interrupted by {interrupted} at t = {end:.2f} s: wrote what was simulated"
            if interrupted else "")


def parameters_line(name: str, config: str | Path | None) -> tuple[str]:
    """The heading of a study's job: its name and parameter file."""
    return (f"{name} parameters: {config or 'packaged default'}",)


def parameters_loader(name: str, load_params: Callable) -> Callable[..., Plan]:
    """load_analysis of a study whose analysis takes its parameter file alone."""
    def load_analysis(config: str | Path | None) -> Plan:
        return Plan(load_params(config), parameters_line(name, config))
    return load_analysis


def simulation_loader(name: str, load_params: Callable,
                      duration_limits: Callable[[Any], dict]) -> Callable[..., Plan]:
    """load_simulation of a study whose simulation takes its parameter file and --duration:
    inputs (params, duration in s), the duration checked within duration_limits(params)
    (checked_duration's default, low, high, why)."""
    def load_simulation(config: str | Path | None, duration_s: float | None) -> Plan:
        params = load_params(config)
        return Plan((params, checked_duration(duration_s, **duration_limits(params))),
                    parameters_line(name, config))
    return load_simulation


def analysis_writer(plots, report) -> Callable[[Any, Path], Written]:
    """write_analysis of a study whose plots module writes the analysis's figures
    (plots.write_analysis) and whose report module its report.md and report.json
    (report.write_analysis) and the lines about it (report.analysis_lines)."""
    def write_analysis(record, out: Path) -> Written:
        return Written(plots.write_analysis(record, out) + report.write_analysis(record, out),
                       report.analysis_lines(record))
    return write_analysis


def checked_duration(duration_s: float | None, default: float, low: float = 0.0,
                     high: float = math.inf, why: str = "") -> float:
    """The command line's --duration (None: the parameter file's default): a number > 0, then
    within low .. high (low excluded when it is 0); ParameterError from the command line (or
    the parameter file, for its default) otherwise."""
    name, value = ("--duration", duration_s) if duration_s is not None else (
        "the run's duration (parameter file)", default)
    try:
        check_number(name, value, 0.0, low_open=True)
        return check_number(name, value, low, high, low_open=low == 0.0, why=why)
    except ParameterError as err:
        raise err.located("command line" if duration_s is not None else "parameter file") \
            from None


def claims_answer(claims: Sequence[dict], what: str) -> str:
    """A seed check's first line (docs/output_style.md): how many readings of the seed's claims
    reproduce its numbers, and which claims none of them does. claims: dicts with "id" and
    "reproduced"; what: the claims' subject."""
    ids = list(dict.fromkeys(c["id"] for c in claims))
    none = [i for i in ids if not any(c["reproduced"] for c in claims if c["id"] == i)]
    held = sum(bool(c["reproduced"]) for c in claims)
    return (f"**Answer:** {held} of {len(claims)} readings of the seed's {what} reproduce its "
            f"numbers; {len(ids) - len(none)} of {len(ids)} claims by at least one reading"
            + (f" (none for {', '.join(none)})." if none else "."))
