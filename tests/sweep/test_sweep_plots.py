"""The sweep's pictures draw every point of the table, with every varied parameter visible, and
count the outcomes as sweep.md does (the example sweep's points, computed without a cluster)."""

from collections import Counter
from pathlib import Path

import matplotlib
import pytest
from matplotlib.colors import to_rgba

from fivebar_drake.sweep.engine import base_inputs
from fivebar_drake.sweep.plots import COLORS, draw_pareto, draw_verdict_map, map_panels
from fivebar_drake.sweep.points import analysis_rows
from fivebar_drake.sweep.report import summarize_sweep
from fivebar_drake.sweep.spec import load_spec

matplotlib.use("Agg")
EXAMPLE = Path(__file__).parents[2] / "fivebar_drake" / "data" / "sweep_example.yaml"
#         3 frequencies x 2 strides x 3 gears


@pytest.fixture(scope="module")
def example():
    """(spec, rows as points.csv holds them: strings)."""
    spec = load_spec(EXAMPLE)
    params, _ = base_inputs(spec)
    rows = analysis_rows(params, (spec.gait, spec.model), list(enumerate(spec.points())))
    return spec, [{k: str(v) for k, v in r.items()} for r in rows]


def drawn_colours(fig) -> Counter:
    """How many points of each outcome's colour the figure's scatters draw."""
    names = {to_rgba(c): o for o, c in COLORS.items()}
    counts = Counter()
    for ax in fig.axes:
        for points in ax.collections:
            colours = points.get_facecolors()
            colours = list(colours) * (len(points.get_offsets()) if len(colours) == 1 else 1)
            counts.update(names[tuple(c)] for c in colours)
    return counts


def test_verdict_map_and_pareto_draw_the_counts_of_sweep_md(example):
    spec, rows = example
    outcomes = summarize_sweep(rows, spec.names, 2.0)["outcomes"]
    assert outcomes == {"pass": 6, "warn": 6, "fail": 6}
    fig = draw_verdict_map(rows, spec.plot, spec.names)
    assert drawn_colours(fig) == outcomes
    # the gear ratio, not on the axes, gets a panel per value; the legend counts
    assert [ax.get_title() for ax in fig.axes if ax.get_visible()] == [
        f"motor.gear_ratio = {n}" for n in (8, 10, 12)]
    assert {t.get_text() for t in fig.legends[0].get_texts()} == {
        "pass (6)", "warn (6)", "fail (6)"}
    fig = draw_pareto(rows, "analysis", 2.0, 1.5, spec.names)
    assert drawn_colours(fig) == outcomes
    labels = {t.get_text() for t in fig.legends[0].get_texts()}
    assert {"motor.gear_ratio = 8", "SF = 1.5: warn at or above, fail below"} <= labels
    assert "the speed shows gait.frequency_hz, gait.a_m" in fig.axes[0].get_title(loc="left")
    matplotlib.pyplot.close("all")


def test_too_many_panels_are_named_as_hidden(example):
    spec, rows = example
    faceted, hidden, panels = map_panels(rows, ("gait.a_m",), spec.names)
    assert (faceted, hidden, len(panels)) == (["gait.frequency_hz", "motor.gear_ratio"], [], 9)
    many = [{**r, "extra": str(i)} for i, r in enumerate(rows)]      # 18 values: no panels
    faceted, hidden, panels = map_panels(many, spec.plot, [*spec.names, "extra"])
    assert hidden == ["extra"] and len(panels) == 3
    assert sum(len(p) for _, p in panels) == len(rows)
    fig = draw_verdict_map(many, spec.plot, [*spec.names, "extra"])
    assert "not shown: extra" in fig.texts[-1].get_text()
    matplotlib.pyplot.close("all")
