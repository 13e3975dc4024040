"""The summary of a simulated run (summary.json's dictionary, SI units; its schema:
verdicts/summary_schema.Summary), composed from three concerns kept apart:

- what was measured: simulation/run_statistics.py (the statistics window, per leg and motor the
  torques against the static estimates and the checks, the motion, the limits reached) and a
  maneuver's own figures beside their plan (simulation/maneuver_figures.py);
- what it means: verdicts/rules.py (achieved or not, the worst motor's verdict, the step check);
- what it says: simulation/summary_text.py (the answer in one sentence, summary.md, the writer of
  summary.md and summary.json);

and what ran (what_ran: each variant's kind and fields, the plan's events, the design, the
motor). Statistics cover the whole gait cycles after the ramp (a one-shot maneuver: its span
after standing); a run with fewer than MIN_CYCLES of them, or one that stopped early, gets the
verdict "insufficient".
"""

from __future__ import annotations

import math

import numpy as np

from fivebar_drake.gaits import Outcome
from fivebar_drake.core import plugins
from fivebar_drake.verdicts.summary_schema import ContactCheck, StepCheck, Summary
from fivebar_drake.verdicts.rules import (achievement, contact_check, contact_checked_verdict,
                                         judge, run_verdict, step_check, step_checked_verdict)
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import standing_height
from fivebar_drake.robots.quadruped.stance_laws import STANCE_LAWS
from fivebar_drake.simulation.maneuver_figures import maneuver_figures
from fivebar_drake.simulation.run_statistics import (MIN_CYCLES, Window, end_height,
                                                     leg_statistics, limit_report,
                                                     motion_statistics, statistics_window)
from fivebar_drake.simulation.runner import DIVERGED_GAP_M, FELL_OVER, SimulationRecord
from fivebar_drake.simulation.signals import Signals, StepSignals
from fivebar_drake.simulation.summary_text import answer, answer_details, seed_analysis_load

BODY_SINK_M = 0.01   # the body's box this far into the ground: the contact model has failed

MANEUVER_KEYS = ("jump", "landing", "phases", "force_capability")


def summarize(sig: Signals, record: SimulationRecord, seed_analysis: dict,
              steps: StepSignals | None) -> Summary:
    """The summary of a run from its signals (signals(record)), its plant steps
    (step_signals(record), a one-shot maneuver's; None for a gait) and record: what ran, the
    statistics over its window, the maneuver's figures, the verdict and the answer.
    seed_analysis: the analysis results of the seed model on the seed's ellipse (report.json's
    results.seed)."""
    scenario, params = record.scenario, record.params
    window = statistics_window(sig, scenario, params)
    legs = leg_statistics(sig, params, window, record.layout.legs)
    motion = motion_statistics(sig, record, window)
    gait_speed = scenario.gait.stance_speed(params.gait)
    maneuver = (None if scenario.gait.periodic else
                maneuver_figures(record, window.start, steps))
    outcome = Outcome(motion["mean_forward_speed_m_s"], end_height(sig, window),
                      standing_height(params), maneuver)
    judge(legs, params.checks, achievement(
        params.checks, scenario.gait.shortfalls(params.gait, outcome, params.checks)
        + broken(sig, params, record.layout.legs), motion["max_tilt_deg"], maneuver))
    sufficient = record.completed and window.cycles >= (MIN_CYCLES if scenario.gait.periodic
                                                        else 1)
    verdict = run_verdict(legs, sufficient)
    if record.error.startswith(FELL_OVER):        # a fall is the motion not done, not a lack
        verdict.update(verdict="not_achieved", deciding_check="achieved")   # of data
    summary = in_schema_order({
        **what_ran(record, window), **verdict, **motion,
        "gait_speed_m_s": gait_speed, **maneuver_summary(maneuver),
        "seed_peak_torque_Nm": max(seed_analysis[m]["peak_torque_Nm"] for m in MOTORS),
        "seed_load_model": seed_analysis_load(params), "step_check": None,
        "step_check_interrupted": "",
        "contact": {"stiffness_N_m": params.body.foot_stiffness_N_m,
                    "relaxation_time_s": params.body.foot_relaxation_time_s},
        "contact_check": None,
        "limits": limit_report(sig, params, record.layout.legs), "legs": legs})
    set_answer(summary, params)
    return summary


def set_answer(summary: Summary, params: Params) -> None:
    """The summary's answer (its one line) and its reasons (answer_details), from its figures:
    set again whenever a check or the need for any controller changes them."""
    summary["answer"] = answer(summary, params)
    summary["answer_details"] = answer_details(summary, params)


def broken(sig: Signals, params: Params, legs) -> list[str]:
    """What left the model's physics in a run that finished (a run is no evidence where its
    model broke): a loop open by more than DIVERGED_GAP_M (the closed chain came apart) or the
    body sunk more than BODY_SINK_M into the ground, each with when."""
    out = []
    gap = np.nan_to_num(sig.gap, nan=np.inf)
    if gap.size and gap.max() > DIVERGED_GAP_M:
        row, leg = np.unravel_index(int(np.argmax(gap)), gap.shape)
        out.append(f"the loop of leg {legs[leg]} opened {gap[row, leg] * 1e3:.2f} mm at "
                   f"t = {sig.t[row]:.2f} s, beyond the {DIVERGED_GAP_M * 1e3:g} mm where the "
                   "closed chain has come apart")
    sink = params.body.height_m / 2 - sig.body_p[:, 2]
    if sink.size and sink.max() > BODY_SINK_M:
        row = int(np.argmax(sink))
        out.append(f"the body sank {sink[row] * 1e3:.0f} mm into the ground at t = "
                   f"{sig.t[row]:.2f} s")
    return out


