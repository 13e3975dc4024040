"""The stand-up's floor (optimal/stand_up.py): its bounds by other methods, its balance against
Drake's centre of mass, its static torques by virtual work, and the simulated stand-up asking at
least it."""

import math

import numpy as np
import pytest

from fivebar_drake.gaits import StandUp
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, link_coms
from pydrake.multibody.plant import MultibodyPlant

from fivebar_drake.optimal.stand_up import GRID_M, balanced_loads, stand_up_floor, static_torques
from fivebar_drake.optimal.vertical_jump import quarter_mass_kg
from fivebar_drake.robots.quadruped.plant import add_model, set_standing_pose
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.simulation.scenario import load_scenario


def _balanced_peak(params, front_x, rear_x, u, payload_kg=0.0):
    """The largest motor torque of a level pose at hip height u with the front and rear feet at
    front_x, rear_x behind their hips, the loads from this test's own moment balance about the
    centre of mass of Drake's plant (mass_properties); inf where the robot tips."""
    mass, com_x = drake_mass_centre(params)
    mass += payload_kg
    com_x *= (mass - payload_kg) / mass
    front = params.body.hip_x_m - np.asarray(front_x, float)
    rear = -params.body.hip_x_m - np.asarray(rear_x, float)
    w = mass * params.robot.gravity_m_s2
    with np.errstate(divide="ignore", invalid="ignore"):
        front_N = w * (com_x - rear) / (front - rear) / 2
    rear_N = w - 2 * front_N
    tips = (com_x > front) | (com_x < rear)
    f = static_torques(params, np.stack(np.broadcast_arrays(front_x, -u), -1), front_N)
    r = static_torques(params, np.stack(np.broadcast_arrays(rear_x, -u), -1), rear_N / 2)
    peak = np.maximum(np.abs(f).max(-1), np.abs(r).max(-1))
    return np.where(tips | ~np.isfinite(peak), np.inf, peak)


def drake_mass_centre(params):
    """(mass kg, centre of mass x forward of the body origin m) of Drake's plant of the generated
    SDF in its standing pose."""
    plant = MultibodyPlant(0.0)
    instance, legs = add_model(plant, params, "quadruped", None)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    set_standing_pose(plant, context, instance, legs, params)
    origin = plant.GetBodyByName("body", instance).EvalPoseInWorld(context).translation()
    com = plant.CalcCenterOfMassPositionInWorld(context, [instance])
    return plant.CalcTotalMass(context, [instance]), com[0] - origin[0]


def test_the_floor_balances_the_body_and_lies_between_every_path_and_one(params):
    """Every balanced loaded path ends at home and starts on the lying line: the floor is at
    least the statics at home and at least the least balanced pose on the line (front and rear
    feet sampled apart, finely, here, with loads from Drake's centre of mass: a second method).
    The maneuver's straight path is one such path: the floor is at most its peak (plus the
    grid's resolution). At the floor's lift point the centre of mass lies between the front and
    rear feet (the robot does not tip), and its torques there are within the floor. A payload
    raises it."""
    plan = StandUp()
    found = stand_up_floor(params, plan)
    u_home, u_lie = -params.gait.y_home_m, -plan.fold_y_m
    at_home = _balanced_peak(params, params.gait.x_center_m, params.gait.x_center_m, u_home)
    xs = np.linspace(-0.3, 0.3, 601)
    on_line = np.min(_balanced_peak(params, xs[:, None], xs[None, :], u_lie))
    assert found.floor_Nm >= max(at_home, on_line) - 2e-3
    lift = _balanced_peak(params, found.lift_front_x_m, found.lift_rear_x_m, u_lie)
    assert np.isfinite(lift) and lift <= found.floor_Nm + 2e-3
    line = np.linspace([plan.fold_x_m, plan.fold_y_m],
                       [params.gait.x_center_m, params.gait.y_home_m], 400)
    straight = max(_balanced_peak(params, x, x, -y) for x, y in line)
    assert found.straight_Nm == pytest.approx(straight, rel=2e-3)
    step = 0.05 * GRID_M / 1e-3          # N*m per grid step: the torques' slope, generously
    assert found.floor_Nm <= straight + step
    assert stand_up_floor(params, plan, payload_kg=1.0).floor_Nm > found.floor_Nm


def test_a_lift_with_every_foot_behind_the_centre_of_mass_is_not_a_pose(params):
    """The old floor's lift point (all four feet 188 mm behind their hips, the centre of mass
    ahead of every foot) tips the robot: no balanced load holds it."""
    front_N, rear_N = balanced_loads(params, 0.188, 0.188)
    assert np.isnan(front_N) and np.isnan(rear_N)


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
        np.testing.assert_allclose(static_torques(params, np.array(foot), load[1]), tau,
                                   atol=2e-5)


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
