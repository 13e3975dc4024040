"""What a sweep's worker does with its design points: plain data in, one table row per point out
(a dict of numbers and strings), errors recorded in the row, never raised.

Columns: `point` (its index in the spec's order), one per varied parameter (its dotted path),
`status` (ok; failed: no result, `error` says why; stopped: the simulation ended early, `error`
says why, the figures are of what it recorded), `worst_motor`, `worst_verdict` (the worst of the
torque, speed and thermal checks, verdicts/checks.motor_checks; simulation: also not_achieved,
marginal, insufficient), `worst_deciding_check`, `worst_safety_factor`, `worst_demand_Nm`
(analysis: the peak torque of the worst motor under the spec's load model; simulation: its
demand p99), `speed_m_s` (analysis: the stride speed 2 a f; simulation: the mean forward
speed), `worst_thermal_margin_K` (the least margin of a winding's steady temperature below its
limit at the RMS current, actuators.thermal.thermal_margin; negative: it overheats), for analysis
points `worst_torque_speed_margin` (the least ratio of the envelope's torque to the demand over
both motors) and `speed_ok` (the seed's check: no motor beyond its no-load speed), then per
motor (analysis: A, B; simulation: FL_A ... RR_B) its figures (speed_margin,
speed_outside_fraction, thermal_current_margin: the checks' figures; sf_step_change with
step_check), the run's figures, `error`.
"""

from __future__ import annotations

import dataclasses

from fivebar_drake.analysis.design_points import evaluate_designs
from fivebar_drake.actuators.thermal import thermal_margin
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.verdicts.checks import SEVERITY
from fivebar_drake.pipeline import run_simulation, run_step_check, summarize_run
from fivebar_drake.robots.quadruped.config import with_changes
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.scenario import ALIASES, Scenario

SCENARIO = "scenario."
ANALYSIS_MOTOR = ("peak_torque_Nm", "rms_torque_Nm", "safety_factor", "verdict",
                  "deciding_check", "peak_speed_rad_s", "speed_ok", "torque_speed_margin",
                  "speed_margin", "speed_outside_fraction", "thermal_current_margin",
                  "thermal_margin_K", "time_to_winding_limit_s")
SIMULATION_MOTOR = ("demand_peak_Nm", "demand_p99_Nm", "rms_torque_Nm", "safety_factor",
                    "verdict", "deciding_check", "speed_margin", "speed_outside_fraction",
                    "thermal_current_margin", "thermal_margin_K", "time_to_winding_limit_s",
                    "sf_step_change")
SIMULATION_RUN = ("completed", "duration_s", "cycles_in_window", "max_tilt_deg",
                  "max_loop_gap_m")      # not the wall time: a row must not depend on the machine
HEAD = ("point",)
WORST = ("status", "worst_motor", "worst_verdict", "worst_deciding_check",
         "worst_safety_factor", "worst_demand_Nm", "speed_m_s", "worst_thermal_margin_K")


def columns(fidelity: str, varied: list[str]) -> list[str]:
    """The table's columns, in order."""
    if fidelity == "analysis":
        motors = [f"{m}_{k}" for m in MOTORS for k in ANALYSIS_MOTOR]
        run = ["worst_torque_speed_margin", "speed_ok"]
    else:
        motors = [f"{leg}_{m}_{k}" for leg in LEGS for m in MOTORS for k in SIMULATION_MOTOR]
        run = list(SIMULATION_RUN)
    return [*HEAD, *varied, *WORST, *motors, *run, "error"]


def _worst(motors: dict, demand_key: str, name: str | None = None) -> dict:
    """The worst motor's figures and the least thermal margin: the motor named (a run's own
    worst motor, summary.json's: verdicts.rules.badness), else the worst verdict, then the
    lowest safety factor."""
    if name is None:
        name = max(motors, key=lambda n: (SEVERITY.get(motors[n]["verdict"], 3),
                                          -motors[n]["safety_factor"]))
    worst = motors[name]
    margins = [m["thermal_margin_K"] for m in motors.values() if "thermal_margin_K" in m]
    return {"worst_motor": name, "worst_verdict": worst["verdict"],
            "worst_deciding_check": worst.get("deciding_check") or "",
            "worst_safety_factor": worst["safety_factor"], "worst_demand_Nm": worst[demand_key],
            "worst_thermal_margin_K": min(margins) if margins else ""}


