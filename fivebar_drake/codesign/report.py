"""The co-design's outputs: design.md (its first line the recommended design and why), design.json,
design.toml (the recommended design's parameter file) and pareto.png; or, when no design is
verified, why not: the requirement no candidate meets and the best candidate's margin."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from fivebar_drake.codesign.designs import actuator_mass, design_name, write_parameter_file
from fivebar_drake.codesign.search import JOURNAL_FILE, corrected, ranked
from fivebar_drake.codesign.spec import CodesignSpec
from fivebar_drake.core.files import json_ready, save_figure, write_atomic
from fivebar_drake.core.text import ANSWER_CHARS
from fivebar_drake.mechanisms.fivebar import MOTORS

FILES = ("design.md", "design.toml", "pareto.png", "design.json")   # design.json last
DEFAULT = "default"      # the default design's key among the simulated
COMPARED = "compared_"   # with its index: a design of the spec's `compare` list
FLAG = 0.10          # predicted and simulated figures further apart than this are flagged


@dataclass
class CodesignRun:
    """What run_codesign did: design.json's dictionary, the files written, and why no design
    is recommended ("" when one is)."""

    report: dict
    files: list[Path]
    failure: str


def compare(prediction: dict, sim: dict) -> list[dict]:
    """Per maneuver whose safety factor a level predicted: the predicted beside the simulated
    (the worst motor's), their relative difference and whether it exceeds FLAG."""
    rows = []
    for name, p in prediction["maneuvers"].items():
        if "safety_factor" not in p:
            continue
        simulated_sf = sim["maneuvers"].get(name, {}).get("figures", {}).get("torque")
        predicted_sf = p.get("safety_factor")
        diff = (predicted_sf / simulated_sf - 1.0 if predicted_sf is not None and simulated_sf
                and math.isfinite(simulated_sf) else None)
        rows.append({"maneuver": name, "level": p["level"], "predicted_sf": predicted_sf,
                     "simulated_sf": simulated_sf, "difference": diff,
                     "flagged": diff is None or abs(diff) > FLAG})
    return rows


def least(sim: dict, accept: tuple[str, ...]) -> tuple[float, str]:
    """(the least simulated margin, "maneuver check" of it), a maneuver whose verdict is not
    accepted first (its deciding check; a margin of 0 without figures: no verdict)."""
    found = (math.inf, "")
    for name, m in sim["maneuvers"].items():
        if m["verdict"] not in accept:
            check = m["deciding_check"]
            return (m["margins"].get(check, 0.0), f"{name} {check or 'verdict'} ({m['verdict']})")
        for check, margin in m["margins"].items():
            found = min(found, (margin, f"{name} {check}"))
    return found


def nobody_meets(spec: CodesignSpec, entries: list[dict], finalists: list[dict]) -> str:
    """Why no design is recommended: a requirement (a maneuver's check) no candidate meets and
    the best candidate's margin on it; else the best candidate and where it falls short."""
    pool = ([(f["name"], f["simulated"], "simulated") for f in finalists] or
            [(e["name"], e, "predicted") for e in entries if not e["error"]])
    if not pool:
        return "no design of the space can be built: " + (entries[0]["error"] if entries else
                                                          "no trial finished")
    best = {}
    for name, result, level in pool:
        for maneuver, m in result["maneuvers"].items():
            for check, margin in (m["margins"] or {"verdict": 0.0}).items():
                key = f"{maneuver} {check}"
                if key not in best or margin > best[key][0]:
                    best[key] = (margin, name, level)
    unmet = sorted((v, k) for k, v in best.items() if v[0] < 1.0)
    if unmet:
        (margin, name, level), key = unmet[0]
        return (f"no candidate meets {key}: the best, {name}, reaches a {level} margin of "
                f"{margin:.2f} (1 meets it; the requirement of {spec.envelope.source or 'the'} "
                f"envelope, accepted {'/'.join(spec.accept)})")
    level = pool[0][2]

    def overall(result):
        return least(result, spec.accept) if level == "simulated" else (result["margin"],
                                                            result["short_of"])

    name, result, _ = max(pool, key=lambda p: overall(p[1])[0])
    margin, where = overall(result)
    return (f"no candidate meets every requirement at once: the best, {name}, is short on "
            f"{where} ({level} margin {margin:.2f}; every requirement alone is met by some "
            "candidate)")


def codesign_report(spec: CodesignSpec, entries: list[dict], chosen: list[dict],
                    verified: dict, factors: dict[str, float]) -> dict:
    """design.json's dictionary (module docstring)."""
    base = spec.envelope.maneuvers[0].params
    default_mass = base.robot.motors_kg / (base.robot.legs * len(MOTORS))
    finalists = [{**e, "key": f"trial_{e['trial']}", "simulated": verified[f"trial_{e['trial']}"],
                  "comparison": compare(e, verified[f"trial_{e['trial']}"])} for e in chosen]
    passing = ranked(spec, [f for f in finalists if f["simulated"]["passes"]])
    recommended = passing[0] if passing else None
    report = {"spec": spec.source, "accept": list(spec.accept),
              "step_check": spec.step_check, "never_at_limit": spec.never_at_limit,
              "objectives": list(spec.objectives), "trials": len(entries),
              "predicted_meeting": sum(e["meets"] for e in entries),
              "default": {"actuator_mass_kg": default_mass,
                          "simulated": verified.get(DEFAULT)},
              "compared": [{"key": f"{COMPARED}{i}", "name": design_name(d), "design": d,
                            "actuator_mass_kg": actuator_mass(d),
                            "simulated": verified.get(f"{COMPARED}{i}")}
                           for i, d in enumerate(spec.compare)],
              "finalists": finalists, "recommended": recommended,
              "failure": "" if recommended else nobody_meets(spec, entries, finalists),
              "corrections": factors, "actuator_mass_band": (
                  None if spec.mass_band is None else
                  {"reference_kg": spec.mass_band[0], "within": spec.mass_band[1]}),
              "candidates": entries}
    report["not_simulated"] = not_simulated(spec, entries, finalists, recommended, factors)
    report["pareto_verified"] = ([f["key"] for f in verified_front(spec, finalists)]
                                 if len(spec.objectives) > 1 else [])
    report["max_jumps"] = max_jumps(report, verified) if spec.simulate_max_jump else []
    report["answer"], report["why"] = answer(spec, report)
    return report


def max_jumps(report: dict, verified: dict) -> list[dict]:
    """The simulated designs' max-effort jumps (run.max_jump), the default design first: key,
    name, actuator mass, the jump's figures."""
    rows = [(DEFAULT, "the default design", report["default"]["actuator_mass_kg"])]
    rows += [(c["key"], c["name"], c["actuator_mass_kg"]) for c in report["compared"]]
    rows += [(f["key"], f["name"], f["objectives"]["actuator_mass_kg"])
             for f in report["finalists"]]
    return [{"key": k, "name": n, "actuator_mass_kg": m, **verified[k]["max_jump"]}
            for k, n, m in rows if k in verified and "max_jump" in verified[k]]


def _jump_text(row: dict) -> str:
    """A simulated max jump in a few words."""
    return (f"{row['height_m'] * 1e3:.0f} mm simulated of its {row['planned_m'] * 1e3:.0f} mm "
            f"plan (ceiling {row['ceiling_m'] * 1e3:.0f} mm"
            + ("" if row["landed"] else "; its landing not verified") + ")")


def answer(spec: CodesignSpec, report: dict) -> tuple[str, list[str]]:
    """design.md's first line (at most ANSWER_CHARS where the design's name allows): the
    recommended design, its simulated outcome and mass, or that there is none; and the reasons,
    one item each."""
    r = report["recommended"]
    if r is None:
        head = f"No design recommended: {report['failure']}."
        if len(head) > ANSWER_CHARS:
            head = f"No design recommended: {report['failure'].split(' (')[0]}."
        return head, [f"{report['failure'][0].upper()}{report['failure'][1:]}."]
    margin, where = least(r["simulated"], spec.accept)
    mass = r["objectives"]["actuator_mass_kg"]
    default = report["default"]["actuator_mass_kg"]
    duty = " and the duty cycle" if r["simulated"]["duty_cycle"] else ""
    head = (f"Recommended: {r['name']}: passes every maneuver{duty} in simulation, least "
            f"margin {margin:.2f}; actuator {mass:.3f} kg (default {default:.3f} kg).")
    if len(head) > ANSWER_CHARS:
        head = f"Recommended: {r['name']} (finalists/{r['key']}): passes in simulation."
    passing = [f for f in report["finalists"] if f["simulated"]["passes"]]
    why = [f"The best by {spec.objectives[0]} of the finalists that pass every maneuver{duty} "
           f"of the requirements in full Drake simulation ({len(passing)} of "
           f"{len(report['finalists'])}; every check of every motor, accepted "
           f"{'/'.join(spec.accept)}{_strictness(spec)}).",
           f"Actuator mass {mass:.3f} kg{_band(spec)}; the default design's {default:.3f} kg "
           f"({_outcome(report['default']['simulated'], spec.accept)})"
           + "".join(f"; {c['name']}'s {c['actuator_mass_kg']:.3f} kg "
                     f"({_outcome(c['simulated'], spec.accept)})" for c in report["compared"])
           + "."]
    why += [f"Decided by {least(f['simulated'], spec.accept)[1]}, where the lighter {f['name']} "
            "fails in simulation." for f in report["finalists"]
            if not f["simulated"]["passes"] and f["objectives"]["actuator_mass_kg"] < mass]
    jumps = {j["key"]: j for j in report["max_jumps"]}
    if r["key"] in jumps:
        others = "; ".join(f"{j['name']}'s {_jump_text(j)}" for k, j in jumps.items()
                           if k != r["key"])
        why.append(f"Its max-effort jump rises {_jump_text(jumps[r['key']])}"
                   + (f", against {others}" if others else "") + ".")
    why.append(f"Its least margin {margin:.2f} ({where}); verified by simulating the whole "
               f"envelope in finalists/{r['key']}.")
    if report["not_simulated"]:
        why.append(f"{len(report['not_simulated'])} better candidates (of each motor the "
                   "nearest: " + ", ".join(c["name"] for c in report["not_simulated"])
                   + ") were kept out by the corrected predictions, not simulated.")
    return head, why


def _band(spec: CodesignSpec) -> str:
    """The mass band in a few words ("" without one)."""
    if spec.mass_band is None:
        return ""
    return f" (held within ±{spec.mass_band[1]:.0%} of {spec.mass_band[0]:.3f} kg)"


def _strictness(spec: CodesignSpec) -> str:
    """What else the simulations were held to, in a few words."""
    return ((", with the step check at half the plant step" if spec.step_check else "")
            + (", never at a motor or joint limit" if spec.never_at_limit else ""))


def _outcome(sim: dict | None, accept: tuple[str, ...]) -> str:
    """A simulated envelope's outcome in a few words: passes, or the first maneuver whose
    verdict is not accepted, that verdict and its deciding check."""
    if sim is None:
        return "not simulated"
    failing = [(n, m) for n, m in sim["maneuvers"].items() if m["verdict"] not in accept]
    if not failing:
        return "passes in simulation"
    name, m = failing[0]
    return (f"{m['verdict']} in simulation: {name}, {m['deciding_check'] or 'no'} check"
            + (f", and {len(failing) - 1} more" if len(failing) > 1 else ""))


def not_simulated(spec: CodesignSpec, entries: list[dict], finalists: list[dict],
                  recommended: dict | None, factors: dict[str, float]) -> list[dict]:
    """The candidates better than the recommended design by the first objective (all, without
    one) that were predicted to meet every requirement but not simulated, of each motor the one
    nearest to passing (the largest corrected least margin, run.corrected): that margin and the
    requirement whose correction kept it out. The search does not show that they fail: only
    that the predictions, corrected by the simulations, did not expect them to pass."""
    done = {f["name"] for f in finalists}
    first = spec.objectives[0]
    sign = 1.0 if spec.directions[0] == "minimize" else -1.0
    bound = sign * recommended["objectives"][first] if recommended else math.inf
    nearest = {}
    for e in ranked(spec, [e for e in entries if e["meets"] and e["name"] not in done
                           and sign * e["objectives"][first] < bound]):
        motor = e["design"]["motor"]
        if motor not in nearest or corrected(e, factors) > corrected(nearest[motor], factors):
            nearest[motor] = e
    out = []
    for e in ranked(spec, list(nearest.values())):
        scaled = {f"{n} {c}": m * factors.get(f"{n} {c}", 1.0)
                  for n, p in e["maneuvers"].items() for c, m in p["margins"].items()}
        worst = min(scaled, key=scaled.get)
        out.append({"name": e["name"], "trial": e["trial"], first: e["objectives"][first],
                    "predicted_margin": e["margin"], "corrected_margin": corrected(e, factors),
                    "kept_out_by": worst, "correction": factors.get(worst, 1.0)})
    return out


def verified_front(spec: CodesignSpec, finalists: list[dict]) -> list[dict]:
    """The passing finalists no other passing finalist dominates on the objectives (simulated
    where given, else predicted)."""
    sign = [1.0 if d == "minimize" else -1.0 for d in spec.directions]

    def key(f):
        sim = f["simulated"].get("objectives", {})
        return [s * (sim[o] if _finite(sim.get(o)) else f["objectives"][o])
                for s, o in zip(sign, spec.objectives)]

    passing = [f for f in finalists if f["simulated"]["passes"]]
    return [f for f in passing if not any(
        all(a <= b for a, b in zip(key(g), key(f))) and key(g) != key(f) for g in passing)]


def _objective_cell(finalist: dict, objective: str) -> str:
    """A finalist's objective, predicted / simulated where the simulation gives it."""
    text = _f(finalist["objectives"].get(objective), "{:.3f}")
    sim = finalist["simulated"].get("objectives", {}).get(objective)
    if objective != "actuator_mass_kg" and sim is not None:
        text += f" / {_f(sim, '{:.3f}')}"
        predicted = finalist["objectives"].get(objective)
        if _finite(sim) and _finite(predicted) and sim and abs(predicted / sim - 1.0) > FLAG:
            text += f" FLAG {predicted / sim - 1.0:+.0%}"
    return text


def _limits(limits: dict | None) -> str:
    """A maneuver's limits (run.at_limits) in a cell: the motors' largest share at a limit,
    the joint limits reached, the step check's finding."""
    if not limits or limits["motor_share"] is None:
        return "—"
    parts = [f"motors {limits['motor_share']:.1%} at a limit"]
    if limits["joint_limits"]:
        parts.append("reached " + ", ".join(limits["joint_limits"]))
    if limits["step_marginal"] is not None:
        parts.append("step check " + ("MARGINAL" if limits["step_marginal"] else "ok"))
    return "; ".join(parts)


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)


