"""Angle and rotation helpers (compiled: the controller calls them at every tick)."""

from __future__ import annotations

import numpy as np

from fivebar_drake.core.compiled import jit


@jit
def wrap(angle):
    """Angle(s) (rad, a number or an array) wrapped to [-pi, pi)."""
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def angle_between(u, v) -> np.ndarray:
    """Unsigned angle (rad, 0 .. pi) between planar vectors u and v (..., 2)."""
    u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
    cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    return np.abs(np.arctan2(cross, np.sum(u * v, axis=-1)))


@jit
def body_rotation(quaternion_wxyz):
    """Rotation matrix (3, 3) of a floating body's quaternion [w, x, y, z] as stored in the
    plant state (normalised first: the state drifts from unit length)."""
    w, x, y, z = quaternion_wxyz / np.sqrt(np.sum(quaternion_wxyz**2))
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@jit
def body_rotations(quaternions_wxyz):
    """body_rotation of each row of quaternions_wxyz (n, 4): (n, 3, 3)."""
    out = np.empty((quaternions_wxyz.shape[0], 3, 3))
    for i in range(quaternions_wxyz.shape[0]):
        out[i] = body_rotation(quaternions_wxyz[i])
    return out


def tilt_deg(quat_wxyz) -> np.ndarray:
    """Angle (deg) between a floating body's z axis and the vertical, for quaternions
    [w, x, y, z] (..., 4) as stored in the plant state (not necessarily unit length)."""
    q = np.asarray(quat_wxyz, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return np.degrees(np.arccos(np.clip(1 - 2 * (q[..., 1] ** 2 + q[..., 2] ** 2), -1, 1)))
