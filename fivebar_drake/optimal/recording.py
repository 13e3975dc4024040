"""The optimal motions as a Rerun recording (optimal.rrd; open it beside a simulation's run.rrd):
the answer, then each optimal jump's leg drawn in its leg plane as the hip rises, the hip's height and speed, and
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


def _view(origin: str, name: str, t_end: float, values) -> rrb.TimeSeriesView:
    """A time-series view of origin over 0..t_end s, its y axis the values' range with a tenth
    either side (every curve inside the axes)."""
    values = np.concatenate([np.ravel(v) for v in values])
    lo, hi = float(np.nanmin(values)), float(np.nanmax(values))
    pad = 0.1 * (hi - lo) or 0.1 * abs(hi) or 1.0
    return rrb.TimeSeriesView(
        origin=origin, name=name, axis_y=rrb.ScalarAxis(range=(lo - pad, hi + pad)),
        axis_x=rrb.TimeAxis(view_range=rr.TimeRange(rr.TimeRangeBoundary.absolute(seconds=0.0),
                                                    rr.TimeRangeBoundary.absolute(seconds=t_end))))


def blueprint(jumps: dict[str, Jump], standing: float, gaits: dict[str, GaitFloor]
              ) -> rrb.Blueprint:
    """The answer above the vertical jump's tab, then one tab per gait's floor, each plot over
    its own span (the push, the period); the side panels collapsed."""
    found = [j for j in jumps.values() if j is not None]
    push = max((float(j.t[-1]) for j in found), default=1.0)
    views = [] if not found else [
        _view("hip/height_m", "hip above standing (m)", push,
              [j.stroke.u[:j.takeoff + 1] - standing for j in found]),
        _view("hip/speed_m_s", "hip speed (m/s)", push, [j.w for j in found]),
        *[_view(f"torque/{m}", f"motor {m} (N·m)", push,
                [j.delivered_Nm[:, k] for j in found]
                + [np.concatenate(j.stroke.motor.limits(j.speed_rad_s))[:, k] for j in found])
          for k, m in enumerate(MOTORS)]]
    jump = rrb.Vertical(
        rrb.TextDocumentView(origin="answer", name="answer"),
        rrb.Horizontal(rrb.Spatial3DView(origin="world", name="the leg in its plane"),
                       rrb.Vertical(*views)), row_shares=[1, 4], name="vertical jump")
    tabs = [rrb.Vertical(*[_view(f"gait/{kind}/{series}", title, float(floor.t[-1]),
                                 [values]) for (series, title), values in
                           zip(GAIT_SERIES, _gait_series(floor))], name=f"{kind} floor")
            for kind, floor in gaits.items()]
    return rrb.Blueprint(rrb.Tabs(jump, *tabs), rrb.BlueprintPanel(state="collapsed"),
                         rrb.SelectionPanel(state="collapsed"),
                         rrb.TimePanel(state="collapsed", timeline=TIMELINE))


def _gait_series(floor: GaitFloor) -> tuple:
    """A floor's series in GAIT_SERIES' order: body height about its mean (m), pitch (deg),
    the feet's vertical forces (legs, knots) N, the stance torques (legs, knots, 2) N*m."""
    return (floor.z_m - floor.z_m.mean(), np.degrees(floor.pitch_rad), floor.force_N[:, :, 1],
            floor.torque_Nm)


def log_gait(rec, kind: str, floor: GaitFloor) -> None:
    """A gait's floor over its period (time from its start, s) under gait/KIND/."""
    t, root = floor.t, f"gait/{kind}"
    height, pitch, force, torque = _gait_series(floor)
    scalars(rec, f"{root}/body_height_m/z", t, height, "height")
    scalars(rec, f"{root}/pitch_deg/pitch", t, pitch, "pitch")
    for i, leg in enumerate(LEGS):
        scalars(rec, f"{root}/force_z_N/{leg}", t, force[i], leg)
        for m, motor in enumerate(MOTORS):
            scalars(rec, f"{root}/torque_Nm/{leg}_{motor}", t, torque[i, :, m],
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
                    gaits: dict[str, GaitFloor] | None = None, answer: str = "") -> Path:
    """optimal.rrd of the jumps by name (None: skipped), the gaits' floors by kind and the
    answer (markdown), which the recording opens on."""
    standing, gaits = -params.gait.y_home_m, gaits or {}
    with recording_file(path, "fivebar_drake-optimal", blueprint(jumps, standing, gaits)) as rec:
        rec.log("answer", rr.TextDocument(answer, media_type=rr.MediaType.MARKDOWN), static=True)
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
