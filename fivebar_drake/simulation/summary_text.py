"""The summary of a simulated run in words: the answer in one sentence (answer: how much torque
the motion needs, naming the check that decided the verdict), each check in a phrase
(check_text), the limits reached (limits_text), summary.md (markdown: what ran, the motion, the
maneuver's figures beside their plan, the limits, the per-motor tables) and the writer of
summary.md and summary.json (write_summary). The figures are the summary's
(verdicts/summary_schema.Summary): statistics from simulation/run_statistics.py, the verdict from
verdicts/rules.py; nothing here computes one."""

from __future__ import annotations

import json
import math
from pathlib import Path

from fivebar_drake.verdicts.checks import (CHECK_ORDER, check_badness, demand_unmet,
                                           limit_shares_text, thresholds_text)
from fivebar_drake.core.files import json_ready, write_atomic
from fivebar_drake.core.text import figure, verdict_word
from fivebar_drake.verdicts.summary_schema import (AnyController, ContactCheck, JumpFigures, LandingFigures, LimitReport,
                                               MotorSummary, Ran, SpeedCheck, Summary,
                                               ThermalCheck, TorqueCheck)
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.run_statistics import MIN_CYCLES, PERCENTILE

SUMMARY_FILES = ("summary.md", "summary.json")   # summary.json last: its presence means complete


def limits_text(report: LimitReport) -> str:
    """The limit report (limit_report) in one line."""
    if not report["set"]:
        return "limits: none set ([limits] of the parameter file)"
    if not report["hits"]:
        return f"limits: none reached ({len(report['set'])} set in [limits])"
    return "limits reached: " + "; ".join(
        f"{h['leg']} {h['limit']} first at t = {h['first_t_s']:.3f} s, {h['share_of_time']:.1%} "
        f"of the time, worst {h['worst_value']:.4g} {h['unit']} (bound {h['bound']:.4g} "
        f"{h['unit']}, {h['field']})" for h in report["hits"])


def seed_analysis_load(params: Params) -> str:
    """The seed's load model in words (its figure is on the seed's own path)."""
    return (f"the seed's model on the seed's ellipse: G(q) with its weight share "
            f"{params.robot.weight_share_kg:.3f} kg at every foot all cycle, swing included")


def answer(s: Summary, params: Params) -> str:
    """The answer to 'how much torque does the gait (or maneuver) need?' for this run in one
    line (every report's first line, docs/output_style.md): the verdict, the check that decided
    it, the worst motor and its figure against its limit (opening); or why the motion was not
    achieved, or why there is no verdict. Its reasons are answer_details'."""
    if s["verdict"] == "insufficient":
        if not s["completed"] and not s["interrupted"]:
            return (f"No verdict: the run stopped early, at {s['duration_s']:.2f} s of the "
                    f"{s['requested_duration_s']:g} s asked.")
        if not s["periodic"]:
            return (f"No verdict: the run ended before the maneuver did; run at least "
                    f"{s['window_s'][1]:.2f} s.")
        return (f"No verdict: {s['cycles_in_window']} whole gait cycles after the "
                f"{s['window_s'][0]:g} s of standing and ramp, fewer than {MIN_CYCLES}.")
    leg, name = s["worst_motor"].split()
    m = s["legs"][leg][name]
    if s["verdict"] == "not_achieved" and s["error"]:
        return (f"NOT ACHIEVED, decided by the achieved check: the run stopped at "
                f"{s['duration_s']:.2f} s of the {s['requested_duration_s']:g} s asked.")
    if s["verdict"] == "not_achieved":
        return (f"NOT ACHIEVED, decided by the achieved check: worst motor {leg} {name}, at its "
                f"limits {m['saturated_fraction']:.1%} of the time.")
    return opening(s, leg, name, m["checks"]["torque"], m["checks"])


