"""Achievement holds across the plant step (issue 39): the pronk of a heavy-rotor actuator (the
AK80-9's reflected inertia, 60x the default's) was not achieved at 1 ms and achieved at 0.5 ms,
because an early touchdown froze the first pair down and the gait flipped between two patterns
with the step. All four feet land together in a pronk: the path declines early touchdown, and
the same design does its motion at both steps."""

import pytest

from fivebar_drake.codesign.designs import design_params
from fivebar_drake.gaits import foot_path
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.config import load_params, with_path_defaults
from fivebar_drake.simulation.scenario import load_scenario


def test_the_pronk_declines_early_touchdown_and_the_trot_keeps_it():
    assert not foot_path("pronk").early_touchdown and foot_path("trot").early_touchdown


@pytest.mark.slow
def test_a_heavy_rotor_pronk_does_its_motion_at_both_steps():
    params = design_params(with_path_defaults(load_params(), "pronk"),
                           {"motor": "cubemars_ak80_9", "gearbox": "built_in",
                            "motor.gear_ratio": 9.0, "leg.ce_m": 0.145})
    speeds = []
    for step in (1e-3, 5e-4):
        s = summarize_run(run_simulation(load_scenario(gait="pronk", duration_s=3.5,
                                                       time_step_s=step), params,
                                         progress=False))
        assert s["verdict"] not in ("not_achieved", "insufficient"), (step, s["answer"])
        speeds.append(s["mean_forward_speed_m_s"])
    assert abs(speeds[0] / speeds[1] - 1.0) < 0.15
