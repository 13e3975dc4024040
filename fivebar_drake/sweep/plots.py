"""A sweep's plots: the verdict map over one or two varied parameters, and the Pareto front of
the worst safety factor against speed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fivebar_drake.core.files import save_figure

SWEEP_PLOTS = ("verdict_map.png", "pareto.png")
COLORS = {"pass": "tab:green", "warn": "tab:orange", "marginal": "gold", "fail": "tab:red",
          "not_achieved": "tab:brown", "insufficient": "tab:purple", "failed": "0.6"}
RANK = {"failed": 0, "pass": 1, "warn": 2, "marginal": 3, "insufficient": 4, "fail": 5,
        "not_achieved": 6}     # where points share a place, the worse is drawn on top
SPEED_LABEL = {"analysis": "stride speed 2 a f (m/s)",
               "simulation": "mean forward speed (m/s)"}


def _value(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def _outcome(row: dict) -> str:
    return "failed" if row["status"] == "failed" else row["worst_verdict"]


def pareto_front(speed, sf) -> np.ndarray:
    """Indices of the points no other point beats in both speed and safety factor (higher is
    better in both), by increasing speed."""
    order = np.lexsort((-sf, -speed))           # fastest first, the safer of equals first
    front, best = [], -np.inf
    for i in order:
        if sf[i] > best:
            front.append(i)
            best = sf[i]
    return np.array(front[::-1], dtype=int)


def write_sweep_plots(rows: list[dict], axes: tuple[str, ...], fidelity: str, sf_pass: float,
                      out: Path) -> list[Path]:
    """verdict_map.png over the axes (one or two varied parameters; where several points share
    a place, the worst outcome is drawn on top) and pareto.png; returns the paths."""
    import matplotlib.pyplot as plt

    written = []
    fig, ax = plt.subplots(figsize=(7, 5))
    outcomes = [_outcome(r) for r in rows]
    size = 160 if len(rows) <= 400 else max(4, 64000 / len(rows))   # one scatter per outcome
    for outcome in sorted(set(outcomes), key=lambda o: RANK.get(o, len(RANK))):
        mine = [r for r, o in zip(rows, outcomes) if o == outcome]
        x = [_value(r[axes[0]]) for r in mine]
        y = [_value(r[axes[1]]) for r in mine] if len(axes) > 1 else [0.0] * len(mine)
        ax.scatter(x, y, s=size, marker="x" if outcome == "failed" else "s",
                   color=COLORS.get(outcome, "k"), label=outcome)
    ax.set_xlabel(axes[0])
    ax.set_ylabel(axes[1] if len(axes) > 1 else "")
    ax.set_title("worst motor's verdict per design point")
    ax.legend(loc="best", fontsize=8)
    written.append(_save(fig, out / SWEEP_PLOTS[0]))
    fig, ax = plt.subplots(figsize=(7, 5))
    ok = [r for r in rows if r["status"] != "failed" and r["worst_safety_factor"] != ""]
    if ok:
        speed = np.array([float(r["speed_m_s"]) for r in ok])
        sf = np.array([float(r["worst_safety_factor"]) for r in ok])
        ax.scatter(speed, sf, color=[COLORS.get(_outcome(r), "k") for r in ok], s=25)
        front = pareto_front(speed, sf)
        ax.plot(speed[front], sf[front], "k-o", mfc="none", label="Pareto front")
        ax.axhline(sf_pass, color="tab:green", ls="--", lw=1, label=f"SF = {sf_pass:g} (pass)")
        ax.legend(loc="best", fontsize=8)
    ax.set_xlabel(SPEED_LABEL[fidelity])
    ax.set_ylabel("worst motor's safety factor")
    ax.set_title("safety factor against speed")
    written.append(_save(fig, out / SWEEP_PLOTS[1]))
    return written


def _save(fig, path: Path) -> Path:
    fig.tight_layout()
    return save_figure(fig, path)
