"""The duty envelope's figures and text: per motor (A, B, over the four legs) and maneuver the
four checks of the verdict, the maneuver that sizes each motor, the worst verdict in one
sentence, the duty cycle's winding temperatures; envelope.json and envelope.md.

A motor's row for a maneuver takes each check from the leg where it is worst (the lowest safety
factor; the largest share beyond the envelope, then the least speed margin; the least thermal
margin; not achieved, then the most time at the torque limit): its verdict is the worst of its
checks, as summary.json's verdict is the worst over the motors, and not_achieved where the
motion was not achieved. The maneuver that sizes a motor is its worst row in summary.json's
order (verdicts/rules.badness: the verdict, then the deciding check and its figure)."""

from __future__ import annotations

import json
import math
from pathlib import Path

from fivebar_drake.verdicts.checks import (CHECK_ORDER, SEVERITY, check_badness,
                                           limit_shares_text, thresholds_text, worst_check)
from fivebar_drake.verdicts.checks import verdict as check_verdict
from fivebar_drake.core.text import figure, verdict_word
from fivebar_drake.core.files import json_ready, write_atomic
from fivebar_drake.verdicts.summary_schema import MotorSummary, Summary
from fivebar_drake.verdicts.rules import badness
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.simulation.summary_text import check_text

REPORT_FILES = ("envelope.md", "envelope.json")      # envelope.json last
VERDICTS = ("pass", "warn", "fail", "not_achieved")  # the verdicts of a maneuver that has one


def _worst_leg(legs: dict[str, dict[str, MotorSummary]], motor: str,
               key) -> tuple[str, MotorSummary]:
    """(leg, that leg's motor) with the largest key(motor's summary)."""
    return max(((leg, ms[motor]) for leg, ms in legs.items()), key=lambda x: key(x[1]))


def _inf(x) -> float:
    return math.inf if x is None else x


def motor_row(summary: Summary, motor: str) -> dict:
    """The checks of one motor (A or B) in a maneuver over the legs (module docstring), with
    the leg of each, its verdict and deciding check; the demand p99 and the time at the torque
    limit of the worst legs. Without checks (no statistics window) the verdict is
    'insufficient'."""
    legs = summary["legs"]
    if any(ms[motor]["checks"] is None for ms in legs.values()):
        return {"checks": None, "verdict": "insufficient", "deciding_check": None}
    rows = {}
    for check in CHECK_ORDER:
        leg, m = _worst_leg(legs, motor, lambda m: check_badness(check, m["checks"][check]))
        rows[check] = {**m["checks"][check], "leg": leg}
    rows["torque"]["demand_p99_Nm"] = legs[rows["torque"]["leg"]][motor]["demand_p99_Nm"]
    leg, m = _worst_leg(legs, motor, lambda m: (
        m["checks"]["achieved"]["verdict"] == "not_achieved", m["saturated_fraction"]))
    rows["achieved"] = {**m["checks"]["achieved"], "leg": leg}
    verdict, deciding = worst_check(rows)
    if rows["achieved"]["verdict"] == "not_achieved":
        verdict, deciding = "not_achieved", "achieved"
    if summary["verdict"] == "insufficient":
        verdict, deciding = "insufficient", None
    return {"checks": rows, "verdict": verdict, "deciding_check": deciding,
            "leg": rows[deciding]["leg"] if deciding else None,
            "saturated_fraction": m["saturated_fraction"]}


