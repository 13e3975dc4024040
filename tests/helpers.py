"""Independent reference computations for the tests: geometry straight from the joint points."""

import numpy as np

from fivebar_drake.mechanisms.fivebar import LINK_NAMES, forward


def link_geometry(params, q, e_branch):
    """COM positions (..., 4, 2) and link angles (..., 4) computed from FK's joint points."""
    pose = forward(params.leg, q, e_branch)
    leg = params.leg
    ends = {"AC": (np.broadcast_to(leg.a, pose.c.shape), pose.c),
            "BD": (np.broadcast_to(leg.b, pose.d.shape), pose.d),
            "CE": (pose.c, pose.e), "DE": (pose.d, pose.e)}
    coms, angles = [], []
    for name in LINK_NAMES:
        p, r = ends[name]
        u = r - p
        unit = u / np.linalg.norm(u, axis=-1, keepdims=True)
        coms.append(p + params.links[name].com_m * unit)
        angles.append(np.arctan2(u[..., 1], u[..., 0]))
    return np.stack(coms, -2), np.unwrap(np.stack(angles, -1), axis=0)


def central_difference(fun, q, h=1e-6):
    """d fun / d q_j by central differences; returns (..., *fun_shape, 2)."""
    cols = []
    for j in range(2):
        dq = np.zeros(2)
        dq[j] = h
        cols.append((fun(q + dq) - fun(q - dq)) / (2 * h))
    return np.stack(cols, -1)


def random_poses(params, rng, n=200):
    """Motor angles scattered around the gait's knees-out poses (all reachable)."""
    from fivebar_drake.mechanisms.fivebar import sample_gait

    base = sample_gait(params.leg, params.gait).pose.q
    q = base[rng.integers(0, len(base), n)] + rng.uniform(-0.15, 0.15, (n, 2))
    return q


def told(summary) -> str:
    """What a run's summary says of its answer: its one line and its reasons, joined."""
    return " ".join([summary["answer"], *summary["answer_details"]])


def signal_mask(pid: int, field: str) -> int:
    """A process's signal set from /proc/PID/status (field: "SigBlk", "SigIgn", "SigCgt"; bit
    n - 1 for signal n), 0 where the process is gone."""
    from pathlib import Path

    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return 0
    return next((int(line.split()[1], 16) for line in status.splitlines()
                 if line.startswith(f"{field}:")), 0)
