"""The run's Rerun recording: rails, path, legs, platform and sliders in 3-D at record_hz; the
actuator forces against the closed form, the platform pose, the tracking error, the loop gaps."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.core.rerun_files import TIMELINE, recording_file, scalars
from fivebar_drake.mechanisms.parallel4.kinematics import PAIR, platform_offsets
from fivebar_drake.mechanisms.parallel4.params import Params
from fivebar_drake.studies.parallel4.model import base_points
from fivebar_drake.studies.parallel4.simulation import Run

RECORDING_FILE = "run.rrd"
RAIL_HALF_LENGTH_M = 0.8


def _leg_strips(params: Params, run: Run) -> np.ndarray:
    """A_i and B_i (n, 4, 2, 3) of every sample, m (from the plant's reached poses)."""
    g = params.geometry
    anchors = base_points(g)[None] + run.q[..., None] * np.array([1.0, 0.0, 0.0])
    tips = run.pose[:, None, :3] + platform_offsets(g, run.pose[:, 3])[:, list(PAIR)]
    return np.stack([anchors, tips], axis=2)


def blueprint() -> rrb.Blueprint:
    return rrb.Blueprint(rrb.Horizontal(
        rrb.Spatial3DView(origin="world", name="manipulator"),
        rrb.Vertical(rrb.TimeSeriesView(origin="actuator", name="actuator forces (N)"),
                     rrb.TimeSeriesView(origin="platform", name="platform pose (m, deg)"),
                     rrb.TimeSeriesView(origin="tracking", name="tracking error (m, deg)"),
                     rrb.TimeSeriesView(origin="loop_gap", name="loop gap (m)")),
        column_shares=[3, 2]), collapse_panels=True)


def write_recording(path: Path, params: Params, run: Run) -> Path:
    """The run's .rrd file (written atomically, with its blueprint and footer)."""
    g = params.geometry
    with recording_file(path, "parallel4", blueprint()) as rec:
        rails = [[[-RAIL_HALF_LENGTH_M, y, z], [RAIL_HALF_LENGTH_M, y, z]]
                 for y, z in ((g.a, g.d), (-g.a, -g.d))]
        rec.log("world/rails", rr.LineStrips3D(rails, radii=0.004, colors=[[90, 90, 90]]),
                static=True)
        rec.log("world/path", rr.LineStrips3D([run.desired[:, :3]], radii=0.0015,
                                              colors=[[230, 80, 60]]), static=True)
        time = [rr.TimeColumn(TIMELINE, duration=run.t)]
        n = len(run.t)
        strips = _leg_strips(params, run)
        rec.send_columns("world/legs", indexes=time, columns=rr.LineStrips3D.columns(
            strips=list(strips.reshape(n * 4, 2, 3))).partition([4] * n))
        rec.log("world/legs", rr.LineStrips3D.from_fields(radii=0.006), static=True)
        tips = platform_offsets(g, run.pose[:, 3]) + run.pose[:, None, :3]
        rec.send_columns("world/platform", indexes=time, columns=rr.LineStrips3D.columns(
            strips=list(tips)).partition([1] * n))
        rec.log("world/platform", rr.LineStrips3D.from_fields(radii=0.012,
                                                             colors=[[60, 180, 90]]),
                static=True)
        rec.send_columns("world/sliders", indexes=time, columns=rr.Points3D.columns(
            positions=list(strips[:, :, 0].reshape(n * 4, 3))).partition([4] * n))
        rec.log("world/sliders", rr.Points3D.from_fields(radii=0.02), static=True)
        for i in range(4):
            scalars(rec, f"actuator/applied/l{i + 1}", run.t, run.force[:, i],
                     f"l{i + 1} applied")
            scalars(rec, f"actuator/static/l{i + 1}", run.t, run.static_closed[:, i],
                     f"l{i + 1} static, closed form")
            scalars(rec, f"loop_gap/leg{i + 1}", run.t, run.gap[:, i], f"leg {i + 1}")
        for k, name in enumerate(("x", "y", "z")):
            scalars(rec, f"platform/{name}_m", run.t, run.pose[:, k], f"{name} (m)")
        scalars(rec, "platform/theta_deg", run.t, np.degrees(run.pose[:, 3]), "theta (deg)")
        scalars(rec, "tracking/position_m", run.t,
                 np.linalg.norm(run.pose[:, :3] - run.desired[:, :3], axis=1), "|P - P_d| (m)")
        scalars(rec, "tracking/theta_deg", run.t,
                 np.degrees(run.pose[:, 3] - run.desired[:, 3]), "theta - theta_d (deg)")
    return path
