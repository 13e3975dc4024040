"""The gaits' floors with the body in motion (optimal/gait_floor.py): the motion recomputed
from the forces (Newton and Euler with the feet's own positions, from the foot path), the body's
mass properties against Drake's plant, the orderings a floor must keep, and the simulated
gaits."""

import math

import numpy as np
import pytest
from pydrake.multibody.plant import MultibodyPlant

from fivebar_drake.gaits import evaluate, foot_path
from fivebar_drake.mechanisms.fivebar import sample_gait
from fivebar_drake.optimal.gait_floor import (KNOTS, fastest_gait, gait_floor, max_pitch_rad,
                                              whole_body, within_envelope, mass_centre)
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.config import (load_params, with_changes, with_gait,
                                                   with_path_defaults)
from fivebar_drake.robots.quadruped.legs import LEGS, hip_positions
from fivebar_drake.robots.quadruped.plant import add_model, set_standing_pose
from fivebar_drake.robots.quadruped.sdf import body_height
from fivebar_drake.simulation.scenario import load_scenario


@pytest.fixture(scope="module")
def params():
    return load_params(None)


def test_the_mass_properties_are_drakes(params):
    """Mass, centre-of-mass height and pitch inertia of the standing robot (body, motors, links
    as point masses) against Drake's plant of the generated SDF in its standing pose (the
    links' own rotational inertia, left out, is under 1 %)."""
    mass, com_x, com_z, inertia = mass_centre(params)
    assert (mass, com_z, inertia) == whole_body(params)
    plant = MultibodyPlant(0.0)
    instance, legs = add_model(plant, params, "quadruped", None)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    set_standing_pose(plant, context, instance, legs, params)
    bodies = plant.GetBodyIndices(instance)
    body = plant.GetBodyByName("body", instance)
    origin = body.EvalPoseInWorld(context).translation()
    com = plant.CalcCenterOfMassPositionInWorld(context, [instance])
    spatial = plant.CalcSpatialInertia(context, plant.world_frame(), bodies)
    about_com = spatial.Shift(com).CalcRotationalInertia().CopyToFullMatrix3()
    assert mass == pytest.approx(spatial.get_mass(), rel=1e-9)
    assert com_z == pytest.approx(com[2] - origin[2], abs=2e-4)
    assert com_x == pytest.approx(com[0] - origin[0], abs=2e-4)
    assert inertia == pytest.approx(about_com[1, 1], rel=1e-2)


def _feet(params, kind, t):
    """(stance (legs, knots), the feet's x relative to the nominal centre of mass (legs, knots),
    from the foot path: the hip's x less the path's leg-plane x)."""
    path = foot_path(kind)
    stance, x = [], []
    for leg in LEGS:
        p = evaluate(params.gait, path, t, path.leg_phase(leg))
        stance.append(np.asarray(p.stance, bool))
        x.append(hip_positions(params)[leg][0] - p.pos[..., 0])
    return np.array(stance), np.array(x)


