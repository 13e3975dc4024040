"""The stand-up's floor: the least peak motor torque with which any controller raises the robot
from lying on its belly (gaits.StandUp: the feet folded at fold_x_m, fold_y_m from the
hips) to standing at the home point (gait.x_center_m, gait.y_home_m).

Model (quasi-static, a level lift, front and rear pairs placed apart). Lying, the belly carries
the body and a foot at the lying line (the leg plane's y = fold_y_m) or above it carries nothing:
the legs can place their feet anywhere on that line. To lift the body level, the feet on the line
must carry the whole robot (M g, its payload too) and balance it about the pitch axis: with the
front feet at x_f and the rear at x_r behind their hips (leg plane, x backwards), the front pair
carries M g (x_c - x_R) / (x_F - x_R) and the rear pair the rest, x_F = hip_x - x_f and
x_R = -hip_x - x_r the feet along the body, x_c the centre of mass (gait_floor.mass_centre): a
pose whose centre of mass lies ahead of the front feet or behind the rear ones tips the robot and
is not a pose of the lift. Left and right feet of a pair alike. The body then rises level (hip
height u above the ground, feet at y = -u) as the feet move; each motor holds its leg's links'
weight and -J_F^T (0, F) of its foot's share F at the pose (the package's IK, J_F and G, knees
out, within [limits]). The floor: the least T for which some path of poses (u, x_f, x_r) from the
lying line to home keeps every motor within +-T (a bottleneck path over a grid of GRID_M: bisection
on T and the grid's connected set, scipy.ndimage.label), and the lift point of that path.

What is neglected and which way it errs: the feet may slide apart or together under load (a
relaxation: the floor can only be lower than with the feet fixed), no horizontal force between
the pairs (friction could move load between the motors of a leg: the floor may be a little
high), the links' centres of mass moving the robot's (taken at the standing pose), the nose or
tail resting on the ground while the other pair lifts (a level lift only), the dynamics: a rise
over rise_s whose feet move d metres accelerates them at most 5.77 d / rise_s^2 (a quintic from
rest to rest), which adds at most that share of g to the load (dynamic_share, reported)."""

from __future__ import annotations

import math
import pickle
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from fivebar_drake.gaits import StandUp
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, limit_tests, past_any
from fivebar_drake.optimal.gait_floor import mass_centre
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.params import Params

GRID_M = 2e-3              # the grid of hip heights and foot points: the floor's resolution
FLOOR_TOLERANCE_NM = 1e-3  # the bisection stops within this of the least torque
QUINTIC_PEAK = 10.0 / math.sqrt(3.0)   # a rest-to-rest quintic's peak acceleration, x d / T^2


@dataclass(frozen=True)
class StandUpFloor:
    """The stand-up's floor (N*m, the least peak motor torque) and its lift point on the lying
    line (lift_front_x_m, lift_rear_x_m: the front and rear feet behind their hips, leg plane,
    m); the maneuver's straight path (all feet alike from the fold point to home, balanced) and
    its peak (N*m; None where it tips the robot or leaves the reach, with why in
    straight_why); the dynamics' bound on the load's share above the weight (the path's
    rise_s)."""

    floor_Nm: float
    lift_front_x_m: float
    lift_rear_x_m: float
    straight_Nm: float | None
    straight_why: str
    dynamic_share: float


def static_torques(params: Params, feet: np.ndarray, foot_load_N) -> np.ndarray:
    """The motors' torques (..., 2) N*m holding foot points feet (..., 2) m (leg plane) at rest
    under a vertical ground force foot_load_N (N, broadcast against feet[..., 0]) and the links'
    weight; nan out of reach or past a limit."""
    leg = params.fivebar_leg
    pose = leg.inverse(feet, KNEES_OUT, strict=False)
    model = full_model(params)
    weight = leg.static_torques(type(model)(**{**model.__dict__, "foot_load_N": 0.0}), pose)
    jt = np.swapaxes(leg.tool_jacobian(pose), -1, -2)
    tau = weight - jt[..., 1] * np.asarray(foot_load_N, dtype=float)[..., None]
    bad = ~np.isfinite(tau).all(-1) | past_any(limit_tests(params.leg, pose), feet.shape[:-1])
    return np.where(bad[..., None], np.nan, tau)


