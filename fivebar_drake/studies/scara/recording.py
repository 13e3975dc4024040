"""Rerun recording (.rrd) of a SCARA run, logged in columns with its blueprint inside.

Entities (timeline "sim_time"): world/arm (column, link 1, link 2, screw as line strips) and
world/tool (the tool point) at simulation.pose_rate_hz; world/path (the seed's trajectory) and
world/trace (the tool's simulated path), static; per sample: tracking/error_mm,
joints/q<i>/{actual, desired}, torque/q<i>/{commanded, applied, limit_pos, limit_neg}."""

from __future__ import annotations

from pathlib import Path
import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.mechanisms.scara import Scara, ScaraParams
from fivebar_drake.core.rerun_files import TIMELINE, pose_frames, recording_file, scalars
from fivebar_drake.studies.scara.simulation import Run

RECORDING_FILE = "run.rrd"
JOINTS = ("q1", "q2", "q3")


def arm_points(params: ScaraParams, q) -> np.ndarray:
    """Points (n, 6, 3) of the arm drawn as one strip: floor, joint 1 top, elbow at link-1
    height, elbow at link-2 height, wrist, tool point (m)."""
    k = params.kinematics
    scara = Scara(k)
    q = np.asarray(q, dtype=float)
    tool = scara.forward(q).f
    elbow = np.stack([k.a1_m * np.cos(q[:, 0]), k.a1_m * np.sin(q[:, 0])], axis=1)
    n = len(q)
    z1, z2 = np.full((n, 1), k.d1_m), np.full((n, 1), scara.z0)
    return np.stack([np.zeros((n, 3)), np.hstack([np.zeros((n, 2)), z1]),
                     np.hstack([elbow, z1]), np.hstack([elbow, z2]),
                     np.hstack([tool[:, :2], z2]), tool], axis=1)


def blueprint() -> rrb.Blueprint:
    return rrb.Blueprint(rrb.Horizontal(
        rrb.Spatial3DView(origin="world", name="arm"),
        rrb.Vertical(rrb.TimeSeriesView(origin="tracking", name="tool error (mm)"),
                     rrb.Tabs(*[rrb.TimeSeriesView(origin=f"torque/{j}", name=f"{j} force")
                                for j in JOINTS], name="joint forces"),
                     rrb.TimeSeriesView(origin="joints", name="joints (rad, m)")),
        column_shares=[3, 2]), collapse_panels=True)


def write_recording(path: Path, params: ScaraParams, r: Run, error_m: np.ndarray) -> Path:
    """Write the run's .rrd atomically (complete with its footer, then renamed into place)."""
    with recording_file(path, "fivebar_drake-scara", blueprint()) as rec:
        _log(rec, params, r, error_m)
    return path


def _log(rec, params: ScaraParams, r: Run, error_m) -> None:
    frames = pose_frames(r.t, params.simulation.pose_rate_hz)
    time = [rr.TimeColumn(TIMELINE, duration=r.t[frames])]
    points = arm_points(params, r.q[frames])
    rec.send_columns("world/arm", indexes=time, columns=rr.LineStrips3D.columns(
        strips=list(points)).partition(np.ones(len(frames), dtype=int)))
    rec.log("world/arm", rr.LineStrips3D.from_fields(radii=0.012, colors=[[70, 110, 200]]),
            static=True)
    rec.send_columns("world/tool", indexes=time, columns=rr.Points3D.columns(
        positions=points[:, -1]).partition(np.ones(len(frames), dtype=int)))
    rec.log("world/tool", rr.Points3D.from_fields(radii=0.015, colors=[[230, 80, 60]]),
            static=True)
    rec.log("world/path", rr.LineStrips3D([r.desired.p], radii=0.002, colors=[[60, 180, 80]]),
            static=True)
    rec.log("world/trace", rr.LineStrips3D([Scara(params.kinematics).forward(r.q).f],
                                           radii=0.0015, colors=[[230, 80, 60]]), static=True)
    scalars(rec, "tracking/error_mm", r.t, error_m * 1e3, "tool error (mm)")
    for j, name in enumerate(JOINTS):
        scalars(rec, f"joints/{name}/actual", r.t, r.q[:, j], f"{name} actual")
        scalars(rec, f"joints/{name}/desired", r.desired.t, r.desired.q[:, j],
                 f"{name} desired")
        base = f"torque/{name}"
        scalars(rec, f"{base}/commanded", r.t, r.record[:, j, 0], f"{name} commanded")
        scalars(rec, f"{base}/applied", r.t, r.record[:, j, 2], f"{name} applied")
        limit = r.motors[j].peak_torque_Nm
        scalars(rec, f"{base}/limit_pos", r.t, np.full(len(r.t), limit), "+limit")
        scalars(rec, f"{base}/limit_neg", r.t, np.full(len(r.t), -limit), "-limit")
