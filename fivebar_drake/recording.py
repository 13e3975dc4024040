"""Rerun recording (.rrd) of a simulated run, logged in columns, with its blueprint inside.

Entities (timeline "sim_time"):
- world/ground, world/body (box + pose), world/legs/<leg> (link segments), world/feet/<leg>
  (foot trace), at pose_rate_hz;
- joints/<leg>/<A|B>/angle, joints/<leg>/<A|B>/speed (every plant step, at most 1 kHz);
- torque/<leg>/<A|B>/{commanded, applied, static_contact, static_seed, limit_pos, limit_neg}
  (every log sample);
- loop_gap/<leg> (worst gap of each 1 ms bin of plant steps), contact/<leg>/{normal,
  tangential} (leg plane, N), body/height, body/forward_speed (at most 1 kHz).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from .params import Params
from .scenario import Scenario
from .simulation import Setup
from .summary import MOTORS, Signals

TIMELINE = "sim_time"
RECORDING_ID = "fivebar_drake-simulation"
STEP_SERIES_RATE_HZ = 1000.0   # per-step series (gap, joints, body) are binned to 1 kHz


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
                         rrb.TimeSeriesView(origin="joints", name="joints (rad, rad/s)"))),
            column_shares=[1, 1]),
        collapse_panels=True)


def _scalars(rec, path: str, t, values, name: str | None = None) -> None:
    rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=t)],
                     columns=rr.Scalars.columns(scalars=np.asarray(values, dtype=float)))
    if name:
        rec.log(path, rr.SeriesLines(names=name), static=True)


def _link_points(setup: Setup, params: Params, state_rows: np.ndarray):
    """World positions (frames, legs, 6, 3) of A, C, E, F and B, D per leg, from the plant."""
    plant = setup.plant
    context = plant.CreateDefaultContext()
    nq = plant.num_positions()
    g = params.leg
    ends = {"AC": g.ac_m, "BD": g.bd_m, "CE": g.ce_m, "DE": g.de_m + g.ef_m}
    bodies = [{n: plant.GetBodyByName(f"{leg}_{n}", setup.instance) for n in ends}
              for leg in setup.legs]
    out = np.zeros((len(state_rows), len(setup.legs), 6, 3))
    for f, row in enumerate(state_rows):
        plant.SetPositions(context, row[:nq])
        for i in range(len(setup.legs)):
            pose = {n: plant.EvalBodyPoseInWorld(context, body) for n, body in bodies[i].items()}
            tip = {n: pose[n].multiply(np.array([ends[n], 0.0, 0.0])) for n in ends}
            e = pose["DE"].multiply(np.array([g.de_m, 0.0, 0.0]))
            out[f, i] = [pose["AC"].translation(), tip["AC"], e, tip["DE"],
                         pose["BD"].translation(), tip["BD"]]
    return out


def write_recording(path: Path, sig: Signals, setup: Setup, params: Params,
                    scenario: Scenario, state: np.ndarray) -> Path:
    """Write the .rrd file; state: the per-step plant state (for the 3-D poses)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    rec = rr.RecordingStream("fivebar_drake", recording_id=RECORDING_ID)
    rec.set_log_time_enabled(False)
    rec.set_log_tick_enabled(False)
    rec.save(str(path), default_blueprint=blueprint(setup.legs))
    with rec:
        _log_scene(rec, sig, setup, params, scenario, state)
        _log_series(rec, sig, setup, params)
    return path


def _log_scene(rec, sig, setup, params, scenario, state):
    b = params.body
    rec.log("world/ground", rr.Boxes3D(centers=[[0.0, 0.0, -0.005]], half_sizes=[[3.0, 3.0, 0.005]],
                                       colors=[[90, 110, 90]]), static=True)
    rec.log("world/body", rr.Boxes3D(half_sizes=[[b.length_m / 2, b.width_m / 2, b.height_m / 2]],
                                     colors=[[150, 150, 165]]), static=True)
    t = sig.t_state
    frames = np.unique(np.searchsorted(t, np.arange(0.0, t[-1] + 1e-9, 1.0 / scenario.pose_rate_hz)))
    frames = frames[frames < len(t)]
    tf = t[frames]
    time = [rr.TimeColumn(TIMELINE, duration=tf)]
    quat = sig.body_quat[frames]
    rec.send_columns("world/body", indexes=time, columns=rr.Transform3D.columns(
        translation=sig.body_p[frames], quaternion=np.column_stack([quat[:, 1:], quat[:, :1]])))
    points = _link_points(setup, params, state[frames])
    for i, leg in enumerate(setup.legs):
        strips = [s for f in range(len(frames)) for s in (points[f, i, :4], points[f, i, 4:])]
        rec.send_columns(f"world/legs/{leg}", indexes=time, columns=rr.LineStrips3D.columns(
            strips=strips).partition([2] * len(frames)))
        rec.log(f"world/legs/{leg}", rr.LineStrips3D.from_fields(radii=0.004), static=True)
        rec.log(f"world/feet/{leg}", rr.LineStrips3D([points[:, i, 3]], radii=0.0015,
                                                     colors=[[230, 80, 60]]), static=True)


def step_bins(t, rate_hz: float) -> np.ndarray:
    """Start indices of bins of the per-step times t, at most rate_hz bins per second (every
    step when the plant step is longer)."""
    edges = np.searchsorted(t, np.arange(t[0], t[-1] + 1.0 / rate_hz, 1.0 / rate_hz))
    return np.unique(edges[edges < len(t)])


def _log_series(rec, sig, setup, params):
    limit = params.motor.peak_torque_Nm
    n_log = len(sig.t_log)
    bins = step_bins(sig.t_state, STEP_SERIES_RATE_HZ)
    t_bins = sig.t_state[bins]
    for i, leg in enumerate(setup.legs):
        # the worst gap of every bin, so no peak between samples is lost
        _scalars(rec, f"loop_gap/{leg}", t_bins, np.maximum.reduceat(sig.gap[i], bins), leg)
        _scalars(rec, f"contact/{leg}/tangential", sig.t_log, sig.foot_force_plane[:, i, 0])
        _scalars(rec, f"contact/{leg}/normal", sig.t_log, sig.foot_force_plane[:, i, 1])
        for j, m in enumerate(MOTORS):
            base = f"torque/{leg}/{m}"
            _scalars(rec, f"joints/{leg}/{m}/angle", t_bins, sig.q[bins, i, j])
            _scalars(rec, f"joints/{leg}/{m}/speed", t_bins, sig.qd[bins, i, j])
            for name, values in (("commanded", sig.command), ("applied", sig.applied),
                                 ("static_contact", sig.static_contact),
                                 ("static_seed", sig.static_seed)):
                _scalars(rec, f"{base}/{name}", sig.t_log, values[:, i, j], f"{m} {name}")
            _scalars(rec, f"{base}/limit_pos", sig.t_log, np.full(n_log, limit), "+limit")
            _scalars(rec, f"{base}/limit_neg", sig.t_log, np.full(n_log, -limit), "-limit")
    _scalars(rec, "body/height", t_bins, sig.body_p[bins, 2], "height (m)")
    _scalars(rec, "body/forward_speed", t_bins, sig.body_v[bins, 0], "forward speed (m/s)")


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
