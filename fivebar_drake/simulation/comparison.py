"""Simulated runs side by side (what a foot path or a design costs): the summaries
(summary.json) as markdown, with each motor's verdict and the check that decided it, and a bar
chart of the demand per motor. Each run is labelled by its folder's name."""

from __future__ import annotations

import json
from pathlib import Path

from fivebar_drake.core.files import read_input_text, save_figure, write_atomic
from fivebar_drake.core.validation import ParameterError, require
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.simulation.summary import MIN_CYCLES


TOP_KEYS = ("gait", "closure", "answer", "verdict", "mean_forward_speed_m_s", "gait_speed_m_s",
            "max_tilt_deg", "seed_peak_torque_Nm", "motor_peak_torque_Nm", "legs")

MOTOR_KEYS = ("demand_p99_Nm", "rms_torque_Nm", "static_seed_Nm", "static_trot_Nm")


def load_summaries(run_dirs) -> list[dict]:
    """summary.json of each run folder, in order; ParameterError naming the file if one is
    missing or is not a summary of `fivebar-drake simulate`."""
    out = []
    for run in run_dirs:
        path = Path(run) / "summary.json"
        try:
            out.append({**_summary(path), "label": Path(run).resolve().name})
        except ParameterError as err:
            raise ParameterError(f"{err.message} (a run folder of `fivebar-drake simulate "
                                 f"--out {run}` holds it)", err.field, str(path)) from None
    legs = [sorted(s["legs"]) for s in out]
    require(all(leg == legs[0] for leg in legs), "legs", legs, "the runs must have the same legs")
    return out


def _summary(path: Path) -> dict:
    try:
        data = json.loads(read_input_text(path, "run summary"))
    except json.JSONDecodeError as err:
        raise ParameterError(f"not valid JSON ({err})") from None
    require(isinstance(data, dict), "summary", type(data).__name__, "must be a JSON object")
    missing = [key for key in TOP_KEYS if key not in data]
    require(not missing, "summary", sorted(data)[:5], f"lacks the keys {missing}")
    require(isinstance(data["legs"], dict), "legs", data["legs"], "must map legs to motors")
    for leg, motors in data["legs"].items():
        for motor in MOTORS:
            for key in MOTOR_KEYS:
                value = motors.get(motor, {}).get(key, "missing") if isinstance(motors, dict) \
                    else "missing"
                require(value is None or isinstance(value, (int, float)),
                        f"legs.{leg}.{motor}.{key}", value, "must be a number or null")
    return data


def _num(value, fmt=".2f") -> str:
    return "n/a" if value is None else format(value, fmt)


def _label(s: dict) -> str:
    return s.get("label") or s["gait"]


def _verdict_cell(m: dict) -> str:
    """A motor's verdict, its deciding check and the checks' figures, in one table cell."""
    c = m.get("checks")
    if not isinstance(c, dict):
        return str(m.get("verdict", "n/a")).upper()
    torque, speed, thermal = (c.get(k) or {} for k in ("torque", "speed", "thermal"))
    return (f"{str(m.get('verdict')).upper()} ({m.get('deciding_check')}): SF "
            f"{_num(torque.get('sf'))}, {_num((speed.get('outside_fraction') or 0) * 100, '.1f')} "
            f"% beyond the envelope, current margin {_num(thermal.get('margin'))}")


def verdict_table(summaries: list[dict]) -> list[str]:
    """Markdown lines: per motor, each run's verdict with its deciding check and figures."""
    lines = ["| leg | motor | " + " | ".join(_label(s) for s in summaries) + " |",
             "|---|---|" + "---|" * len(summaries)]
    for leg in summaries[0]["legs"]:
        for motor in MOTORS:
            lines.append(f"| {leg} | {motor} | " + " | ".join(
                _verdict_cell(s["legs"][leg][motor]) for s in summaries) + " |")
    return lines


def markdown(summaries: list[dict]) -> str:
    lines = ["# Runs side by side", "",
             "Each run's demand (the controller's command before saturation, 99th percentile "
             "over its whole gait cycles) and RMS applied torque per motor, beside the static "
             "estimates for the same poses: the seed's (G(q) with the weight share at the foot) "
             "and the trot's (the robot's weight shared by the feet in stance). N·m.", ""]
    for s in summaries:
        lines.append(f"- **{_label(s)}** ({s['gait']} gait, {s['closure']} closure, gear "
                     f"{_num((s.get('motor') or {}).get('gear_ratio'), 'g')}:1): {s['answer']} Walking "
                     f"{_num(s['mean_forward_speed_m_s'], '.3f')} m/s of the path's "
                     f"{s['gait_speed_m_s']:.3f} m/s, largest tilt "
                     f"{_num(s['max_tilt_deg'], '.1f')} deg, verdict {s['verdict'].upper()}.")
    lines += ["", "## Verdicts", "", "Each motor's verdict, the check that decided it (torque: "
              "safety factor; speed: the demand beyond the actuator's envelope; thermal: "
              "continuous / RMS current):", "", *verdict_table(summaries), "", "## Torques", ""]
    header = "| leg | motor | " + " | ".join(
        f"{_label(s)} demand p99 | {_label(s)} RMS | {_label(s)} seed static | "
        f"{_label(s)} trot static" for s in summaries) + " |"
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


def figure(summaries: list[dict]):
    import matplotlib.pyplot as plt
    import numpy as np

    labels = [f"{leg} {m}" for leg in summaries[0]["legs"] for m in MOTORS]
    x = np.arange(len(labels))
    width = 0.8 / len(summaries)
    fig, ax = plt.subplots(figsize=(11, 4))
    for k, s in enumerate(summaries):
        demand = [s["legs"][leg][m]["demand_p99_Nm"] or np.nan
                  for leg in s["legs"] for m in MOTORS]
        ax.bar(x + (k - (len(summaries) - 1) / 2) * width, demand, width,
               label=f"{_label(s)} demand p99 ({s['verdict']})")
    seed = summaries[0]["seed_peak_torque_Nm"]
    ax.axhline(seed, color="k", ls="--", lw=1, label=f"seed static {seed:.2f} N·m")
    ax.axhline(summaries[0]["motor_peak_torque_Nm"], color="r", lw=1, label="motor limit")
    ax.set(xticks=x, xticklabels=labels, ylabel="torque (N·m)",
           title="Torque demand per motor, run by run")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    return fig


def write_comparison(run_dirs, out_md: Path) -> list[Path]:
    """Write out_md and a PNG beside it comparing the runs in run_dirs (each atomically)."""

    summaries = load_summaries(run_dirs)
    out_md.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(out_md, markdown(summaries))
    png = out_md.with_suffix(".png")
    return [out_md, save_figure(figure(summaries), png)]
