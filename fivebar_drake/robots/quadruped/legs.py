"""The quadruped's legs in one place: their names in the order every leg-indexed list uses
(plant joints, controller, gait phases, tables), where each leg's plane sits on the body and how
leg-plane points map into the body frame.

Body frame: x forward, y left, z up. Each leg's plane frame sits at its hip with x backwards,
y up and z (the hinge axis) to the left.
"""

from __future__ import annotations

import numpy as np

from fivebar_drake.gaits import foot_path

LEGS = ("FL", "FR", "RL", "RR")           # front/rear, left/right


def path_phases(path) -> tuple[float, ...]:
    """Gait phases (rad) of LEGS for a foot path (a FootPath or its kind): the path's own
    (FootPath.leg_phase)."""
    return tuple(foot_path(path).leg_phase(leg) for leg in LEGS)


TROT_PHASES_RAD = path_phases("trot")   # diagonal pairs in phase, the pairs half a cycle apart
PLANE_RPY = (np.pi / 2, 0.0, np.pi)       # roll, pitch, yaw (rad) of a leg plane in the body


def hip_positions(params) -> dict[str, tuple[float, float, float]]:
    """Leg-plane origins (m) in the body frame for Params `params` (its body.hip_*_m), by leg
    in LEGS order: front legs at +hip_x_m, left legs at +hip_y_m, all at hip_z_m."""
    b = params.body
    return {leg: ((b.hip_x_m if leg[0] == "F" else -b.hip_x_m),
                  (b.hip_y_m if leg[1] == "L" else -b.hip_y_m), b.hip_z_m) for leg in LEGS}


def plane_rotation() -> np.ndarray:
    """R_body_plane: columns are the leg plane's x (backwards), y (up), z (left) in the body."""
    return np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])


def plane_to_body(hips_m, points_m) -> np.ndarray:
    """Body-frame positions (m) of leg-plane points (..., 2) m of legs whose plane origins are at
    hips_m (..., 3) m in the body frame (arrays broadcast): hip + R_body_plane [x, y, 0]."""
    return np.asarray(hips_m) + np.asarray(points_m) @ plane_rotation()[:, :2].T


def motor_positions(params) -> np.ndarray:
    """Positions (2 * len(LEGS), 3) in m of the motor axes A and B of every leg (LEGS order) in
    the body frame, for Params `params`."""
    hips = np.array(list(hip_positions(params).values()))[:, None, :]
    return plane_to_body(hips, np.array([params.leg.motor_a_m, params.leg.motor_b_m])).reshape(-1, 3)
