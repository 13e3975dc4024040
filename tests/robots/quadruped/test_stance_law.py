"""The stance law delivers the body wrench in full while a foot gives off its load; a foot takes
load from its measured contact (control_law.support_weights), and after a flight the first foot
down takes its share only."""

import dataclasses

import numpy as np
import pytest
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.gaits import REFERENCES_PER_LEG, reference_parts
from fivebar_drake.mechanisms.fivebar import foot_jacobian, forward, static_torques
from fivebar_drake.robots.quadruped.closure import Ball
from fivebar_drake.robots.quadruped.control_law import AIRBORNE_S, support_weights
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
                                   scenario.controller, scenario.load_transfer_s)
    context = plant.CreateDefaultContext()
    set_standing_pose(plant, context, instance, layout.legs, params)
    return controller, layout, plant.GetPositionsAndVelocities(context)


def at_home(params, n):
    """Foot references (REFERENCES_PER_LEG x n legs) with every foot at home, at rest, and a
    view of their stance weights (to set)."""
    references = np.zeros(REFERENCES_PER_LEG * n)
    targets, _, _, weights = reference_parts(references)
    targets[:] = (params.gait.x_center_m, params.gait.y_home_m)
    return references, weights


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
    weight = layout.mass_kg * params.robot.gravity_m_s2
    references, weights = at_home(params, len(layout.legs))
    sums = []
    for w in np.linspace(1.0, 0.0, 21):
        weights[:] = 1.0
        weights[leaving] = w
        forces = delivered_forces(params, layout, state, controller.command(references, state))
        vertical = forces @ plane_rotation()[2, :2]         # leg plane (x, y) -> body z
        if w == 0.0:
            assert np.abs(forces[leaving]).max() < 1e-6     # a foot off the support pushes not
        sums.append(vertical.sum())
    assert np.array(sums) == pytest.approx(weight, rel=0.01), np.array(sums) / weight


def smoothstep(x):
    """3 x^2 - 2 x^3 on [0, 1] (the load transfer's shape), written out here."""
    x = min(max(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def run_support(controller, scheduled, descending, loads, times, memory=None):
    """support_weights over a sequence of ticks: the weights (ticks, legs) and the memory."""
    k = controller.constants
    memory = controller.standing_support() if memory is None else memory
    out = [support_weights(k, np.asarray(s, float), np.asarray(d, bool), np.asarray(f, float),
                           memory, t) for s, d, f, t in zip(scheduled, descending, loads, times)]
    return np.array(out), memory


def test_a_foot_takes_load_from_its_measured_contact(standing):
    """A foot due in stance (scheduled weight 1) that is not on the ground has weight 0; from the
    tick its measured force exceeds the threshold its weight rises as the load transfer's
    smoothstep from that tick, not from its schedule."""
    controller = standing[0]
    k = controller.constants
    transfer, dt = k.transfer_s, 0.002
    times = np.arange(0.0, 0.1, dt)
    lands = 0.03                                        # the foot meets the ground 30 ms late
    memory = controller.standing_support()
    memory[0, 0], memory[0, 2] = 0.0, 1e9               # leg 0 in its swing before t = 0
    loads = [[k.contact_N * (2.0 if t >= lands else 0.5)] + [30.0] * 3 for t in times]
    w, memory = run_support(controller, [[1.0] * 4] * len(times), [[False] * 4] * len(times),
                            loads, times, memory)
    expect = [smoothstep((t - lands) / transfer) if t >= lands else 0.0 for t in times]
    assert w[:, 0] == pytest.approx(expect, abs=1e-12)
    assert np.all(w[:, 1:] == 1.0)


def test_early_touchdown_needs_the_air_and_the_way_down(standing):
    """A swing foot (scheduled weight 0) joins the support on contact only after it has been
    unloaded AIRBORNE_S and while its target moves down; a foot unloaded that long in full
    stance has lost the ground: weight 0, due again."""
    controller = standing[0]
    k = controller.constants
    dt = 0.002
    times = np.arange(0.0, 0.06, dt)
    swing = [[0.0] + [1.0] * 3] * len(times)
    # lifted off at t = 0, touching again at 4 ms (chatter: not yet in the air 10 ms)
    chatter = [[k.contact_N * 2 if 0.004 <= t < 0.008 else 0.0] + [30.0] * 3 for t in times]
    w, _ = run_support(controller, swing, [[True] * 4] * len(times), chatter, times)
    assert np.all(w[:, 0] == 0.0)
    # in the air 20 ms, then down: it joins on the way down, not on the way up
    late = [[k.contact_N * 2 if t >= 0.03 else 0.0] + [30.0] * 3 for t in times]
    for down in (True, False):
        w, memory = run_support(controller, swing, [[down] * 4] * len(times), late, times)
        joined = times >= 0.03
        assert np.all(w[~joined, 0] == 0.0)
        assert np.all(w[times > 0.03 + 1e-9, 0] > 0.0) == down
        if down:
            assert w[joined, 0] == pytest.approx([smoothstep((t - 0.03) / k.transfer_s)
                                                  for t in times[joined]], abs=1e-12)
    # in full stance, unloaded from t = 0: on for AIRBORNE_S, then off and due again
    lost = [[0.0] + [30.0] * 3 for _ in times]
    w, memory = run_support(controller, [[1.0] * 4] * len(times), [[False] * 4] * len(times),
                            lost, times)
    assert np.all(w[times < AIRBORNE_S - 1e-9, 0] == 1.0)
    assert np.all(w[times >= AIRBORNE_S + 1e-9, 0] == 0.0) and memory[0, 0] == 0.0


def test_the_first_foot_down_after_a_flight_takes_its_share_only(params, standing):
    """In a scheduled flight (every stance weight 0) feet measured down early, and at a landing
    (every foot due in stance) feet just down, carry their weights' share of the body's weight,
    not the whole of it: the vertical forces the commands hold sum to 4 w m g for four feet
    down together at weight w each (a sum of weights >= 1 gives the whole)."""
    controller, layout, state = standing
    weight = layout.mass_kg * params.robot.gravity_m_s2
    references, weights = at_home(params, len(layout.legs))
    transfer = controller.constants.transfer_s
    for scheduled, early in ((0.0, 1.0), (1.0, 0.0)):       # a flight, a landing
        weights[:] = scheduled
        for since in (0.15 * transfer, 0.3 * transfer):
            memory = controller.standing_support()
            memory[:] = (1.0, early, 0.0, 0.0)                  # all down at t = 0
            command = controller.command(references, state, np.full(len(layout.legs), 100.0), memory, since)
            vertical = delivered_forces(params, layout, state, command) @ plane_rotation()[2, :2]
            w = smoothstep(since / transfer)
            assert 4 * w < 1.0 and vertical.sum() == pytest.approx(4 * w * weight, rel=0.01)


def test_a_leg_wholly_in_stance_needs_no_reachable_swing_target(params, standing):
    """A foot on the ground with its whole support weight is held by the stance law alone: its
    target out of the leg's reach (a landing that sank past it) still gives a finite command
    (before, the unused swing command's NaN times 0 stopped the run), while the same target on
    a leg partly in swing is refused naming it."""
    from fivebar_drake.mechanisms.fivebar import UnreachableError

    controller, layout, state = standing
    references, weights = at_home(params, len(layout.legs))
    weights[:] = 1.0
    targets = reference_parts(references)[0]
    targets[0] = (params.gait.x_center_m, -0.01)                 # 10 mm below the hip
    assert np.isfinite(controller.command(references, state)).all()
    weights[0] = 0.5
    with pytest.raises(UnreachableError):
        controller.command(references, state)