def maneuver_entry(maneuver, result) -> dict:
    """envelope.json's entry of a maneuver (spec.Maneuver) and its result
    (maneuver.ManeuverResult, None if it did not finish)."""
    entry = {"gait": maneuver.scenario.gait.kind, "changes": maneuver.changes,
             "folder": maneuver.name}
    if result is None:
        return {**entry, "status": "missing", "error": "not run (the envelope was interrupted)",
                "verdict": "insufficient", "motors": None, "timing": None}
    s = result.summary
    if s is None:
        return {**entry, "status": "failed", "error": result.error, "verdict": "insufficient",
                "motors": None, "timing": None}
    return {**entry, "status": "stopped" if s["error"] else "ok", "error": s["error"],
            "verdict": s["verdict"], "deciding_check": s["deciding_check"],
            "worst_motor": s["worst_motor"], "duration_s": s["duration_s"],
            "cycles_in_window": s["cycles_in_window"], "time_step_s": s["time_step_s"],
            "mean_forward_speed_m_s": s["mean_forward_speed_m_s"],
            "max_tilt_deg": s["max_tilt_deg"], "answer": s["answer"],
            "any_controller": s["any_controller"],
            "operating_point_rows": result.rows,
            "motors": {m: motor_row(s, m) for m in MOTORS},
            "timing": {"real_time_factor": s["real_time_factor"],
                       "wall_time_s": s["wall_time_s"]}}


def _rated(row: dict) -> bool:
    return row["verdict"] in VERDICTS


def sizing(maneuvers: dict) -> dict:
    """Per motor: the maneuver that sizes it (its worst row in verdicts.badness order) and, per
    check, the maneuver where that check is worst (torque: the lowest safety factor; speed: the
    largest share beyond the envelope, then the least margin; thermal: the highest RMS
    current); None where no maneuver has a verdict."""
    out = {}
    for motor in MOTORS:
        rows = {name: e["motors"][motor] for name, e in maneuvers.items()
                if e["motors"] and _rated(e["motors"][motor])}
        if not rows:
            out[motor] = None
            continue
        name = max(rows, key=lambda n: badness(rows[n]))
        per_check = {
            "torque": max(rows, key=lambda n: -_inf(rows[n]["checks"]["torque"]["sf"])),
            "speed": max(rows, key=lambda n: (rows[n]["checks"]["speed"]["outside_fraction"],
                                              -_inf(rows[n]["checks"]["speed"]["least_margin"]))),
            "thermal": max(rows, key=lambda n: rows[n]["checks"]["thermal"].get(
                "rms_current_A", 0.0))}
        out[motor] = {"maneuver": name, "verdict": rows[name]["verdict"],
                      "deciding_check": rows[name]["deciding_check"],
                      "leg": rows[name]["leg"], "worst_per_check": per_check}
    return out


def sized_by_floor(maneuvers: dict) -> dict | None:
    """The maneuver whose need (its any_controller: the least peak motor torque any controller
    needs, against the motors' limit in the quadrant each phase acts) leaves the least safety
    factor, with its floor and that safety factor; a maneuver beyond a bound by another method
    sizes the motors first (floor None, safety factor 0: no motion does it); the maneuvers
    undecided (beyond their model's optimum, within its bound) and those without a floor are
    listed apart, never given a safety factor. None when no maneuver has a need."""
    needs = {name: e["any_controller"] for name, e in maneuvers.items()
             if e.get("any_controller")}
    if not needs:
        return None
    status = {name: {p["status"] for p in a["phases"].values()} for name, a in needs.items()}
    beyond = [n for n in needs if "beyond bound" in status[n]]
    floored = [n for n in needs if needs[n]["floor_Nm"] is not None]
    out = {"undecided": [n for n in needs if "undecided" in status[n] and n not in beyond],
           "without_floor": [n for n in maneuvers if n not in needs
                             or "unknown" in status.get(n, ())]}
    if beyond:
        return {"maneuver": beyond[0], "floor_Nm": None, "safety_factor": 0.0, **out}
    if not floored:
        return {"maneuver": None, "floor_Nm": None, "safety_factor": None, **out}
    name = min(floored, key=lambda n: needs[n]["floor_safety_factor"])
    return {"maneuver": name, "floor_Nm": needs[name]["floor_Nm"],
            "safety_factor": needs[name]["floor_safety_factor"], **out}