def _f(x, pattern: str = "{:.2f}") -> str:
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else \
        pattern.format(x)


def markdown(spec: CodesignSpec, report: dict) -> str:
    """design.md."""
    lines = [report["answer"], ""] + [f"- {item}" for item in report["why"]] + [""]
    r, default = report["recommended"], report["default"]["simulated"]
    if default is None:
        default = {"maneuvers": {}}
        lines += ["No design was predicted to meet the requirements: none was simulated.", ""]
    lines += ["## Margins per check per maneuver (simulated)", "",
              "Figure: torque the worst motor's safety factor, speed its least speed margin, "
              "thermal its current margin; margin: the figure over what the accepted verdict "
              "needs (>= 1 meets it).", "",
              "| maneuver | check | recommended | margin | default design | margin |",
              "|---|---|---|---|---|---|"]
    for name, d in default["maneuvers"].items():
        rec = (r["simulated"]["maneuvers"] if r else {}).get(
            name, {"verdict": "—", "figures": {}, "margins": {}})
        lines.append(f"| {name} | verdict | {rec['verdict']} | | {d['verdict']} | |")
        lines.append(f"| {name} | limits | {_limits(rec.get('limits'))} | | "
                     f"{_limits(d.get('limits'))} | |")
        for check in d["figures"] or rec["figures"]:
            lines.append(f"| {name} | {check} | {_f(rec['figures'].get(check))} | "
                         f"{_f(rec['margins'].get(check))} | {_f(d['figures'].get(check))} | "
                         f"{_f(d['margins'].get(check))} |")
    if report["compared"]:
        lines += ["", "## Compared designs (simulated beside the default)", "",
                  "| design | actuator mass kg | simulated |", "|---|---|---|"]
        lines += [f"| {c['name']} | {c['actuator_mass_kg']:.3f} | "
                  f"{_outcome(c['simulated'], spec.accept)} |" for c in report["compared"]]
    lines += ["", "## Predicted vs simulated", "",
              "Predicted: (a) closed form (trot maneuvers), (b) the optimal-maneuver floors "
              "(jumps and drops: optimal/vertical_jump; walks, bounds and pronks: "
              "optimal/gait_floor, the body free to surge, heave and pitch): the motors' peak "
              "over the least any controller needs, so an upper bound on the simulated. "
              f"Flagged: more than {FLAG:.0%} apart.", "",
              "| finalist | maneuver | level | predicted SF | simulated SF | difference | |",
              "|---|---|---|---|---|---|---|"]
    for f in report["finalists"]:
        for c in f["comparison"]:
            lines.append(f"| {f['key']} | {c['maneuver']} | {c['level']} | "
                         f"{_f(c['predicted_sf'])} | {_f(c['simulated_sf'])} | "
                         f"{_f(c['difference'], '{:+.0%}')} | "
                         f"{'FLAG' if c['flagged'] else ''} |")
    lines += ["", "## Finalists", "",
              "Objectives: predicted / simulated (the power objectives: predicted on the gait "
              "floors' motions, which neglect the swing legs, simulated over the runs' "
              f"statistics windows; FLAG: more than {FLAG:.0%} apart; the jump: its ceiling "
              + ("predicted, its planned max jump's apex simulated)." if spec.simulate_max_jump
                 else "a prediction only)."), "",
              "| finalist | design | " + " | ".join(spec.objectives)
              + " | predicted margin | simulated | least simulated margin |",
              "|---|---|" + "---|" * len(spec.objectives) + "---|---|---|"]
    for f in report["finalists"]:
        margin, where = least(f["simulated"], spec.accept)
        lines.append(f"| {f['key']} | {f['name']} | " + " | ".join(
            _objective_cell(f, o) for o in spec.objectives)
            + f" | {_f(f['margin'])} ({f['short_of']}) | "
            + ("passes" if f["simulated"]["passes"] else "fails")
            + f" | {_f(margin)} ({where}) |")
    if report["max_jumps"]:
        lines += ["", "## Max-effort jump simulated", "",
                  "Each simulated design's highest jump (optimal --simulate's: the jump maneuver "
                  "planned at its ceiling, max_jump_height_m predicted, taking off where the leg "
                  "can still stop its extension, the jump height it asks, run with the "
                  "tracking controller; finalists/KEY/max_jump/). "
                  "Heights: the body's apex above standing. A run stopped after the apex (the "
                  "landing sinking past the leg's reach), or whose legs gave way at the "
                  "landing, still measured its apex: its landing is not verified.", "",
                  "| design | actuator mass (kg) | max_jump_height_m predicted (mm) | jump height "
                  "(mm) | body apex above standing: simulated (mm) | share of jump height | "
                  "verdict | achieved |", "|---|---|---|---|---|---|---|---|"]
        lines += [f"| {j['key']}: {j['name']} | {j['actuator_mass_kg']:.4f} | "
                  f"{j['ceiling_m'] * 1e3:.1f} | {j['planned_m'] * 1e3:.1f} | "
                  f"{j['height_m'] * 1e3:.1f} | {j['share_of_plan']:.1%} | {j['verdict']} | "
                  + ("yes" if j["landed"] else f"no, its landing not verified: "
                                               f"{j['not_landed']}")
                  + " |" for j in report["max_jumps"]]
    speeds = [(f["key"], f["name"], gait, v) for f in report["finalists"]
              for gait, v in (f["simulated"].get("top_speeds") or {}).items()]
    if speeds:
        lines += ["", "## Top speeds tracked", "",
                  "Each required gait (or objective) at the finalist's top speed for any "
                  "controller "
                  "(optimal/top_speed.py), run with the tracking controller "
                  "(finalists/KEY/top_speed/GAIT/): it meets the requirement when the run is "
                  "achieved (a torque FAIL is the optimum's own: it rides the envelope) at the "
                  "speed required.", "",
                  "| finalist | gait | required (m/s) | optimum (m/s) | tracked, mean (m/s) | "
                  "share of the optimum | verdict | meets |", "|---|---|---|---|---|---|---|---|"]
        lines += [f"| {key}: {name} | {gait} | {_f(v['required_m_s'])} | "
                  f"{_f(v['predicted_m_s'])} | {v['simulated_m_s']:.3f} | "
                  + (f"{v['simulated_m_s'] / v['predicted_m_s']:.0%}"
                     if v["predicted_m_s"] else "")
                  + f" | {v['verdict']} | "
                  + {True: "yes", False: "no", None: "(an objective)"}[v["meets"]] + " |"
                  for key, name, gait, v in speeds]
    if report["not_simulated"]:
        first = spec.objectives[0]
        lines += ["", "## Better candidates not simulated", "",
                  f"Predicted to meet every requirement and better by {first} than the "
                  "recommended design, but not simulated: the predictions corrected by the "
                  "simulations (the least simulated over predicted margin per requirement) put "
                  "them below 1. The search does not show that they fail; simulate one with a "
                  "larger budget.finalists, or with `compare`, to know (of each motor the one nearest "
                  "to passing).",
                  "", f"| trial | design | {first} | predicted margin | corrected | kept out by |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| trial_{c['trial']} | {c['name']} | {c[first]:.3f} | "
                  f"{_f(c['predicted_margin'])} | {_f(c['corrected_margin'])} | "
                  f"{c['kept_out_by']} (x{c['correction']:.2f}) |"
                  for c in report["not_simulated"]]
    if len(spec.objectives) > 1:
        front = verified_front(spec, report["finalists"])
        lines += ["", "## Pareto front (verified)", "",
                  "The finalists that pass in simulation and that no other such finalist beats "
                  "on every objective (simulated where the simulation gives it, else predicted): "
                  + (", ".join(f"{f['key']} ({f['name']})" for f in front) or "none") + "."]
    if report["corrections"]:
        lines += ["", "The finalists were chosen in turn, each predicted margin scaled by what the "
                  "simulations before showed (the least simulated over predicted margin, below "
                  "1): " + ", ".join(f"{k} x{v:.2f}" for k, v in report["corrections"].items())
                  + "."]
    unpredicted = [m.name for m in spec.envelope.maneuvers
                   if not any(m.name in e["maneuvers"] for e in report["candidates"])]
    lines += ["", "## Search", "",
              f"- {report['trials']} trials (Optuna TPE, seed {spec.seed}, journal "
              f"{JOURNAL_FILE}), {report['predicted_meeting']} predicted to meet every "
              f"predicted requirement; {len(report['finalists'])} finalists simulated, and the "
              "default design.",
              "- Judged by simulation only (no closed form or floor here): "
              + (", ".join(unpredicted) or "none") + ".",
              "- Assumptions: a catalogue motor keeps the base parameter file's friction and "
              "thermal model (the catalogue gives neither); robot.motors_kg is the 8 "
              "actuators' mass.",
              "- " + ("Every run was step-checked (run again at half the plant step; a marginal "
                      "verdict fails)." if spec.step_check else "The envelope's runs have no "
                      "step check.")]
    if spec.never_at_limit:
        lines.append("- A run at a limit fails: a motor at its torque or voltage limit in any "
                     "sample, or a leg at a joint or extension limit.")
    if spec.mass_band:
        lines.append(f"- Actuator mass held equal: every design's within "
                     f"±{spec.mass_band[1]:.1%} of {spec.mass_band[0]:.4f} kg (motor and gearbox "
                     "as the catalogue models them; margin: the band's half-width over the "
                     "design's distance from it, at most 10).")
    lines.append("")
    return "\n".join(lines)


