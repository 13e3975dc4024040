"""The toolkit's two jobs as functions: run, then write, with plain records in between.

    run_analysis(config, gait)  -> AnalysisRecord    -> write_analysis(record, out_dir)
    run_simulation(scenario)    -> SimulationRecord  -> summarize_run(record)
                                                     -> write_simulation(record, out_dir)

A record is plain data (numpy arrays and dataclasses: the parameters, the scenario, the plant's
layout, the closure design, the controller gains, the recorded table; no Drake object), so it
pickles: a run can happen in another process (a sweep's worker) and be summarized, plotted and
recorded here, or later. The command line, the notebooks and the benchmarks go through these
functions; the writers keep the command line's guarantees: each file written atomically, the
previous run's files removed first, report.json and summary.json written last (a folder holding
one holds a complete set, and summary.json's `completed` says whether the run reached its
duration).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
import time
from typing import Callable

from fivebar_drake.analysis.plots import write_plots
from fivebar_drake.analysis.report import ANALYSIS_FILES, write_report
from fivebar_drake.analysis.torques import Analysis, analyze, seed_results
from fivebar_drake.core.files import prepare_output_dir
from fivebar_drake.verdicts.summary_schema import AnyController, Summary
from fivebar_drake.verdicts.rules import beyond_limit, fails_for
from fivebar_drake.optimal import vertical_jump
from fivebar_drake.optimal.needs import needs_of
from fivebar_drake.optimal.vertical_jump import Need
from fivebar_drake.optimal.report import max_jump_plan
from fivebar_drake.robots.quadruped.config import load_params, sampling_error, with_changes
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.plots import CAPABILITY_FILE, SIM_PLOT_FILES, write_sim_plots
from fivebar_drake.simulation.recording import RECORDING_FILE, write_recording
from fivebar_drake.simulation.runner import SimulationRecord, simulate
from fivebar_drake.simulation.scenario import Scenario, load_scenario
from fivebar_drake.simulation.signals import signals, step_signals
from fivebar_drake.simulation.summary import (apply_contact_check, apply_step_check,
                                              in_schema_order, set_answer, summarize)
from fivebar_drake.simulation.summary_text import SUMMARY_FILES, write_summary


SIMULATION_FILES = (SIM_PLOT_FILES + (CAPABILITY_FILE, RECORDING_FILE)
                    + SUMMARY_FILES)   # summary.json last


@dataclass(frozen=True)
class AnalysisRecord:
    """The torque analysis of one foot path as plain data: the Analysis (parameters, sampled
    gait, each model's torques in N*m, singularity measures, the JSON-ready results) and the
    sampling error of its central differences (config.sampling_error: relative errors of the
    peak joint speed and acceleration, the reference sample count, a warning or "")."""

    analysis: Analysis
    sampling_error: dict

    @property
    def params(self) -> Params:
        return self.analysis.params

    @property
    def results(self) -> dict:
        """report.json's results: per model ("seed", "full", "full_trot") and motor."""
        return self.analysis.results["results"]


def run_analysis(config: str | Path | Params | None = None,
                 gait: str = "seed_ellipse") -> AnalysisRecord:
    """The seed's torque analysis over one cycle of the foot path `gait` (gaits.PATHS).
    config: a parameter file (TOML), None for the packaged one, or parameters already loaded.
    ParameterError naming the file and field for a bad parameter file."""
    params = config if isinstance(config, Params) else load_params(config)
    return AnalysisRecord(analysis=analyze(params, path=gait),
                          sampling_error=sampling_error(params, gait))


def write_analysis(record: AnalysisRecord, out_dir: str | Path) -> list[Path]:
    """Write ANALYSIS_FILES into out_dir (made if needed), each atomically: first remove a
    previous analysis's files, then the plots, report.md and report.json last. Returns the
    paths in the order written."""
    out = prepare_output_dir(out_dir, "out_dir", ANALYSIS_FILES)
    return write_plots(record.analysis, out) + write_report(record.analysis, out,
                                                            record.sampling_error)


def run_simulation(scenario: Scenario, params: Params | None = None, progress: bool = True,
                   stop: Callable[[], str] | None = None,
                   log_actuation: bool = False) -> SimulationRecord:
    """Simulate the scenario (a validated copy of it; every check before a run first:
    ParameterError naming the field); params: None loads the scenario's
    (Scenario.load_params). progress: print progress lines to stderr.
    stop: polled every 10 ms of simulated time, a non-empty answer (a signal's name) ends the
    run there (record.interrupted). log_actuation: also record the joint torques the plant
    received at every step (record.actuation). A run that stops early (diverged, fell over)
    still returns what it recorded, with record.error saying why."""
    scenario = dataclasses.replace(scenario)
    scenario.validate()
    return simulate(scenario, scenario.load_params() if params is None else params,
                    progress=progress, log_actuation=log_actuation, stop=stop)


MAX_JUMP_MARGIN_S = 0.1   # the max jump's run goes this past its span (its last sample in)


def max_jump_scenario(params: Params, ceiling: vertical_jump.Jump,
                      payload_kg: float = 0.0) -> Scenario:
    """The scenario of the highest jump's simulation (`optimal --simulate`, the co-design's
    max_jump): the jump maneuver planned at the ceiling (optimal.report.max_jump_plan) with
    the tracking controller, from standing to MAX_JUMP_MARGIN_S past its span (the duration
    rounded to 1 ms)."""
    plan = max_jump_plan(params, ceiling, payload_kg)
    return load_scenario(gait=plan, payload_kg=payload_kg, controller={"kind": "tracking"},
                         duration_s=round(Scenario().stand_s + plan.span_s(params.gait)
                                          + MAX_JUMP_MARGIN_S, 3))


TOP_SPEED_RUN_S = 3.0     # a top speed's tracked run: this long after the stand and the ramp


def top_speed_scenario(kind: str, payload_kg: float = 0.0, duty_factor: float | None = None,
                       share: float = 1.0) -> Scenario:
    """The scenario of a gait's top speed tracked (`optimal --simulate`): the gait at its top
    speed (gait: {kind: KIND, speed_m_s: max}, runner.at_top_speed; at duty_factor alone where
    given; at that share of it, Scenario.top_speed_share) with the tracking controller,
    TOP_SPEED_RUN_S of gait after the stand and the ramp."""
    default = Scenario()
    gait = {"kind": kind, "speed_m_s": "max", "share": share}
    if duty_factor is not None:
        gait["duty_factor"] = duty_factor
    return load_scenario(gait=gait, payload_kg=payload_kg,
                         controller={"kind": "tracking"},
                         duration_s=round(default.stand_s + default.ramp_s + TOP_SPEED_RUN_S, 3))


def run_step_check(record: SimulationRecord, progress: bool = True,
                   stop: Callable[[], str] | None = None) -> SimulationRecord:
    """The run's scenario again at half its plant step (the step check: summarize_run and
    write_simulation take it as `half`)."""
    scenario = dataclasses.replace(record.scenario, time_step_s=record.design.time_step_s / 2)
    return run_simulation(scenario, record.params, progress=progress, stop=stop)


CONTACT_FACTORS = {"softer": 0.5, "stiffer": 2.0}   # the contact check's foot stiffness factors


def run_contact_check(record: SimulationRecord, progress: bool = True,
                      stop: Callable[[], str] | None = None) -> dict[str, SimulationRecord]:
    """The run's scenario again with the foot contact softer and stiffer (the contact check:
    summarize_run and write_simulation take it as `contacts`): the foot's point-contact
    stiffness times each of CONTACT_FACTORS, its relaxation time kept (SAP's dissipation, the
    relaxation time times the stiffness, scales with it). A run stopped by `stop` ends the check
    there (the variants run so far)."""
    k = record.params.body.foot_stiffness_N_m
    out = {}
    for label, factor in CONTACT_FACTORS.items():
        if stop is not None and stop():
            break
        params = with_changes(record.params, {"body.foot_stiffness_N_m": factor * k})
        out[label] = run_simulation(record.scenario, params, progress=progress, stop=stop)
    return out


def _signals(record: SimulationRecord) -> tuple:
    """(Signals, StepSignals or None: a one-shot maneuver's plant steps) of a run."""
    return signals(record), step_signals(record) if record.steps is not None else None


def any_controller(record: SimulationRecord, summary: Summary) -> AnyController:
    """What any controller would need for the run's path (optimal/needs.py: its kind's need
    function, built-in or a plugin's; on the run's payload): each phase's need in the quadrant
    it acts beside what the run's controller asked in it (a phase the run measured by name, the
    largest demand peak of its motors otherwise), the optima and the bound, and whom a failing
    verdict blames (verdict_split). A path whose kind has no floor: one phase, unknown."""
    path, params = record.scenario.gait, record.params
    needs = needs_of(params, path, record.scenario.payload_kg)
    if needs is None:
        needs = {path.kind: (Need("unknown", None, f"no floor for the {path.kind} path", None),
                             params.motor.peak_torque_Nm)}
    measured = {name: figures["demand_peak_Nm"] for name, figures in
                (summary["phases"] or {}).items()}
    by_name = bool(set(measured) & set(needs))     # the run measured these phases by name
    phases = {name: _phase(need.status, need.floor_Nm, limit,
                           measured.get(name) if by_name else _most_asked(summary))
              for name, (need, limit) in needs.items()}
    why = [need.why for need, _ in needs.values() if need.why]
    first = next(iter(needs.values()))[0]
    return verdict_split(record, path.kind, getattr(path, "height_m", 0.0), phases, why, summary,
                         ceiling_m=first.stroke_optimum_m, reach_ceiling_m=first.reach_optimum_m,
                         bound_m=first.bound_m, reached_m=(summary["jump"] or {}).get("height_m"))


def _phase(status: str, floor: float | None, limit: float, asked: float | None) -> dict:
    """A phase's need (summary_schema.PhaseFloor)."""
    return {"status": status, "floor_Nm": floor, "limit_Nm": limit, "asked_Nm": asked}


def _most_asked(summary: Summary) -> float | None:
    """The largest demand peak (N*m) of the run's motors (None: none finite)."""
    return max((m["demand_peak_Nm"] for motors in summary["legs"].values()
                for m in motors.values() if math.isfinite(m["demand_peak_Nm"])), default=None)


def verdict_split(record: SimulationRecord, maneuver: str, height_m: float, phases: dict,
                  why: list[str], summary: Summary, ceiling_m: float | None = None,
                  reach_ceiling_m: float | None = None, bound_m: float | None = None,
                  reached_m: float | None = None) -> AnyController:
    """The summary's any_controller from each phase's need (_phase): on a slope every phase has
    none (the floors model flat ground: unknown); the maneuver's floor (the largest; None if a
    phase has none), its safety factor (the least of each phase's limit over its floor), what
    the controller asked at most and its cost, and whom a failing verdict blames
    (verdicts.rules.fails_for, the one rule)."""
    params = record.params
    if record.scenario.slope_deg:
        phases = {name: {**p, "status": "unknown", "floor_Nm": None}
                  for name, p in phases.items()}
        why = why + [f"no floor on a {record.scenario.slope_deg:g} deg slope (the floors model "
                     "flat ground)"]
    floors = [p["floor_Nm"] for p in phases.values()]
    floor = None if None in floors else max(floors)
    most = max((p["asked_Nm"] for p in phases.values() if p["asked_Nm"] is not None),
               default=None)
    floor_sf = (None if floor is None else
                min(p["limit_Nm"] / p["floor_Nm"] for p in phases.values()))
    blamed = fails_for(summary["verdict"], phases, params.checks.floor_margin)
    if blamed == "this controller" and any(
            p["status"] == "floor" and beyond_limit(p["floor_Nm"], p["limit_Nm"],
                                                    params.checks.floor_margin)
            for p in phases.values()):
        why.append("the run did its motion, so its floor's claim is set aside")
    return {"maneuver": maneuver, "height_m": height_m, "phases": phases,
            "floor_Nm": floor, "floor_safety_factor": floor_sf,
            "floor_margin": params.checks.floor_margin, "ceiling_m": ceiling_m,
            "reach_ceiling_m": reach_ceiling_m, "bound_m": bound_m, "reached_m": reached_m,
            "asked_Nm": most,
            "controller_cost": most / floor if most is not None and floor else None,
            "fails_for": blamed, "why": "; ".join(why)}


def _review(record: SimulationRecord, half: SimulationRecord | None = None,
            contacts: dict[str, SimulationRecord] | None = None):
    """(Signals, StepSignals or None, Summary) of a run; with `half` (run_step_check) its step
    check (any_controller's split recomputed at half the step); with `contacts`
    (run_contact_check) its contact check; its any_controller."""
    sig, steps = _signals(record)
    reference = seed_results(record.params)
    summary = summarize(sig, record, reference, steps)
    verdict = summary["verdict"]
    summary = in_schema_order({**summary, "any_controller": any_controller(record, summary)})
    if half is not None and half.interrupted:    # a step check cut short is none, and says so
        summary["step_check_interrupted"] = (
            f"{half.interrupted} stopped the run at half the plant step at t = "
            f"{half.table['t'][-1] if len(half.table['t']) else 0.0:.2f} s")
    set_answer(summary, record.params)
    if half is not None and not half.interrupted:
        apply_step_check(summary, _variant(half, reference), record.params)
    if contacts and not any(r.interrupted for r in contacts.values()):
        apply_contact_check(summary, verdict, {label: _variant(r, reference)
                                               for label, r in contacts.items()}, record.params)
    return sig, steps, summary


def _variant(record: SimulationRecord, reference: dict) -> Summary:
    """The summary of a check's run (at half the step, another contact) with its any_controller."""
    sig, steps = _signals(record)
    summary = summarize(sig, record, reference, steps)
    summary["any_controller"] = any_controller(record, summary)
    return summary


def summarize_run(record: SimulationRecord, half: SimulationRecord | None = None,
                  contacts: dict[str, SimulationRecord] | None = None) -> Summary:
    """The run's summary (summary.json's dictionary, SI units): whole-cycle statistics per leg
    and motor against the static estimates, the checks, the verdict and the answer in one
    sentence; with `half`, the same run at half the plant step (run_step_check), the step
    check (summary["step_check"], verdict "marginal" where the step error reaches a
    threshold); with `contacts` (run_contact_check), the contact check
    (summary["contact_check"], verdict "marginal" where the contact decides it)."""
    return _review(record, half, contacts)[2]


def write_simulation(record: SimulationRecord, out_dir: str | Path,
                     half: SimulationRecord | None = None, name: str = "",
                     contacts: dict[str, SimulationRecord] | None = None
                     ) -> tuple[Summary, list[Path]]:
    """Write SIMULATION_FILES into out_dir (made if needed), each atomically: first remove a
    previous run's files, then the plots, the Rerun recording, summary.md and summary.json
    last, so a summary.json always describes complete files. Returns (the summary as written,
    the paths in the order written). half: the step check's run (summarize_run); name: the
    run's name in its recording's id; contacts: the contact check's runs (run_contact_check).
    summary["timing"]: simulate_s, the wall time of the stepping (s; with the step and contact
    checks, of every run), outputs_s, the wall time of this function up to the summary files (the review,
    plots and recording; the summary files take milliseconds), and outputs_share, outputs_s
    over their sum."""
    start = time.perf_counter()
    out = prepare_output_dir(out_dir, "out_dir", SIMULATION_FILES)
    sig, steps, summary = _review(record, half, contacts)
    written = write_sim_plots(sig, record.layout.legs, record.params, summary, out, steps)
    written.append(write_recording(out / RECORDING_FILE, sig, record, summary, name))
    outputs = time.perf_counter() - start
    simulated = record.wall_s + sum(r.wall_s for r in [half, *(contacts or {}).values()]
                                    if r is not None)
    summary["timing"] = {"simulate_s": simulated, "outputs_s": outputs,
                         "outputs_share": outputs / (simulated + outputs)}
    written += write_summary(summary, record.params, out)
    return summary, written
