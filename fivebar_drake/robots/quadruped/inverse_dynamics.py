"""Motor torques from Drake's tree inverse dynamics, projected through the loop constraint.

`CalcInverseDynamics` works on the tree (the loop cut at E) and ignores the closure. With tree
velocities x_dot = S q_dot, S = [I; -J_phi^-1 J_q] from the loop-closure Jacobian J_c = [J_q J_phi]
(relative velocity of the two E points in the leg plane), virtual work gives the motor torques
tau = S^T tau_tree: the constraint force J_c^T lambda does no work along S.
"""

from __future__ import annotations

import numpy as np
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JacobianWrtVariable, MultibodyForces

from fivebar_drake.mechanisms.fivebar import LegPose, tree_positions
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import LegIndices


def plane_point_jacobian(plant: MultibodyPlant, context, instance, leg: str, link: str,
                         x_m: float):
    """Jacobian (2, nv) and bias acceleration J_dot v (2,) of the point at x_m (m) along a link
    of the leg, measured and expressed in the leg plane."""
    plane = plant.GetFrameByName(f"{leg}_plane", instance)
    frame = plant.GetBodyByName(f"{leg}_{link}", instance).body_frame()
    p = np.array([x_m, 0.0, 0.0])
    jac = plant.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV, frame, p,
                                                  plane, plane)[:2]
    bias = plant.CalcBiasTranslationalAcceleration(context, JacobianWrtVariable.kV, frame, p,
                                                   plane, plane)[:2, 0]
    return jac, bias


def loop_jacobian(plant: MultibodyPlant, context, instance, params: Params, leg: str):
    """J_c (2, nv) and bias J_c_dot v (2,) of the gap p(E on DE) - p(E on CE), in the leg plane."""
    j_de, b_de = plane_point_jacobian(plant, context, instance, leg, "DE", params.leg.de_m)
    j_ce, b_ce = plane_point_jacobian(plant, context, instance, leg, "CE", params.leg.ce_m)
    return j_de - j_ce, b_de - b_ce


def projected_inverse_dynamics(plant: MultibodyPlant, context, instance, params: Params,
                               leg: str, idx: LegIndices, pose: LegPose, qd, qdd,
                               foot_force_N: float) -> np.ndarray:
    """Motor torques (N, 2) in N*m for a fixed-hip leg following poses (N) with motor rates qd
    and accelerations qdd (N, 2), the ground pushing the foot up with foot_force_N (N) along the
    leg plane's +y."""
    x = tree_positions(pose)
    foot_body = plant.GetBodyByName(f"{leg}_DE", instance)
    p_foot = np.array([params.leg.de_m + params.leg.ef_m, 0.0, 0.0])
    plane = plant.GetFrameByName(f"{leg}_plane", instance)
    tau = np.zeros((len(x), 2))
    q_all = plant.GetPositions(context)
    for k in range(len(x)):
        q_all[idx.q] = x[k]
        plant.SetPositions(context, q_all)
        jc, _ = loop_jacobian(plant, context, instance, params, leg)
        jq, jphi = jc[:, idx.v[:2]], jc[:, idx.v[2:]]
        s = np.vstack([np.eye(2), -np.linalg.solve(jphi, jq)])
        v = np.zeros(plant.num_velocities())
        v[idx.v] = s @ qd[k]
        plant.SetVelocities(context, v)
        _, bias = loop_jacobian(plant, context, instance, params, leg)
        vdot = np.zeros(plant.num_velocities())
        vdot[idx.v] = np.concatenate([qdd[k], -np.linalg.solve(jphi, jq @ qdd[k] + bias)])
        forces = MultibodyForces(plant)
        plant.CalcForceElementsContribution(context, forces)   # gravity (and bushings)
        r_wp = plane.CalcRotationMatrixInWorld(context).matrix()
        r_wb = foot_body.EvalPoseInWorld(context).rotation().matrix()
        up_world = r_wp @ np.array([0.0, foot_force_N, 0.0])
        foot_body.AddInForce(context, r_wb @ p_foot, SpatialForce(np.zeros(3), up_world),
                             plant.world_frame(), forces)
        tau_tree = plant.CalcInverseDynamics(context, vdot, forces)
        tau[k] = s.T @ tau_tree[idx.v]
    return tau
