"""A foot path (gaits/: the seed's ellipse or the trot path) sampled over one cycle, the IK
mode tracking along it (seed 000 appendix B) and periodic central differences (seed 000
section 5)."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.gaits import (FootPath, Gait, PathPoints, cycle_times, evaluate,
                                         foot_path)
from fivebar_drake.core.rotation import wrap
from fivebar_drake.mechanisms.fivebar.geometry import LegGeometry
from fivebar_drake.mechanisms.fivebar.kinematics import (ALL_MODES, KNEES_OUT, LegPose,
                                                         UnreachableError, inverse)


def track_modes(leg: LegGeometry, foot, start_mode=KNEES_OUT) -> tuple[LegPose, np.ndarray]:
    """IK along paths of foot targets (N, ..., 2), time first (the trailing axes are separate
    paths of N samples each): the first sample in start_mode, then at each sample the solution
    nearest the previous one in wrap-aware angular distance sum_j min(|dq_j|, 2 pi - |dq_j|).
    Returns the poses (N, ...) and the chosen mode index (into ALL_MODES) per sample (N, ...).
    UnreachableError where start_mode cannot reach a target."""
    foot = np.asarray(foot, dtype=float)
    order = [start_mode] + [m for m in ALL_MODES if m != start_mode]
    solutions = [inverse(leg, foot, mode, strict=(mode == start_mode)) for mode in order]
    q_all = np.stack([s.q for s in solutions])                 # (modes, N, ..., 2)
    flat = q_all.reshape(len(order), len(foot), -1, 2)         # (modes, N, paths, 2)
    paths = np.arange(flat.shape[2])
    choice = np.zeros(flat.shape[1:3], dtype=int)
    for k in range(1, len(foot)):
        dist = np.abs(wrap(flat[:, k] - flat[choice[k - 1], k - 1, paths])).sum(-1)
        choice[k] = np.nanargmin(dist, axis=0)
    choice = choice.reshape(foot.shape[:-1])
    picked = {}
    for name in ("q", "c", "d", "e"):
        value = getattr(solutions[0], name).copy()
        for m in range(1, len(order)):
            where = choice == m
            value[where] = getattr(solutions[m], name)[where]
        picked[name] = value
    pose = LegPose(**picked, f=foot)
    mode_index = np.array([ALL_MODES.index(m) for m in order])[choice]
    return pose, mode_index


def periodic_derivatives(q, dt):
    """Central differences over periodic cycles of samples q (N, ...), time first, spaced dt
    (s; a number, or an array broadcasting against q[0]):
    q_dot = (q[i+1] - q[i-1]) / (2 dt), q_ddot = (q[i+1] - 2 q[i] + q[i-1]) / dt^2, with angle
    differences wrapped so a turn through +-pi is not a jump."""
    fwd = wrap(np.roll(q, -1, axis=0) - q)
    bwd = wrap(q - np.roll(q, 1, axis=0))
    return (fwd + bwd) / (2.0 * dt), (fwd - bwd) / dt**2


@dataclass(frozen=True)
class GaitSamples:
    """One gait cycle of a foot path: times t (N,) s, foot targets (N, 2) m, scheduled stance
    (N,), poses, motor rates qd (N, 2) rad/s and accelerations qdd (N, 2) rad/s^2 by central
    differences, IK mode index per sample."""

    path: str
    t: np.ndarray
    foot: np.ndarray
    stance: np.ndarray
    pose: LegPose
    qd: np.ndarray
    qdd: np.ndarray
    mode_index: np.ndarray


def path_poses(leg: LegGeometry, gait: Gait, path: FootPath | str,
               t) -> tuple[PathPoints, LegPose, np.ndarray]:
    """The foot path (a FootPath or its kind) at times t (n,) s, its poses with mode tracking
    from knees out (track_modes) and the mode index per sample. UnreachableError located at the
    first sample out of reach or past a limit (its index, time and foot target; the limit)."""
    points = evaluate(gait, path, t)
    try:
        pose, mode_index = track_modes(leg, points.pos)
    except UnreachableError as err:
        raise err.at_sample(f"{foot_path(path).kind} path", t) from None
    return points, pose, mode_index


def sample_gait(leg: LegGeometry, gait: Gait, path: str = "seed_ellipse") -> GaitSamples:
    """Sample one cycle of the foot path at t_k = k T / N, solve IK with mode tracking
    (path_poses) and differentiate."""
    t = cycle_times(gait)
    points, pose, mode_index = path_poses(leg, gait, path, t)
    qd, qdd = periodic_derivatives(pose.q, gait.period_s / gait.samples)
    return GaitSamples(path=path, t=t, foot=points.pos, stance=points.stance, pose=pose, qd=qd,
                       qdd=qdd, mode_index=mode_index)
