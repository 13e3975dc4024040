"""Simulated runs side by side (what a foot path or a design costs): the summaries
(summary.json) as markdown, with each motor's verdict and the check that decided it, and a bar
chart of the demand per motor. Each run is labelled by its folder's name."""

from __future__ import annotations

import json
from pathlib import Path

from fivebar_drake.core import text as words
from fivebar_drake.verdicts.checks import Checks, thresholds_text
from fivebar_drake.core.files import read_input_text, save_figure, write_atomic
from fivebar_drake.verdicts.summary_schema import MotorSummary, Summary
from fivebar_drake.core.validation import ParameterError, require
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.robots.quadruped.config import load_params
from fivebar_drake.simulation.run_statistics import MIN_CYCLES


TEXT_KEYS = ("gait", "closure", "answer", "verdict")
NUMBER_KEYS = ("mean_forward_speed_m_s", "gait_speed_m_s", "max_tilt_deg", "seed_peak_torque_Nm",
               "motor_peak_torque_Nm")              # numbers, or null (a run that diverged)
TOP_KEYS = (*TEXT_KEYS, *NUMBER_KEYS, "legs")
MOTOR_KEYS = ("demand_p99_Nm", "rms_torque_Nm", "static_seed_Nm", "static_trot_Nm")
MAX_LEGS = 16


class Labelled(Summary):
    """A run's summary.json (its types checked for the keys read here: TOP_KEYS, MOTOR_KEYS)
    with its folder's name."""

    label: str


def load_summaries(run_dirs) -> list[Labelled]:
    """summary.json of each run folder, in order; ParameterError naming the file if one is
    missing or is not a summary of `fivebar-drake simulate`."""
    out = []
    labels = _labels([Path(run).resolve() for run in run_dirs])
    for run, label in zip(run_dirs, labels):
        path = Path(run) / "summary.json"
        try:
            out.append({**_summary(path), "label": label})
        except ParameterError as err:
            raise ParameterError(f"{err.message} (a run folder of `fivebar-drake simulate "
                                 f"--out {run}` holds it)", err.field, str(path)) from None
    legs = [sorted(s["legs"]) for s in out]
    require(all(leg == legs[0] for leg in legs), "legs", legs, "the runs must have the same legs")
    return out


def _number(value) -> bool:
    return value is None or (isinstance(value, (int, float)) and not isinstance(value, bool))


def _summary(path: Path) -> Summary:
    """summary.json at path, its types checked: it is untrusted data (ParameterError naming
    the field)."""
    try:
        data = json.loads(read_input_text(path, "run summary"))
    except json.JSONDecodeError as err:
        raise ParameterError(f"not valid JSON ({err.msg} at line {err.lineno})") from None
    except RecursionError:
        raise ParameterError("not a run summary: nested too deeply") from None
    require(isinstance(data, dict), "summary", type(data).__name__, "must be a JSON object")
    missing = [key for key in TOP_KEYS if key not in data]
    require(not missing, "summary", sorted(map(str, data))[:5], f"lacks the keys {missing}")
    for key in TEXT_KEYS:
        require(isinstance(data[key], str), key, data[key], "must be text")
    for key in NUMBER_KEYS:
        require(_number(data[key]), key, data[key], "must be a number or null")
    legs = data["legs"]
    require(isinstance(legs, dict) and 0 < len(legs) <= MAX_LEGS, "legs", type(legs).__name__,
            f"must map 1 .. {MAX_LEGS} legs to their motors")
    for leg, motors in legs.items():
        require(isinstance(motors, dict), f"legs.{leg}", type(motors).__name__,
                f"must map the motors {list(MOTORS)} to their figures")
        for motor in MOTORS:
            figures = motors.get(motor)
            require(isinstance(figures, dict), f"legs.{leg}.{motor}", type(figures).__name__,
                    "must be the motor's figures")
            for key in MOTOR_KEYS:
                value = figures.get(key, "missing")
                require(_number(value), f"legs.{leg}.{motor}.{key}", value,
                        "must be a number or null")
            require(isinstance(figures.get("verdict", ""), str), f"legs.{leg}.{motor}.verdict",
                    figures.get("verdict"), "must be text")
            require(isinstance(figures.get("checks", {}), (dict, type(None))),
                    f"legs.{leg}.{motor}.checks", figures.get("checks"), "must be an object")
    motor = data.get("motor")
    require(motor is None or isinstance(motor, dict), "motor", motor, "must be an object")
    return data


def _num(value, fmt=".2f") -> str:
    return words.figure(value, "{:" + fmt + "}")


def _labels(folders: list[Path]) -> list[str]:
    """Each run's label: its folder's name, with as many parent folders as it takes to tell the
    runs apart (two envelopes' `drop` folders: `a/drop`, `b/drop`)."""
    for depth in range(1, max(len(f.parts) for f in folders) + 1):
        labels = ["/".join(f.parts[-depth:]) for f in folders]
        if len(set(labels)) == len(labels) or len(set(folders)) < len(folders):
            return labels
    return [str(f) for f in folders]


def _label(s: Labelled) -> str:
    return s.get("label") or s["gait"]


