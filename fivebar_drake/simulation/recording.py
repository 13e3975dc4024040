"""Rerun recording (.rrd) of a simulated run, logged in columns, with its blueprint inside.

Entities (timeline "sim_time"):
- world/ground, world/body (box + pose), world/legs/<leg> (link segments: A-C-E-F and B-D-E),
  world/feet/<leg> (foot trace), world/forces/<leg> (ground force arrows at the feet, 1 cm per
  10 N), at pose_rate_hz;
- per log interval (means over the plant steps of the interval): joints/<leg>/<A|B>/{angle,
  speed}, torque/<leg>/<A|B>/{commanded, applied, static_contact, static_trot, static_seed,
  limit_pos, limit_neg}, loop_gap/<leg> (worst gap of the interval), contact/<leg>/{normal,
  tangential} (leg plane, N), body/height, body/forward_speed, body/tilt_deg,
  stats/window (1 inside the statistics window);
- cycle_peak/<leg>/<A|B>: the peak applied torque of each whole cycle, at the cycle's end.
Each run gets its own recording id, so two runs open side by side in one viewer.
"""

from __future__ import annotations

from pathlib import Path
import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.core.rerun_files import TIMELINE, pose_frames, recording_file, scalars
from fivebar_drake.core.rotation import body_rotation
from fivebar_drake.mechanisms.fivebar import forward_points
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.robots.quadruped.legs import plane_to_body
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.summary import MOTORS, Signals


RECORDING_FILE = "run.rrd"
FORCE_ARROW_M_PER_N = 0.001    # 1 mm of arrow per newton
LEG_STRIPS = ([0, 1, 2, 3], [4, 5, 2])   # of link_points' A, C, E, F, B, D: A-C-E-F and B-D-E


def blueprint(legs) -> rrb.Blueprint:
    torque_views = [rrb.TimeSeriesView(origin=f"torque/{leg}", name=f"torque {leg} (N·m)")
                    for leg in legs]
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="world", name="robot"),
                rrb.TimeSeriesView(origin="body", name="body height (m), speed (m/s)"),
                row_shares=[3, 1]),
            rrb.Vertical(
                rrb.Tabs(*torque_views, name="motor torques"),
                rrb.Tabs(rrb.TimeSeriesView(origin="loop_gap", name="loop gap (m)"),
                         rrb.TimeSeriesView(origin="contact", name="foot forces (N)"),
                         rrb.TimeSeriesView(origin="joints", name="joints (rad, rad/s)"),
                         rrb.TimeSeriesView(origin="cycle_peak", name="per-cycle peaks (N·m)"),
                         rrb.TimeSeriesView(origin="stats", name="statistics window"))),
            column_shares=[1, 1]),
        collapse_panels=True)


def link_points(layout: RobotLayout, params: Params, states: np.ndarray) -> np.ndarray:
    """World positions (rows, legs, 6, 3) in m of the joints A, C, E, F, B, D of every leg for
    plant states (rows, nx): the 5-bar's forward kinematics (the seed's E branch) of the motor
    angles in the leg plane, placed by the hip (layout.hips_m, body frame), the leg plane's
    rotation in the body and the body pose of the state. The plant's own E and F differ by at
    most a few loop gaps; NaN where the motor angles cannot close the loop (a run that came
    apart)."""
    q = states[:, layout.state.q_index]                                     # (rows, legs, 2) rad
    ta, tb = (np.ascontiguousarray(q[..., j].ravel()) for j in (0, 1))
    cx, cy, dx, dy, ex, ey, fx, fy = forward_points(params.leg.core, ta, tb,
                                                    np.ones_like(ta), True)
    a, b = (np.broadcast_to(p, (ta.size, 2)) for p in (params.leg.a, params.leg.b))
    plane = np.stack([a, np.stack([cx, cy], -1), np.stack([ex, ey], -1), np.stack([fx, fy], -1),
                      b, np.stack([dx, dy], -1)], 1).reshape(q.shape[:2] + (6, 2))
    in_body = plane_to_body(layout.hips_m[:, None, :], plane)
    pose = states[:, layout.state.body_q:layout.state.body_q + 7]                 # quaternion wxyz, position
    r_world_body = np.array([body_rotation(v) for v in pose[:, :4]])
    return pose[:, None, None, 4:] + np.einsum("sij,slpj->slpi", r_world_body, in_body)


def write_recording(path: Path, sig: Signals, record: SimulationRecord, summary: dict,
                    name: str = "") -> Path:
    """Write the run's .rrd file atomically (complete with its footer, then renamed into place)
    from its signals (summary.signals), its record (the 3-D poses come from the recorded plant
    states) and its summary (statistics window, per-cycle peaks). name: the run's name in its
    recording id (e.g. an envelope's maneuver), beside the gait and the closure."""
    scenario = record.scenario
    path.parent.mkdir(parents=True, exist_ok=True)
    title = "-".join(filter(None, ("fivebar_drake", name, scenario.gait.kind,
                                   scenario.closure.kind)))
    with recording_file(path, title, blueprint(record.layout.legs)) as rec:
        if len(sig.t):
            _log_scene(rec, sig, record)
            _log_series(rec, sig, record.layout.legs, record.params, summary)
    return path


