"""A sweep's summary: counts per outcome, the fastest passing design, the Pareto front, as a
dictionary and as sweep.md."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fivebar_drake.core.files import write_atomic
from fivebar_drake.sweep.plots import SPEED_LABEL, pareto_front

REPORT_FILE = "sweep.md"


def summarize_sweep(rows: list[dict], varied: list[str], sf_pass: float) -> dict:
    """Counts of the points' outcomes (status failed, else the worst verdict), the Pareto
    front (safety factor against speed: each entry the varied values, speed, worst SF) and the
    fastest point whose every motor passes (SF >= sf_pass), or None."""
    counts: dict[str, int] = {}
    for r in rows:
        key = "failed" if r["status"] == "failed" else r["worst_verdict"]
        counts[key] = counts.get(key, 0) + 1
    ok = [r for r in rows if r["status"] != "failed" and r["worst_safety_factor"] != ""]

    def entry(r):
        return {"point": int(r["point"]), **{k: r[k] for k in varied},
                "speed_m_s": float(r["speed_m_s"]),
                "worst_safety_factor": float(r["worst_safety_factor"]),
                "worst_verdict": r["worst_verdict"]}

    front = []
    if ok:
        speed = np.array([float(r["speed_m_s"]) for r in ok])
        sf = np.array([float(r["worst_safety_factor"]) for r in ok])
        front = [entry(ok[i]) for i in pareto_front(speed, sf)]
    passing = [entry(r) for r in ok if float(r["worst_safety_factor"]) >= sf_pass]
    fastest = max(passing, key=lambda e: e["speed_m_s"]) if passing else None
    return {"points": len(rows), "outcomes": counts, "pareto_front": front,
            "fastest_passing": fastest}


def answer(summary: dict, varied: list[str], path: str = "") -> str:
    """sweep.md's first line: how many points pass, warn and fail (the worst motor's verdict)
    and the fastest point where every motor passes, with its worst safety factor, on the path
    the points ran (path: its name, "" for a simulated sweep's scenario)."""
    counts = summary["outcomes"]
    told = ", ".join(f"{counts[k]} {k.upper()}" for k in ("pass", "warn", "fail", "failed")
                     if k in counts)
    best = summary["fastest_passing"]
    fastest = ("no point passes" if best is None else
               f"the fastest passing: point {best['point']}, {best['speed_m_s']:.3f} m/s, worst "
               f"SF {best['worst_safety_factor']:.2f}")
    on = f" on the {path} path" if path else ""
    return f"**Answer:** of {summary['points']} design points{on} {told}; {fastest}."


def fastest_text(summary: dict, varied: list[str]) -> str:
    """The fastest passing point's parameters in a line ("" where none passes)."""
    best = summary["fastest_passing"]
    return ("" if best is None else f"Point {best['point']}: "
            + ", ".join(f"{k} = {best[k]}" for k in varied) + ".")


def write_sweep_report(summary: dict, varied: list[str], fidelity: str, out: Path,
                       thresholds: str = "", path: str = "") -> Path:
    """sweep.md: the answer (the counts, the fastest passing point) with the verdict's
    thresholds, the Pareto front as a table."""
    lines = [f"# Sweep: {summary['points']} design points ({fidelity})", "",
             answer(summary, varied, path), "",
             *([fastest_text(summary, varied), ""] if summary["fastest_passing"] else []),
             "A sweep of the spec's parameters on its path: a trade, not a recommendation "
             "(which motor, gearbox and leg pass every maneuver in simulation is `fivebar-drake "
             "codesign`'s answer).", "",
             "Outcomes (the worst motor's verdict; failed: no result, see points.csv's "
             "`error`): " + ", ".join(f"{k} {v}" for k, v in sorted(summary["outcomes"].items()))
             + (f". {thresholds}" if thresholds else "")]
    lines += ["", f"Pareto front, worst safety factor against {SPEED_LABEL[fidelity]}:", "",
              "| point | " + " | ".join(varied) + " | speed (m/s) | worst SF | verdict |",
              "|---" * (len(varied) + 4) + "|"]
    for e in summary["pareto_front"]:
        lines.append(f"| {e['point']} | " + " | ".join(str(e[k]) for k in varied)
                     + f" | {e['speed_m_s']:.3f} | {e['worst_safety_factor']:.2f} | "
                     f"{e['worst_verdict']} |")
    return write_atomic(out / REPORT_FILE, "\n".join(lines) + "\n")
