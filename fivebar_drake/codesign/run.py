"""Run a co-design: the search (search.py: closed-form screening and the optimal-maneuver
floors, predict.py), then level (c), full Drake simulation of the requirements' envelope for the
default design and the finalists on the package's Dask engine (envelope/run.py, a local cluster
or an existing scheduler), then the report (report.py):

    OUT/codesign.journal          the Optuna study (rerunning into OUT resumes it)
    OUT/finalists/default/        the default design's envelope (the base parameters)
    OUT/finalists/compared_I/     each design of the spec's `compare` list's envelope
    OUT/finalists/trial_N/        each finalist's envelope: envelope.md/json and a folder per
                                  maneuver with its recordings
    OUT/finalists/KEY/max_jump/   with requirements.simulate_max_jump, each simulated design's
                                  max-effort jump (optimal --simulate's: the jump planned at its
                                  ceiling, the tracking controller): its measured apex is the
                                  design's simulated max_jump_height_m
    OUT/finalists/KEY/top_speed/GAIT/  with requirements.top_speed_m_s (or an objective
                                  top_speed_m_s:GAIT), each such gait at the design's top speed
                                  tracked (optimal --simulate's: the optimum's path, the
                                  tracking controller): the design meets the requirement when
                                  the run is achieved at the speed asked; the objective's
                                  simulated value is its mean speed (0 where not achieved)
    OUT/design.md, design.json    the recommended design and why, margins, predicted vs simulated
    OUT/design.toml               the recommended design's parameter file
    OUT/pareto.png                the objectives, predicted and verified

A design is verified only when its simulated envelope has every maneuver (and the duty cycle)
in the accepted verdicts, and each required top speed is run, achieved, at that speed; with requirements.step_check every run is judged against its run at
half the plant step (a marginal verdict is not accepted), with requirements.never_at_limit a run
with a motor at its torque or voltage limit in any sample, or a leg at a joint limit, fails. The finalists are simulated one after the other, `budget.finalists` of
them at most: each is the best (the first objective; with several, the predicted Pareto front
first) of the designs not simulated yet that are predicted to meet every requirement once the
predictions are corrected by what the simulations so far showed: per requirement (a maneuver's
check), the least ratio of a simulated margin to its predicted one below 1 scales that margin
of every candidate (a prediction found optimistic is trusted less). With one objective the
search stops at the first finalist that passes (the next would be worse). Without a design
predicted to meet the requirements nothing is simulated. Each envelope's outcome is kept in the
journal, so a rerun simulates only what it lacks, and picks the same finalists.
"""

from __future__ import annotations

import math
from contextlib import ExitStack
from pathlib import Path

import numpy as np

from fivebar_drake.core.files import json_ready, lock_folder
from fivebar_drake.core.progress import Progress
from fivebar_drake.codesign.designs import actuator_mass, design_envelope, design_name
from fivebar_drake.codesign.predict import (CHECKS, DUTY, ceiling, needs, power_maneuvers,
                                            top_speed_of)
from fivebar_drake.codesign.dossier import write_dossier
from fivebar_drake.codesign.report import COMPARED, DEFAULT, CodesignRun, write_report
from fivebar_drake.codesign.search import corrected, predictions, ranked, search
from fivebar_drake.codesign.spec import ON_GAIT, ON_MANEUVER, CodesignSpec
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.optimal import gait_floor
from fivebar_drake.pipeline import (max_jump_scenario, run_simulation, top_speed_scenario,
                                    write_simulation)
from fivebar_drake.envelope.run import run_envelope
from fivebar_drake.sweep.engine import (check_output_folder, check_scheduler,
                                        check_workers, dask_client)
from fivebar_drake.verdicts.rules import ACHIEVED_VERDICTS

FINALISTS_DIR = "finalists"
MAX_JUMP_DIR = "max_jump"
TOP_SPEED_DIR = "top_speed"


def pareto(spec: CodesignSpec, entries: list[dict]) -> list[dict]:
    """The entries no other entry dominates on the objectives."""
    sign = [1.0 if d == "minimize" else -1.0 for d in spec.directions]

    def key(e):
        return [s * e["objectives"][o] for s, o in zip(sign, spec.objectives)]

    return [e for e in entries if not any(
        all(a <= b for a, b in zip(key(f), key(e))) and key(f) != key(e) for f in entries)]


