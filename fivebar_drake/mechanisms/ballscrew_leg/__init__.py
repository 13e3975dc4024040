"""The serial two-link leg with a ball-screw knee (seed 001): the mechanism (BallScrewLeg), the
comparison with the geared knee over a vertical squat, and the parameters. Code outside this
folder imports from here, never from its modules.

BallScrewLeg has three parts of mechanisms/base.py: kinematics (one assembly mode, the knee bent
back; the tool Jacobian), statics (for a foot force) and the Drake model's tree coordinates and
loop gap at D. It has no dynamics or SDF elements: the seed's analysis is massless and static,
and the study builds its own Drake model (studies/ballscrew_leg)."""

from fivebar_drake.mechanisms.ballscrew_leg.leg import (KNEE_BACK, MOTORS, TREE_JOINTS,
                                                         BallScrewLeg, Pose, UnreachableError)
from fivebar_drake.mechanisms.ballscrew_leg.params import DEFAULT_PATH, Params, load_params
from fivebar_drake.mechanisms.ballscrew_leg.squat import (EFFICIENCY_READINGS, RATIO_READINGS,
                                                           SquatStatics, StrokeRange,
                                                           ball_screw_leg, peak_ratio_q1,
                                                           squat_statics, stroke_range)

__all__ = ["BallScrewLeg", "DEFAULT_PATH", "EFFICIENCY_READINGS", "KNEE_BACK", "MOTORS", "Params",
           "Pose", "RATIO_READINGS", "SquatStatics", "StrokeRange", "TREE_JOINTS",
           "UnreachableError", "ball_screw_leg", "load_params", "peak_ratio_q1", "squat_statics",
           "stroke_range"]