def floor_text(f: dict) -> str:
    """The envelope's need for any controller in a sentence (sized_by_floor's dictionary)."""
    if f["floor_Nm"] is None and f["safety_factor"] == 0.0:
        text = (f"**{f['maneuver']}** is beyond these motors for any controller (beyond a bound "
                "by another method)")
    elif f["floor_Nm"] is None:
        text = "No maneuver has a floor"
    else:
        text = (f"Sized by its need: **{f['maneuver']}** needs at least {f['floor_Nm']:.2f} N·m "
                f"at the peak whatever the controller: the motors' safety factor on it, in the "
                f"quadrant it acts, is {f['safety_factor']:.2f}")
    if f["undecided"]:
        text += (f". Undecided for any controller (beyond the model's optimum, within its "
                 f"bound): {', '.join(f['undecided'])}")
    if f["without_floor"]:
        text += f". No floor for {', '.join(f['without_floor'])}"
    return text + "."


def _reason(motor: str, maneuver: str, row: dict) -> str:
    check = row["deciding_check"]
    where = f"motor {motor} in {maneuver} (leg {row['leg']})"
    if check == "achieved":
        return f"{where} did not achieve its motion: {row['checks']['achieved']['why']}"
    return f"{where}, decided by the {check} check ({check_text(check, row['checks'][check])})"


def answer(maneuvers: dict, sized: dict, duty: dict | None) -> tuple[str, str]:
    """(the worst verdict, the sentence that gives it and its reason)."""
    candidates = []
    for motor in MOTORS:
        if sized[motor]:
            row = maneuvers[sized[motor]["maneuver"]]["motors"][motor]
            candidates.append((badness(row), row["verdict"],
                               _reason(motor, sized[motor]["maneuver"], row)))
    if duty:
        m = duty["motors"][duty["worst_motor"]]
        candidates.append(((SEVERITY[duty["verdict"]], -CHECK_ORDER.index("thermal"), 0.0,
                            -_inf(m["margin"])), duty["verdict"],
                           f"the duty cycle heats motor {duty['worst_motor']}'s winding (leg "
                           f"{m['leg']}) to {m['peak_C']:.1f} °C against its "
                           f"{duty['winding_limit_C']:g} °C limit"))
    missing = [n for n, e in maneuvers.items() if not _rated(e)]
    tail = (f" No verdict for {', '.join(missing)} (see their entries)." if missing else "")
    if not candidates:
        return "insufficient", f"No verdict: no maneuver has one.{tail}"
    _, verdict, reason = max(candidates, key=lambda c: c[0])
    label = verdict_word(verdict)
    if missing and verdict in ("pass", "warn"):   # what did not run cannot pass
        return "insufficient", (f"No verdict for {', '.join(missing)} (see their entries), so "
                                f"none for the envelope; the others' worst is {label}: "
                                f"{reason}.")
    return verdict, f"Worst verdict {label}: {reason}.{tail}"


def worst_sf(entry: dict) -> float | None:
    """A maneuver's worst torque safety factor over its motors (envelope.json's entry; None
    where no motor has checks)."""
    sfs = [m["checks"]["torque"]["sf"] for m in (entry.get("motors") or {}).values()
           if m and m.get("checks")]
    return min(sfs) if sfs else None