def corrections(pairs: list[tuple[dict, dict]]) -> dict[str, float]:
    """Per requirement ("maneuver check"), the least ratio of the simulated margin to the
    predicted one over the (prediction, simulated) pairs, where below 1 (a requirement the
    simulation has no figure for, e.g. the duty cycle of an envelope with a maneuver without a
    verdict, corrects nothing)."""
    out = {}
    for entry, sim in pairs:
        for name, predicted in entry["maneuvers"].items():
            margins = sim["maneuvers"].get(name, {}).get("margins", {})
            for check, margin in predicted["margins"].items():
                key = f"{name} {check}"
                if check in margins and margin > 0:
                    out[key] = min(out.get(key, 1.0), margins[check] / margin)
    return {k: v for k, v in out.items() if v < 1.0}


def next_finalist(spec: CodesignSpec, entries: list[dict], done: set[str],
                  factors: dict[str, float]) -> dict | None:
    """The next design to simulate (module docstring), or None."""
    meeting = [e for e in entries if e["meets"] and e["name"] not in done
               and corrected(e, factors) >= 1.0]
    front = ranked(spec, pareto(spec, meeting)) if len(spec.objectives) > 1 else []
    order = front or ranked(spec, meeting)
    return order[0] if order else None


def at_limits(summary: dict | None) -> dict:
    """A run's limits (its summary.json's dictionary): the largest share of the samples any
    motor spent at its torque or voltage limit (limit_shares, either quadrant), the joint and
    extension limits a leg reached, and whether the step check found the run marginal (None
    without a step check)."""
    if summary is None:
        return {"motor_share": None, "joint_limits": [], "step_marginal": None}
    shares = [sum(m["limit_shares"].values()) for motors in summary["legs"].values()
              for m in motors.values()]
    step = summary.get("step_check")
    return {"motor_share": max(shares, default=0.0),
            "joint_limits": sorted({f"{h['leg']} {h['limit']}" for h in
                                    (summary.get("limits") or {}).get("hits", [])}),
            "step_marginal": None if step is None else bool(step["marginal"])}


def power_figures(result, maneuver) -> dict:
    """A simulated gait maneuver's electrical figures (ManeuverResult.power_W over its
    statistics window): the robot's peak electrical power (W, summed over the motors) and the
    cost of transport (the positive electrical energy over m g times the distance the body
    made: its mean forward speed times the window); nan without them."""
    power = getattr(result, "power_W", None)
    if power is None or not power.size or result.summary is None:
        return {"peak_W": math.nan, "cost_of_transport": math.nan}
    params, dt = maneuver.params, result.current_dt_s
    mass = gait_floor.whole_body(params, maneuver.scenario.payload_kg)[0]
    distance = result.summary["mean_forward_speed_m_s"] * power.size * dt
    energy = float(np.clip(power, 0.0, None).sum() * dt)
    return {"peak_W": float(power.max()),
            "cost_of_transport": (energy / (mass * params.robot.gravity_m_s2 * distance)
                                  if distance > 0 else math.nan)}


def simulated_objectives(spec: CodesignSpec, design: dict | None, results: dict) -> dict:
    """The spec's objectives as the simulation gives them (the power ones, power_figures, on
    the maneuvers predict.power_maneuvers names), the actuator mass as designed; the others
    (the jump ceiling) are predictions only."""
    base = spec.envelope.maneuvers[0].params
    out = {"actuator_mass_kg": actuator_mass(design) if design is not None else
           base.robot.motors_kg / (base.robot.legs * len(MOTORS))}
    for objective in spec.objectives:
        kind = objective.partition(":")[0]
        if kind not in ON_MANEUVER:
            continue
        figures = [power_figures(results[m.name], m) for m in power_maneuvers(spec, objective)
                   if m.name in results]
        values = [f["peak_W"] if kind == "peak_electrical_power_W" else f["cost_of_transport"]
                  for f in figures]
        out[objective] = (max(values) if values and kind == "peak_electrical_power_W" else
                          values[0] if values else math.nan)
    return out


