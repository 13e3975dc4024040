"""A simulated jump's verdict split (pipeline.any_controller): whom a failing verdict blames,
from the floor of the same jump (optimal/vertical_jump.py) and what the run's controller asked."""

import pytest

from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.simulation.scenario import load_scenario


def jump_summary(height_m):
    return summarize_run(run_simulation(load_scenario(
        gait={"kind": "jump", "height_m": height_m}, duration_s=2.8), progress=False))


@pytest.mark.slow
def test_a_jump_the_motors_can_do_fails_for_this_controller():
    """100 mm: the package's controller fails the torque check, the floor (push-off and
    landing) is inside the motors (its safety factor above the warning threshold): a better
    controller would pass."""
    s = jump_summary(0.10)
    a = s["any_controller"]
    assert s["verdict"] == "fail" and a["fails_for"] == "this controller"
    assert a["floor_Nm"] < a["asked_Nm"] and a["floor_safety_factor"] >= 1.5
    for phase in ("push-off", "landing"):
        assert a["phases"][phase]["floor_Nm"] <= a["phases"][phase]["asked_Nm"]
    assert "fails for this controller" in s["answer"]


@pytest.mark.slow
def test_a_jump_beyond_the_motors_fails_for_any_controller():
    """130 mm on a stroke whose highest jump is lower: no controller could do it, and the
    answer says how high the stroke allows."""
    s = jump_summary(0.13)
    a = s["any_controller"]
    assert s["verdict"] == "not_achieved" and a["fails_for"] == "any controller"
    assert a["floor_Nm"] is None and a["ceiling_m"] < 0.13
    assert "beyond what the motors allow" in a["why"] and "for any controller" in s["answer"]


@pytest.mark.slow
def test_the_drops_landing_floor_is_below_what_the_controller_asked(simulated):
    """The drop from 0.1 m: the landing's floor (stopping the touchdown speed within the
    landing stroke, braking) is below what the package's controller asked over its landing;
    the highest drop the stroke absorbs lies above the drop."""
    s = summarize_run(simulated(gait="drop", duration_s=2.0))
    a = s["any_controller"]
    landing = a["phases"]["landing"]
    assert landing["floor_Nm"] <= landing["asked_Nm"] and a["ceiling_m"] > 0.1
    assert a["floor_Nm"] == landing["floor_Nm"]


def test_a_path_without_a_floor_has_none_and_a_run_without_demand_asks_nothing():
    """The doggo path has no floor (gait_floor.KINDS); a bound too short for a whole cycle has
    its floor and no demand to set beside it (asked None, not nan)."""
    s = summarize_run(run_simulation(load_scenario(gait="doggo", duration_s=0.3,
                                                   closure="ball"), progress=False))
    assert s["any_controller"] is None
    s = summarize_run(run_simulation(load_scenario(gait="bound", duration_s=0.3,
                                                   closure="ball"), progress=False))
    a = s["any_controller"]
    assert a["floor_Nm"] > 0.0 and a["asked_Nm"] is None and a["controller_cost"] is None


@pytest.mark.slow
def test_a_trot_faster_than_the_motors_turn_fails_for_any_controller():
    """At 1.5 Hz the trot's path asks a joint beyond the motors' no-load speed (its fastest is
    about 1.37 Hz): whatever check decided, no controller could follow it."""
    s = summarize_run(run_simulation(load_scenario(gait="trot", gait_frequency_hz=1.5,
                                                   duration_s=4.5), progress=False))
    a = s["any_controller"]
    assert s["verdict"] in ("fail", "not_achieved") and a["fails_for"] == "any controller"
    assert "no-load speed" in a["why"]
