"""The stand-up's floor: the least peak motor torque with which any controller raises the robot
from lying on its belly (core.footpath.StandUp: the feet folded at fold_x_m, fold_y_m from the
hips) to standing at the home point (gait.x_center_m, gait.y_home_m).

Model (all four legs alike, quasi-static). Lying, the belly carries the body and a foot at the
lying line (the leg plane's y = fold_y_m) or above it carries nothing: the legs can place their
feet anywhere on that line. To lift the body a foot on the line must carry the quarter robot's
weight m_q g; the body then rises as the feet move below the line, each foot fixed on the ground
(the hip moves over it). Each motor holds its leg's links' weight and -J_F^T (0, m_q g) at the
pose (the package's IK, J_F and G, knees out, within [limits]). The floor: the least T for which
the feet, loaded, can go from some point of the lying line to the home point through poses whose
torques all lie within +-T (a bottleneck path over a grid of foot points: bisection on T and the
grid's connected set, scipy.ndimage.label), and the path's point of largest torque. The body's
pitch and the order in which feet load are not modelled (all alike), nor the dynamics: a rise
over rise_s whose feet move d metres accelerates them at most 5.77 d / rise_s^2 (a quintic from
rest to rest), which adds at most that share of g to the load (dynamic_share, reported)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from fivebar_drake.core.footpath import StandUp
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, limit_tests, past_any
from fivebar_drake.optimal.vertical_jump import quarter_mass_kg
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.params import Params

GRID_M = 1e-3             # the grid of foot points: the floor's resolution in position
FLOOR_TOLERANCE_NM = 1e-3  # the bisection stops within this of the least torque
QUINTIC_PEAK = 10.0 / math.sqrt(3.0)   # a rest-to-rest quintic's peak acceleration, x d / T^2


@dataclass(frozen=True)
class StandUpFloor:
    """The stand-up's floor (N*m, the least peak motor torque), where the feet take the load on
    the lying line (lift_x_m, leg plane, m), the straight path's own peak (the maneuver's line
    from the fold point to home, N*m; None where it leaves the reach) and the dynamics' bound
    on the load's share above the weight (the path's rise_s)."""

    floor_Nm: float
    lift_x_m: float
    straight_Nm: float | None
    dynamic_share: float


def static_torques(params: Params, feet: np.ndarray, payload_kg: float = 0.0) -> np.ndarray:
    """The motors' torques (..., 2) N*m holding foot points feet (..., 2) m (leg plane) at rest
    under a quarter of the robot (its weight on the foot) and the links' weight; nan out of
    reach or past a limit."""
    leg, g = params.fivebar_leg, params.robot.gravity_m_s2
    pose = leg.inverse(feet, KNEES_OUT, strict=False)
    model = full_model(params)
    weight = leg.static_torques(type(model)(**{**model.__dict__, "foot_load_N": 0.0}), pose)
    jt = np.swapaxes(leg.tool_jacobian(pose), -1, -2)
    load = np.broadcast_to([0.0, quarter_mass_kg(params, payload_kg) * g], feet.shape)
    tau = weight - np.einsum("...ij,...j->...i", jt, load)
    bad = ~np.isfinite(tau).all(-1) | past_any(limit_tests(params.leg, pose), feet.shape[:-1])
    return np.where(bad[..., None], np.nan, tau)


def stand_up_floor(params: Params, path: StandUp | None = None,
                   payload_kg: float = 0.0) -> StandUpFloor:
    """The floor of standing up (module docstring) from path's lying line to the home point.
    ParameterError if the home point is out of reach or no loaded path reaches it."""
    path = path or StandUp()
    g = params.gait
    home = np.array([g.x_center_m, g.y_home_m])
    span = params.leg.ce_m + params.leg.ac_m + params.leg.ef_m
    xs = np.arange(-span, span + GRID_M / 2, GRID_M)
    ys = np.arange(path.fold_y_m, -span - GRID_M / 2, -GRID_M)      # row 0: the lying line
    feet = np.stack(np.meshgrid(xs, ys, indexing="xy"), -1)          # (rows, cols, 2)
    cost = np.abs(static_torques(params, feet, payload_kg)).max(-1)
    cost = np.where(np.isfinite(cost), cost, np.inf)
    row, col = int(round((path.fold_y_m - home[1]) / GRID_M)), int(np.argmin(abs(xs - home[0])))
    if not (0 <= row < ys.size and math.isfinite(cost[row, col])):
        raise ParameterError(f"the home point ({home[0]:g}, {home[1]:g}) m is not below the "
                             f"lying line y = {path.fold_y_m:g} m within the leg's reach",
                             "fold_y_m")

    def lifts(limit: float) -> np.ndarray | None:
        """The lying line's points joined to home by feet within limit (None: none)."""
        labels, _ = ndimage.label(cost <= limit)
        mine = labels[row, col]
        top = labels[0] == mine
        return top if mine and top.any() else None

    low, high = float(cost[row, col]), float(np.max(cost[np.isfinite(cost)]))
    if lifts(high) is None:
        raise ParameterError("no loaded path from the lying line reaches the home point within "
                             "the leg's reach and limits", "fold_y_m")
    while high - low > FLOOR_TOLERANCE_NM:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if lifts(mid) is not None else (mid, high)
    top = lifts(high)
    lift = int(np.argmin(np.where(top, cost[0], np.inf)))
    line = np.linspace([path.fold_x_m, path.fold_y_m], home, 400)
    straight = float(np.abs(static_torques(params, line, payload_kg)).max())
    distance = float(np.hypot(*(home - [path.fold_x_m, path.fold_y_m])))
    return StandUpFloor(high, float(xs[lift]), straight if math.isfinite(straight) else None,
                        QUINTIC_PEAK * distance / path.rise_s**2 / params.robot.gravity_m_s2)
