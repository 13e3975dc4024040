"""The quadruped's 5-bar leg as a study (`fivebar-drake analyze|simulate`, the default
mechanism): the seed's torque analysis of one leg over a foot path and the Drake simulation of
the trotting robot, through fivebar_drake.pipeline (the Study contract of studies/base.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Callable, NamedTuple

from fivebar_drake import pipeline
from fivebar_drake.core.files import say
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.core.yaml_files import load_yaml
from fivebar_drake.robots.quadruped.config import load_params, with_changes
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.builder import check_run
from fivebar_drake.simulation.runner import SimulationRecord, load_run
from fivebar_drake.studies.base import Plan, Written
from fivebar_drake.studies.fivebar_leg import report

ANALYSIS_FILES = pipeline.ANALYSIS_FILES
SIMULATION_FILES = pipeline.SIMULATION_FILES
OPTIONS = frozenset({"--gait", "--set", "--scenario", "--closure", "--step-check",
                     "--contact-check"})


class Simulated(NamedTuple):
    """A simulation's record and, with --step-check, the same run at half the plant step, with
    --contact-check the same run with the foot contact softer and stiffer (by label)."""

    record: SimulationRecord
    half: SimulationRecord | None
    contacts: dict[str, SimulationRecord] | None = None


def with_sets(params: Params, sets: list[str] | None) -> Params:
    """The parameters with the command line's --set FIELD=VALUE edits (each VALUE read as a
    sweep's spec reads it: YAML, so integers and lists too), their foot paths checked
    (ParameterError naming the command line)."""
    if not sets:
        return params
    from fivebar_drake.robots.quadruped.config import check_gait_reachable

    changes = {}
    for item in sets:
        field, sep, text = item.partition("=")
        if not sep or not field:
            raise ParameterError(f"--set {item}: write FIELD=VALUE, e.g. motor.gear_ratio=11.5",
                                 "--set", "command line")
        # the value as a sweep's spec gives it: YAML 1.2 (a number, an integer, a list, a word)
        changes[field.strip()] = load_yaml(text, "command line (--set)",
                                           f" (--set {item})")
    try:
        params = with_changes(params, changes)
        check_gait_reachable(params)          # the edited leg, gait or limits
        return params
    except ParameterError as err:
        raise err.located("command line (--set)") from None


def load_analysis(config: str | Path | None, gait: str | None = None,
                  sets: list[str] | None = None) -> Plan:
    """The parameters with the foot path's own gait fields (with_path_defaults, as simulate
    runs it) and the --set edits over them, and the foot path (default: the seed's ellipse)."""
    from fivebar_drake.robots.quadruped.config import check_path, with_path_defaults

    path = gait or "seed_ellipse"
    params = with_sets(with_path_defaults(load_params(config), path), sets)
    try:
        check_path(params, path)
    except ParameterError as err:
        raise err.located(f"command line (--gait {path})") from None
    return Plan((params, path), (f"parameters: {config or 'packaged default'}",))


def analyze(inputs: tuple[Params, str]) -> pipeline.AnalysisRecord:
    return pipeline.run_analysis(*inputs)


def write_analysis(record: pipeline.AnalysisRecord, out: Path) -> Written:
    warning = record.sampling_error["warning"]
    return Written(pipeline.write_analysis(record, out), report.analysis_lines(record),
                   warnings=[f"warning: {warning}"] if warning else [])


def load_simulation(config: str | Path | None, duration_s: float | None,
                    scenario: str | None = None, gait: str | None = None,
                    closure: str | None = None, sets: list[str] | None = None,
                    step_check: bool | None = None, contact_check: bool | None = None) -> Plan:
    """The scenario (its file, or the built-in one) with the command line's overrides, its
    parameters (--config overrides the scenario's params_file) with their --set edits, every
    check before a run; and whether to run the step check and the contact check."""
    scenario_, params = load_run(scenario, duration_s=duration_s, closure=closure, gait=gait,
                                 params_file=config)
    used = scenario_.gait.gait_fields()
    for item in sets or ():                  # a gait field the path never reads does nothing
        name = item.partition("=")[0].strip()
        if name.startswith("gait.") and name[len("gait."):] not in used:
            raise ParameterError(f"--set {item}: the {scenario_.gait.kind} path does not read "
                                 f"{name} (it reads gait.{', gait.'.join(used)})", "--set",
                                 "command line")
    params = with_sets(params, sets)
    if sets or step_check:                   # the edited robot, before the folder is touched
        design = check_run(scenario_, params)
    if step_check:                           # and the step check's run at half the step
        half = dataclasses.replace(scenario_, time_step_s=design.time_step_s / 2)
        try:
            half.validate()
            check_run(half, params)
        except ParameterError as err:
            raise ParameterError(f"--step-check runs again at half the plant step "
                                 f"({half.time_step_s:g} s), which fails its checks: "
                                 f"{err.message}", err.field, err.source) from None
    if contact_check:                        # and the contact check's contacts
        for factor in pipeline.CONTACT_FACTORS.values():
            try:
                check_run(scenario_, with_changes(params, {
                    "body.foot_stiffness_N_m": factor * params.body.foot_stiffness_N_m}))
            except ParameterError as err:
                raise ParameterError(f"--contact-check runs again with the foot stiffness x"
                                     f"{factor:g}, which fails its checks: {err.message}",
                                     err.field, err.source) from None
    return Plan((scenario_, params, bool(step_check), bool(contact_check)))


def simulate(inputs, progress: bool, stop: Callable[[], str]) -> Simulated:
    """The run, and (unless the run failed or was stopped) with the step check the same run at
    half the plant step, with the contact check the same run with the foot contact softer and
    stiffer."""
    scenario, params, step_check, contact_check = inputs
    record = pipeline.run_simulation(scenario, params, progress=progress, stop=stop)
    if record.error or record.interrupted or stop():
        return Simulated(record, None, None)
    half = contacts = None
    if step_check:
        if progress:
            say(f"step check: the same run at half the plant step "
                f"({record.design.time_step_s / 2:g} s)")
        half = pipeline.run_step_check(record, progress=progress, stop=stop)
    if contact_check and not stop():
        if progress:
            say("contact check: the same run with the foot contact softer and stiffer (x"
                + ", x".join(f"{f:g}" for f in pipeline.CONTACT_FACTORS.values()) + ")")
        contacts = pipeline.run_contact_check(record, progress=progress, stop=stop)
    return Simulated(record, half, contacts)  # interrupted: the summary says there is no check


def write_simulation(run: Simulated, out: Path) -> Written:
    """The plots, recording and summary (summary.json last); exit 1 for a run that stopped
    early, has no verdict or did not achieve its motion."""
    summary, files = pipeline.write_simulation(run.record, out, run.half,
                                               contacts=run.contacts)
    return Written(files, report.simulation_lines(summary),
                   closing=[report.recording_line(out / pipeline.RECORDING_FILE)],
                   warnings=report.simulation_warnings(run.record.params),
                   failure=report.failure(run.record, summary),
                   interrupted=(f"{summary['error']}: wrote what was simulated (summary.json: "
                                "completed false, interrupted true)"
                                if run.record.interrupted else
                                f"{summary['step_check_interrupted']}: wrote the run without its "
                                "step check (summary.json: step_check_interrupted)"
                                if summary["step_check_interrupted"] else ""),
                   timed=False)