def analysis_rows(base: Params, settings: tuple[str, str],
                  points: list[tuple[int, dict]]) -> list[dict]:
    """Rows of analysis points (index, {dotted path: value}): settings = (foot path, load
    model); the model over one cycle of the path, all points of a leg geometry at once
    (design_points.evaluate_designs)."""
    rows, designs, where = [], [], []
    for index, changes in points:
        row = {"point": index, **changes}
        try:
            designs.append(with_changes(base, changes))
            where.append(len(rows))
        except ParameterError as err:
            row.update(status="failed", error=str(err))
        rows.append(row)
    for i, result in zip(where, evaluate_designs(designs, *settings)):
        if "error" in result:
            rows[i].update(status="failed", error=result["error"])
            continue
        motors = {m: result[m] for m in MOTORS}
        speed_ok = all(m["speed_ok"] for m in motors.values())
        rows[i].update(status="ok", speed_m_s=result["stride_speed_m_s"],
                       **_worst(motors, "peak_torque_Nm"), speed_ok=speed_ok, error="",
                       worst_torque_speed_margin=min(m["torque_speed_margin"]
                                                     for m in motors.values()))
        rows[i].update({f"{m}_{k}": motors[m].get(k, "") for m in MOTORS for k in ANALYSIS_MOTOR})
    return rows


def scenario_with(scenario: Scenario, changes: dict) -> Scenario:
    """The scenario with fields changed by `scenario.NAME` paths, validated (ParameterError
    naming the path)."""
    known = {f.name for f in dataclasses.fields(scenario)} | set(ALIASES)
    for path in changes:
        if path[len(SCENARIO):] not in known:
            raise ParameterError(f"{path}: no such scenario field; the fields are "
                                 f"{sorted(known)}", path)
    changed = scenario.replaced(**{k[len(SCENARIO):]: v for k, v in changes.items()})
    changed.validate()
    return changed


def simulation_rows(base: Params, settings: tuple[Scenario, bool],
                    points: list[tuple[int, dict]]) -> list[dict]:
    """Rows of simulation points (index, {dotted path: value}), one after the other
    (simulation_row); settings = (the base scenario, whether to step-check each point)."""
    return [simulation_row(base, *settings, index, changes) for index, changes in points]


def simulation_row(base: Params, scenario: Scenario, step_check: bool, index: int,
                   changes: dict) -> dict:
    """The row of one simulation point: the scenario with its `scenario.` changes, the
    parameters with the others, simulated (run_simulation) and summarized (summarize_run; with
    step_check, against the run at half the plant step: run_step_check)."""
    row = {"point": index, **changes}
    try:
        scenario = scenario_with(scenario, {k: v for k, v in changes.items()
                                            if k.startswith(SCENARIO)})
        params = with_changes(base, {k: v for k, v in changes.items()
                                     if not k.startswith(SCENARIO)})
        record = run_simulation(scenario, params, progress=False)
        half = run_step_check(record, progress=False) if step_check and not record.error \
            else None
        summary = summarize_run(record, half)
    except Exception as err:  # noqa: BLE001  (a failed point is recorded; the sweep goes on)
        return {**row, "status": "failed", "error": f"{type(err).__name__}: {err}"}
    motors = {f"{leg}_{m}": v for leg, ms in summary["legs"].items() for m, v in ms.items()}
    step = summary["step_check"]
    for name, figures in motors.items():       # the windings at the run's RMS current
        checks = figures["checks"] or {}
        figures["speed_margin"] = checks.get("speed", {}).get("least_margin")
        figures["speed_outside_fraction"] = checks.get("speed", {}).get("outside_fraction")
        figures["thermal_current_margin"] = checks.get("thermal", {}).get("margin")
        if step:
            figures["sf_step_change"] = step["motors"][name.replace("_", " ", 1)]["sf_change"]
        thermal = checks.get("thermal", {})
        if params.motor.has_thermal_model and "rms_current_A" in thermal:
            heat = thermal_margin(params.motor, thermal["rms_current_A"])
            figures["thermal_margin_K"] = float(heat.margin_K)
            figures["time_to_winding_limit_s"] = float(heat.time_to_limit_s)
    row.update(status="stopped" if record.error else "ok", error=record.error or "",
               speed_m_s=summary["mean_forward_speed_m_s"],
               **_worst(motors, "demand_p99_Nm", summary["worst_motor"].replace(" ", "_")))
    if summary["verdict"] in ("insufficient", "not_achieved", "marginal"):
        row["worst_verdict"] = summary["verdict"]
    row.update({f"{name}_{k}": v.get(k, "") for name, v in motors.items()
                for k in SIMULATION_MOTOR})
    row.update({k: summary[k] for k in SIMULATION_RUN})
    return row
