"""Statics, stiffness and workspace of the 4-DOF parallel manipulator (seed 004, sections 2.3
and 2.4), vectorised over leading axes.

Wrenches on the platform are W = (f_x, f_y, f_z, M_y) in N and N*m, the moment about the y axis
through P; actuator forces tau (..., 4) in N along +x on the sliders.
"""

from __future__ import annotations

import numpy as np

from fivebar_drake.mechanisms.parallel4.geometry import Geometry
from fivebar_drake.mechanisms.parallel4.kinematics import (SEED_MODE, inverse, reach,
                                                           branch_side, velocity_jacobian)


def holding_forces(g: Geometry, pose, load, mode=SEED_MODE, q=None) -> np.ndarray:
    """Actuator forces tau (..., 4), N, holding the platform at rest against the external
    wrench `load` (..., 4) applied to it: virtual work J^T tau + load = 0 (the seed's
    F = J^T tau, eq. 2.26, with F = -load the wrench the platform exerts). q: the actuator
    positions (m) of the poses (None: their IK in mode)."""
    J = velocity_jacobian(g, pose, inverse(g, pose, mode) if q is None else q)
    load = np.asarray(load, dtype=float)[..., None]
    return -np.linalg.solve(np.swapaxes(J, -1, -2), load)[..., 0]


def stiffness(g: Geometry, pose, k, mode=SEED_MODE, scale=(1.0, 1.0, 1.0, 1.0)) -> np.ndarray:
    """K = J^T diag(k) J (eq. 2.27), (..., 4, 4), for actuator stiffnesses k (4,) N/m, with the
    platform coordinates in units `scale` times SI (e.g. 1e3 for mm, pi/180 for degrees):
    N/m, N/rad and N*m/rad for scale 1."""
    J = velocity_jacobian(g, pose, inverse(g, pose, mode)) / np.asarray(scale, dtype=float)
    return np.swapaxes(J, -1, -2) @ (np.asarray(k, dtype=float)[:, None] * J)


def condition_number(M) -> np.ndarray:
    """sqrt(lambda_max / lambda_min) of symmetric matrices (..., n, n) (eq. 2.28); inf where
    lambda_min <= 0 (singular)."""
    w = np.linalg.eigvalsh(M)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(w[..., 0] > 0, np.sqrt(w[..., -1] / w[..., 0]), np.inf)


def translational_block(K) -> np.ndarray:
    """The 3x3 translational block of K (..., 4, 4): the stiffness with theta held."""
    return np.asarray(K)[..., :3, :3]


def translational_free_rotation(K) -> np.ndarray:
    """The translational stiffness with theta free (..., 3, 3): the Schur complement
    K_tt - K_tr K_rr^-1 K_rt (the inverse of the compliance's translational block)."""
    K = np.asarray(K)
    return K[..., :3, :3] - K[..., :3, 3, None] * K[..., None, 3, :3] / K[..., 3, 3, None, None]


def in_workspace(g: Geometry, pose) -> np.ndarray:
    """Whether poses (..., 4) are in the workspace: each leg pair reaches with a spread
    |l1 - l2| = 2 sqrt(R^2 - y_i^2 - z_i^2) within [d_min, d_max] (seed Fig. 2.8), on the
    seed's forward branch (branch_side < 0) and with |theta| < 90 deg (eq. 2.15)."""
    h = reach(g, pose)
    lo, hi = (g.d_min_over_R * g.R / 2) ** 2, (g.d_max_over_R * g.R / 2) ** 2
    with np.errstate(invalid="ignore"):
        stroke = np.all((h >= lo) & (h <= hi), axis=-1)
    pose = np.asarray(pose, dtype=float)
    return stroke & (branch_side(g, pose) < 0) & (np.abs(pose[..., 3]) < np.pi / 2)


def yz_grid(half_width: float, z_low: float, z_high: float, step: float):
    """(y, z) grids (ny, nz) in m, cell-centred with spacing step, and the cell area (m^2)."""
    y = np.arange(-half_width + step / 2, half_width, step)
    z = np.arange(z_low + step / 2, z_high, step)
    Y, Z = np.meshgrid(y, z, indexing="ij")
    return Y, Z, step * step


def poses_yz(Y, Z, theta: float) -> np.ndarray:
    """Poses (..., 4) at x = 0 (the kinematics does not depend on x) on a yz grid at theta."""
    return np.stack([np.zeros_like(Y), Y, Z, np.full_like(Y, theta)], axis=-1)

