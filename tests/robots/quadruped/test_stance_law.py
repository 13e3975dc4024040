"""The stance law delivers the body wrench in full while a foot gives off its load."""

import dataclasses

import numpy as np
import pytest
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.mechanisms.fivebar import foot_jacobian, forward, static_torques
from fivebar_drake.robots.quadruped.closure import Ball
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.plant import ClosureDesign, add_robot, set_standing_pose
from fivebar_drake.robots.quadruped.legs import plane_rotation
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.simulation.systems import FootLegController


@pytest.fixture(scope="module")
def standing(params):
    """(controller, layout, plant state) with the robot standing at rest at the height target."""
    scenario = load_scenario(closure="ball")
    builder = DiagramBuilder()
    plant, instance, layout = add_robot(builder, params,
                                        ClosureDesign(Ball(), 1e-3, None, 0.0, 0.0))
    controller = FootLegController(params, layout, scenario.controller.gains(params, layout),
                                   scenario.controller)
    context = plant.CreateDefaultContext()
    set_standing_pose(plant, context, instance, layout.legs, params)
    return controller, layout, plant.GetPositionsAndVelocities(context)


def delivered_forces(params, layout, state, command):
    """Ground forces on the feet (legs, 2) in N, leg plane, that the command holds at rest:
    command = links' static torque - J_F^T F, so F = -J_F^-T (command - links' static torque)."""
    links = dataclasses.replace(full_model(params), foot_load_N=0.0)
    out = []
    for q_index, actuators in zip(layout.state.q_index, layout.state.actuators):
        pose = forward(params.leg, state[q_index])
        links_static = static_torques(params.leg, params.links, links, pose)
        out.append(-np.linalg.solve(foot_jacobian(params.leg, pose).T,
                                    command[actuators] - links_static))
    return np.array(out)


@pytest.mark.parametrize("leaving", [0, 3])
def test_feet_carry_the_weight_while_a_foot_gives_off_its_load(params, standing, leaving):
    """All feet at home, at rest, the body at its height target; one leg's stance weight goes
    1 -> 0: the vertical ground forces the commands hold sum to the robot's weight at every tick
    (the least-squares split is already weighted: blending the push again by w loses force)."""
    controller, layout, state = standing
    n = len(layout.legs)
    weight = layout.mass_kg * params.robot.gravity_m_s2
    references = np.zeros(7 * n)
    references[:2 * n] = np.tile([params.gait.x_center_m, params.gait.y_home_m], n)
    sums = []
    for w in np.linspace(1.0, 0.0, 21):
        references[6 * n:] = 1.0
        references[6 * n + leaving] = w
        forces = delivered_forces(params, layout, state, controller.command(references, state))
        vertical = forces @ plane_rotation()[2, :2]         # leg plane (x, y) -> body z
        if w == 0.0:
            assert np.abs(forces[leaving]).max() < 1e-6     # a foot off the support pushes not
        sums.append(vertical.sum())
    assert np.array(sums) == pytest.approx(weight, rel=0.01), np.array(sums) / weight