@pytest.mark.parametrize("kind", ["trot", "walk", "bound", "pronk"])
def test_the_motion_obeys_newton_and_euler(params, kind):
    """Recomputed from the floor's motion and forces with the feet where the path puts them on
    the nominal course, each fixed while it is down: the centre of mass's acceleration is the
    net force over the mass (knot-wise constant accelerations: second differences equal the
    mean of two knots' forces), the pitch acceleration the moment about the centre of mass over
    the inertia, roll and yaw moments vanish; the feet push inside the friction cone and are
    free in swing; the pitch stays within its bound; no stance torque exceeds the floor."""
    params = with_path_defaults(params, kind)
    floor = gait_floor(params, kind)
    mass, com_z, inertia = whole_body(params)
    dt = params.gait.period_s / KNOTS
    g = params.robot.gravity_m_s2
    stance, nominal_x = _feet(params, kind, floor.t)
    fx, fz = floor.force_N[..., 0], floor.force_N[..., 1]
    assert np.all(floor.force_N[~stance] == 0.0)
    assert fz.min() >= -1e-7 and np.all(np.abs(fx) <= params.body.foot_friction * fz + 1e-7)
    # each foot fixed on the ground while down: on the nominal course (speed v) its x is
    v, period = foot_path(kind).stance_speed(params.gait), params.gait.period_s
    for leg in range(len(LEGS)):                     # constant over each stance
        down = stance[leg]
        for s in np.flatnonzero(down & ~np.roll(down, 1)):
            held, i = [], 0
            while down[(s + i) % KNOTS] and i < KNOTS:
                k = (s + i) % KNOTS
                held.append(nominal_x[leg, k] + v * (floor.t[k] + period * (s + i >= KNOTS)))
                i += 1
            assert np.ptp(held) < 1e-9
    height = float(body_height(params, params.gait.y_home_m)) + com_z - params.body.foot_radius_m
    rx = np.where(stance, nominal_x - floor.x_m, 0.0)
    rz = -height - floor.z_m
    moment = (rz * fx - rx * fz).sum(0)
    y = np.array([hip_positions(params)[leg][1] for leg in LEGS])[:, None]

    def second(p):
        return (np.roll(p, -1) - 2.0 * p + np.roll(p, 1)) / dt**2

    def mean(f):
        return 0.5 * (f + np.roll(f, 1))

    scale = mass * g
    np.testing.assert_allclose(mass * second(floor.x_m), mean(fx.sum(0)), atol=1e-4 * scale)
    np.testing.assert_allclose(mass * (second(floor.z_m) + g), mean(fz.sum(0)),
                               atol=1e-4 * scale)
    np.testing.assert_allclose(inertia * second(floor.pitch_rad), mean(moment),
                               atol=1e-3 * scale * 0.1)
    np.testing.assert_allclose((y * fz).sum(0), 0.0, atol=1e-6)            # roll
    np.testing.assert_allclose((y * fx).sum(0), 0.0, atol=1e-6)            # yaw
    assert np.abs(floor.pitch_rad).max() <= max_pitch_rad(params) + 1e-5       # the solver's tolerance
    assert np.abs(floor.torque_Nm).max() == pytest.approx(floor.floor_Nm)
    assert floor.moment_residual_Nm < 1e-3 * floor.moment_scale_Nm + 1e-6
    assert abs(np.mean(floor.z_m)) < 1e-9 and abs(np.mean(floor.pitch_rad)) < 1e-9


def test_the_orderings_a_floor_keeps(params):
    """A freer body needs no more: the walk's floor is at most its level floor and its free
    height's at most its own; the trot cannot be held level (one pair at a time: no level
    balance). The least worst-motor RMS torque (the thermal floor, a cone program) heats the
    worst motor no more than the least peak torque's gait, and its peak is no lower. A payload
    raises the floor."""
    walk = with_path_defaults(params, "walk")
    floor = gait_floor(walk, "walk")
    assert floor.floor_Nm <= floor.level_Nm + 1e-6
    assert gait_floor(walk, "walk", free_height=True).floor_Nm <= floor.floor_Nm + 1e-6
    trot = gait_floor(params, "trot")
    assert trot.level_Nm is None
    thermal = gait_floor(params, "trot", thermal=True)
    rms = np.sqrt(np.mean(trot.torque_Nm**2, axis=1)).max()
    assert thermal.floor_Nm <= rms + 1e-3 and thermal.rms_current_A <= trot.rms_current_A + 1e-3
    assert np.abs(thermal.torque_Nm).max() >= trot.floor_Nm - 1e-3
    assert 0.0 < thermal.rms_current_A < params.motor.law.peak_current
    assert gait_floor(params, "trot", payload_kg=1.0).floor_Nm > trot.floor_Nm
    assert gait_floor(params, "jump") is None


def test_the_fastest_trot_runs_its_joints_at_the_no_load_speed(params):
    """The default trot is limited by speed: at the fastest frequency, the path sampled
    finely, its joints' speeds by central differences of its poses (the analysis's method), has
    its fastest joint at the motors' no-load speed (within 0.2 %), and its floor is inside the
    envelope. A motor with a third more speed (a
    gear 3/4 as large, so its torque falls too) lets the trot go faster."""
    fast = fastest_gait(params, "trot")
    assert fast["limited_by"] == "speed" and fast["frequency_hz"] > params.gait.frequency_hz
    at = with_gait(params, frequency_hz=fast["frequency_hz"],
                   samples=3000)
    joint = np.abs(sample_gait(at.leg, at.gait, "trot").qd).max()
    assert joint == pytest.approx(params.motor.no_load_speed_rad_s, rel=2e-3)
    assert within_envelope(at, gait_floor(at, "trot"))
    assert fast["speed_m_s"] == pytest.approx(
        2 * params.gait.a_m * fast["frequency_hz"] / params.gait.duty_factor)
    quick = with_changes(params, {"motor.gear_ratio": 0.75 * params.motor.gear_ratio})
    assert fastest_gait(quick, "trot")["frequency_hz"] > fast["frequency_hz"]


