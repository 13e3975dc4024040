"""The 5-bar's loop in a tree model: tree coordinates of a pose and the gap where the loop is cut at
E."""

from __future__ import annotations

import numpy as np

from fivebar_drake.core.rotation import wrap
from fivebar_drake.mechanisms.fivebar.geometry import LegGeometry
from fivebar_drake.mechanisms.fivebar.kinematics import LegPose


JOINTS = ("A", "B", "C", "D")


def tree_positions(pose: LegPose) -> np.ndarray:
    """[theta_A, theta_B, phi_C, phi_D] (..., 4) in rad for leg poses."""
    ce, de = pose.e - pose.c, pose.e - pose.d
    phi_c = np.arctan2(ce[..., 1], ce[..., 0]) - pose.q[..., 0]
    phi_d = np.arctan2(de[..., 1], de[..., 0]) - pose.q[..., 1]
    phi = [np.asarray(wrap(phi))[..., None] for phi in (phi_c, phi_d)]
    return np.concatenate([pose.q, *phi], axis=-1)


def loop_gaps(g: LegGeometry, x) -> np.ndarray:
    """Loop gap (m) |E on CE - E on DE| for tree coordinates x (..., 4) of one leg."""
    ta, tb, pc, pd = np.moveaxis(np.asarray(x), -1, 0)
    u = lambda a: np.stack([np.cos(a), np.sin(a)], -1)  # noqa: E731
    e_ce = g.a + g.ac_m * u(ta) + g.ce_m * u(ta + pc)
    e_de = g.b + g.bd_m * u(tb) + g.de_m * u(tb + pd)
    return np.linalg.norm(e_ce - e_de, axis=-1)
