"""A sweep's plots: the verdict map over one or two varied parameters (a panel per value of the
others), and the Pareto front of the worst safety factor against speed. Every point is drawn;
the legends count the outcomes as sweep.md does."""

from __future__ import annotations

import itertools
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
SPEED_FROM = {"analysis": ("gait.frequency_hz", "gait.a_m"), "simulation": ()}
MAX_PANELS = 12       # the verdict map's panels: one per combination of the other parameters
MARKERS = "o^sDvP*X"  # pareto.png: one marker per value of a parameter the speed does not show


def _value(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def _outcome(row: dict) -> str:
    return "failed" if row["status"] == "failed" else row["worst_verdict"]


def _values(rows: list[dict], name: str) -> list:
    return sorted({_value(r[name]) for r in rows}, key=lambda v: (isinstance(v, str), v))


def _ranked(outcomes) -> list[str]:
    return sorted(set(outcomes), key=lambda o: RANK.get(o, len(RANK)))


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


def map_panels(rows: list[dict], axes: tuple[str, ...], varied=None):
    """The verdict map's panels: (the varied parameters not on the axes that get a panel per
    combination of their values, the hidden ones, [(title, rows of the panel)]). Panels while
    their number stays within MAX_PANELS (the parameters in order), the rest hidden (said under
    the map: their points may share a place, the worse drawn on top)."""
    others = [n for n in (varied or axes) if n not in axes]
    faceted, count = [], 1
    for name in others:
        n = len(_values(rows, name))
        if count * n > MAX_PANELS:
            break
        faceted.append(name)
        count *= n
    hidden = others[len(faceted):]
    panels = []
    for combo in itertools.product(*(_values(rows, n) for n in faceted)):
        mine = [r for r in rows if all(_value(r[n]) == v for n, v in zip(faceted, combo))]
        panels.append((", ".join(f"{n} = {v:g}" if isinstance(v, float) else f"{n} = {v}"
                                 for n, v in zip(faceted, combo)), mine))
    return faceted, hidden, panels


def draw_verdict_map(rows: list[dict], axes: tuple[str, ...], varied=None):
    """The verdict map: a panel per combination of the varied parameters not on its axes
    (map_panels), one scatter per outcome and panel; the legend counts every point."""
    import matplotlib.pyplot as plt

    _, hidden, panels = map_panels(rows, axes, varied)
    columns = min(3, len(panels))
    lines = -(-len(panels) // columns)
    fig, grid = plt.subplots(lines, columns, figsize=(4.2 * columns + 1.5, 3.6 * lines + 0.8),
                             squeeze=False, sharex=True, sharey=True, layout="constrained")
    size = 160 if len(rows) <= 400 else max(4, 64000 / len(rows))
    outcomes = [_outcome(r) for r in rows]
    for ax, (title, mine) in zip(grid.flat, panels):
        for outcome in _ranked(_outcome(r) for r in mine):
            drawn = [r for r in mine if _outcome(r) == outcome]
            x = [_value(r[axes[0]]) for r in drawn]
            y = [_value(r[axes[1]]) for r in drawn] if len(axes) > 1 else [0.0] * len(drawn)
            ax.scatter(x, y, s=size, marker="x" if outcome == "failed" else "s",
                       color=COLORS.get(outcome, "k"), label=outcome)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(axes[0])
        if len(axes) > 1:
            ax.set_ylabel(axes[1])
        else:
            ax.set_yticks([])
    for ax in grid.flat[len(panels):]:
        ax.set_visible(False)
    handles = [plt.Line2D([], [], ls="", marker="x" if o == "failed" else "s", ms=9,
                          color=COLORS.get(o, "k"), label=f"{o} ({outcomes.count(o)})")
               for o in _ranked(outcomes)]
    fig.legend(handles=handles, loc="outside right upper", fontsize=8,
               title=f"{len(rows)} points")
    fig.suptitle("worst motor's verdict per design point")
    if hidden:
        fig.text(0.01, 0.0, f"not shown: {', '.join(hidden)} (too many panels): points that "
                 "differ only there share a place, the worse drawn on top", fontsize=8,
                 va="bottom")
    return fig


def draw_pareto(rows: list[dict], fidelity: str, sf_pass: float, sf_warn=None, varied=()):
    """Worst safety factor against speed, coloured by outcome (counted in the legend), a marker
    per value of the first varied parameter the speed does not show (if it has at most
    len(MARKERS) values), the Pareto front with its points' numbers (as in sweep.md), the pass
    and warn lines."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.5, 5), layout="constrained")
    ok = [r for r in rows if r["status"] != "failed" and r["worst_safety_factor"] != ""]
    shown = [n for n in varied if n not in SPEED_FROM[fidelity]]
    marked = next((n for n in shown if len(_values(ok, n)) <= len(MARKERS)), None) if ok \
        else None
    if ok:
        speed = np.array([float(r["speed_m_s"]) for r in ok])
        sf = np.array([float(r["worst_safety_factor"]) for r in ok])
        outcomes = [_outcome(r) for r in ok]
        kinds = _values(ok, marked) if marked else [None]
        for j, kind in enumerate(kinds):          # one scatter per marker
            pick = [i for i, r in enumerate(ok) if marked is None or _value(r[marked]) == kind]
            ax.scatter(speed[pick], sf[pick], s=30, marker=MARKERS[j],
                       color=[COLORS.get(outcomes[i], "k") for i in pick])
        front = pareto_front(speed, sf)
        ax.plot(speed[front], sf[front], "k-", lw=0.8)
        for i in front:
            ax.annotate(f"#{ok[i]['point']}", (speed[i], sf[i]), textcoords="offset points",
                        xytext=(4, 4), fontsize=7)
        handles = [plt.Line2D([], [], ls="", marker="s", color=COLORS.get(o, "k"),
                              label=f"{o} ({outcomes.count(o)})") for o in _ranked(outcomes)]
        handles += [plt.Line2D([], [], ls="", marker=MARKERS[j], color="0.3",
                               label=f"{marked} = {k:g}" if isinstance(k, float)
                               else f"{marked} = {k}")
                    for j, k in enumerate(kinds) if marked]
        handles.append(plt.Line2D([], [], color="k", lw=0.8,
                                  label="Pareto front (#: point, as in sweep.md)"))
        handles.append(ax.axhline(sf_pass, color="tab:green", ls="--", lw=1,
                                  label=f"SF = {sf_pass:g}: pass at or above"))
        if sf_warn is not None:
            handles.append(ax.axhline(sf_warn, color="tab:orange", ls="--", lw=1,
                                      label=f"SF = {sf_warn:g}: warn at or above, fail below"))
        fig.legend(handles=handles, loc="outside right upper", fontsize=8)
    in_speed = [n for n in varied if n in SPEED_FROM[fidelity]]
    hidden = [n for n in shown if n != marked]
    note = ([f"the speed shows {', '.join(in_speed)}"] if in_speed else []) + (
        [f"not shown: {', '.join(hidden)}"] if hidden else []) + (
        [f"{len(rows) - len(ok)} points without a safety factor (failed) not drawn"]
        if len(rows) > len(ok) else [])
    ax.set_title("; ".join(note), fontsize=8, loc="left")
    ax.set_xlabel(SPEED_LABEL[fidelity])
    ax.set_ylabel("worst motor's safety factor")
    fig.suptitle("safety factor against speed")
    return fig


def write_sweep_plots(rows: list[dict], axes: tuple[str, ...], fidelity: str, sf_pass: float,
                      out: Path, varied=None, sf_warn=None) -> list[Path]:
    """verdict_map.png over the axes (one or two varied parameters; a panel per value of the
    other varied ones, draw_verdict_map) and pareto.png (draw_pareto); returns the paths."""
    varied = list(varied or axes)
    return [save_figure(draw_verdict_map(rows, axes, varied), out / SWEEP_PLOTS[0]),
            save_figure(draw_pareto(rows, fidelity, sf_pass, sf_warn, varied),
                        out / SWEEP_PLOTS[1])]
