"""The jump's torques (optimal/vertical_jump.py, the package's own 5-bar dynamics on one leg)
against Drake: the whole quadruped's MultibodyPlant (the generated SDF as an open tree, the
reflected rotor inertia as the plant declares it), all four legs on the same trajectory, its
inverse dynamics M v' + C v - tau_g solved for the motor torques, the loop forces at E and the
ground forces at the feet (shared by the four legs, least squares over the 22 equations)."""

import numpy as np
import pytest
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JacobianWrtVariable, MultibodyForces

from fivebar_drake.optimal.vertical_jump import push, reach, stroke
from fivebar_drake.robots.quadruped.config import load_params
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.robots.quadruped.plant import add_model, leg_indices
from fivebar_drake.robots.quadruped.sdf import body_height

NODES = (0.05, 0.3, 0.6, 0.9)        # where along the push (share of its nodes) it is checked
AGREE_NM = 2e-3                       # |tau_ours - tau_drake| (N m): measured at most 6.4e-4
#                                       (the stroke's finite differences), torques of 0.7-5 N m


def drake_torques(params, s, k, w, b):
    """(motor torques A, B in N m; the residual of the 22 equations, N m or N; the body's first
    velocity index) of the open-tree quadruped with every leg at stroke node k, the hip rising
    at w (m/s) with acceleration b (m/s^2), by Drake's inverse dynamics."""
    plant = MultibodyPlant(0.0)
    instance, legs = add_model(plant, params, "quadruped", None)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    leg = params.fivebar_leg
    tree = leg.tree_positions(leg.inverse(np.stack([np.full_like(s.u, params.gait.x_center_m),
                                                    -s.u], -1)))
    rate = np.gradient(tree, s.u, axis=0, edge_order=2)
    curve = np.gradient(rate, s.u, axis=0, edge_order=2)
    q, v, vdot = (plant.GetPositions(context), np.zeros(plant.num_velocities()),
                  np.zeros(plant.num_velocities()))
    for name in LEGS:
        index = leg_indices(plant, instance, name)
        q[index.q] = tree[k]
        v[index.v] = rate[k] * w
        vdot[index.v] = curve[k] * w * w + rate[k] * b
    body = plant.GetBodyByName("body", instance)
    plant.SetPositions(context, q)
    plant.SetFreeBodyPose(context, body, plant.GetFreeBodyPose(context, body).__class__(
        [0.0, 0.0, float(body_height(params, -s.u[k]))]))
    start = body.floating_velocities_start_in_v()
    v[start + 5], vdot[start + 5] = w, b                        # world z: linear after angular
    plant.SetVelocities(context, v)
    forces = MultibodyForces(plant)
    plant.CalcForceElementsContribution(context, forces)        # gravity
    needed = plant.CalcInverseDynamics(context, vdot, forces)
    g, world = params.leg, plant.world_frame()
    actuation = plant.MakeActuationMatrix()
    columns = np.zeros((plant.num_velocities(), 6))
    for name in LEGS:
        ce = plant.GetBodyByName(f"{name}_CE", instance).body_frame()
        de = plant.GetBodyByName(f"{name}_DE", instance).body_frame()
        index = leg_indices(plant, instance, name)
        columns[:, 0] += actuation[:, index.actuators[0]]
        columns[:, 1] += actuation[:, index.actuators[1]]

        def jac(frame, point):
            return plant.CalcJacobianTranslationalVelocity(
                context, JacobianWrtVariable.kV, frame, point, world, world)

        loop = jac(ce, [g.ce_m, 0.0, 0.0]) - jac(de, [g.de_m, 0.0, 0.0])   # E on CE, on DE
        foot_w = plant.CalcPointsPositions(context, de, [g.de_m + g.ef_m, 0.0, 0.0], world)
        ground = foot_w.ravel() - [0.0, 0.0, params.body.foot_radius_m]   # the sphere's bottom
        on_de = plant.CalcPointsPositions(context, world, ground, de).ravel()
        foot = jac(de, on_de)
        columns[:, 2] += loop[0]
        columns[:, 3] += loop[2]
        columns[:, 4] += foot[0]
        columns[:, 5] += foot[2]
    solution, *_ = np.linalg.lstsq(columns, needed, rcond=None)
    return solution[:2], columns @ solution - needed, body.floating_velocities_start_in_v()


@pytest.mark.parametrize("share", NODES)
def test_the_jumps_torques_match_drakes_inverse_dynamics(share):
    """Every joint's equation holds with the shared unknowns, and the motor torques agree with
    the package's to AGREE_NM. What the one-leg model neglects shows in the body's equations
    alone: all four legs lean the same way (their links' mass behind the hips), a pitch moment
    (up to 0.17 N m) that equal front and rear feet cannot balance: a difference of
    M / (2 hip_x) between the front and the rear feet would (up to 0.53 N, 3 % of a foot's
    share of the weight); and a few hundredths of a newton along x."""
    params = load_params(None)
    u0, u1 = reach(params)
    jump = push(stroke(params, u0, u1), -params.gait.y_home_m)
    s, k = jump.stroke, int(share * jump.takeoff)
    ours = jump.torque_Nm[k]
    theirs, residual, body = drake_torques(params, s, k, jump.w[k], jump.b[k])
    joints = np.delete(residual, np.arange(body, body + 6))
    assert np.abs(joints).max() < 1e-9
    share = params.robot.total_mass_kg * s.g / 4
    moment = np.abs(residual[body:body + 3]).max()                   # pitch (roll, yaw: 0)
    assert moment / (2 * params.body.hip_x_m) < 0.05 * share
    assert np.abs(residual[body + 3:body + 6]).max() < 1e-3 * params.robot.total_mass_kg * s.g
    np.testing.assert_allclose(ours, theirs, atol=AGREE_NM)