def design_answer(verdict: str, maneuvers: dict, floor: dict | None, duty: dict | None,
                  checks) -> dict:
    """The design's one answer over the envelope (every output that gives it reads this):
    kind "carries" (every maneuver and the duty cycle pass or warn with this controller),
    "this controller" (it fails a maneuver on a check no need for any controller bounds: speed,
    thermal), "better controller" (this controller fails some on torque or achievement, and the
    least need found for any controller leaves the motors a passing or warning safety factor on
    every maneuver), "short
    of margin" (that need leaves a failing safety factor, though within the motors), "beyond"
    (a maneuver beyond the motors for any controller: fails_for "any controller", or beyond a
    bound by another method), "no verdict"; with its sentence (text, at most core.text.ANSWER_CHARS),
    the maneuvers this controller fails, and the need that decides (maneuver, N*m, SF, its
    verdict on the checks' thresholds)."""
    decided = {n: e["deciding_check"] for n, e in maneuvers.items()
               if e["verdict"] in ("fail", "not_achieved")}
    if duty and duty["verdict"] == "fail":
        decided["the duty cycle"] = "thermal"
    failed = list(decided)
    unbounded = sorted({c for c in decided.values() if c not in ("torque", "achieved")})
    need = dict(maneuver=None, need_Nm=None, need_sf=None, need_verdict=None)
    if floor is not None and floor["safety_factor"] is not None:
        need = dict(maneuver=floor["maneuver"], need_Nm=floor["floor_Nm"],
                    need_sf=floor["safety_factor"],
                    need_verdict=check_verdict(checks, floor["safety_factor"]))
    beyond = [n for n, e in maneuvers.items()
              if (e.get("any_controller") or {}).get("fails_for") == "any controller"]
    if floor is not None and floor["safety_factor"] == 0.0 and floor["maneuver"] not in beyond:
        beyond.append(floor["maneuver"])
    named = ", ".join(failed)
    total = len(maneuvers) + (duty is not None)
    if verdict == "insufficient":
        missing = sum(e["verdict"] not in VERDICTS for e in maneuvers.values())
        kind, text = "no verdict", (f"No verdict: {missing} of {len(maneuvers)} maneuvers "
                                    "have none (see their entries).")
    elif beyond:
        kind, text = "beyond", (f"No: FAIL in {len(beyond)} of {total} for any controller: "
                                f"{', '.join(beyond)} beyond these motors.")
    elif not failed:
        sfs = {n: worst_sf(e) for n, e in maneuvers.items()}
        least = min(sfs, key=lambda n: math.inf if sfs[n] is None else sfs[n])
        kind, text = "carries", (f"Yes: the motors carry the robot through the envelope with "
                                 f"this controller ({verdict_word(verdict)}; least SF "
                                 f"{figure(sfs[least])}, {least}).")
    elif unbounded:
        kind, text = "this controller", (
            f"Not with this controller: FAIL in {len(failed)} of {total} ({named}); no need for "
            f"any controller bounds the {' or '.join(unbounded)} check.")
    elif need["need_verdict"] in ("pass", "warn"):
        kind, text = "better controller", (
            f"Only with a better controller: this one fails {named}; the least found for any "
            f"controller leaves SF {need['need_sf']:.2f} ({need['maneuver']}, "
            f"{verdict_word(need['need_verdict'])}).")
    elif need["need_verdict"] == "fail":
        kind, text = "short of margin", (
            f"Not with margin: FAIL, {need['maneuver']} needs at least {need['need_Nm']:.2f} "
            f"N·m for the best motion found, SF {need['need_sf']:.2f} (fail below "
            f"{checks.sf_warn:g}).")
    else:
        kind, text = "undecided", (f"Undecided: this controller fails {named}, and no need for "
                                   "any controller decides it (see For any controller).")
    return {"kind": kind, "text": text, "fails": failed, **need}


def envelope_report(spec, results: dict, duty: dict | None, duty_why: str,
                    params) -> dict:
    """envelope.json's dictionary: the spec, the motor, every maneuver (spec order), the
    sizing, the duty cycle (None with duty_why if it has none), the worst verdict and the
    sentence, and whether every maneuver finished (complete)."""
    maneuvers = {m.name: maneuver_entry(m, results.get(m.name)) for m in spec.maneuvers}
    sized = sizing(maneuvers)
    verdict, sentence = answer(maneuvers, sized, duty)
    floor = sized_by_floor(maneuvers)
    motor = params.motor
    return {
        "spec": spec.source, "complete": all(m.name in results for m in spec.maneuvers),
        "design_answer": design_answer(verdict, maneuvers, floor, duty, params.checks),
        "verdict": verdict, "answer": sentence, "thresholds": thresholds_text(params.checks),
        "motor": {"peak_torque_Nm": motor.peak_torque_Nm,
                  "braking_peak_torque_Nm": motor.braking_peak_torque_Nm,
                  "no_load_speed_rad_s": motor.no_load_speed_rad_s,
                  "continuous_torque_Nm": motor.continuous_torque_Nm},
        "sized_by": sized,
        "sized_by_floor": floor,
        "maneuvers": maneuvers,
        "duty_cycle": None if duty is None else {
            "steps": [{"maneuver": s.maneuver, "duration_s": s.duration_s}
                      for s in spec.duty_cycle], **duty},
        "duty_cycle_why_none": duty_why,
    }


