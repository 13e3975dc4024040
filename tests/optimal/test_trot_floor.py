"""The trot's stance floor (optimal/trot_floor.py) against a closed form, its own physics and
the simulated trot."""

import numpy as np
import pytest

from fivebar_drake.core.footpath import Trot
from fivebar_drake.optimal.trot_floor import KNOTS, trot_floor
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.config import load_params, with_changes
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.simulation.scenario import load_scenario


@pytest.fixture(scope="module")
def params():
    return load_params(None)


def test_level_with_one_pair_down_it_is_the_static_torque(params):
    """At duty factor 0.5 and constant height one pair carries the weight at every instant,
    m g / 2 a foot: the linear program's floor at constant height is the largest static torque
    of the full model (leg_loads.full_model, the analysis's) over the stance's poses."""
    half = with_changes(params, {"gait.duty_factor": 0.5})
    floor = trot_floor(half).constant_height_Nm
    g = half.gait
    x = g.x_center_m + np.linspace(-g.a_m, g.a_m, KNOTS // 2 + 1)
    pose = half.fivebar_leg.inverse(np.stack([x, np.full_like(x, g.y_home_m)], -1))
    model = full_model(half)
    load = half.robot.total_mass_kg * half.robot.gravity_m_s2 / 2
    static = half.fivebar_leg.static_torques(type(model)(**{**model.__dict__,
                                                            "foot_load_N": load}), pose)
    assert floor == pytest.approx(np.abs(static).max(), rel=1e-3)


def test_the_floor_carries_the_robot(params):
    """The optimal trot's forces carry the weight and the body's vertical acceleration at every
    knot (2 F_1(t) + 2 F_1(t + T/2) = m (g + z'')), push only, and no stance torque exceeds the
    floor; letting the body rise lowers it; the body's mean height is the gait's."""
    trot = trot_floor(params)
    period = params.gait.period_s
    dt = period / KNOTS
    zdd = (np.roll(trot.z_m, -1) - 2 * trot.z_m + np.roll(trot.z_m, 1)) / dt**2
    mass, g = params.robot.total_mass_kg, params.robot.gravity_m_s2
    half = KNOTS // 2
    total = 2 * trot.force_N[:half] + 2 * trot.force_N[half:]
    np.testing.assert_allclose(total, mass * (g + zdd[:half]), rtol=2e-2)
    assert trot.force_N.min() >= -1e-9 and np.abs(trot.torque_Nm).max() <= trot.floor_Nm + 1e-6
    assert abs(np.mean(trot.z_m)) < 1e-9
    assert trot_floor(params, free_height=True).floor_Nm <= trot.floor_Nm
    assert trot.floor_Nm <= trot.constant_height_Nm


@pytest.mark.slow
def test_the_trot_floor_is_below_what_the_controller_asked(params):
    summary = summarize_run(run_simulation(load_scenario(duration_s=4.5), progress=False))
    a = summary["any_controller"]
    assert a["maneuver"] == "trot" and a["floor_Nm"] == pytest.approx(trot_floor(params).floor_Nm)
    assert a["floor_Nm"] < a["asked_Nm"]
    assert trot_floor(params, Trot(duty_factor=0.75)).floor_Nm == pytest.approx(a["floor_Nm"])


def test_the_thermal_floor_heats_less_than_the_peak_floor(params):
    """The least copper loss (a quadratic program) leaves the worst motor an RMS torque and
    current no larger than those of the least peak torque's trot, and its peak no smaller;
    its current is the motor law's at the stance joint speeds (below the peak current)."""
    peak, thermal = trot_floor(params), trot_floor(params, thermal=True)
    rms = np.sqrt(np.mean(peak.torque_Nm**2, axis=0)).max()
    assert thermal.floor_Nm <= rms + 1e-3 and thermal.rms_current_A <= peak.rms_current_A + 1e-3
    assert np.abs(thermal.torque_Nm).max() >= peak.floor_Nm - 1e-3
    assert 0.0 < thermal.rms_current_A < params.motor.law.peak_current
