"""A foot path (core/footpath.py: the seed's ellipse or the trot path) sampled over one cycle, the IK
mode tracking along it (seed 000 appendix B) and periodic central differences (seed 000
section 5)."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.footpath import Gait, cycle_times, evaluate
from fivebar_drake.core.rotation import wrap
from fivebar_drake.mechanisms.fivebar.geometry import LegGeometry
from fivebar_drake.mechanisms.fivebar.kinematics import ALL_MODES, KNEES_OUT, LegPose, inverse


def track_modes(leg: LegGeometry, foot, start_mode=KNEES_OUT) -> tuple[LegPose, np.ndarray]:
    """IK along a path of foot targets (N, 2): the first sample in start_mode, then at each sample
    the solution nearest the previous one in wrap-aware angular distance
    sum_j min(|dq_j|, 2 pi - |dq_j|). Returns the poses and the chosen mode index (into
    ALL_MODES) per sample."""
    foot = np.asarray(foot, dtype=float)
    order = [start_mode] + [m for m in ALL_MODES if m != start_mode]
    solutions = [inverse(leg, foot, mode, strict=(mode == start_mode)) for mode in order]
    q_all = np.stack([s.q for s in solutions])                     # (modes, N, 2)
    choice = np.zeros(len(foot), dtype=int)
    for k in range(1, len(foot)):
        dist = np.abs(wrap(q_all[:, k] - q_all[choice[k - 1], k - 1])).sum(-1)
        choice[k] = int(np.nanargmin(dist))
    rows = np.arange(len(foot))
    picked = {name: np.stack([getattr(s, name) for s in solutions])[choice, rows]
              for name in ("q", "c", "d", "e")}
    pose = LegPose(**picked, f=foot)
    mode_index = np.array([ALL_MODES.index(order[c]) for c in choice])
    return pose, mode_index


def periodic_derivatives(q, dt: float):
    """Central differences over one periodic cycle of samples q (N, ...) spaced dt (s):
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


def sample_gait(leg: LegGeometry, gait: Gait, path: str = "seed_ellipse") -> GaitSamples:
    """Sample one cycle of the foot path at t_k = k T / N, solve IK with mode tracking and
    differentiate."""
    t = cycle_times(gait)
    points = evaluate(gait, path, t)
    pose, mode_index = track_modes(leg, points.pos)
    qd, qdd = periodic_derivatives(pose.q, gait.period_s / gait.samples)
    return GaitSamples(path=path, t=t, foot=points.pos, stance=points.stance, pose=pose, qd=qd,
                       qdd=qdd, mode_index=mode_index)
