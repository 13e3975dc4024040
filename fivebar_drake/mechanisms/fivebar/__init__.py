"""The planar 5-bar leg with the offset foot (seeds 000 and 003): the mechanism (FiveBarLeg)
and the public functions of its modules. Code outside this folder imports from here, never from
its modules."""

from fivebar_drake.mechanisms.fivebar.dynamics import (DynamicsModel, TorqueBreakdown, coriolis,
                                                        coriolis_at, mass_matrix, mass_matrix_at,
                                                        static_at, static_torques, torques)
from fivebar_drake.mechanisms.fivebar.gait import (GaitSamples, periodic_derivatives, sample_gait,
                                                   track_modes)
from fivebar_drake.mechanisms.fivebar.geometry import (LINK_NAMES, MOTORS, LegGeometry,
                                                        LinkInertia, physical_izz)
from fivebar_drake.mechanisms.fivebar.jacobians import (LinkJacobians, bias_accelerations, bias_at,
                                                         com_fractions, foot_from, foot_jacobian,
                                                         held_force, link_coms,
                                                         link_jacobians, link_jacobians_at,
                                                         point_jacobians, pose_jacobians)
from fivebar_drake.mechanisms.fivebar.kinematics import (ALL_MODES, KNEES_OUT, LegPose,
                                                          UnreachableError, forward, forward_points,
                                                          forward_pose, inverse, inverse_pose,
                                                          knee_modes, reachable)
from fivebar_drake.mechanisms.fivebar.leg import FiveBarLeg
from fivebar_drake.mechanisms.fivebar.loop import JOINTS, loop_gaps, tree_positions
from fivebar_drake.mechanisms.fivebar.singularity import (SingularityMeasures,
                                                           singularity_measures, workspace)

__all__ = ["held_force", "link_coms", "ALL_MODES", "DynamicsModel", "FiveBarLeg", "GaitSamples", "JOINTS", "KNEES_OUT",
           "LINK_NAMES", "LegGeometry", "LegPose", "LinkInertia", "LinkJacobians", "MOTORS",
           "SingularityMeasures", "TorqueBreakdown", "UnreachableError", "bias_accelerations",
           "bias_at", "com_fractions", "coriolis", "coriolis_at", "foot_from", "foot_jacobian", "forward",
           "forward_points", "forward_pose", "inverse", "inverse_pose", "knee_modes", "link_jacobians", "link_jacobians_at",
           "loop_gaps", "mass_matrix", "mass_matrix_at", "periodic_derivatives", "physical_izz", "point_jacobians", "pose_jacobians", "reachable",
           "sample_gait", "singularity_measures", "static_at", "static_torques", "torques",
           "track_modes", "tree_positions", "workspace"]
