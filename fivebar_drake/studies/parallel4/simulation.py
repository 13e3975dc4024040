"""The platform moved along the configured path by the four actuators of the Drake model (the
plant's implicit PD on each actuator towards the path's inverse kinematics, plus the closed-form
static forces as feedforward), sampled at record_hz, and its headline figures."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydrake.systems.analysis import Simulator
from pydrake.systems.primitives import TrajectorySource
from pydrake.trajectories import PiecewisePolynomial

from fivebar_drake.core.interrupts import advance
from fivebar_drake.studies.base import duration_limits as base_limits
from fivebar_drake.mechanisms.parallel4.kinematics import forward, inverse, velocity_jacobian
from fivebar_drake.mechanisms.parallel4.params import Params
from fivebar_drake.studies.parallel4.model import Parallel4Plant, closed_form_static_forces

FEEDFORWARD_HZ = 500.0     # samples of the desired state and feedforward trajectories


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
    interrupted: str = ""       # the signal that stopped the run early ("" if it did not)


def duration_limits(params: Params) -> dict:
    """A run's duration: the file's by default."""
    return base_limits(params.simulation.duration_s, params.simulation.time_step_s)


def _velocities(params: Params, t) -> np.ndarray:
    """Path velocity (..., 4) by central differences of the path (m/s, rad/s; h = 1e-6 s)."""
    h = 1e-6
    return (params.simulation.poses(t + h) - params.simulation.poses(t - h)) / (2 * h)


def simulate(params: Params, duration_s: float | None = None, stop=None) -> Run:
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
    rows, interrupted = [], ""
    for t in np.arange(0.0, duration + 1e-9, 1 / sim.record_hz):
        interrupted = advance(simulator, t, stop)
        if interrupted:
            break
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
               static_drake, gap, forward(g, qs, strict=False), interrupted)


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
