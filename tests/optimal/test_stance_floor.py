"""The walking gaits' stance floors (optimal/stance_floor.py) against a closed form, the body's
balance recomputed from the forces, and the simulated gaits."""

import numpy as np
import pytest

from fivebar_drake.optimal.stance_floor import KNOTS, Stances, stance_floor
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.config import load_params, with_changes
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.sdf import body_height
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.core.footpath import foot_path


@pytest.fixture(scope="module")
def params():
    return load_params(None)


def test_level_with_one_pair_down_it_is_the_static_torque(params):
    """A trot at duty factor 0.5 held level: one diagonal pair carries the weight at every
    instant, m g / 2 a foot (the roll balance splits it evenly; no horizontal force): the
    linear program's floor is the largest static torque of the full model (leg_loads.full_model,
    the analysis's) over the stance's poses."""
    half = with_changes(params, {"gait.duty_factor": 0.5})
    floor = stance_floor(half, "trot").constant_height_Nm
    g = half.gait
    x = g.x_center_m + np.linspace(-g.a_m, g.a_m, KNOTS // 2 + 1)
    pose = half.fivebar_leg.inverse(np.stack([x, np.full_like(x, g.y_home_m)], -1))
    model = full_model(half)
    load = half.robot.total_mass_kg * half.robot.gravity_m_s2 / 2
    static = half.fivebar_leg.static_torques(type(model)(**{**model.__dict__,
                                                            "foot_load_N": load}), pose)
    assert floor == pytest.approx(np.abs(static).max(), rel=2e-3)


@pytest.mark.parametrize("kind", ["trot", "walk"])
def test_the_floors_forces_balance_the_body(params, kind):
    """Recomputed from the floor's forces and the feet's positions: the vertical forces carry
    m (g + z''), the horizontal ones cancel, every moment about the centre of mass vanishes
    (the walk's all three; the trot's roll and yaw, its pitch left to the body's rotation);
    the feet push, inside the friction cone; no stance torque exceeds the floor."""
    floor = stance_floor(params, kind)
    st = Stances(params, foot_path(kind), floor.t)
    dt = params.gait.period_s / KNOTS
    zdd = (np.roll(floor.z_m, -1) - 2 * floor.z_m + np.roll(floor.z_m, 1)) / dt**2
    fx, fz = floor.force_N[..., 0], floor.force_N[..., 1]
    mass, g = params.robot.total_mass_kg, params.robot.gravity_m_s2
    np.testing.assert_allclose(fz.sum(0), mass * (g + zdd), rtol=2e-2)
    np.testing.assert_allclose(fx.sum(0), 0.0, atol=1e-6)
    y = st.hips[:, 1:2]
    x = st.hips[:, 0:1] - np.nan_to_num(st.x)
    h = body_height(params, params.gait.y_home_m - floor.z_m)[None, :]
    np.testing.assert_allclose((y * fz).sum(0), 0.0, atol=1e-6)              # roll
    np.testing.assert_allclose((y * fx).sum(0), 0.0, atol=1e-6)              # yaw
    pitch = (-x * fz - h * fx).sum(0)
    if kind == "walk":
        np.testing.assert_allclose(pitch, 0.0, atol=1e-6)
    else:
        assert np.abs(pitch).max() > 1.0          # the trot's pair cannot hold it: relaxed
    assert fz.min() >= -1e-9 and np.all(np.abs(fx) <= params.body.foot_friction * fz + 1e-9)
    assert np.all(fz[~st.stance] == 0.0)
    assert np.abs(floor.torque_Nm).max() <= floor.floor_Nm + 1e-6
    assert abs(np.mean(floor.z_m)) < 1e-9
    assert stance_floor(params, kind, free_height=True).floor_Nm <= floor.floor_Nm + 1e-6
    assert floor.floor_Nm <= floor.constant_height_Nm + 1e-6


def test_the_thermal_floor_heats_less_than_the_peak_floor(params):
    """The least copper loss (a quadratic program) leaves the worst motor an RMS torque and
    current no larger than those of the least peak torque's trot, and its peak no smaller;
    its current is the motor law's at the stance joint speeds (below the peak current)."""
    peak, thermal = stance_floor(params, "trot"), stance_floor(params, "trot", thermal=True)
    rms = np.sqrt(np.mean(peak.torque_Nm**2, axis=1)).max()
    assert thermal.floor_Nm <= rms + 1e-3 and thermal.rms_current_A <= peak.rms_current_A + 1e-3
    assert np.abs(thermal.torque_Nm).max() >= peak.floor_Nm - 1e-3
    assert 0.0 < thermal.rms_current_A < params.motor.law.peak_current


def test_gaits_that_need_the_body_to_rotate_have_no_floor(params):
    assert stance_floor(params, "bound") is None and stance_floor(params, "pronk") is None


@pytest.mark.slow
@pytest.mark.parametrize("kind, blame", [("trot", "undecided"), ("walk", None)])
def test_the_floor_is_below_what_the_controller_asked(params, kind, blame):
    """The simulated gait asked at least its stance floor; a failing trot's verdict is
    undecided (its floor is a relaxation within the motors)."""
    record = run_simulation(load_scenario(gait=kind, duration_s=4.5), progress=False)
    summary = summarize_run(record)
    a = summary["any_controller"]
    assert a["maneuver"] == kind and a["floor_Nm"] == pytest.approx(
        stance_floor(record.params, kind).floor_Nm)     # the walk's own gait defaults
    assert a["floor_Nm"] < a["asked_Nm"]
    if summary["verdict"] in ("fail", "not_achieved") and blame:
        assert a["fails_for"] in (blame, "any controller")
