"""Drake's tree inverse dynamics, projected through the loop constraint, against the full model."""

import dataclasses

import numpy as np
import pytest
from pydrake.multibody.tree import MultibodyForces

from fivebar_drake.robots.quadruped.config import with_gait
from fivebar_drake.mechanisms.fivebar import LegPose, sample_gait, torques, tree_positions
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.inverse_dynamics import projected_inverse_dynamics
from fivebar_drake.robots.quadruped.closure import fixed_leg


@pytest.fixture()
def no_rotor(params):
    return dataclasses.replace(params, motor=dataclasses.replace(params.motor,
                                                                 rotor_inertia_kg_m2=0.0))


@pytest.mark.parametrize("frequency", [1.0, 3.0])
def test_drake_inverse_dynamics_matches_full_model(no_rotor, frequency):
    p = with_gait(no_rotor, frequency_hz=frequency)
    plant, context, instance, idx = fixed_leg(p)
    s = sample_gait(p.leg, p.gait)
    model = full_model(p)
    tau_drake = projected_inverse_dynamics(plant, context, instance, p, "leg", idx, s.pose, s.qd,
                                           s.qdd, model.foot_load_N)
    tau_model = torques(p.leg, p.links, model, s.pose, s.qd, s.qdd).total
    assert np.max(np.abs(tau_drake - tau_model)) < 0.01 * np.max(np.abs(tau_model))
    # without the foot load the dynamics alone (links, Coriolis) must agree as well
    free = projected_inverse_dynamics(plant, context, instance, p, "leg", idx, s.pose, s.qd,
                                      s.qdd, 0.0)
    free_model = torques(p.leg, p.links, dataclasses.replace(model, foot_load_N=0.0), s.pose, s.qd, s.qdd).total
    assert np.max(np.abs(free - free_model)) < 0.01 * np.max(np.abs(free_model))


def test_rotor_inertia_adds_reflected_inertia(params, no_rotor):
    s = sample_gait(params.leg, params.gait)
    taus = []
    for p in (params, no_rotor):
        plant, context, instance, idx = fixed_leg(p)
        taus.append(projected_inverse_dynamics(plant, context, instance, p, "leg", idx, s.pose,
                                               s.qd, s.qdd, 0.0))
    assert np.allclose(taus[0] - taus[1], params.motor.reflected_inertia_kg_m2 * s.qdd, atol=1e-12)


def test_tree_inverse_dynamics_alone_is_wrong(no_rotor):
    """The unprojected tree result (motor rows only) ignores the loop and misses the torque."""
    p = no_rotor
    plant, context, instance, idx = fixed_leg(p)
    s = sample_gait(p.leg, p.gait)
    model = full_model(p)
    x = tree_positions(s.pose)
    q = plant.GetPositions(context)
    q[idx.q] = x[0]
    plant.SetPositions(context, q)
    forces = MultibodyForces(plant)
    plant.CalcForceElementsContribution(context, forces)
    naive = plant.CalcInverseDynamics(context, np.zeros(plant.num_velocities()), forces)[idx.v[:2]]
    zero = np.zeros(2)
    first = LegPose(*(a[0] for a in (s.pose.q, s.pose.c, s.pose.d, s.pose.e, s.pose.f)))
    right = torques(p.leg, p.links, dataclasses.replace(model, foot_load_N=0.0), first, zero, zero).total
    assert np.max(np.abs(naive - right)) > 0.2 * np.max(np.abs(right))
