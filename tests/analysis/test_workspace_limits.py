"""The workspace plot drawn with the leg's limits: each limit whose boundary crosses the reach
outlined and named in the legend with its bound, the region the limits cut filled; none for a leg
without limits."""

import dataclasses

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fivebar_drake.analysis.design_plots import draw_limits  # noqa: E402
from fivebar_drake.analysis.force_capability import workspace_grid  # noqa: E402
from fivebar_drake.mechanisms.fivebar import LegLimits  # noqa: E402


def test_the_limits_are_outlined_and_named(params):
    x, y = workspace_grid(params.leg, 121, 81)
    fig, ax = plt.subplots()
    assert draw_limits(ax, params.leg, x, y)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[0] == "reachable, cut by the limits"
    assert set(labels[1:]) == {"motor A angle >= -170 deg", "motor A angle <= 10 deg",
                               "motor B angle >= -170 deg", "motor B angle <= 110 deg",
                               "leg extension >= 0.1 m", "leg extension <= 0.27 m",
                               "knee C angle >= 20 deg", "knee D angle >= 20 deg",
                               "upper links' angle >= 10 deg"}
    # a bound no reachable foot position comes near draws no outline
    far = dataclasses.replace(params.leg, limits=LegLimits(extension_max_m=1.5,
                                                           knee_min_deg=20.0))
    fig, ax = plt.subplots()
    assert draw_limits(ax, far, x, y)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "leg extension <= 1.5 m" not in labels and "knee D angle >= 20 deg" in labels
    fig, ax = plt.subplots()
    free = dataclasses.replace(params.leg, limits=LegLimits())
    assert not draw_limits(ax, free, x, y)
    assert ax.get_legend() is None and not ax.collections
    plt.close("all")
