"""What a sweep's worker does with its design points: plain data in, one table row per point out
(a dict of numbers and strings), errors recorded in the row, never raised.

Columns: `point` (its index in the spec's order), one per varied parameter (its dotted path),
`status` (ok; failed: no result, `error` says why; stopped: the simulation ended early, `error`
says why, the figures are of what it recorded), `worst_motor`, `worst_verdict`,
`worst_safety_factor`, `worst_demand_Nm` (analysis: the peak torque of the worst motor under
the spec's load model; simulation: its demand p99), `speed_m_s` (analysis: the stride speed 2 a f; simulation:
the mean forward speed), for analysis points `worst_torque_speed_margin` (the least ratio of
the torque-speed line to the demand over both motors: below 1 the line is crossed) and
`speed_ok` (the seed's speed check: no motor beyond its no-load speed; where it fails, the
worst verdict is "fail" whatever the safety factor), `worst_thermal_margin_K` (the least margin
of a winding's steady temperature below its limit at the cycle's RMS torque,
analysis.thermal.thermal_margin; negative: it overheats), then per motor (analysis: A, B; simulation: FL_A ... RR_B) its figures,
the run's figures, `error`.
"""

from __future__ import annotations

import dataclasses
import math

from fivebar_drake.analysis.design_points import evaluate_designs, with_changes
from fivebar_drake.analysis.thermal import thermal_margin
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.scenario import Scenario

SCENARIO = "scenario."
LEGS = ("FL", "FR", "RL", "RR")
ANALYSIS_MOTOR = ("peak_torque_Nm", "rms_torque_Nm", "safety_factor", "verdict",
                  "peak_speed_rad_s", "speed_ok", "torque_speed_margin", "thermal_margin_K",
                  "time_to_winding_limit_s")
SIMULATION_MOTOR = ("demand_peak_Nm", "demand_p99_Nm", "rms_torque_Nm", "safety_factor",
                    "verdict", "thermal_margin_K", "time_to_winding_limit_s")
SIMULATION_RUN = ("completed", "duration_s", "cycles_in_window", "max_tilt_deg",
                  "max_loop_gap_m")      # not the wall time: a row must not depend on the machine
HEAD = ("point",)
WORST = ("status", "worst_motor", "worst_verdict", "worst_safety_factor", "worst_demand_Nm",
         "speed_m_s", "worst_thermal_margin_K")


def columns(fidelity: str, varied: list[str]) -> list[str]:
    """The table's columns, in order."""
    if fidelity == "analysis":
        motors = [f"{m}_{k}" for m in MOTORS for k in ANALYSIS_MOTOR]
        run = ["worst_torque_speed_margin", "speed_ok"]
    else:
        motors = [f"{leg}_{m}_{k}" for leg in LEGS for m in MOTORS for k in SIMULATION_MOTOR]
        run = list(SIMULATION_RUN)
    return [*HEAD, *varied, *WORST, *motors, *run, "error"]


def _worst(motors: dict, demand_key: str) -> dict:
    """The worst motor's figures (lowest safety factor) and the least thermal margin."""
    name, worst = min(motors.items(), key=lambda kv: kv[1]["safety_factor"])
    margins = [m["thermal_margin_K"] for m in motors.values() if "thermal_margin_K" in m]
    return {"worst_motor": name, "worst_verdict": worst["verdict"],
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
        if not speed_ok:
            rows[i]["worst_verdict"] = "fail"
        rows[i].update({f"{m}_{k}": motors[m].get(k, "") for m in MOTORS for k in ANALYSIS_MOTOR})
    return rows


def scenario_with(scenario: Scenario, changes: dict) -> Scenario:
    """The scenario with fields changed by `scenario.NAME` paths, validated (ParameterError
    naming the path)."""
    known = {f.name for f in dataclasses.fields(scenario)}
    for path in changes:
        if path[len(SCENARIO):] not in known:
            raise ParameterError(f"{path}: no such scenario field; the fields are "
                                 f"{sorted(known)}", path)
    changed = dataclasses.replace(scenario, **{k[len(SCENARIO):]: v for k, v in changes.items()})
    changed.validate()
    return changed


def simulation_rows(base: Params, scenario: Scenario, points: list[tuple[int, dict]]) -> list[dict]:
    """Rows of simulation points (index, {dotted path: value}), one after the other
    (simulation_row)."""
    return [simulation_row(base, scenario, index, changes) for index, changes in points]


def simulation_row(base: Params, scenario: Scenario, index: int, changes: dict) -> dict:
    """The row of one simulation point: the scenario with its `scenario.` changes, the
    parameters with the others, simulated (run_simulation) and summarized (summarize_run)."""
    row = {"point": index, **changes}
    try:
        scenario = scenario_with(scenario, {k: v for k, v in changes.items()
                                            if k.startswith(SCENARIO)})
        params = with_changes(base, {k: v for k, v in changes.items()
                                     if not k.startswith(SCENARIO)})
        record = run_simulation(scenario, params, progress=False)
        summary = summarize_run(record)
    except Exception as err:  # noqa: BLE001  (a failed point is recorded; the sweep goes on)
        return {**row, "status": "failed", "error": f"{type(err).__name__}: {err}"}
    motors = {f"{leg}_{m}": v for leg, ms in summary["legs"].items() for m, v in ms.items()}
    for figures in motors.values():       # the windings at the run's RMS torque
        if params.motor.has_thermal_model and math.isfinite(figures["rms_torque_Nm"]):
            heat = thermal_margin(params.motor, figures["rms_torque_Nm"])
            figures["thermal_margin_K"] = float(heat.margin_K)
            figures["time_to_winding_limit_s"] = float(heat.time_to_limit_s)
    row.update(status="stopped" if record.error else "ok", error=record.error or "",
               speed_m_s=summary["mean_forward_speed_m_s"],
               **_worst(motors, "demand_p99_Nm"))
    if summary["verdict"] == "insufficient":
        row["worst_verdict"] = "insufficient"
    row.update({f"{name}_{k}": v.get(k, "") for name, v in motors.items()
                for k in SIMULATION_MOTOR})
    row.update({k: summary[k] for k in SIMULATION_RUN})
    return row
