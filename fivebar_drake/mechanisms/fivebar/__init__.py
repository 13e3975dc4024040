"""The planar 5-bar leg with the offset foot (seeds 000 and 003): the mechanism (FiveBarLeg)
and the public functions of its modules. Code outside this folder imports from here, never from
its modules."""

from fivebar_drake.mechanisms.fivebar.dynamics import (DynamicsModel, TorqueBreakdown, coriolis,
                                                        coriolis_at, mass_matrix, mass_matrix_at,
                                                        static_at, static_torques, torques)
from fivebar_drake.mechanisms.fivebar.gait import (GaitSamples, path_poses, periodic_derivatives,
                                                   sample_gait, track_modes)
from fivebar_drake.mechanisms.fivebar.geometry import (LINK_NAMES, MOTORS, LegGeometry, LegLimits,
                                                        LinkInertia, physical_izz)
from fivebar_drake.mechanisms.fivebar.jacobians import (LinkJacobians, bias_accelerations, bias_at,
                                                         com_fractions, foot_from, foot_jacobian,
                                                         held_force, link_coms,
                                                         link_jacobians, link_jacobians_at,
                                                         point_jacobians, pose_jacobians)
from fivebar_drake.mechanisms.fivebar.kinematics import (ALL_MODES, KNEES_OUT, MODE_ALIASES,
                                                          MODE_NAMES, LegPose, UnreachableError,
                                                          mode_name, forward, forward_points,
                                                          forward_pose, inverse, inverse_pose,
                                                          knee_modes, reachable)
from fivebar_drake.mechanisms.fivebar.leg import FiveBarLeg
from fivebar_drake.mechanisms.fivebar.limits import (LIMITS, LimitTest, joint_ranges, limit_tests,
                                                     past_any)
from fivebar_drake.mechanisms.fivebar.loop import JOINTS, loop_gaps, tree_positions
from fivebar_drake.mechanisms.fivebar.sdf import link_inertias
from fivebar_drake.mechanisms.fivebar.singularity import (SingularityMeasures,
                                                           singularity_measures, workspace)

__all__ = ["ALL_MODES", "DynamicsModel", "FiveBarLeg", "GaitSamples", "JOINTS", "KNEES_OUT",
           "LIMITS", "LINK_NAMES", "MODE_ALIASES", "MODE_NAMES", "LegGeometry", "LegLimits", "LegPose", "LimitTest",
           "LinkInertia", "LinkJacobians", "MOTORS", "SingularityMeasures",
           "TorqueBreakdown", "UnreachableError", "bias_accelerations", "bias_at",
           "com_fractions", "coriolis", "coriolis_at", "foot_from", "foot_jacobian",
           "forward", "forward_points", "forward_pose", "held_force", "inverse", "inverse_pose",
           "joint_ranges", "knee_modes", "limit_tests", "link_inertias", "link_jacobians",
           "link_coms", "link_jacobians_at", "loop_gaps", "mode_name", "mass_matrix", "mass_matrix_at",
           "past_any", "path_poses", "periodic_derivatives", "physical_izz",
           "point_jacobians", "pose_jacobians", "reachable", "sample_gait",
           "singularity_measures", "static_at", "static_torques", "torques",
           "track_modes", "tree_positions", "workspace"]