def balanced_loads(params: Params, front_x, rear_x, payload_kg: float = 0.0):
    """The vertical ground force on each front and each rear foot (N; arrays broadcast from
    front_x, rear_x: the feet behind their hips, leg plane, m) holding the robot level at rest
    by moment balance about its pitch axis; nan where the centre of mass is not between the
    front and rear feet (the robot tips)."""
    mass, x_c, _, _ = mass_centre(params, payload_kg)
    weight = mass * params.robot.gravity_m_s2
    hip = params.body.hip_x_m
    front, rear = hip - np.asarray(front_x, float), -hip - np.asarray(rear_x, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = (x_c - rear) / (front - rear)
    share = np.where((front > rear) & (share >= 0.0) & (share <= 1.0), share, np.nan)
    legs_per_pair = params.robot.legs / 2
    return weight * share / legs_per_pair, weight * (1.0 - share) / legs_per_pair


def _pair_peaks(params: Params, u: float, xf, xr, payload_kg: float) -> np.ndarray:
    """The largest motor torque magnitude (N*m) of the balanced pose at hip height u with the
    front feet at xf and the rear at xr (arrays broadcast); nan where it tips or is out of
    reach."""
    front_N, rear_N = balanced_loads(params, xf, xr, payload_kg)
    xf, xr = np.broadcast_arrays(np.asarray(xf, float), np.asarray(xr, float))
    f = static_torques(params, np.stack([xf, np.full_like(xf, -u)], -1), front_N)
    r = static_torques(params, np.stack([xr, np.full_like(xr, -u)], -1), rear_N)
    return np.maximum(np.abs(f).max(-1), np.abs(r).max(-1))


def _cost(params: Params, us: np.ndarray, xs: np.ndarray, payload_kg: float) -> np.ndarray:
    """The peak torque (N*m) of every grid pose (u, x_f, x_r) (len(us), len(xs), len(xs)); inf
    where it tips or a foot is out of reach. The torques are affine in the load, so each leg's
    weight and unit-load torques are tabulated on (u, x) first."""
    feet = np.stack(np.meshgrid(-us, xs, indexing="ij")[::-1], -1)       # (nu, nx, 2)
    weight = static_torques(params, feet, 0.0)
    unit = static_torques(params, feet, 1.0) - weight                    # per N of load
    front_N, rear_N = balanced_loads(params, xs[:, None], xs[None, :], payload_kg)
    cost = np.zeros((us.size, xs.size, xs.size))
    for m in range(2):
        for table, load, axis in ((weight, front_N, 2), (weight, rear_N, 1)):
            w, k = table[..., m], unit[..., m]
            per = np.expand_dims(w, axis) + np.expand_dims(k, axis) * load[None]
            cost = np.maximum(cost, np.abs(per))
    return np.where(np.isfinite(cost), cost, np.inf)


CACHE_SIZE = 32   # stand_up_floor's results kept per process (a summary, its step and contact
#                   checks and its report ask for the same floor)
_FLOORS: dict[bytes, StandUpFloor] = {}   # oldest first


def stand_up_floor(params: Params, path: StandUp | None = None,
                   payload_kg: float = 0.0) -> StandUpFloor:
    """The floor of standing up (module docstring) from path's lying line to the home point,
    cached per process by every input. ParameterError if the home point is out of reach or no
    balanced loaded path reaches it."""
    path = path or StandUp()
    key = pickle.dumps((params, path, float(payload_kg)))
    if key not in _FLOORS:
        if len(_FLOORS) >= CACHE_SIZE:
            _FLOORS.pop(next(iter(_FLOORS)))
        _FLOORS[key] = _floor(params, path, payload_kg)
    return _FLOORS[key]


def _floor(params: Params, path: StandUp, payload_kg: float) -> StandUpFloor:
    """stand_up_floor, computed."""
    g = params.gait
    lying, standing = -path.fold_y_m, -g.y_home_m
    if not standing > lying:
        raise ParameterError(f"the home point's hip height {standing:g} m must be above the "
                             f"lying line's {lying:g} m", "fold_y_m")
    span = params.leg.ce_m + params.leg.ac_m + params.leg.ef_m
    rows = int(math.ceil((standing - lying) / GRID_M))
    us = np.linspace(lying, standing, rows + 1)                          # row 0: the lying line
    side = int(math.ceil(span / GRID_M))
    xs = g.x_center_m + GRID_M * np.arange(-side, side + 1)
    cost = _cost(params, us, xs, payload_kg)
    reached = np.isfinite(cost).any(axis=(0, 2)) | np.isfinite(cost).any(axis=(0, 1))
    keep = np.flatnonzero(reached)
    if keep.size == 0 or not math.isfinite(cost[-1, side, side]):
        raise ParameterError(f"the home point ({g.x_center_m:g}, {g.y_home_m:g}) m is not "
                             "within the leg's reach and limits under the robot's weight",
                             "fold_y_m")
    lo, hi = keep[0], keep[-1] + 1
    cost, xs = cost[:, lo:hi, lo:hi], xs[lo:hi]
    home = (us.size - 1, side - lo, side - lo)

    def lifts(limit: float) -> np.ndarray | None:
        """The lying line's poses joined to home by poses within limit (None: none)."""
        labels, _ = ndimage.label(cost <= limit)
        mine = labels[home]
        top = labels[0] == mine
        return top if mine and top.any() else None

    low, high = float(cost[home]), float(np.max(cost[np.isfinite(cost)]))
    if lifts(high) is None:
        raise ParameterError("no balanced loaded path from the lying line reaches the home "
                             "point within the leg's reach and limits", "fold_y_m")
    while high - low > FLOOR_TOLERANCE_NM:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if lifts(mid) is not None else (mid, high)
    top = lifts(high)
    i, j = np.unravel_index(int(np.argmin(np.where(top, cost[0], np.inf))), top.shape)
    straight, why = _straight(params, path, payload_kg)
    distance = float(np.hypot(g.x_center_m - path.fold_x_m, g.y_home_m - path.fold_y_m))
    return StandUpFloor(high, float(xs[i]), float(xs[j]), straight, why,
                        QUINTIC_PEAK * distance / path.rise_s**2 / params.robot.gravity_m_s2)


def _straight(params: Params, path: StandUp, payload_kg: float) -> tuple[float | None, str]:
    """The peak torque (N*m) of the maneuver's straight path, all feet alike from the fold
    point to home, balanced (None and why where it tips or leaves the reach)."""
    g = params.gait
    line = np.linspace([path.fold_x_m, path.fold_y_m], [g.x_center_m, g.y_home_m], 400)
    peaks = np.array([_pair_peaks(params, -y, x, x, payload_kg) for x, y in line])
    front_N, _ = balanced_loads(params, line[:, 0], line[:, 0], payload_kg)
    if not np.isfinite(front_N).all():
        return None, ("the straight path tips the robot: its centre of mass is not between the "
                      "front and rear feet along it")
    if not np.isfinite(peaks).all():
        return None, "the straight path leaves the leg's reach or limits"
    return float(peaks.max()), ""
