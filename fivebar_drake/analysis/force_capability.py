"""Foot forces two motors can hold statically: the image of the torque box |tau_i| <= peak
through J_F^-T (Minitaur's "force production"), per pose, over the workspace and along a gait.

A foot force F (N, leg plane) is held by the motor torques tau = J_F^T F (virtual work, link
weights aside), so F is available in direction u (unit) up to the largest s with
|c_i . (s u)| <= peak for both columns c_i of J_F (m/rad): s = peak / max_i |c_i . u|. The
force available in every direction is the smallest of these over u, and since
max_u |c_i . u| = ||c_i||, it is peak / max_i ||c_i||: the radius of the largest circle
inside the parallelogram J_F^-T [-peak, peak]^2.
"""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.mechanisms.fivebar import (ALL_MODES, MODE_NAMES, LegGeometry, foot_jacobian,
                                              held_force,
                                              inverse)


CAPABILITY_KEYS = ("max_vertical_N", "max_horizontal_N", "isotropic_N")


def workspace_grid(leg: LegGeometry, nx: int = 241, ny: int = 161):
    """Foot positions x (nx,), y (ny,) in m covering the leg's reach: x within +-R,
    y from -R to 0.4 R, R = AC + CE + EF + the motors' spacing."""
    reach = leg.ac_m + leg.ce_m + leg.ef_m + abs(leg.motor_b_m[0] - leg.motor_a_m[0])
    return np.linspace(-reach, reach, nx), np.linspace(-reach, 0.4 * reach, ny)


def max_force(jf, peak_torque_Nm: float, direction) -> np.ndarray:
    """Largest foot force (N) along the unit vector direction (2,) that torques within
    |tau_i| <= peak_torque_Nm hold, for foot Jacobians jf (..., 2, 2) in m/rad."""
    return held_force(jf, peak_torque_Nm, -peak_torque_Nm, direction)


def force_capability(jf, peak_torque_Nm: float) -> dict[str, np.ndarray]:
    """CAPABILITY_KEYS -> arrays (...) N for foot Jacobians jf (..., 2, 2) m/rad: the largest
    vertical and horizontal foot forces and the largest force available in every direction
    (peak / max_i ||column i of J_F||)."""
    return {"max_vertical_N": max_force(jf, peak_torque_Nm, (0.0, 1.0)),
            "max_horizontal_N": max_force(jf, peak_torque_Nm, (1.0, 0.0)),
            "isotropic_N": peak_torque_Nm / np.max(np.linalg.norm(jf, axis=-2), axis=-1)}


def support_available(jf, peak_torque_Nm: float, spent_Nm) -> np.ndarray:
    """Largest upward ground force on the foot (N, >= 0) the motors can take on top of torques
    spent_Nm (..., 2) already spent (motion and link weights) within |tau_i| <= peak: per unit
    load the torques are g = -J_F^T [0, 1], so motor i allows the loads between
    (-peak - sign(g_i) spent_i) / |g_i| and (peak - sign(g_i) spent_i) / |g_i|; the largest load
    of both intervals and F >= 0, 0 where they have none in common."""
    g = -jf[..., 1, :]
    with np.errstate(divide="ignore"):
        hi = np.min((peak_torque_Nm - np.sign(g) * spent_Nm) / np.abs(g), axis=-1)
        lo = np.max((-peak_torque_Nm - np.sign(g) * spent_Nm) / np.abs(g), axis=-1)
    return np.where(hi >= np.maximum(lo, 0.0), hi, 0.0)


@dataclass(frozen=True)
class CapabilityMap:
    """Force capability of one assembly mode on the grid x (nx,) by y (ny,) m: CAPABILITY_KEYS
    -> (ny, nx) N, NaN where the mode cannot reach."""

    mode: tuple[int, int]
    x: np.ndarray
    y: np.ndarray
    forces: dict[str, np.ndarray]


def capability_map(leg: LegGeometry, peak_torque_Nm: float, x, y, mode) -> CapabilityMap:
    """force_capability over the foot positions of the grid x by y (m) in one assembly mode."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    foot = np.stack(np.meshgrid(x, y), axis=-1)
    pose = inverse(leg, foot, mode, strict=False)
    ok = ~np.isnan(pose.q).any(axis=-1)
    forces = {key: np.full(ok.shape, np.nan) for key in CAPABILITY_KEYS}
    if ok.any():
        reached = inverse(leg, foot[ok], mode)
        for key, value in force_capability(foot_jacobian(leg, reached), peak_torque_Nm).items():
            forces[key][ok] = value
    return CapabilityMap(mode=tuple(mode), x=x, y=y, forces=forces)


def home_capability(leg: LegGeometry, peak_torque_Nm: float, foot) -> dict[str, dict | None]:
    """MODE_NAMES -> {CAPABILITY_KEYS: N} at one foot position (2,) m, None for a mode that
    cannot reach it."""
    out = {}
    for mode, name in zip(ALL_MODES, MODE_NAMES):
        pose = inverse(leg, np.asarray(foot, dtype=float), mode, strict=False)
        out[name] = None if np.isnan(pose.q).any() else {
            key: float(v) for key, v in force_capability(foot_jacobian(leg, pose),
                                                         peak_torque_Nm).items()}
    return out