def simulated(report: dict, spec: CodesignSpec, summaries: dict | None = None) -> dict:
    """An envelope's outcome (envelope.json's dictionary; summaries: each maneuver's
    summary.json dictionary) against the requirements: per maneuver, and for the duty cycle
    (DUTY), its verdict, deciding check, each check's worst figure over the motors and legs
    (torque: safety factor, speed: least margin, thermal: current margin; the duty cycle: its
    hottest winding's current margin), its margin (the figure over what the accepted verdict
    needs, predict.needs) and its limits (at_limits); `passes` when every verdict is accepted
    (with the step check a marginal one is not) and, where the spec requires it, no maneuver
    was at a limit."""
    need = needs(spec.envelope.maneuvers[0].params, spec.accept)
    keys = {"torque": "sf", "speed": "least_margin", "thermal": "margin"}
    summaries = summaries or {}
    out = {}
    for name, e in report["maneuvers"].items():
        rows = [r for r in (e["motors"] or {}).values() if r["checks"] is not None]
        figures = {c: min(_finite(r["checks"][c][keys[c]]) for r in rows) for c in CHECKS} \
            if rows and len(rows) == len(e["motors"]) else {}
        limits = at_limits(summaries.get(name))
        verdict = e["verdict"]
        if spec.never_at_limit and verdict in spec.accept and (
                limits["motor_share"] is None or limits["motor_share"] > 0.0
                or limits["joint_limits"]):
            verdict = "at a limit"
        out[name] = {"verdict": verdict, "deciding_check": (
            "limits" if verdict == "at a limit" else e.get("deciding_check")),
                     "figures": figures, "margins": {c: f / need[c] for c, f in figures.items()},
                     "limits": limits}
    duty = report["duty_cycle"]
    if duty is not None:
        margin = min(_finite(m["margin"]) for m in duty["motors"].values())
        out[DUTY] = {"verdict": duty["verdict"], "deciding_check": "thermal",
                     "figures": {"thermal": margin},
                     "margins": {"thermal": margin / need["thermal"]}}
    return {"maneuvers": out, "duty_cycle": duty is not None,
            "passes": all(m["verdict"] in spec.accept for m in out.values())}


def _finite(x) -> float:
    return math.inf if x is None else x


def max_jump(params, folder: Path) -> dict:
    """The design's max-effort jump simulated (as `optimal --simulate`: the jump maneuver
    planned at its ceiling, optimal.report.max_jump_plan, run with the tracking controller) into
    folder: the ceiling, the plan's height, the measured apex (m above standing; 0 without a
    measured jump), its share of the plan, the run's verdict and why its landing is not verified
    (landing_not_verified; a run stopped at the landing, e.g. a foot target out of the leg's
    reach, or whose legs gave way, still has its measured apex)."""
    jump = ceiling(params)
    if jump is None:
        return {"ceiling_m": 0.0, "planned_m": 0.0, "height_m": 0.0, "share_of_plan": 0.0,
                "verdict": "none", "landed": False, "not_landed": "no jump: no ceiling"}
    scenario = max_jump_scenario(params, jump)
    plan = scenario.gait
    record = run_simulation(scenario, params, progress=False)
    summary = write_simulation(record, folder)[0]
    height = summary["jump"]["height_m"] if summary["jump"] else 0.0
    not_landed = landing_not_verified(summary, record.error)
    return {"ceiling_m": jump.body_apex_above_standing_m, "planned_m": plan.height_m,
            "height_m": height, "share_of_plan": height / plan.height_m, "plan": plan.fields(),
            "verdict": summary["verdict"], "landed": not not_landed, "not_landed": not_landed}


def speed_gaits(spec: CodesignSpec) -> tuple:
    """The gaits a simulated design runs at its top speed: the required ones (gait, least m/s),
    then those only an objective top_speed_m_s:GAIT names (gait, None)."""
    gaits = dict(spec.top_speeds)
    for gait in gait_objectives(spec).values():
        gaits.setdefault(gait, None)
    return tuple(gaits.items())


def gait_objectives(spec: CodesignSpec) -> dict[str, str]:
    """The spec's objectives on a gait (ON_GAIT: top_speed_m_s:GAIT), each to its gait."""
    return {o: o.partition(":")[2] for o in spec.objectives if o.partition(":")[0] in ON_GAIT}


def tracked_top_speeds(params, required, folder: Path) -> dict:
    """Each gait's top speed for any controller (optimal/top_speed.py) run by the tracking
    controller (pipeline.top_speed_scenario, as `optimal --simulate`) into folder/GAIT: per
    gait (required: (gait, least speed m/s or None for an objective alone) pairs) the speed
    required, the optimum's, the run's mean forward speed (m/s; 0 without one), its verdict,
    whether the motion was achieved (a verdict of pass, warn or fail: a torque FAIL at the top
    speed is the optimum's own, which rides the envelope) and whether it meets the requirement
    (achieved, at least the speed required; None without one)."""
    out = {}
    for gait, least in required:
        optimum = top_speed_of(params, gait)
        entry = {"required_m_s": least, "predicted_m_s": optimum, "simulated_m_s": 0.0,
                 "verdict": "none", "achieved": False}
        if optimum > 0.0:
            record = run_simulation(top_speed_scenario(gait), params, progress=False)
            summary = write_simulation(record, folder / gait)[0]
            entry.update(simulated_m_s=summary["mean_forward_speed_m_s"] or 0.0,
                         verdict=summary["verdict"],
                         achieved=summary["verdict"] in ACHIEVED_VERDICTS)
        entry["meets"] = None if least is None else (entry["achieved"]
                                                      and entry["simulated_m_s"] >= least)
        out[gait] = entry
    return out


