"""A coaxial 5-bar leg (both hips on one axis, equal upper links: Stanford Doggo's and
Minitaur's layout) through the same checks as the seeds' offset leg: FK(IK) in every real mode,
the degenerate modes refused, J_F against finite differences, the static torques against
Drake's projected inverse dynamics, and a short simulation whose loops stay closed."""

import numpy as np
import pytest

from fivebar_drake.mechanisms.fivebar import UnreachableError, sample_gait
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.closure import fixed_leg
from fivebar_drake.robots.quadruped.config import load_params, with_changes
from fivebar_drake.robots.quadruped.inverse_dynamics import projected_inverse_dynamics
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.simulation.scenario import load_scenario

DOGGO_LIKE = {"leg.motor_a_m": (0.0, 0.0), "leg.motor_b_m": (0.0, 0.0), "leg.ac_m": 0.09,
              "leg.bd_m": 0.09, "leg.ce_m": 0.162, "leg.de_m": 0.162, "leg.ef_m": 0.0}
REAL_MODES = ((1, 1), (-1, -1))          # the two others put both knees on one point


@pytest.fixture(scope="module")
def coaxial():
    params = with_changes(load_params(), DOGGO_LIKE)
    return params, params.fivebar_leg, sample_gait(params.leg, params.gait).pose.f[::12]


def test_round_trip_in_every_real_mode_and_degenerate_modes_refused(coaxial):
    params, leg, points = coaxial
    for mode in REAL_MODES:
        pose = leg.inverse(points, mode)
        assert any(np.allclose(leg.forward(pose.q, b).f, points, atol=1e-12)
                   for b in leg.branches), mode
        assert np.min(np.linalg.norm(pose.c - pose.d, axis=-1)) > 1e-3
    for mode in ((1, -1), (-1, 1)):
        with pytest.raises(UnreachableError, match="coincide"):
            leg.inverse(points, mode)
        assert np.isnan(leg.inverse(points, mode, strict=False).q).all()


def test_foot_jacobian_against_finite_differences(coaxial):
    params, leg, points = coaxial
    for mode in REAL_MODES:
        pose = leg.inverse(points, mode)
        branch = next(b for b in leg.branches
                      if np.allclose(leg.forward(pose.q, b).f, points, atol=1e-12))
        h = 1e-6
        fd = np.stack([(leg.forward(pose.q + e, branch).f - leg.forward(pose.q - e, branch).f)
                       / (2 * h) for e in np.eye(2) * h], axis=-1)
        assert leg.tool_jacobian(pose) == pytest.approx(fd, rel=1e-6, abs=1e-9)


def test_static_torques_against_drake(coaxial):
    params, leg, points = coaxial
    model = full_model(params)
    plant, context, instance, idx = fixed_leg(params)
    for mode in REAL_MODES:
        pose = leg.inverse(points, mode)
        rest = np.zeros(pose.q.shape)
        drake = projected_inverse_dynamics(plant, context, instance, params, "leg", idx, pose,
                                           rest, rest, model.foot_load_N)
        mine = leg.static_torques(model, pose)
        assert mine == pytest.approx(drake, rel=1e-9, abs=1e-9 * np.max(np.abs(drake)))


@pytest.mark.slow
def test_short_trot_keeps_the_loops_closed(coaxial):
    params, _, _ = coaxial
    record = run_simulation(load_scenario(duration_s=2.0), params, progress=False)
    summary = summarize_run(record)
    assert summary["completed"] and not record.error
    assert summary["max_loop_gap_m"] < 1e-4
    assert summary["max_tilt_deg"] < 10.0