def answer_details(s: Summary, params: Params) -> list[str]:
    """The answer's reasons, one item each (summary.md lists them under the answer): the need
    in words, each check at the motor where it is worst, the static torque on the same poses,
    a gait's seed figure with its load model, what any controller needs, and a step check cut
    short."""
    interrupted = ([f"No step check: {s['step_check_interrupted']} (the verdict is the plant "
                    "step's alone)."] if s.get("step_check_interrupted") else [])
    floor = []
    if s.get("any_controller"):
        need, *blame = any_controller_text(s["any_controller"], params.checks.sf_warn)
        floor = [f"For any controller: {need}", *blame]
    if s["verdict"] == "insufficient":
        why = ([f"The run stopped: {s['error']}."] if s["error"] else
               [] if not s["periodic"] else
               [f"Run at least {MIN_CYCLES} whole cycles after the standing and the ramp."])
        return why + floor + interrupted
    leg, name = s["worst_motor"].split()
    m = s["legs"][leg][name]
    c = m["checks"]
    hz = figure(s["gait_frequency_hz"], "{:.3g}")
    head = (f"At {hz} Hz with the {s['gait']} gait" if s["periodic"] else
            f"For the {s['gait']} maneuver")
    seed = ([f"Separately, {seed_analysis_load(params)}, gives {s['seed_peak_torque_Nm']:.2f} "
             "N·m (its peak)."] if s["periodic"] else [])
    if s["verdict"] == "not_achieved" and s["error"]:
        return [f"The run stopped: {s['error']}."] + seed + floor + interrupted
    if s["verdict"] == "not_achieved":
        if m["saturated_fraction"] > params.checks.achieved_max_limit_fraction:
            below = m["unsaturated_demand_p99_Nm"]
            need = (f"the motors need more than they give (worst motor {leg} {name}, at "
                    f"{limit_shares_text(m['limit_shares'])}; "
                    + (f"below its limits its demand p99 is {below:.2f} N·m)"
                       if below is not None and math.isfinite(below) else
                       "it was at a limit in every sample)"))
        else:
            need = (f"its demand p99 of {m['demand_p99_Nm']:.2f} N·m (worst motor {leg} {name}) "
                    "is not a need")
        return ([f"Not achieved: {c['achieved']['why']}.",
                 f"{head} {need}; the saturated demand is the controller's error growing, not "
                 f"what the {'gait' if s['periodic'] else 'maneuver'} takes."]
                + seed + floor + interrupted)
    static = m["static_trot_Nm"]
    over = f"over {s['cycles_in_window']} cycles" if s["periodic"] else "over the maneuver"
    limited = demand_unmet(c)
    need_Nm = m["p99_torque_Nm"] if limited else m["demand_p99_Nm"]
    others = [f"{lg} {nm} {o['saturated_fraction']:.1%}" for lg, ms in s["legs"].items()
              for nm, o in ms.items() if o["saturated_fraction"] and (lg, nm) != (leg, name)]
    if limited:
        need = (f"the motors worked at their limits (worst motor {leg} {name}, at "
                f"{limit_shares_text(limited['limits'])}, {over}): they delivered "
                f"{m['p99_torque_Nm']:.2f} N·m ({PERCENTILE:g}th percentile); what the "
                "controller asked beyond the limit was not needed: the motion was achieved "
                f"without it (the demand's {PERCENTILE:g}th percentile: "
                f"{m['demand_p99_Nm']:.2f} N·m)")
    else:
        reached = (f"it sat at {limit_shares_text(m['limit_shares'])}"
                   if m["saturated_fraction"] else
                   "it never reached a limit" if others else "no motor reached a limit")
        need = (f"the motors need {m['demand_p99_Nm']:.2f} N·m ({PERCENTILE:g}th percentile "
                f"of the demand {over}, worst motor {leg} {name}; {reached})")
    checks = [f"At the motor where it is worst, {where}: {check_text(k, w)}."
              for k, (where, w) in worst_checks(s).items()]
    return ([f"{head} {need}."]
            + ([f"Other motors at a limit (share of the time, each limit in the table): "
                f"{', '.join(others)}."] if others else [])
            + checks
            + [f"On the same poses with the same load schedule (the robot's weight shared by "
               f"the feet in stance) the static torque is {static:.2f} N·m: the dynamics add "
               f"{need_Nm / static - 1:+.0%}."] + seed + floor + interrupted)


def worst_checks(s: Summary) -> dict[str, tuple[str, dict]]:
    """Per check (torque, speed, thermal) the motor where it is worst over the run's motors
    ("LEG M") and its check (verdicts.checks.check_badness, as the envelope takes them)."""
    motors = [(f"{leg} {name}", m["checks"]) for leg, ms in s["legs"].items()
              for name, m in ms.items() if m["checks"] is not None]
    return {k: max(((w, c[k]) for w, c in motors), key=lambda x: check_badness(k, x[1]))
            for k in CHECK_ORDER}


