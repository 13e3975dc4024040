"""The platform moved along the configured path by the four actuators of the Drake model (the
plant's implicit PD on each actuator towards the path's inverse kinematics, plus the closed-form
static forces as feedforward), its results, and the Rerun recording (3-D at record_hz)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb
from pydrake.systems.analysis import Simulator
from pydrake.systems.primitives import TrajectorySource
from pydrake.trajectories import PiecewisePolynomial

from fivebar_drake.mechanisms.parallel4.kinematics import (PAIR, forward, inverse,
                                                           platform_offsets, velocity_jacobian)
from fivebar_drake.mechanisms.parallel4.params import Params
from fivebar_drake.core.rerun_files import TIMELINE, recording_file, scalars
from fivebar_drake.studies.parallel4.model import (Parallel4Plant, base_points,
                                                   closed_form_static_forces)

FEEDFORWARD_HZ = 500.0     # samples of the desired state and feedforward trajectories
RAIL_HALF_LENGTH_M = 0.8


@dataclass
class Run:
    """Sampled results at record_hz: t (n,) s, pose (n, 4) of the platform (guide joints),
    desired pose (n, 4), actuator positions q (n, 4) m, forces (n, 4) N applied by the plant's
    actuators, the closed-form static forces at the reached poses (n, 4) N, Drake's projected
    static forces there (n, 4) N, loop gaps (n, 4) m, and FK of q (n, 4)."""

    t: np.ndarray
    pose: np.ndarray
    desired: np.ndarray
    q: np.ndarray
    force: np.ndarray
    static_closed: np.ndarray
    static_drake: np.ndarray
    gap: np.ndarray
    fk: np.ndarray


def _velocities(params: Params, t) -> np.ndarray:
    """Path velocity (..., 4) by central differences of the path (m/s, rad/s; h = 1e-6 s)."""
    h = 1e-6
    return (params.simulation.poses(t + h) - params.simulation.poses(t - h)) / (2 * h)


def simulate(params: Params, duration_s: float | None = None) -> Run:
    """Run the model along the path for duration_s (default: the file's) and sample it."""
    g, m, sim = params.geometry, params.model, params.simulation
    duration = sim.duration_s if duration_s is None else duration_s
    model = Parallel4Plant(g, m, sim.time_step_s, pd_gains=(sim.kp_N_m, sim.kd_N_s_m))
    plant, builder = model.plant, model.builder
    order = model.actuator_order()
    ts = np.arange(0.0, duration + 2 / FEEDFORWARD_HZ, 1 / FEEDFORWARD_HZ)
    poses = sim.poses(ts)
    q = inverse(g, poses)
    qd = np.einsum("nij,nj->ni", velocity_jacobian(g, poses, q), _velocities(params, ts))
    desired = np.hstack([q[:, order], qd[:, order]])
    feedforward = closed_form_static_forces(g, m, poses)[:, order]
    for port, values in ((plant.get_desired_state_input_port(model.instance), desired),
                         (plant.get_actuation_input_port(), feedforward)):
        source = builder.AddSystem(TrajectorySource(
            PiecewisePolynomial.FirstOrderHold(ts, values.T)))
        builder.Connect(source.get_output_port(), port)
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    start = poses[0]
    plant.SetPositions(plant_context, model.positions(start))
    h = 1e-6
    plant.SetVelocities(plant_context, (model.positions(sim.poses(h)) -
                                        model.positions(sim.poses(-h))) / (2 * h))
    simulator.Initialize()
    guide = [j.position_start() for j in model.guide]
    sliders = [j.position_start() for j in model.sliders]
    static_context = plant.CreateDefaultContext()
    rows = []
    for t in np.arange(0.0, duration + 1e-9, 1 / sim.record_hz):
        simulator.AdvanceTo(t)
        x = plant.GetPositions(plant_context)
        force = plant.get_net_actuation_output_port().Eval(plant_context)
        plant.SetPositions(static_context, x)
        forces = np.empty(4)
        forces[order] = force
        drake_static = np.empty(4)
        drake_static[order] = model.projected_static_forces(static_context)
        rows.append((t, x[guide], x[sliders], forces, drake_static,
                     model.loop_gaps(static_context)))
    t, pose, qs, force, static_drake, gap = (np.array(c) for c in zip(*rows))
    return Run(t, pose, sim.poses(t), qs, force, closed_form_static_forces(g, m, pose),
               static_drake, gap, forward(g, qs, strict=False))


def run_summary(run: Run) -> dict:
    """The run's headline figures (SI)."""
    static_err = np.abs(run.static_drake - run.static_closed) / np.max(np.abs(run.static_closed))
    return {
        "duration_s": float(run.t[-1]),
        "samples": int(len(run.t)),
        "tracking_error_max_m": float(np.max(np.linalg.norm(run.pose[:, :3] - run.desired[:, :3],
                                                            axis=1))),
        "tracking_error_max_deg": float(np.degrees(np.max(np.abs(run.pose[:, 3]
                                                                 - run.desired[:, 3])))),
        "loop_gap_max_m": float(run.gap.max()),
        "fk_vs_plant_max_m": float(np.nanmax(np.abs(run.fk[:, :3] - run.pose[:, :3]))),
        "actuator_force_peak_N": [float(v) for v in np.max(np.abs(run.force), axis=0)],
        "static_drake_vs_closed_form_max_relative": float(static_err.max()),
    }


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
