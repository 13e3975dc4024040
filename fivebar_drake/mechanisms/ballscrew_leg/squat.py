"""The seed's comparison over a vertical squat (q2 = -2 q1, foot below the hip for l1 = l2):
static motor torques of the geared knee and the screw knee under the foot load, the screw's
equivalent reduction ratio in each reading of the seed's text, and the knee range the screw's
stroke allows."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fivebar_drake.mechanisms.ballscrew_leg.leg import BallScrewLeg
from fivebar_drake.mechanisms.ballscrew_leg.params import Params

# The screw's one efficiency figure read two ways: the motor drives the screw (rising), or the
# load drives the motor through it (lowering).
EFFICIENCY_READINGS = {
    "forward": "screw efficiency 90 % forward: the motor drives the screw, "
               "tau = F lead / (2 pi eta)",
    "back-driven": "screw efficiency 90 % back-driven: the load drives the motor, "
                   "tau = F lead eta / (2 pi)",
}
# "The geared joint motor's output torque over the screw motor's torque": the output of the
# geared knee (its joint torque) or the geared motor's own torque (before its 10:1 gear).
RATIO_READINGS = {
    "joint": "ratio = geared knee's output (knee joint) torque / screw motor torque: the screw's "
             "equivalent reduction ratio, comparable with the 10:1 gear",
    "motor": "ratio = geared knee motor's own torque (knee torque / (10 x 1.0)) / screw motor "
             "torque",
}


def ball_screw_leg(params: Params, lever_m: float) -> BallScrewLeg:
    """The leg of the parameter file with lever s1 = lever_m."""
    return BallScrewLeg(params.leg.thigh_m, params.leg.shank_m, lever_m, params.screw.lead_m)


@dataclass(frozen=True)
class SquatStatics:
    """One lever over the sampled squat, arrays over q1 (SI). Torques hold the pose against the
    ground's force F = (0, foot_force_N) on the foot: knee joint torque, geared knee motor torque,
    screw force (N, negative: the screw pulls), screw motor torque per efficiency reading, ratio
    per (ratio reading, efficiency reading), angle ODP (rad); hip torque (the same in both
    designs)."""

    lever_m: float
    q1: np.ndarray
    q2: np.ndarray
    q2l: np.ndarray
    hip_Nm: np.ndarray
    knee_Nm: np.ndarray
    geared_motor_Nm: np.ndarray
    screw_force_N: np.ndarray
    screw_motor_Nm: dict
    ratio: dict
    odp_rad: np.ndarray


def squat_statics(params: Params, lever_m: float, q1=None) -> SquatStatics:
    """The comparison for one lever over q1 (rad; default: the file's squat samples)."""
    leg = ball_screw_leg(params, lever_m)
    q1 = params.squat.q1_rad if q1 is None else np.asarray(q1, dtype=float)
    pose = leg.points(q1, -2.0 * q1)
    force = np.array([0.0, params.load.foot_force_N])
    hip, knee = np.moveaxis(-np.einsum("...ij,i->...j", leg.knee_jacobian(q1, pose.q2), force),
                            -1, 0)
    g = params.geared_knee
    geared = knee / (g.gear_ratio * g.efficiency)
    screw_force = leg.screw_force(knee, pose.q2)
    eta = params.screw.efficiency
    motor = {name: leg.screw_motor_torque(screw_force, eta, driving=name == "forward")
             for name in EFFICIENCY_READINGS}
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = {(r, e): np.abs(knee if r == "joint" else geared) / np.abs(motor[e])
                 for r in RATIO_READINGS for e in EFFICIENCY_READINGS}
    return SquatStatics(lever_m=lever_m, q1=q1, q2=pose.q2, q2l=pose.q[..., 1], hip_Nm=hip,
                        knee_Nm=knee, geared_motor_Nm=geared, screw_force_N=screw_force,
                        screw_motor_Nm=motor, ratio=ratio, odp_rad=leg.angle_odp(pose))


def peak_ratio_q1(params: Params, lever_m: float) -> float:
    """The hip angle (rad) of the ratio's peak, from the geometry alone: the ratio is
    proportional to s1 sin(ODA), largest where the screw is square to the lever, and there the
    triangle OAD has its right angle at D: cos(OAD) = s1 / l1, OAD = -q2 = 2 q1."""
    return 0.5 * np.arccos(lever_m / params.leg.thigh_m)


@dataclass(frozen=True)
class StrokeRange:
    """What the screw's stroke allows for one lever: the screw length at the retracted end and
    at the extended end (m), the knee bend -q2 (rad) and the squat angle q1 (rad) at each end,
    and the stroke the whole analysed squat would need (m)."""

    lever_m: float
    screw_m: tuple
    bend_rad: tuple
    q1_rad: tuple
    needed_stroke_m: float


def stroke_range(params: Params, lever_m: float) -> StrokeRange:
    """The knee's range under the screw's stroke: fully retracted at the squat angle
    screw.retracted_at_q1_deg, extended by screw.stroke_m (at most to the folded knee)."""
    leg = ball_screw_leg(params, lever_m)
    lengths, bends = leg.stroke_window(params.screw.stroke_m,
                                       2.0 * np.radians(params.screw.retracted_at_q1_deg))
    squat = params.squat
    ends = leg.screw_from_knee(-2.0 * np.radians([squat.q1_min_deg, squat.q1_max_deg]))
    return StrokeRange(lever_m=lever_m, screw_m=lengths, bend_rad=bends,
                       q1_rad=tuple(b / 2.0 for b in bends),
                       needed_stroke_m=float(abs(ends[1] - ends[0])))