def origins(scenario) -> dict[str, dict[str, str]]:
    """Where each variant of the run comes from (core.plugins.origin: module, distribution and
    version, a plugin's entry point, the kind it replaced): the gait, the controller, the
    closure and the controller's stance law where it has one."""
    out = {what: plugins.origin(type(getattr(scenario, what)))
           for what in ("gait", "controller", "closure")}
    law = getattr(scenario.controller, "stance_law", None)
    if law in STANCE_LAWS:
        out["stance_law"] = plugins.origin(STANCE_LAWS[law])
    return out


def what_ran(record: SimulationRecord, window: Window) -> dict:
    """The summary's record of what ran and how far: the gait's and closure's kinds, every
    variant's fields and the plan's events (s from t = 0), the duration and how the run ended,
    the window, the scenario's payload and slope, the plant step and log period, the speed of
    the stepping, the closure's design, the controller's gains and the motor."""
    scenario, params, design = record.scenario, record.params, record.design
    t_end, motor = window.t_end, params.motor
    return {
        "gait": scenario.gait.kind, "closure": scenario.closure.kind,
        "ran": {"gait": scenario.gait.fields(), "controller": scenario.controller.fields(),
                "closure": scenario.closure.fields(), "origins": origins(scenario),
                "planned_events_s": {k: window.start + v for k, v in
                                     scenario.gait.events(params.gait).planned().items()}},
        "duration_s": t_end, "requested_duration_s": scenario.duration_s,
        "completed": record.completed, "interrupted": bool(record.interrupted),
        "error": record.error or (f"interrupted by {record.interrupted} at t = {t_end:.2f} s"
                                  if record.interrupted else ""),
        "cycles_in_window": window.cycles, "window_s": [window.start, window.end],
        "gait_frequency_hz": params.gait.frequency_hz,
        "periodic": scenario.gait.periodic, "cycle_s": scenario.gait.span_s(params.gait),
        "payload_kg": scenario.payload_kg, "slope_deg": scenario.slope_deg,
        "time_step_s": design.time_step_s, "log_period_s": scenario.log_period_s,
        "real_time_factor": t_end / record.wall_s if record.wall_s > 0 else math.nan,
        "wall_time_s": record.wall_s,
        "bushing": None if design.bushing is None else {
            "stiffness_N_m": design.bushing.stiffness_N_m,
            "damping_N_s_m": design.bushing.damping_N_s_m},
        "knee_effective_mass_kg": design.m_eff_kg, "design_loop_force_N": design.loop_force_N,
        "controller_gains": None if record.gains is None else {
            k: np.asarray(v).tolist() for k, v in record.gains._asdict().items()},
        "motor_peak_torque_Nm": motor.peak_torque_Nm,
        "motor": {"model": motor.model, "gear_ratio": motor.gear_ratio,
                  "peak_torque_Nm": motor.peak_torque_Nm,
                  "braking_peak_torque_Nm": motor.braking_peak_torque_Nm,
                  "no_load_speed_rad_s": motor.no_load_speed_rad_s,
                  "continuous_torque_Nm": motor.continuous_torque_Nm},
    }


def maneuver_summary(maneuver: dict | None) -> dict:
    """The summary's MANEUVER_KEYS from maneuver_figures (the force capability without its
    arrays per phase); None each for a gait."""
    if maneuver is None:
        return dict.fromkeys(MANEUVER_KEYS)
    capability = maneuver["force_capability"]
    return {"jump": maneuver["jump"], "landing": maneuver["landing"],
            "phases": maneuver["phases"],
            "force_capability": {k: v for k, v in capability.items() if k != "phases"}
            if capability else None}


def in_schema_order(parts: dict) -> Summary:
    """The summary's parts in summary.json's order (Summary's); KeyError naming a key the
    schema does not have (add it to verdicts/summary_schema.py)."""
    order = {key: i for i, key in enumerate(Summary.__annotations__)}
    unknown = sorted(set(parts) - set(order))
    if unknown:
        raise KeyError(f"not in verdicts/summary_schema.Summary: {unknown}")
    return dict(sorted(parts.items(), key=lambda item: order[item[0]]))


def apply_contact_check(summary: Summary, verdict: str, runs: dict[str, Summary],
                        params: Params) -> ContactCheck:
    """Put the contact check (verdicts.contact_check) into the summary (summary["contact_check"])
    from the summaries of the same run with the foot contact varied (verdict: the run's own
    before any check): the verdict becomes "marginal" where it says so
    (verdicts.contact_checked_verdict), and the answer says so."""
    check = contact_check(summary, verdict, runs, params.checks)
    summary["contact_check"] = check
    if summary["verdict"] != "marginal":
        summary["verdict"] = contact_checked_verdict(summary["verdict"], check)
    set_answer(summary, params)
    return check


def apply_step_check(summary: Summary, half: Summary, params: Params) -> StepCheck:
    """Put the step check (verdicts.step_check) into the summary (summary["step_check"]) from
    the summary of the same run at half the plant step: the verdict becomes "marginal" where
    it says so (verdicts.step_checked_verdict), and the answer says so."""
    check = step_check(summary, half, params.checks)
    summary["step_check"] = check
    summary["verdict"] = step_checked_verdict(summary["verdict"], check)
    set_answer(summary, params)
    return check