def _achieved(check: dict) -> str:
    """The achieved check in a cell: yes, or no with the leg and why."""
    if check["verdict"] == "pass":
        return "yes"
    return f"no ({check['leg']}): {check.get('why') or check['verdict'].replace('_', ' ')}"


def _at_limit(check: dict) -> str:
    """', at its braking torque limit (the peak current) X% of the time, ...' for a check that
    failed at the motor's limits (verdicts/checks.at_limit), each limit with its quadrant: its
    demand was not met, and is not a need."""
    return "" if "limits" not in check else f", at {limit_shares_text(check['limits'])}"


def _sf(check: dict) -> str:
    """A torque check's safety factor with the quadrant of its figure."""
    return "—" if check.get("sf") is None else f"{check['sf']:.2f} {check['quadrant']}"


def markdown(report: dict) -> str:
    lines = ["# Duty envelope of the hip motors", "", report["design_answer"]["text"], "",
             f"This controller: {report['answer']}", "",
             report.get("thresholds", ""), ""]
    if not report["complete"]:
        lines += ["**Incomplete:** the envelope was interrupted; the maneuvers marked missing "
                  "did not run.", ""]
    m = report["motor"]
    lines += [f"- Spec: `{report['spec']}`. Motor: {m['peak_torque_Nm']:.2f} N·m peak driving "
              f"({m['braking_peak_torque_Nm']:.2f} braking), no-load speed "
              f"{m['no_load_speed_rad_s']:.2f} rad/s, continuous "
              f"{figure(m['continuous_torque_Nm'])} N·m.",
              "- Each check is from the leg where it is worst; the verdict is the worst check "
              "(not achieved where the motion was not).",
              "- SF: 1 / the 99th percentile of the demand over the limit of each sample's own "
              "quadrant (driving: torque and speed of one sign; braking: opposite signs), with "
              "the quadrant of that percentile.",
              "- \"At its ... limit\": the motor's commands were clipped more than 1 % of the "
              "time, at the limits named (quadrant, and torque: the peak current, or voltage: "
              "the back-EMF at speed), so the SF is on the torque it delivered (1 at the limit): "
              "the controller's demand beyond it was not met and is not a need.",
              ""]
    for motor in MOTORS:
        lines += [f"## Motor {motor}", "",
                  "| maneuver | verdict | deciding | torque: SF (leg) | speed: least margin, "
                  "beyond envelope (leg) | thermal: continuous / RMS current, RMS A (leg) | "
                  "achieved |", "|---|---|---|---|---|---|---|"]
        for name, e in report["maneuvers"].items():
            row = (e["motors"] or {}).get(motor)
            if not row or row["checks"] is None:
                lines.append(f"| {name} | {verdict_word(e['verdict'])} | — | — | — | — | "
                             f"{e['status']}: {e['error'] or 'no whole gait cycle'} |")
                continue
            c = row["checks"]
            lines.append(
                f"| {name} | {verdict_word(row['verdict'])} | {row['deciding_check'] or '—'} | "
                f"{_sf(c['torque'])} ({c['torque']['leg']}){_at_limit(c['torque'])} | "
                f"{figure(c['speed']['least_margin'])}, {c['speed']['outside_fraction']:.1%} "
                f"({c['speed']['leg']}){_at_limit(c['speed'])} | "
                f"{figure(c['thermal'].get('margin'))}, "
                f"{figure(c['thermal'].get('rms_current_A'), '{:.3f}')} ({c['thermal']['leg']}) | "
                f"{_achieved(c['achieved'])} |")
        s = report["sized_by"][motor]
        lines += ["", "Sized by: " + ("no maneuver with a verdict" if s is None else
                  f"**{s['maneuver']}** ({verdict_word(s['verdict'])}, "
                  f"{s['deciding_check']} check, leg {s['leg']}); worst torque "
                  f"{s['worst_per_check']['torque']}, speed {s['worst_per_check']['speed']}, "
                  f"thermal {s['worst_per_check']['thermal']}."), ""]
    f = report["sized_by_floor"]
    if f is not None:
        lines += ["## For any controller", "", floor_text(f), ""]
    lines += ["## Maneuvers", "", "Floor: the least peak motor torque any controller needs for "
              "the maneuver, against what this controller asked (— : no floor for it); fails "
              "for: whom a failing verdict blames (any controller: the motors cannot; this "
              "controller: the motors can, this controller did not; undecided: beyond the "
              "model's optimum, within its bound; unknown: no floor).", "",
              "| maneuver | gait | changes | status | verdict | floor / asked N·m | fails for | "
              "simulated s | step ms | real-time factor | folder |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, e in report["maneuvers"].items():
        changes = ", ".join(f"{k}: {v}" for k, v in e["changes"].items() if k != "gait")
        timing = e["timing"] or {}
        a = e.get("any_controller")
        floor = ("—" if not a else f"none / {figure(a['asked_Nm'])}" if a["floor_Nm"] is None
                 else f"{a['floor_Nm']:.2f} / {figure(a['asked_Nm'])}")
        lines.append(f"| {name} | {e['gait']} | {changes or '—'} | {e['status']} | "
                     f"{verdict_word(e['verdict'])} | {floor} | "
                     f"{(a or {}).get('fails_for') or '—'} | "
                     f"{figure(e.get('duration_s'))} | "
                     f"{figure(e.get('time_step_s') and e['time_step_s'] * 1e3, '{:g}')} | "
                     f"{figure(timing.get('real_time_factor'))} | `{e['folder']}/` |")
    lines += ["", "## Duty cycle", ""]
    d = report["duty_cycle"]
    if d is None:
        lines.append(report["duty_cycle_why_none"] or "The spec gives no duty cycle.")
    else:
        steps = " → ".join(f"{s['maneuver']} {s['duration_s']:g} s" for s in d["steps"])
        lines += [f"{steps}; winding from {d['ambient_C']:g} °C, limit "
                  f"{d['winding_limit_C']:g} °C; verdict {verdict_word(d['verdict'])}.", "",
                  "| motor | peak °C | leg | at s | end °C | equivalent current A | margin | "
                  "verdict |", "|---|---|---|---|---|---|---|---|"]
        for motor, v in d["motors"].items():
            lines.append(f"| {motor} | {v['peak_C']:.1f} | {v['leg']} | {v['at_s']:.0f} | "
                         f"{v['end_C']:.1f} | {v['equivalent_current_A']:.3f} | "
                         f"{figure(v['margin'])} | {verdict_word(v['verdict'])} |")
        lines += ["", "Equivalent current: the constant current that would hold the winding "
                  "at the peak for ever; margin: the thermal model's continuous current over "
                  "it (fail below 1, as the thermal check)."]
    lines += ["", "Figures: `operating_points.png` (every maneuver's demand at the joint speed "
              "over the motor's envelope), `duty_cycle.png`. Each maneuver's folder holds "
              "`simulate`'s outputs (summary.json, plots, run.rrd: open them side by side in "
              "one viewer)."]
    return "\n".join(lines) + "\n"


def write_report(report: dict, out: Path) -> list[Path]:
    """envelope.md, then envelope.json (last), each atomically."""
    texts = (markdown(report), json.dumps(json_ready(report), indent=1, allow_nan=False) + "\n")
    return [write_atomic(out / name, text) for name, text in zip(REPORT_FILES, texts)]