def opening(s: Summary, leg: str, name: str, t: TorqueCheck, c) -> str:
    """The answer's first sentence: "FAIL, decided by the torque check: worst motor RL A, SF
    1.46 (its demand's 99th percentile at 69 % of its 5.00 N·m driving limit, ...)." — the
    verdict, the deciding check, the worst motor, the deciding figure of a speed check ("3.2 %
    of the time beyond the torque–speed envelope (least margin 1.00)") or a thermal one, then
    its torque figure as a share of the limit of its quadrant (each sample's own: driving or
    braking; no torque in N·m: the demand's p99 in N·m, quadrants mixed, follows it)."""
    verdict = (f"{verdict_word(s['verdict'])}, decided by the {s['deciding_check']} check"
               if s["verdict"] != "marginal" else f"MARGINAL ({marginal_why(s)})")
    check, d = s.get("deciding_check"), c.get(s.get("deciding_check")) or {}
    deciding = ""
    if check == "speed":
        least = "none driving" if d["least_margin"] is None else f"{d['least_margin']:.2f}"
        deciding = (f"{d['outside_fraction'] * 100:.1f} % of the time beyond the torque–speed "
                    f"envelope (least margin {least}); ")
    elif check == "thermal" and d.get("margin") is not None:
        deciding = f"continuous / RMS current {d['margin']:.2f}; "
    torque = ("no torque demand" if t["sf"] is None else f"SF {t['sf']:.2f}" if deciding else
              f"SF {t['sf']:.2f} (its demand's 99th percentile at "
              f"{t['share_of_limit'] * 100:.0f} % of its {t['limit_Nm']:.2f} N·m {t['quadrant']} "
              f"limit, each sample against its own quadrant's)")
    return f"{verdict}: worst motor {leg} {name}, {deciding}{torque}."


def check_text(name: str, c: TorqueCheck | SpeedCheck | ThermalCheck) -> str:
    """One check of a motor (name: "torque", "speed" or "thermal") in a phrase: its figure, its
    verdict and, at the motor's limits, why."""
    limit = f" ({c['why']})" if "at_limit_fraction" in c else ""
    if name == "torque":
        if c["sf"] is None:
            return f"torque: no demand, {c['verdict']}"
        what = " on what it delivered" if "demand_sf" in c else ""
        return (f"torque: safety factor {c['sf']:.2f}{what} ({c['quadrant']}, against its "
                f"{c['limit_Nm']:.2f} N·m limit), {c['verdict']}{limit}")
    if name == "speed":
        least = "none driving" if c["least_margin"] is None else f"{c['least_margin']:.2f}"
        return (f"speed: least margin {least}, {c['outside_fraction']:.1%} of the time beyond "
                f"the envelope, {c['verdict']}{limit}")
    if c["margin"] is None:
        return f"thermal: {c.get('why', 'no model')}"
    return (f"thermal: continuous / RMS current {c['margin']:.2f}, {c['verdict']}")


def marginal_why(s: Summary) -> str:
    """Why a run is marginal: its step check's reason, else its contact check's."""
    step, contact = s.get("step_check"), s.get("contact_check")
    if step and (step["marginal"] or step["achieved"] != step["achieved_at_half_step"]):
        return f"{step['why']}; step check at half the plant step"
    return f"{contact['why']}; contact check, foot stiffness x0.5 and x2" if contact else ""


def contact_text(c: ContactCheck) -> str:
    """The contact check in a line: each contact's verdict, the worst safety factor's band and
    each event figure's."""
    band = c["worst_sf_band"]
    shown = {"height_m": ("apex", 1e3, "mm"), "peak_force_N": ("peak force", 1.0, "N"),
             "impulse_N_s": ("impulse", 1.0, "N·s"), "peak_torque_Nm": ("peak torque", 1.0, "N·m")}
    events = "; ".join(
        f"{group} {shown[key][0]} {lo * shown[key][1]:.3g}–{hi * shown[key][1]:.3g} {shown[key][2]}"
        for group, figures in c["events"].items() for key, (lo, hi) in figures.items()
        if key in shown)
    return ("contact check (foot stiffness " + ", ".join(
        f"{label} {v['stiffness_N_m']:.3g} N/m" for label, v in c["variants"].items()) + "): "
        + ", ".join(f"{k} {verdict_word(v)}" for k, v in c["verdicts"].items())
        + ("" if band is None else f"; worst SF {band[0]:.2f}–{band[1]:.2f}")
        + (f"; {events}" if events else "")
        + (f"; MARGINAL: {c['why']}" if c["marginal"] else ""))


