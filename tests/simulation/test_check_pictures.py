"""The pictures of the check that decided a run: gear_comparison.png draws each run's demand
against its own motor's limit with its verdict and deciding check; every run folder's
sim_torque_speed.png draws the window's operating points over the envelope."""

import matplotlib
import numpy as np
import pytest

from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.simulation.comparison import figure
from fivebar_drake.simulation.plots import coinciding
from fivebar_drake.simulation.run_statistics import window_rows

matplotlib.use("Agg")


def run(label, gear, driving, braking, deciding, beyond):
    """A summary of the keys the comparison reads: one leg, motor A driving, B braking."""
    def motor(limit, verdict):
        return {"demand_p99_Nm": 3.0, "verdict": verdict, "deciding_check": deciding,
                "checks": {"torque": {"limit_Nm": limit}, "speed": {"outside_fraction": beyond}}}
    return {"label": label, "verdict": "fail", "deciding_check": deciding,
            "motor_peak_torque_Nm": driving,
            "motor": {"gear_ratio": gear, "peak_torque_Nm": driving,
                      "braking_peak_torque_Nm": braking},
            "legs": {"FL": {"A": motor(driving, "fail"), "B": motor(braking, "warn")}}}


def test_gear_comparison_draws_each_run_against_its_own_limit():
    fig = figure([run("trot", 8.0, 5.0, 6.17, "torque", 0.0),
                  run("trot_gear_11.5", 11.5, 7.1875, 8.87, "speed", 0.03)])
    top, low = fig.axes
    limits = [seg[0][1] for lines in top.collections for seg in lines.get_segments()]
    assert limits == [5.0, 6.17, 7.1875, 8.87]
    texts = [t.get_text().strip() for t in top.texts]
    assert texts == ["FAIL (torque)", "WARN (torque)", "FAIL (speed)", "WARN (speed)"]
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert any("trot_gear_11.5 (11.5:1): its limit, driving 7.19 N·m" in t for t in legend)
    assert [b.get_height() for b in low.patches] == pytest.approx([0, 0, 3, 3])
    matplotlib.pyplot.close(fig)


def test_every_run_draws_its_torque_speed_check(simulated):
    from fivebar_drake.pipeline import _review
    from fivebar_drake.simulation.plots import torque_speed_figure

    record = simulated(gait="trot", duration_s=2.5)
    sig, _, summary = _review(record)
    fig = torque_speed_figure(sig, record.layout.legs, record.params, summary)
    rows = int(np.sum(window_rows(sig.t, summary["window_s"])))
    for ax, name in zip(fig.axes, MOTORS):
        points = [len(c.get_offsets()) for c in ax.collections]
        assert points[::2] == [rows] * len(record.layout.legs)     # every point of the window
        legend = [t.get_text() for t in ax.get_legend().get_texts()][2:]
        for leg, text in zip(record.layout.legs, legend):
            m = summary["legs"][leg][name]
            assert text.startswith(f"{leg} {name}: {m['verdict'].upper()} "
                                   f"({m['deciding_check']})")
    assert summary["verdict"].upper() in fig.texts[0].get_text()
    matplotlib.pyplot.close(fig)


def test_coinciding_legs_are_drawn_once():
    t = np.linspace(0.0, 1.0, 50)
    curves = np.stack([t, t + 0.001, 2 * t, t], axis=1)          # legs 0, 1, 3 coincide
    with_nan = curves.copy()
    with_nan[:5] = np.nan                                          # unloaded: NaN alike
    assert coinciding((curves, with_nan), (0.01, 0.01)) == [[0, 1, 3], [2]]


def test_force_capability_names_every_leg_once_and_fits(simulated):
    from fivebar_drake.pipeline import _review
    from fivebar_drake.simulation.plots import capability_figure

    record = simulated(gait="jump", duration_s=2.6)
    _, steps, summary = _review(record)
    fig = capability_figure(steps, record.layout.legs, record.params, summary)
    fig.canvas.draw()
    box = fig.bbox
    title = fig.get_suptitle()
    assert "least ratio held / needed" in title and "below 1 the motors could not" in title
    extent = fig._suptitle.get_window_extent()
    assert box.x0 <= extent.x0 and extent.x1 <= box.x1           # not cut off
    for ax in fig.axes:
        named = [t.get_text().split(":")[0].split(" (")[0] for t in ax.get_legend().get_texts()
                 if t.get_text().endswith("required")]
        assert sorted(", ".join(named).split(", ")) == sorted(record.layout.legs)
        drawn = np.concatenate([line.get_ydata() for line in ax.get_lines()])
        assert ax.get_ylim()[1] <= 1.1 * np.nanmax(drawn) + 1e-9     # scaled to its data
    matplotlib.pyplot.close(fig)


def test_the_torque_plots_draw_each_quadrants_limit(simulated, params):
    """sim_torques.png and the analysis' total_torque.png draw the driving limit and the braking
    limit (a landing's braking peak above the driving limit is no violation), each at the
    motor's own value."""
    from fivebar_drake.analysis.plots import total_torque
    from fivebar_drake.analysis.torques import analyze
    from fivebar_drake.pipeline import _review
    from fivebar_drake.simulation.plots import torque_figure

    record = simulated(gait="trot", duration_s=2.5)
    sig, _, summary = _review(record)
    motor = record.params.motor
    fig = torque_figure(sig, record.layout.legs, record.params, summary["window_s"])
    text = fig.texts[0].get_text()
    assert f"±{motor.peak_torque_Nm:.2f}" in text and f"±{motor.braking_peak_torque_Nm:.2f}" in text
    matplotlib.pyplot.close(fig)
    fig = total_torque(analyze(params))
    levels = {round(abs(line.get_ydata()[0]), 6) for ax in fig.axes for line in ax.lines
              if len(set(line.get_ydata())) == 1}
    assert {round(params.motor.peak_torque_Nm, 6),
            round(params.motor.braking_peak_torque_Nm, 6)} <= levels
    matplotlib.pyplot.close(fig)