def _verdict_cell(m: MotorSummary) -> str:
    """A motor's verdict, its deciding check and the checks' figures, in one table cell."""
    c = m.get("checks")
    if not isinstance(c, dict):
        return words.verdict_word(m.get("verdict", "—"))
    torque, speed, thermal = (c.get(k) or {} for k in ("torque", "speed", "thermal"))
    return (f"{words.verdict_word(m.get('verdict'))} ({m.get('deciding_check')}): SF "
            f"{_num(torque.get('sf'))}, {_num((speed.get('outside_fraction') or 0) * 100, '.1f')} "
            f"% beyond the envelope, current margin {_num(thermal.get('margin'))}")


def verdict_table(summaries: list[Labelled]) -> list[str]:
    """Markdown lines: per motor, each run's verdict with its deciding check and figures."""
    lines = ["| leg | motor | " + " | ".join(_label(s) for s in summaries) + " |",
             "|---|---|" + "---|" * len(summaries)]
    for leg in summaries[0]["legs"]:
        for motor in MOTORS:
            lines.append(f"| {leg} | {motor} | " + " | ".join(
                _verdict_cell(s["legs"][leg][motor]) for s in summaries) + " |")
    return lines


def answer(summaries: list[Labelled]) -> str:
    """The comparison in one line: each run's verdict with the check that decided it and its
    figure, and, where the deciding check changes from one run to the next with the later one
    failing, that the change moved the limit (each run's full answer is in its item below)."""
    def one(s: Labelled) -> str:
        check = s.get("deciding_check")
        return (f"{_label(s)} {words.verdict_word(s['verdict'])}"
                + (f" ({check}{_short_figure(s, check)})" if check else ""))

    text = ", ".join(one(s) for s in summaries)
    for a, b in zip(summaries, summaries[1:]):
        ca, cb = a.get("deciding_check"), b.get("deciding_check")
        if ca and cb and ca != cb and b["verdict"] in ("fail", "not_achieved"):
            text += (f"; {_label(b)} moved the limit from the {ca} check to the {cb} check, it "
                     "did not remove it")
    return text + "."


def _short_figure(s: Labelled, check: str) -> str:
    """', SF 1.41' — the deciding figure of a run's worst motor in a few characters."""
    leg, _, motor = str(s.get("worst_motor") or "").partition(" ")
    c = ((((s.get("legs") or {}).get(leg) or {}).get(motor) or {}).get("checks") or {}).get(
        check) or {}
    if check == "torque" and c.get("sf") is not None:
        return f", SF {words.figure(c['sf'])}"
    if check == "speed" and c:
        return (f", {words.figure((c.get('outside_fraction') or 0) * 100, '{:.1f}')} % beyond "
                "the envelope")
    if check == "thermal" and c:
        return f", current margin {words.figure(c.get('margin'))}"
    return ""


def markdown(summaries: list[Labelled]) -> str:
    lines = ["# Runs side by side", "", f"**Answer:** {answer(summaries)}", "",
             thresholds_text(load_params().checks).rstrip(".") + " (the default checks).", "",
             "Each run's demand (the controller's command before saturation, 99th percentile "
             "over its whole gait cycles) and RMS applied torque per motor, beside the static "
             "estimates for the same poses: the seed's (G(q) with the weight share at the foot) "
             "and the one with the run's own loads (the robot's weight shared by the feet in "
             "stance). N·m.", ""]
    for s in summaries:
        lines.append(f"- **{_label(s)}** ({s['gait']} gait, {s['closure']} closure, gear "
                     f"{_num((s.get('motor') or {}).get('gear_ratio'), 'g')}:1): {s['answer']} "
                     + (f"Walking {_num(s['mean_forward_speed_m_s'], '.3f')} m/s of the path's "
                        f"{_num(s['gait_speed_m_s'], '.3f')} m/s, largest"
                        if s.get("periodic", True) else "Largest")
                     + f" tilt {_num(s['max_tilt_deg'], '.1f')} deg, verdict "
                     f"{words.verdict_word(s['verdict'])}.")
    lines += ["", "## Verdicts", "", "Each motor's verdict, the check that decided it (torque: "
              "safety factor; speed: the demand beyond the actuator's envelope; thermal: "
              "continuous / RMS current):", "", *verdict_table(summaries), "", "## Torques", ""]
    header = "| leg | motor | " + " | ".join(
        f"{_label(s)} demand p99 | {_label(s)} RMS | {_label(s)} seed's model | "
        f"{_label(s)} static, same loads" for s in summaries) + " |"
    lines += [header, "|---|---|" + "---|" * (4 * len(summaries))]
    for leg in summaries[0]["legs"]:
        for motor in MOTORS:
            cells = []
            for s in summaries:
                m = s["legs"][leg][motor]
                cells += [_num(m["demand_p99_Nm"]), _num(m["rms_torque_Nm"]),
                          _num(m["static_seed_Nm"]), _num(m["static_trot_Nm"])]
            lines.append(f"| {leg} | {motor} | " + " | ".join(cells) + " |")
    lines += ["", f"A run with the verdict INSUFFICIENT stopped early or covered fewer than "
              f"{MIN_CYCLES} whole cycles: its figures describe what it did before that, not a "
              "trot."]
    return "\n".join(lines) + "\n"