def landing_not_verified(summary: dict, error: str = "") -> str:
    """Why a max jump's run does not verify its landing ("" where it does: the run went to its
    end with a verdict, the motion achieved): the run's error where it stopped, else the
    achieved check's reasons (summary.json's legs), else a pointer to its summary.md."""
    if error:
        return error
    if summary["verdict"] in ACHIEVED_VERDICTS:
        return ""
    why = sorted({m["checks"]["achieved"]["why"] for motors in summary["legs"].values()
                  for m in motors.values()
                  if ((m.get("checks") or {}).get("achieved") or {}).get("why")})
    return "; ".join(why) or f"{summary['verdict']}: its summary.md says why"


def run_codesign(spec: CodesignSpec, out: str | Path, workers: int | None = None,
                 scheduler: str | None = None, progress: bool = True,
                 client=None) -> CodesignRun:
    """Search, verify and report into out (module docstring). client: a Dask client to use
    (and leave open); otherwise one of the scheduler, or of a new local cluster of
    `workers`."""
    out = Path(out)
    check_workers(workers)
    if scheduler:
        check_scheduler(scheduler)
    check_output_folder(out)
    out.mkdir(parents=True, exist_ok=True)
    lock_folder(out, "--out")
    study = search(spec, out, progress)
    entries = predictions(study)
    chosen, verified, pairs = [], {}, []
    bar = Progress(spec.finalists + 1 + len(spec.compare), 0, progress, "verify", "envelopes")
    with ExitStack() as stack:
        opened = []                 # the Dask client, opened when a simulation is first needed

        def check(key: str, design: dict | None) -> dict:
            """The design's simulated envelope, from the journal or run and kept there."""
            attr = f"envelope:{key}"
            if attr not in study.user_attrs:
                if not opened:
                    opened.append(stack.enter_context(dask_client(workers, scheduler, client)))
                envelope = design_envelope(spec.envelope, design)
                run = run_envelope(envelope, out / FINALISTS_DIR / key, progress=False,
                                   client=opened[0])
                outcome = simulated(run.report, spec, {
                    name: r.summary for name, r in run.results.items()})
                outcome["objectives"] = simulated_objectives(spec, design, run.results)
                if spec.simulate_max_jump:
                    jump = max_jump(envelope.maneuvers[0].params,
                                    out / FINALISTS_DIR / key / MAX_JUMP_DIR)
                    outcome["max_jump"] = jump
                    outcome["objectives"]["max_jump_height_m"] = jump["height_m"]
                gaits = speed_gaits(spec)
                if gaits:
                    speeds = tracked_top_speeds(envelope.maneuvers[0].params, gaits,
                                                out / FINALISTS_DIR / key / TOP_SPEED_DIR)
                    outcome["top_speeds"] = speeds
                    outcome["passes"] = outcome["passes"] and all(
                        v["meets"] for v in speeds.values() if v["meets"] is not None)
                    for objective, gait in gait_objectives(spec).items():
                        v = speeds[gait]
                        outcome["objectives"][objective] = (v["simulated_m_s"]
                                                            if v["achieved"] else 0.0)
                study.set_user_attr(attr, json_ready(outcome))
            verified[key] = study.user_attrs[attr]
            return verified[key]

        while len(chosen) < spec.finalists:
            entry = next_finalist(spec, entries, {e["name"] for e in chosen},
                                  corrections(pairs))
            if entry is None:
                break
            if not chosen:
                bar.add(1, int(not check(DEFAULT, None)["passes"]))
                for i, design in enumerate(spec.compare):
                    bar.add(1, int(not check(f"{COMPARED}{i}", design)["passes"]))
            chosen.append(entry)
            pairs.append((entry, check(f"trial_{entry['trial']}", entry["design"])))
            passing = ranked(spec, [e for e, sim in pairs if sim["passes"]])
            bar.note = "best verified: " + (design_name(passing[0]["design"]) if passing
                                            else "none yet")
            bar.add(1, int(not pairs[-1][1]["passes"]))
            if passing and len(spec.objectives) == 1:
                break
    if 0 < bar.done < bar.total:
        bar.total = bar.done
        bar.add(0)                  # the last line, as it ended
    run = write_report(spec, out, entries, chosen, verified, corrections(pairs))
    run.files += write_dossier(spec, run.report, out, out / FINALISTS_DIR)
    return run
