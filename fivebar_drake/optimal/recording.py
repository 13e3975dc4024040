"""The optimal motions as a Rerun recording (optimal.rrd; open it beside a simulation's run.rrd):
each optimal jump's leg drawn in its leg plane as the hip rises, the hip's height and speed, and
each motor's delivered torque against the envelope's limit at its speed, over the push; each
gait's floor (one tab per gait) over its period: the body's height and pitch, the feet's
vertical forces and the stance motors' torques."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.core.rerun_files import TIMELINE, pose_frames, recording_file, scalars
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.optimal.gait_floor import GaitFloor
from fivebar_drake.optimal.vertical_jump import Jump
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.robots.quadruped.params import Params

RECORDING_FILE = "optimal.rrd"
POSE_RATE_HZ = 200.0     # leg drawings per second of the push (it lasts 0.1-0.4 s)
SPACING_M = 0.2          # the jumps' legs side by side along y
COLORS = {"ceiling": (31, 119, 180), "floor": (255, 127, 14)}


GAIT_SERIES = (("body_height_m", "body above its mean height (m)"),
               ("pitch_deg", "pitch, nose down (deg)"),
               ("force_z_N", "feet's vertical forces (N)"),
               ("torque_Nm", "stance motors' torques (N·m)"))


def blueprint(gaits=()) -> rrb.Blueprint:
    """The vertical jump's tab, then one per gait's floor (gaits: their kinds)."""
    jump = rrb.Horizontal(
        rrb.Spatial3DView(origin="world", name="the leg in its plane"),
        rrb.Vertical(rrb.TimeSeriesView(origin="hip/height_m", name="hip above standing (m)"),
                     rrb.TimeSeriesView(origin="hip/speed_m_s", name="hip speed (m/s)"),
                     *[rrb.TimeSeriesView(origin=f"torque/{m}", name=f"motor {m} (N·m)")
                       for m in MOTORS]), name="vertical jump")
    tabs = [rrb.Vertical(*[rrb.TimeSeriesView(origin=f"gait/{kind}/{series}", name=title)
                           for series, title in GAIT_SERIES], name=f"{kind} floor")
            for kind in gaits]
    return rrb.Blueprint(rrb.Tabs(jump, *tabs))


def log_gait(rec, kind: str, floor: GaitFloor) -> None:
    """A gait's floor over its period (time from its start, s) under gait/KIND/."""
    t, root = floor.t, f"gait/{kind}"
    scalars(rec, f"{root}/body_height_m/z", t, floor.z_m - floor.z_m.mean(), "height")
    scalars(rec, f"{root}/pitch_deg/pitch", t, np.degrees(floor.pitch_rad), "pitch")
    for i, leg in enumerate(LEGS):
        scalars(rec, f"{root}/force_z_N/{leg}", t, floor.force_N[i, :, 1], leg)
        for m, motor in enumerate(MOTORS):
            scalars(rec, f"{root}/torque_Nm/{leg}_{motor}", t, floor.torque_Nm[i, :, m],
                    f"{leg} {motor}")


def leg_strips(params: Params, q, hip_height) -> np.ndarray:
    """(n, 6, 3) world points A, C, E, F, E, D, B... of the leg at joint angles q (n, 2), its
    hip hip_height (n,) m above the ground; leg-plane x backwards drawn along -x."""
    leg = params.fivebar_leg
    pose = leg.forward(q)
    g = params.leg
    a, b = np.broadcast_to(g.a, pose.c.shape), np.broadcast_to(g.b, pose.d.shape)
    plane = np.stack([a, pose.c, pose.e, pose.f, pose.e, pose.d, b], -2)     # (n, 7, 2)
    out = np.zeros(plane.shape[:-1] + (3,))
    out[..., 0] = -plane[..., 0]
    out[..., 2] = plane[..., 1] + np.asarray(hip_height)[:, None]
    return out


def write_recording(path: Path, jumps: dict[str, Jump | None], params: Params,
                    gaits: dict[str, GaitFloor] | None = None) -> Path:
    """optimal.rrd of the jumps by name (None: skipped) and the gaits' floors by kind."""
    standing, gaits = -params.gait.y_home_m, gaits or {}
    with recording_file(path, "fivebar_drake-optimal", blueprint(gaits)) as rec:
        for kind, floor in gaits.items():
            log_gait(rec, kind, floor)
        for i, (name, j) in enumerate(jumps.items()):
            if j is None:
                continue
            color = COLORS.get(name)
            nodes = slice(0, j.takeoff + 1)
            u = j.stroke.u[nodes]
            scalars(rec, f"hip/height_m/{name}", j.t, u - standing, name, color)
            scalars(rec, f"hip/speed_m_s/{name}", j.t, j.w, name, color)
            cells = j.t[:-1]
            upper, lower = j.stroke.motor.limits(j.speed_rad_s)
            for m, motor in enumerate(MOTORS):
                scalars(rec, f"torque/{motor}/{name}", cells, j.delivered_Nm[:, m], name, color)
                limit = np.where(j.delivered_Nm[:, m] >= 0.0, upper[:, m], lower[:, m])
                scalars(rec, f"torque/{motor}/{name}_limit", cells, limit,
                        f"{name}: envelope at its speed", color, width=0.8)
            frames = pose_frames(j.t, POSE_RATE_HZ)
            points = leg_strips(params, j.stroke.q[frames], u[frames] + params.body.foot_radius_m)
            points[..., 1] = i * SPACING_M
            time = [rr.TimeColumn(TIMELINE, duration=j.t[frames])]
            rec.send_columns(f"world/{name}/leg", indexes=time, columns=rr.LineStrips3D.columns(
                strips=list(points)).partition(np.ones(len(frames), dtype=int)))
            rec.log(f"world/{name}/leg", rr.LineStrips3D.from_fields(
                radii=0.004, colors=[color or (90, 90, 90)]), static=True)
        rec.log("world/ground", rr.Boxes3D(centers=[[0.0, SPACING_M / 2, -0.005]],
                                           half_sizes=[[0.2, SPACING_M, 0.005]],
                                           colors=[[200, 200, 200]]), static=True)
    return path
