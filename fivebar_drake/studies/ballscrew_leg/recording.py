"""The squat's Rerun recording: the leg in 3-D at simulation.pose_rate_hz, the screw motor's
torques (commanded, applied, closed-form static, limit), q1 and its reference, the loop gaps,
the motor speed and the carriage height."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.core.rerun_files import TIMELINE, pose_frames, recording_file, scalars
from fivebar_drake.mechanisms.ballscrew_leg import Params
from fivebar_drake.studies.ballscrew_leg.simulation import Signals

RECORDING_FILE = "run.rrd"


def write_recording(sig: Signals, p: Params, path: Path) -> Path:
    """The run's .rrd (blueprint inside, footer written, then renamed into place)."""
    view = rrb.Blueprint(rrb.Horizontal(
        rrb.Spatial3DView(origin="world", name="leg"),
        rrb.Vertical(rrb.TimeSeriesView(origin="torque", name="screw motor torque (N·m)"),
                     rrb.TimeSeriesView(origin="joints", name="q1 (deg)"),
                     rrb.TimeSeriesView(origin="loop_gap", name="loop gaps (m)"))),
        collapse_panels=True)
    frames = pose_frames(sig.t, p.simulation.pose_rate_hz)
    pts = np.concatenate([sig.points, np.zeros(sig.points.shape[:2] + (1,))], -1)[frames]
    strips = [s for f in pts for s in (f[[0, 1, 3]], f[[2, 1]], f[[0, 4]])]
    with recording_file(path, "ballscrew_leg", view) as rec:
        rec.send_columns("world/leg", indexes=[rr.TimeColumn(TIMELINE, duration=sig.t[frames])],
                         columns=rr.LineStrips3D.columns(strips=strips).partition(
                             [3] * len(frames)))
        rec.log("world/leg", rr.LineStrips3D.from_fields(radii=0.004), static=True)
        for name, values in (("commanded", sig.command), ("applied", sig.applied),
                             ("static_closed_form", sig.static)):
            scalars(rec, f"torque/{name}", sig.t, values, name)
        scalars(rec, "torque/limit", sig.t, np.full(len(sig.t), -p.motor.peak_torque_Nm),
                "-limit")
        scalars(rec, "joints/q1", sig.t, np.degrees(sig.q1), "q1")
        scalars(rec, "joints/q1_reference", sig.t, np.degrees(sig.q1_ref), "reference")
        scalars(rec, "loop_gap/D", sig.t, sig.gap_d, "D")
        scalars(rec, "loop_gap/foot", sig.t, sig.gap_foot, "foot")
        scalars(rec, "motor/speed", sig.t, sig.motor_speed, "motor speed (rad/s)")
        scalars(rec, "carriage/height", sig.t, sig.height, "hip height (m)")
    return path
