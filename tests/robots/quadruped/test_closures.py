"""The closures SAP treats implicitly: the compliant "bushing" (the bushing's force law at E) down
to its least gap at the plant step, and the "ball", which SAP regularises to a spring."""

import numpy as np
import pytest
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import (ExternallyAppliedSpatialForce, MultibodyPlant,
                                     MultibodyPlantConfig, ApplyMultibodyPlantConfig)
from pydrake.multibody.tree import PdControllerGains
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.common.value import AbstractValue

from fivebar_drake.core.validation import ParameterError
from fivebar_drake.robots.quadruped.closure import (CLOSURES, IMPLICIT_TIME_STEP_S,
                                                    bushing_parameters,
                                                    design_closure, loop_load, min_loop_gap,
                                                    near_rigid_mass)
from fivebar_drake.mechanisms.fivebar import inverse, tree_positions
from fivebar_drake.robots.quadruped.plant import add_model, leg_indices
from fivebar_drake.mechanisms.base import Bushing

DT = 1e-3


def leg_plant(params, bushing, foot_force_N=None, motors="locked", dt=DT, closure="bushing"):
    """A fixed-hip leg closed by the compliant bushing (or the closure) at the home pose, without
    gravity, plant step dt (s); the foot pushed by foot_force_N (leg plane (x, y), N). Motors
    "locked", "free", or "held" at home by SAP's implicit PD (free in the mass matrix, as in
    the robot). Returns simulator, plant, context, instance, LegIndices."""
    builder = DiagramBuilder()
    plant = builder.AddSystem(MultibodyPlant(dt))
    ApplyMultibodyPlantConfig(MultibodyPlantConfig(time_step=dt,
                                                   discrete_contact_approximation="sap"), plant)
    instance, _ = add_model(plant, params, "leg", CLOSURES[closure](), bushing)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    if motors == "held":
        for j in ("A", "B"):
            plant.GetJointActuatorByName(f"leg_{j}", instance).set_controller_gains(
                PdControllerGains(p=1e4, d=10.0))
    plant.Finalize()
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    idx = leg_indices(plant, instance, "leg")
    q = plant.GetPositions(context)
    q[idx.q] = tree_positions(inverse(params.leg, [params.gait.x_center_m, params.gait.y_home_m]))
    plant.SetPositions(context, q)
    plant.get_actuation_input_port().FixValue(context, np.zeros(2))
    if motors == "held":
        plant.get_desired_state_input_port(instance).FixValue(context, np.r_[q[idx.q[:2]], 0, 0])
    foot = plant.GetBodyByName("leg_DE", instance)
    plane = plant.GetFrameByName("leg_plane", instance)
    force = ExternallyAppliedSpatialForce()
    force.body_index = foot.index()
    force.p_BoBq_B = [params.leg.de_m + params.leg.ef_m, 0.0, 0.0]
    f_plane = np.zeros(3) if foot_force_N is None else np.r_[foot_force_N, 0.0]
    force.F_Bq_W = SpatialForce(np.zeros(3),
                                plane.CalcRotationMatrixInWorld(context).matrix() @ f_plane)
    plant.get_applied_spatial_force_input_port().FixValue(context, AbstractValue.Make([force]))
    if motors == "locked":
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
    simulator, plant, context, instance, idx = leg_plant(params, bushing, motors="free")
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


def static_gap(params, bushing, foot_force_N, dt, closure="bushing"):
    """(gap |E on DE - E on CE| m, loop force |lambda| N) of the loaded leg at rest, its motors
    held as in the robot (free in the mass matrix SAP sees)."""
    simulator, plant, context, instance, idx = leg_plant(params, bushing, foot_force_N, "held",
                                                         dt, closure)
    simulator.AdvanceTo(0.5)                                # settle
    assert np.max(np.abs(plant.GetVelocities(context))) < 1e-6
    e_ce, e_de = e_points(plant, context, instance, params)
    lam = loop_force(plant, context, instance, idx, params, foot_force_N)
    return np.linalg.norm(e_de - e_ce), np.linalg.norm(lam)


@pytest.mark.parametrize("dt", [1e-3, 5e-4])
def test_gap_is_force_over_stiffness_down_to_the_least_gap(params, dt):
    """At closure.min_loop_gap for the step (1.7 um at 1 ms, 0.43 um at 0.5 ms) the static gap
    is F / k; a tenth below it SAP regularises the stiffer constraint (near-rigid) and the gap
    no longer follows the law."""
    m_eff, force = loop_load(params)
    least = min_loop_gap(m_eff, near_rigid_mass(params), force, dt)
    ratios = []
    for target in (least, 0.9 * least):
        bushing, _ = bushing_parameters(m_eff, force, target)
        gap, lam = static_gap(params, bushing, [0.0, 30.0], dt)
        ratios.append(gap / (lam / bushing.stiffness_N_m))
    assert ratios[0] == pytest.approx(1.0, rel=0.01)        # measured 1.0000
    assert ratios[1] > 1.03                                 # measured 1.049


def test_a_gap_below_the_least_gap_is_refused(params):
    m_eff, force = loop_load(params)
    least = min_loop_gap(m_eff, near_rigid_mass(params), force, IMPLICIT_TIME_STEP_S)
    design = design_closure(params, "bushing", least)
    assert design.bushing.stiffness_N_m == pytest.approx(force / least)
    double = 2.0 * IMPLICIT_TIME_STEP_S
    for gap, step in ((0.99 * least, 0.0), (1e-12, 0.0), (3.9 * least, double)):
        with pytest.raises(ParameterError, match="near-rigid") as err:
            design_closure(params, "bushing", gap, step)    # the bound grows with step^2
        assert err.value.field == "scenario.target_loop_gap_m"
        assert f"scenario.target_loop_gap_m = {gap!r}: must be >= " in str(err.value)
    assert design_closure(params, "bushing", 0.99 * least, IMPLICIT_TIME_STEP_S / 2).bushing
    assert design_closure(params, "ball", 1e-12).bushing is None    # nothing designed


@pytest.mark.parametrize("dt", [1e-3, 5e-4])
def test_ball_is_compliant_at_the_step(params, dt):
    """SAP regularises the 'ball' closure too: under load its gap is that of a spring whose
    stiffness grows as 1 / dt^2 (measured 2.6e7 N/m at 1 ms, 1.0e8 at 0.5 ms)."""
    gap, lam = static_gap(params, None, [0.0, 30.0], dt, closure="ball")
    assert lam / gap == pytest.approx(2.6e7 * (1e-3 / dt) ** 2, rel=0.05)
