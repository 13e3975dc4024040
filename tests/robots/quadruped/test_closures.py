"""The compliant closure ("bushing"): the bushing's force law at E, treated implicitly by SAP."""

import numpy as np
import pytest
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import (ExternallyAppliedSpatialForce, MultibodyPlant,
                                     MultibodyPlantConfig, ApplyMultibodyPlantConfig)
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.common.value import AbstractValue

from fivebar_drake.robots.quadruped.closure import bushing_parameters
from fivebar_drake.mechanisms.fivebar import inverse, tree_positions
from fivebar_drake.robots.quadruped.plant import add_model, leg_indices
from fivebar_drake.mechanisms.base import Bushing

DT = 1e-3


def leg_plant(params, bushing, foot_force_N=None, lock_motors=True):
    """A fixed-hip leg closed by the compliant bushing at the home pose, without gravity;
    the foot pushed by foot_force_N (leg plane (x, y), N). Returns simulator, plant, context."""
    builder = DiagramBuilder()
    plant = builder.AddSystem(MultibodyPlant(DT))
    ApplyMultibodyPlantConfig(MultibodyPlantConfig(time_step=DT,
                                                   discrete_contact_approximation="sap"), plant)
    instance, _ = add_model(plant, params, "leg", "bushing", bushing)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    plant.Finalize()
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    idx = leg_indices(plant, instance, "leg")
    q = plant.GetPositions(context)
    q[idx.q] = tree_positions(inverse(params.leg, [params.gait.x_center_m, params.gait.y_home_m]))
    plant.SetPositions(context, q)
    plant.get_actuation_input_port().FixValue(context, np.zeros(2))
    foot = plant.GetBodyByName("leg_DE", instance)
    plane = plant.GetFrameByName("leg_plane", instance)
    force = ExternallyAppliedSpatialForce()
    force.body_index = foot.index()
    force.p_BoBq_B = [params.leg.de_m + params.leg.ef_m, 0.0, 0.0]
    f_plane = np.zeros(3) if foot_force_N is None else np.r_[foot_force_N, 0.0]
    force.F_Bq_W = SpatialForce(np.zeros(3),
                                plane.CalcRotationMatrixInWorld(context).matrix() @ f_plane)
    plant.get_applied_spatial_force_input_port().FixValue(context, AbstractValue.Make([force]))
    if lock_motors:
        for j in ("A", "B"):
            plant.GetJointByName(f"leg_{j}", instance).Lock(context)
    return simulator, plant, context, instance, idx


def e_points(plant, context, instance, params):
    """E on CE and E on DE in the leg plane (m)."""
    plane = plant.GetFrameByName("leg_plane", instance)
    out = []
    for link, length in (("CE", params.leg.ce_m), ("DE", params.leg.de_m)):
        frame = plant.GetBodyByName(f"leg_{link}", instance).body_frame()
        out.append(plant.CalcPointsPositions(context, frame, [length, 0.0, 0.0], plane)[:2, 0])
    return out


def loop_force(plant, context, instance, idx, params, foot_force):
    """The force (leg plane, N) the closure must carry in static equilibrium with the motors
    locked: passive joints C and D carry no torque, so J_phi^T lambda = tau_tree[phi] with
    tau_tree the generalized force of the foot load (virtual work, by finite differences)."""
    from fivebar_drake.robots.quadruped.inverse_dynamics import loop_jacobian, plane_point_jacobian
    jc, _ = loop_jacobian(plant, context, instance, params, "leg")
    j_foot, _ = plane_point_jacobian(plant, context, instance, "leg", "DE",
                                     params.leg.de_m + params.leg.ef_m)
    tau_tree = j_foot.T @ np.asarray(foot_force)
    return np.linalg.solve(jc[:, idx.v[2:]].T, -tau_tree[idx.v[2:]])


@pytest.mark.parametrize("force", [[0.0, 30.0], [10.0, 20.0], [-15.0, 5.0]])
def test_gap_is_loop_force_over_stiffness(params, force):
    bushing = Bushing(stiffness_N_m=2.0e5, damping_N_s_m=20.0)
    simulator, plant, context, instance, idx = leg_plant(params, bushing, force)
    simulator.AdvanceTo(1.0)                                # settle
    e_ce, e_de = e_points(plant, context, instance, params)
    gap = e_de - e_ce
    lam = loop_force(plant, context, instance, idx, params, force)
    k = bushing.stiffness_N_m
    assert np.linalg.norm(gap) == pytest.approx(np.linalg.norm(lam) / k, rel=0.05)
    cos = gap @ lam / (np.linalg.norm(gap) * np.linalg.norm(lam))
    assert abs(cos) > 0.99                                  # along the loop force
    v = plant.GetVelocities(context)
    assert np.max(np.abs(v)) < 1e-6                         # settled


def test_no_torque_about_the_hinge(params):
    """Motors free, no gravity, no load: the linkage set moving coasts on. A closure with any
    stiffness about the hinge would turn kinetic energy into spring energy and back."""
    m_eff, force = 0.006, 34.0
    bushing, _ = bushing_parameters(m_eff, force, 1e-5)
    simulator, plant, context, instance, idx = leg_plant(params, bushing, lock_motors=False)
    home = np.array([params.gait.x_center_m, params.gait.y_home_m])
    h = 1e-6
    x0, x1 = (tree_positions(inverse(params.leg, home + d)) for d in (0.0, h * np.array([1.0, 0.5])))
    v = plant.GetVelocities(context)
    v[idx.v] = (x1 - x0) / h * 0.2                          # foot moving at 0.22 m/s
    plant.SetVelocities(context, v)
    ke0 = plant.CalcKineticEnergy(context)
    for t in (0.05, 0.1):
        simulator.AdvanceTo(t)
        assert plant.CalcKineticEnergy(context) == pytest.approx(ke0, rel=0.02)
    e_ce, e_de = e_points(plant, context, instance, params)
    assert np.linalg.norm(e_de - e_ce) < 1e-5               # the loop stayed closed
