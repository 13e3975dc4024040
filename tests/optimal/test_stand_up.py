"""The stand-up's floor (optimal/stand_up.py): its bounds by other methods, its static torques by
virtual work, and the simulated stand-up asking at least it."""

import math

import numpy as np
import pytest

from fivebar_drake.core.footpath import StandUp
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, link_coms
from fivebar_drake.optimal.stand_up import GRID_M, stand_up_floor, static_torques
from fivebar_drake.optimal.vertical_jump import quarter_mass_kg
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.simulation.scenario import load_scenario


def test_the_floor_lies_between_what_every_path_must_pass_and_one_path(params):
    """Every loaded path ends at home and starts on the lying line: the floor is at least the
    static torque at home and at least the least on the line (sampled finely here, not on the
    floor's grid). The maneuver's straight path is one such path: the floor is at most its
    peak (the grid's resolution: one grid step's change of torque). A payload raises it."""
    plan = StandUp()
    found = stand_up_floor(params, plan)
    home = np.array([params.gait.x_center_m, params.gait.y_home_m])
    at_home = np.abs(static_torques(params, home)).max()
    line = np.stack([np.linspace(-0.3, 0.3, 6001), np.full(6001, plan.fold_y_m)], -1)
    on_line = np.nanmin(np.abs(static_torques(params, line)).max(-1))
    assert found.floor_Nm >= max(at_home, on_line) - 1e-3
    straight = np.linspace([plan.fold_x_m, plan.fold_y_m], home, 2000)
    peak = np.abs(static_torques(params, straight)).max()
    step = np.abs(np.diff(static_torques(params, straight), axis=0)).max() / (
        np.linalg.norm(straight[1] - straight[0]) / GRID_M)
    assert found.floor_Nm <= peak + 2 * step + 1e-3
    assert found.straight_Nm == pytest.approx(peak, rel=1e-3)
    assert stand_up_floor(params, plan, payload_kg=1.0).floor_Nm > found.floor_Nm


def test_the_static_torques_are_the_virtual_works(params):
    """The torques holding a loaded foot recomputed at a few foot points by virtual work: finite
    differences of the forward kinematics (the foot's displacement per motor angle) and of the
    links' potential energy, the quarter robot's weight on the foot."""
    leg, g, h = params.fivebar_leg, params.robot.gravity_m_s2, 1e-6
    masses = np.array([link.mass_kg for link in params.links.values()])
    load = np.array([0.0, quarter_mass_kg(params) * g])
    for foot in ([0.15, -0.03], [0.05, -0.12], [0.017, -0.2]):
        pose = leg.inverse(np.array(foot), KNEES_OUT)
        tau = np.zeros(2)
        for m in range(2):
            dq = np.zeros(2)
            dq[m] = h
            ends = [leg.forward(pose.q + s * dq, pose.e_branch) for s in (1, -1)]
            energy = [g * masses @ link_coms(leg.geometry, params.links, e)[..., 1] for e in ends]
            tau[m] = (energy[0] - energy[1]) / (2 * h) - (ends[0].f - ends[1].f) / (2 * h) @ load
        np.testing.assert_allclose(static_torques(params, np.array(foot)), tau, atol=2e-5)


@pytest.mark.slow
def test_the_simulated_stand_up_asks_at_least_the_floor():
    """The packaged stand-up simulated on the Drake Diagram: its summary splits the verdict
    on the floor, which lies below what the controller asked (a floor above a real run's
    demand would not be a floor)."""
    summary = summarize_run(run_simulation(load_scenario(gait="stand_up", duration_s=2.6),
                                           progress=False))
    split = summary["any_controller"]
    assert split["maneuver"] == "stand_up"
    assert math.isfinite(split["floor_Nm"]) and split["floor_Nm"] <= split["asked_Nm"]