def _run_name(s: Labelled) -> str:
    gear = (s.get("motor") or {}).get("gear_ratio")
    return _label(s) + (f" ({gear:g}:1)" if gear else "")


def figure(summaries: list[Labelled]):
    """Per motor, each run's demand (p99) against that run's own limit (the torque check's, in
    the quadrant of the figure: a tick over its bar) labelled with its verdict and deciding
    check, and the speed check's share of the time beyond the envelope against the fail rule."""
    import matplotlib.pyplot as plt
    import numpy as np

    legs = summaries[0]["legs"]
    labels = [f"{leg} {m}" for leg in legs for m in MOTORS]
    x = np.arange(len(labels))
    width = 0.8 / len(summaries)
    fig, (top, low) = plt.subplots(2, 1, figsize=(12, 7.5), sharex=True, height_ratios=(2, 1),
                                   layout="constrained")
    for k, s in enumerate(summaries):
        at = x + (k - (len(summaries) - 1) / 2) * width
        motors = [s["legs"][leg][m] for leg in legs for m in MOTORS]
        checks = [m.get("checks") or {} for m in motors]
        demand = [m["demand_p99_Nm"] or np.nan for m in motors]
        # the torque check's limit, in the quadrant of its figure (no check: none drawn)
        limit = [(c.get("torque") or {}).get("limit_Nm") or np.nan for c in checks]
        color = f"C{k}"
        rating = s.get("motor") or {}
        top.bar(at, demand, width, color=color, alpha=0.75,
                label=f"{_run_name(s)}: demand p99, verdict {words.verdict_word(s['verdict'])} "
                      f"({s.get('deciding_check') or 'no check'})")
        top.hlines(limit, at - width / 2, at + width / 2, color=color, lw=2.5,
                   label=f"{_run_name(s)}: its limit, driving "
                         f"{_num(rating.get('peak_torque_Nm'))} N·m, braking "
                         f"{_num(rating.get('braking_peak_torque_Nm'))} N·m")
        for xi, lim, d, m in zip(at, limit, demand, motors):
            top.text(xi, np.nanmax([lim, d, 0.0]), f" {str(m.get('verdict')).upper()} ({m.get('deciding_check') or 'no check'})",
                     rotation=90, ha="center", va="bottom", fontsize=7)
        beyond = [100 * ((c.get("speed") or {}).get("outside_fraction") or 0.0) for c in checks]
        low.bar(at, beyond, width, color=color, alpha=0.75, label=_run_name(s))
    fail = 100 * Checks.speed_outside_fail
    low.axhline(fail, color="r", lw=1, label=f"the speed check fails beyond {fail:g} %")
    top.set(ylabel="torque (N·m)", ylim=(0, 1.45 * top.get_ylim()[1]),
            title="Each run's demand against its own motor's limit: the safety factor is the "
                  "tick over the bar; the verdict (deciding check) above")
    low.set(xticks=x, xticklabels=labels, ylabel="time beyond (%)",
            title="Speed check: share of the time the demand lies beyond the torque–speed "
                  "envelope")
    for ax in (top, low):
        ax.legend(fontsize=7, loc="upper left")
        ax.grid(alpha=0.3, axis="y")
    return fig


def check_outputs(run_dirs, out_md: Path) -> Path:
    """The PNG's path beside out_md, after checking the outputs (ParameterError naming --out):
    out_md is a .md file, neither output is a folder, an input or inside an input's folder."""
    out_md = Path(out_md)
    where = f"--out {out_md}"
    if out_md.is_dir():
        raise ParameterError("is a folder; give a file name", "--out", where)
    if out_md.suffix.lower() != ".md":
        raise ParameterError(f"the comparison is markdown: give a .md file name (its PNG is "
                             f"written beside it, {out_md.with_suffix('.png').name})", "--out",
                             where)
    png = out_md.with_suffix(".png")
    runs = [Path(r).resolve() for r in run_dirs]
    for path in (out_md, png):
        if path.is_dir():
            raise ParameterError(f"{path} is a folder: the comparison writes {out_md.name} and "
                                 f"{png.name}", "--out", where)
        inside = [r for r in runs if path.resolve() == r or path.resolve().is_relative_to(r)]
        if inside:       # every file in a run's folder is the run's (summary.md, plots, ...)
            raise ParameterError(f"{path} lies in the input run {inside[0]}: the comparison "
                                 "never writes into a run's folder", "--out", where)
    return png


def write_comparison(run_dirs, out_md: Path) -> list[Path]:
    """Write out_md and a PNG beside it comparing the runs in run_dirs (each atomically), after
    every input and output is checked (check_outputs, load_summaries)."""
    png = check_outputs(run_dirs, out_md)
    summaries = load_summaries(run_dirs)
    text, fig = markdown(summaries), figure(summaries)
    out_md.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(out_md, text)
    return [out_md, save_figure(fig, png)]