def test_a_motor_too_weak_for_the_gait_has_no_fastest(params):
    weak = with_changes(params, {"motor.peak_current_A": 0.3 * params.motor.law.peak_current})
    fast = fastest_gait(weak, "bound")
    assert fast["limited_by"] == "its own frequency" and math.isnan(fast["speed_m_s"])


@pytest.mark.slow
@pytest.mark.parametrize("kind, duration", [("trot", 3.5), ("bound", 3.0)])
def test_the_floor_is_below_what_the_controller_asked(kind, duration):
    """The simulated gait asked at least its floor (the run's own gait fields); a failing
    verdict names whom it blames."""
    record = run_simulation(load_scenario(gait=kind, duration_s=duration), progress=False)
    summary = summarize_run(record)
    a = summary["any_controller"]
    assert a["maneuver"] == kind and a["floor_Nm"] == pytest.approx(
        gait_floor(record.params, kind).floor_Nm)
    assert a["floor_Nm"] < a["asked_Nm"]
    if summary["verdict"] in ("fail", "not_achieved"):
        assert a["fails_for"] in ("this controller", "any controller")
    assert not math.isnan(a["floor_safety_factor"])


def test_a_floor_is_the_same_for_any_motor(params):
    """The floor does not depend on the motor (only its current does): solved afresh for
    another motor and gear it is the same, so the cache shares it (no new solve) and only the
    RMS current changes."""
    from fivebar_drake.optimal import gait_floor as module

    other = with_changes(params, {"motor.gear_ratio": 11.5, "motor.peak_current_A": 2.0})
    first = gait_floor(params, "trot")
    solved = module._solve(other, foot_path("trot"), 0.0, False, False)
    assert solved.floor_Nm == pytest.approx(first.floor_Nm, rel=1e-12)
    count = len(module._FLOORS)
    shared = gait_floor(other, "trot")
    assert len(module._FLOORS) == count and shared.floor_Nm == first.floor_Nm
    assert shared.rms_current_A != first.rms_current_A


def test_the_floors_torques_are_the_virtual_works(params):
    """The bound's floor torques recomputed at its pitched poses by another method: virtual
    work with finite differences of the forward kinematics (the foot's displacement per motor
    angle, instead of the analytic J_F) and of the links' potential energy (their centres of
    mass heights, instead of G), the ground force turned into the pitched leg plane here."""
    from fivebar_drake.mechanisms.fivebar import KNEES_OUT, link_coms
    from fivebar_drake.optimal import gait_floor as module

    p = with_path_defaults(params, "bound")
    floor = gait_floor(p, "bound")
    mass, com_z, _ = whole_body(p)
    body = module.Body(p, module.Schedule(p, foot_path("bound"), floor.t), mass, com_z)
    feet = body.poses(floor.x_m, floor.z_m, floor.pitch_rad)
    leg, g, h = p.fivebar_leg, p.robot.gravity_m_s2, 1e-6
    masses = np.array([link.mass_kg for link in p.links.values()])

    def foot_and_energy(q, branch):
        pose = leg.forward(q, branch)
        return pose.f, g * masses @ link_coms(leg.geometry, p.links, pose)[..., 1]

    for i in range(0, body.legs.size, 7):
        k, j = body.knots[i], body.legs[i]
        pose = leg.inverse(feet[i], KNEES_OUT)
        c, s = math.cos(floor.pitch_rad[k]), math.sin(floor.pitch_rad[k])
        fx, fz = floor.force_N[j, k]
        plane = np.array([-(c * fx - s * fz), s * fx + c * fz])     # -f_body x, f_body z
        tau = np.zeros(2)
        for m in range(2):
            dq = np.zeros(2)
            dq[m] = h
            (f1, v1), (f0, v0) = (foot_and_energy(pose.q + dq, pose.e_branch),
                                  foot_and_energy(pose.q - dq, pose.e_branch))
            tau[m] = (v1 - v0) / (2 * h) - (f1 - f0) / (2 * h) @ plane
        np.testing.assert_allclose(tau, floor.torque_Nm[j, k], atol=2e-5)