def pareto_figure(spec: CodesignSpec, report: dict):
    """Left: the objectives of every trial (the first against the second, or against the
    predicted least margin), the finalists marked by their simulated outcome, the recommended
    design labelled. Right: each finalist's least margin predicted and simulated."""
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
    first = spec.objectives[0]
    second = spec.objectives[1] if len(spec.objectives) > 1 else None
    ylabel = second or "predicted least margin"

    def y(e):
        return e["objectives"][second] if second else min(e["margin"], 3.0)

    built = [e for e in report["candidates"] if first in e["objectives"]]
    for meets, style, label in ((True, dict(marker="o", color="tab:blue"), "predicted to meet"),
                                (False, dict(marker="x", color="0.6"), "predicted short")):
        pts = [e for e in built if e["meets"] == meets]
        ax.scatter([e["objectives"][first] for e in pts], [y(e) for e in pts], label=label,
                   **style)
    for passes, style, label in ((True, dict(marker="*", s=200, color="tab:green"),
                                  "finalist: simulation passes"),
                                 (False, dict(marker="s", s=80, color="tab:red"),
                                  "finalist: simulation fails")):
        pts = [f for f in report["finalists"] if f["simulated"]["passes"] == passes]
        ax.scatter([f["objectives"][first] for f in pts], [y(f) for f in pts], label=label,
                   zorder=3, **style)
    verified = [f for f in report["finalists"] if second and all(
        _finite(f["simulated"].get("objectives", {}).get(o)) for o in (first, second))]
    for f in verified:                  # the simulated objectives beside the predicted
        sim = f["simulated"]["objectives"]
        ax.plot([f["objectives"][first], sim[first]], [y(f), sim[second]], color="0.5", lw=0.8)
        ax.scatter([sim[first]], [sim[second]], marker="D", facecolors="none",
                   edgecolors="tab:green" if f["simulated"]["passes"] else "tab:red", zorder=3,
                   label="finalist: simulated objectives" if f is verified[0] else None)
    if first == "max_jump_height_m":        # the simulated max jumps beside the predicted
        finalists = {f["key"]: f for f in report["finalists"]}
        for j in report.get("max_jumps", []):
            f = finalists.get(j["key"])
            if f is None:
                ax.axvline(j["height_m"], color="k" if j["key"] == "default" else "tab:purple",
                           ls="--" if j["key"] == "default" else ":",
                           label=f"{j['key']}: max jump simulated")
            elif not second:
                ax.plot([f["objectives"][first], j["height_m"]], [y(f)] * 2, color="0.5", lw=0.8)
                ax.scatter([j["height_m"]], [y(f)], marker="D", facecolors="none", zorder=3,
                           edgecolors="tab:green" if f["simulated"]["passes"] else "tab:red",
                           label=f"{j['key']}: max jump simulated")
    r = report["recommended"]
    if r is not None:
        x = r["objectives"][first]
        left = first == "actuator_mass_kg" and report["default"]["actuator_mass_kg"] > x
        ax.annotate("recommended\n" + r["name"].replace(", ", "\n").replace(" at ", "\nat "),
                    (x, y(r)), xytext=(-15 if left else 15, -60), textcoords="offset points",
                    fontsize=8, ha="right" if left else "left",       # away from the default's
                    bbox=dict(boxstyle="round", fc="white", ec="0.7", alpha=0.9),      # line
                    arrowprops=dict(arrowstyle="->"))
    if first == "actuator_mass_kg":
        ax.axvline(report["default"]["actuator_mass_kg"], color="k", ls="--",
                   label="default design's actuator")
        for c in report["compared"]:
            sim = c["simulated"]
            ax.axvline(c["actuator_mass_kg"], color="tab:purple", ls=":",
                       label=f"compared: {c['name'].split(' ')[0]} ("
                             + ("passes" if sim and sim["passes"] else "fails") + ")")
    ax.set(xlabel=first, ylabel=ylabel,
           title="co-design: every trial (predicted)" + (", finalists simulated" if verified
                                                         else ""))
    ax.legend(fontsize=8)
    for i, f in enumerate(report["finalists"]):
        sim = least(f["simulated"], spec.accept)[0]
        bx.plot([i, i], [min(f["margin"], 5.0), min(sim, 5.0)], color="0.7")
        bx.scatter([i], [min(f["margin"], 5.0)], marker="o", color="tab:blue",
                   label="predicted" if i == 0 else None)
        bx.scatter([i], [min(sim, 5.0)], marker="*", s=150,
                   color="tab:green" if f["simulated"]["passes"] else "tab:red",
                   label="simulated" if i == 0 else None)
    bx.axhline(1.0, color="k", ls=":", label="meets (margin 1)")
    bx.set_xticks(range(len(report["finalists"])), [f["key"] for f in report["finalists"]],
                  rotation=20, fontsize=8)
    bx.set(ylabel="least margin (capped at 5)", title="finalists: predicted vs simulated")
    bx.legend(fontsize=8)
    fig.tight_layout()
    return fig


def write_report(spec: CodesignSpec, out: Path, entries: list[dict], chosen: list[dict],
                 verified: dict, factors: dict[str, float]) -> CodesignRun:
    """Write FILES into out (design.toml only with a recommended design; a previous one is
    removed); returns the CodesignRun. factors: the predictions' corrections (run.corrections)
    the last finalist was chosen with."""
    report = codesign_report(spec, entries, chosen, verified, factors)
    files = [write_atomic(out / "design.md", markdown(spec, report))]
    (out / "design.toml").unlink(missing_ok=True)
    if report["recommended"] is not None:
        files.append(write_parameter_file(spec.envelope, report["recommended"]["design"],
                                          out / "design.toml"))
    files.append(save_figure(pareto_figure(spec, report), out / "pareto.png"))
    files.append(write_atomic(out / "design.json", json.dumps(json_ready(report), indent=1)))
    return CodesignRun(report, files, report["failure"])