def markdown(s: Summary, params: Params) -> str:
    """summary.md of the summary s: the answer, what ran, the motion (and a maneuver's figures
    beside their plan: maneuver_lines), the limits, the torque table and the torque split."""
    periodic = s["periodic"]
    over = (f"{s['cycles_in_window']} whole gait cycles" if periodic else "the maneuver")
    lines = [
        f"# Simulated {s['gait']} {'gait' if periodic else 'maneuver'}: the motor torque it "
        "needs", "", s["answer"], "", *[f"- {item}" for item in s["answer_details"]], "",
        f"Simulated {s['duration_s']:.2f} s (requested {s['requested_duration_s']:g} s), "
        f"{s['closure']} closure, time step {s['time_step_s'] * 1e3:.3f} ms, "
        f"{s['real_time_factor']:.2f}x real time. Statistics over {over}, "
        f"t = {s['window_s'][0]:.2f} .. {s['window_s'][1]:.2f} s; every value is a "
        f"mean over {s['log_period_s'] * 1e3:g} ms of plant steps.",
    ]
    lines += ["", ran_text(s["ran"])]
    if s["error"]:
        lines += ["", f"**The run stopped early:** {s['error']}"]
    motion = (f"largest tilt {s['max_tilt_deg']:.1f} deg; worst loop gap "
              f"{s['max_loop_gap_m'] * 1e3:.4f} mm")
    if periodic:
        clear = min(s["swing_clear_fraction"].values())
        drag = max(s["swing_drag_fraction"].values())
        dragged = ("" if not math.isfinite(drag) else
                   f", on it {drag * 100:.0f} % of mid-swing (worst legs; the rest is early "
                   "touchdown)")
        motion = (f"walking: {figure(s['mean_forward_speed_m_s'], '{:.3f}')} m/s against the "
                  f"gait's {figure(s['gait_speed_m_s'], '{:.3f}')} m/s; swing feet clear of the "
                  f"ground {figure(clear * 100, '{:.0f}')} % of scheduled swing{dragged}; {motion}")
    lines += [
        "", f"- {motion}", *maneuver_lines(s, params.checks.sf_warn),
        *([f"- {contact_text(s['contact_check'])}"] if s.get("contact_check") else []),
        f"- {limits_text(s['limits'])}",
        *([f"- vertical ground force (every plant step, {s['log_period_s'] * 1e3:g} ms means) "
           f"between {s['vertical_support']['least_share']:.2f} (t = "
           f"{s['vertical_support']['least_at_s']:.3f} s) and "
           f"{s['vertical_support']['largest_share']:.2f} (t = "
           f"{s['vertical_support']['largest_at_s']:.3f} s) of the weight"]
          if s.get("vertical_support") else []),
        "", thresholds_text(params.checks),
        "", "| leg | motor | demand p99 | demand peak | applied p99 | RMS | seed's model | "
        "static, same loads | contact peak | demand / seed's | demand / static | SF | verdict | "
        "clipped | p99 speed (rad/s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for leg, motors in s["legs"].items():
        for name, m in motors.items():
            lines.append(
                f"| {leg} | {name} | " + " | ".join(figure(m[k]) for k in (
                    "demand_p99_Nm", "demand_peak_Nm", "p99_torque_Nm", "rms_torque_Nm",
                    "static_seed_Nm", "static_trot_Nm", "static_contact_Nm"))
                + f" | {figure(m['dynamic_to_seed_static'], '{:.2f}x')} | "
                f"{figure(m['dynamic_to_trot_static'], '{:.2f}x')} | "
                f"{figure(m['safety_factor'])} ({_quadrant(m)}) | {verdict_word(m['verdict'])} | "
                f"{_clipped(m)} | {figure(m['p99_speed_rad_s'])} |")
    lines += ["", "Torque split (RMS over the window, N·m): contact -J^T F, links M q'' + c + G, "
              "rotor N^2 J q'', friction; residual = applied - their sum.", "",
              "| leg | motor | contact | links | rotor | friction | residual |",
              "|---|---|---|---|---|---|---|"]
    for leg, motors in s["legs"].items():
        for name, m in motors.items():
            d = m["decomposition_rms_Nm"]
            lines.append(f"| {leg} | {name} | " + " | ".join(figure(d[k], "{:.3f}") for k in (
                "contact", "links", "rotor", "friction", "residual")) + " |")
    motor = params.motor
    lines += ["", "Units N·m unless stated.", "",
              f"- Motor limits at the output: {motor.peak_torque_Nm:.2f} N·m driving (torque and "
              f"speed of one sign), {motor.braking_peak_torque_Nm:.2f} braking (opposite signs), "
              f"both at the peak current; the driving torque falls beyond its corner to zero at "
              f"the no-load speed {motor.no_load_speed_rad_s:.2f} rad/s, beyond which the "
              "back-EMF forces braking.",
              "- Demand: the controller's command before saturation.",
              f"- SF: 1 / the {PERCENTILE:g}th percentile of the demand over the limit of each "
              "sample's own quadrant (the quadrant of that percentile in brackets), or of the "
              f"applied torque where the motor sat at its limits more than "
              f"{100 - PERCENTILE:g} % of the time (clipped, with the limit it sat at most: its "
              "demand p99 was not met, and is not a need).",
              f"- Seed's model: the seed's static torque G(q) on the run's poses with "
              f"{params.robot.weight_share_kg:.3f} kg at every foot all the time.",
              "- Static, same loads: the static torque on the same poses with the robot's weight "
              "shared by the feet in stance.",
              "- Contact peak: the largest -J_Fᵀ F of the measured ground force.",
              "- Per-cycle spreads are in summary.json."]
    return "\n".join(lines) + "\n"


def ran_text(ran: Ran) -> str:
    """What ran in one line: each variant's kind and fields (numbers to 4 significant digits: the
    optimum's swing shape has all its digits in summary.json), and the plan's events."""
    events = ran["planned_events_s"]

    def shown(x):
        return f"{x:.4g}" if isinstance(x, float) else repr(x)
    return ("Ran: " + "; ".join(
        f"{what} {v['kind']} (" + ", ".join(f"{k} = {shown(x)}" for k, x in v.items()
                                            if k != "kind")
        + ")" for what, v in ((w, ran[w]) for w in ("gait", "controller", "closure")))
        + (", planned events " + ", ".join(f"{k} {x:.3f} s" for k, x in events.items())
           if events else "") + ".")


BLAME = {
    "any controller": "No controller could do it: its need is beyond the motors (a floor less "
                      "its {margin:.0%} model margin beyond the motors' limit, or a bound by "
                      "another method).",
    "this controller": "The motors could do the motion; this controller failed it{sf}.",
    "undecided": "Whether any controller could do it is undecided: it lies beyond the reduced "
                 "model's optimum and within the bound; the tracking controller's run decides.",
    "unknown": "Whether a better controller would pass is unknown: no floor for this task.",
    None: ""}


def any_controller_text(a: AnyController, sf_warn: float | None = None) -> list[str]:
    """What any controller would need for the maneuver (pipeline.any_controller), then whom a
    failing verdict blames (verdicts.rules.fails_for; none where nothing failed), a sentence
    each; sf_warn: the warn threshold a need's safety factor is set against."""
    parts = []
    for p, v in a["phases"].items():
        asked = "" if v["asked_Nm"] is None else f", asked {v['asked_Nm']:.2f}"
        parts.append(f"{p} {v['floor_Nm']:.2f} of {v['limit_Nm']:.2f}{asked}"
                     if v["floor_Nm"] is not None else f"{p} {v['status']}{asked}")
    what = (f"{a['height_m'] * 1e3:.0f} mm {a['maneuver']}" if a["height_m"] else a["maneuver"])
    text = (f"Any controller needs at least {a['floor_Nm']:.2f} N·m at the peak for this {what}"
            if a["floor_Nm"] is not None else f"No floor for this {what}")
    if any(v["floor_Nm"] is not None for v in a["phases"].values()):
        text += f" ({'; '.join(parts)} N·m)"
    if "push-off" in a["phases"] or a.get("reached_m") is not None:     # it jumps
        optima = [f"{label} {a[key] * 1e3:.1f} mm" for key, label in (
            ("reached_m", "this run reached"), ("ceiling_m", "its stroke's optimum"),
            ("reach_ceiling_m", "the whole reach's optimum"), ("bound_m", "the bound"))
            if a.get(key) is not None]
        text += "; " + ", ".join(optima) if optima else ""
    elif "landing" in a["phases"] and a.get("ceiling_m") is not None:         # it lands
        text += f"; the highest drop its stroke absorbs: {a['ceiling_m'] * 1e3:.0f} mm"
    if a["controller_cost"] is not None:
        text += f"; this controller asked {a['controller_cost']:.2f}x the floor"
    if a["why"]:
        text += f" ({a['why']})"
    sf = ""
    if (a["fails_for"] == "this controller" and sf_warn is not None
            and a["floor_safety_factor"] is not None and a["floor_safety_factor"] < sf_warn):
        sf = (f", though the least need found leaves SF {a['floor_safety_factor']:.2f} < "
              f"{sf_warn:g} (a lower need may exist)")
    elif a["fails_for"] == "this controller":
        sf = ": a better controller would pass"
    blame = BLAME[a["fails_for"]].format(margin=a["floor_margin"], sf=sf).strip()
    return [text + "."] + ([blame] if blame else [])


def maneuver_lines(s: Summary, sf_warn: float) -> list[str]:
    """A maneuver's measured figures beside their plan (each group's `planned`): the jump and
    the landing, a line each where it happened."""
    lines = []
    if s["jump"]:
        j = s["jump"]
        lines.append(f"- jump: apex {_beside(j, 'height_m', 1e3, 'mm', '.1f')} above standing, "
                     f"takeoff at t = {_beside(j, 'takeoff_s', 1.0, 's', '.3f')} at "
                     f"{j['takeoff_speed_m_s']:.2f} m/s, apex {j['time_to_apex_s']:.3f} s after "
                     f"the push-off's onset (agility {j['agility_m_s']:.2f} m/s)")
    if s["landing"]:
        ld = s["landing"]
        converged = (((s.get("step_check") or {}).get("events") or {}).get("landing") or {})
        peak = converged.get("peak_torque_Nm")
        band = ("" if peak is None else
                f" (converged {peak['converged']:.2f} ± {peak['error']:.2f} by the step check)")
        lines.append(f"- landing: touchdown at t = {_beside(ld, 'touchdown_s', 1.0, 's', '.3f')} "
                     f"at {ld['touchdown_speed_m_s']:.2f} m/s, peak ground force "
                     f"{ld['peak_force_N']:.0f} N, peak motor torque {ld['peak_torque_Nm']:.2f} "
                     f"N·m{band}, body drop {ld['compression_m'] * 1e3:.1f} mm over "
                     f"{ld['duration_s'] * 1e3:.0f} ms")
    return lines


def _beside(figures: JumpFigures | LandingFigures, key: str, scale: float, unit: str,
            spec: str) -> str:
    """A measured figure (figures[key] x scale, in unit, format spec) with its plan beside it,
    e.g. "60.7 mm (planned 60.0 mm)"; alone where nothing planned it."""
    text = f"{figures[key] * scale:{spec}} {unit}"
    plan = figures["planned"].get(key)
    return text if plan is None else f"{text} (planned {plan * scale:{spec}} {unit})"


def _quadrant(m: MotorSummary) -> str:
    """The quadrant of a motor's torque figure (summary table)."""
    c = m["checks"]
    return c["torque"]["quadrant"] or "—" if c else "—"


def _clipped(m: MotorSummary) -> str:
    """The share of the time a motor was clipped, with the limit it sat at most."""
    if not m["saturated_fraction"] or not math.isfinite(m["saturated_fraction"]):
        return figure(m["saturated_fraction"], "{:.1f} %")
    most = max(m["limit_shares"], key=lambda k: m["limit_shares"][k]).replace("_", " ")
    return f"{m['saturated_fraction'] * 100:.1f} % ({most} most)"


def write_summary(summary: Summary, params: Params, out_dir: Path) -> list[Path]:
    """Write SUMMARY_FILES into out_dir, each atomically, summary.json last: call it after every
    other output of the run is written, so a summary.json always describes complete files."""
    texts = (markdown(summary, params),
             json.dumps(json_ready(summary), indent=2, allow_nan=False) + "\n")
    out_dir.mkdir(parents=True, exist_ok=True)
    return [write_atomic(out_dir / name, text) for name, text in zip(SUMMARY_FILES, texts)]