def _log_scene(rec, sig: Signals, record: SimulationRecord):
    b = record.params.body
    rec.log("world/ground", rr.Boxes3D(centers=[[0.0, 0.0, -0.005]], half_sizes=[[3.0, 3.0, 0.005]],
                                       colors=[[90, 110, 90]]), static=True)
    rec.log("world/body", rr.Boxes3D(half_sizes=[[b.length_m / 2, b.width_m / 2, b.height_m / 2]],
                                     colors=[[150, 150, 165]]), static=True)
    t = sig.t
    frames = pose_frames(t, record.scenario.pose_rate_hz)
    tf = t[frames]
    time = [rr.TimeColumn(TIMELINE, duration=tf)]
    quat = sig.body_quat[frames]
    rec.send_columns("world/body", indexes=time, columns=rr.Transform3D.columns(
        translation=sig.body_p[frames], quaternion=np.column_stack([quat[:, 1:], quat[:, :1]])))
    points = link_points(record.layout, record.params, record.table["state"][frames])
    for i, leg in enumerate(record.layout.legs):
        strips = [points[f, i, strip] for f in range(len(frames)) for strip in LEG_STRIPS]
        rec.send_columns(f"world/legs/{leg}", indexes=time, columns=rr.LineStrips3D.columns(
            strips=strips).partition([len(LEG_STRIPS)] * len(frames)))
        rec.log(f"world/legs/{leg}", rr.LineStrips3D.from_fields(radii=0.004), static=True)
        rec.log(f"world/feet/{leg}", rr.LineStrips3D([points[:, i, 3]], radii=0.0015,
                                                     colors=[[230, 80, 60]]), static=True)
        origin = points[:, i, 3] - np.array([0.0, 0.0, b.foot_radius_m])
        force = sig.foot_force_world[frames, i] * FORCE_ARROW_M_PER_N
        rec.send_columns(f"world/forces/{leg}", indexes=time, columns=rr.Arrows3D.columns(
            origins=origin, vectors=force))
        rec.log(f"world/forces/{leg}", rr.Arrows3D.from_fields(colors=[[40, 160, 60]],
                                                               radii=0.002), static=True)


def _log_series(rec, sig: Signals, legs, params: Params, summary: dict):
    limit = params.motor.peak_torque_Nm
    n = len(sig.t)
    start, end = summary["window_s"]
    cycle_ends = start + summary["cycle_s"] * np.arange(1, summary["cycles_in_window"] + 1)
    for i, leg in enumerate(legs):
        scalars(rec, f"loop_gap/{leg}", sig.t, sig.gap[:, i], leg)
        scalars(rec, f"contact/{leg}/tangential", sig.t, sig.foot_force_plane[:, i, 0])
        scalars(rec, f"contact/{leg}/normal", sig.t, sig.foot_force_plane[:, i, 1])
        for j, m in enumerate(MOTORS):
            base = f"torque/{leg}/{m}"
            scalars(rec, f"joints/{leg}/{m}/angle", sig.t, sig.q[:, i, j])
            scalars(rec, f"joints/{leg}/{m}/speed", sig.t, sig.qd[:, i, j])
            for name, values in (("commanded", sig.command), ("applied", sig.applied),
                                 ("static_contact", sig.static_contact),
                                 ("static_trot", sig.static_trot),
                                 ("static_seed", sig.static_seed)):
                scalars(rec, f"{base}/{name}", sig.t, values[:, i, j], f"{m} {name}")
            scalars(rec, f"{base}/limit_pos", sig.t, np.full(n, limit), "+limit")
            scalars(rec, f"{base}/limit_neg", sig.t, np.full(n, -limit), "-limit")
            if len(cycle_ends):
                scalars(rec, f"cycle_peak/{leg}/{m}", cycle_ends,
                         summary["legs"][leg][m]["per_cycle_peak_Nm"], f"{leg} {m}")
    scalars(rec, "body/height", sig.t, sig.body_p[:, 2], "height (m)")
    scalars(rec, "body/forward_speed", sig.t, sig.body_v[:, 0], "forward speed (m/s)")
    scalars(rec, "body/tilt_deg", sig.t, sig.tilt_deg, "tilt (deg)")
    scalars(rec, "stats/window", sig.t, ((sig.t > start) & (sig.t <= end)).astype(float),
             "statistics window")


def read_series(path: Path, entity: str) -> tuple[np.ndarray, np.ndarray]:
    """Time (s) and values of a scalar entity of a recording, read back from the file."""
    from rerun.chunk import RrdReader

    chunks = RrdReader(str(path)).stream().filter(content=entity, is_static=False).to_chunks()
    if not chunks:
        raise ValueError(f"{path} has no entity {entity!r}")
    t, v = [], []
    for chunk in chunks:
        batch = chunk.to_record_batch()
        t.append(batch.column(TIMELINE).cast("int64").to_numpy() * 1e-9)
        v.append(np.array([row[0] for row in batch.column("Scalars:scalars").to_pylist()]))
    t, v = np.concatenate(t), np.concatenate(v)
    order = np.argsort(t, kind="stable")
    return t[order], v[order]
