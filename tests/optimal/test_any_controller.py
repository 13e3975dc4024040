"""A simulated jump's verdict split (pipeline.any_controller): whom a failing verdict blames,
from the floor of the same jump (optimal/vertical_jump.py) and what the run's controller asked."""

import dataclasses

import pytest

from helpers import told
from fivebar_drake.gaits import Jump as JumpPath
from fivebar_drake.verdicts.rules import fails_for
from fivebar_drake.optimal.vertical_jump import jump_need
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
    assert a["phases"]["landing"]["limit_Nm"] > a["phases"]["push-off"]["limit_Nm"]   # braking
    assert "this controller failed it: a better controller would pass" in told(s)


@pytest.mark.slow
def test_the_tracked_130_mm_jump_is_never_called_impossible():
    """130 mm lies beyond the maneuver's own stroke (its optimum about 127 mm) but within the
    leg's whole reach: its need is the floor there, inside the motors, so no 'any controller'
    claim whatever the run; the run's apex stands beside the optima and the bound (and the
    tracked run rises above the stroke's optimum: the optimum is not a bound)."""
    s = summarize_run(run_simulation(load_scenario(
        gait={"kind": "jump", "height_m": 0.13}, controller={"kind": "tracking"},
        duration_s=2.8), progress=False))
    a = s["any_controller"]
    assert a["fails_for"] != "any controller" and "No controller could" not in told(s)
    assert a["phases"]["push-off"]["status"] == "floor"
    assert a["ceiling_m"] < 0.13 < a["reach_ceiling_m"] < a["bound_m"]
    assert a["reached_m"] == s["jump"]["height_m"] and a["reached_m"] > a["ceiling_m"]
    assert "this run reached" in told(s) and "the bound" in told(s)


def test_a_jump_between_the_optimum_and_the_bound_is_undecided(params):
    """The need of a jump maneuver: up to the whole reach's optimum a floor, between it and the
    point-mass bound undecided, beyond the bound no motion does it; the one rule then blames
    a failed run of each: this controller, undecided, any controller (and never any controller
    where the run did its motion)."""
    plan = JumpPath()
    top = jump_need(params, dataclasses.replace(plan, height_m=0.13))
    assert top.status == "floor" and top.reach_optimum_m < top.bound_m
    between = jump_need(params, dataclasses.replace(
        plan, height_m=0.5 * (top.reach_optimum_m + top.bound_m)))
    beyond = jump_need(params, dataclasses.replace(plan, height_m=top.bound_m + 0.005))
    assert (between.status, beyond.status) == ("undecided", "beyond bound")
    assert between.floor_Nm is None and "undecided" in between.why
    for need, blamed in ((top, "this controller"), (between, "undecided"),
                         (beyond, "any controller")):
        phases = {"push-off": {"status": need.status, "floor_Nm": need.floor_Nm,
                               "limit_Nm": params.motor.peak_torque_Nm}}
        assert fails_for("not_achieved", phases, 0.05) == blamed
        assert fails_for("fail", phases, 0.05) != "any controller"
        assert fails_for("pass", phases, 0.05) is None


def test_a_floor_is_beyond_the_motors_only_beyond_its_margin():
    """A floor within its limit, or beyond it by less than its model margin, is a failing of
    this controller; a braking phase is judged against its braking limit."""
    def phase(floor, limit):
        return {"stance": {"status": "floor", "floor_Nm": floor, "limit_Nm": limit}}
    assert fails_for("not_achieved", phase(4.9, 5.0), 0.05) == "this controller"
    assert fails_for("not_achieved", phase(5.2, 5.0), 0.05) == "this controller"
    assert fails_for("not_achieved", phase(5.4, 5.0), 0.05) == "any controller"
    assert fails_for("not_achieved", phase(5.4, 6.17), 0.05) == "this controller"
    assert fails_for("not_achieved", {"x": {"status": "unknown", "floor_Nm": None,
                                            "limit_Nm": 5.0}}, 0.05) == "unknown"


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
    """The doggo path's kind registers no need (optimal/needs.py): one phase, unknown, never
    another path's floor; a bound too short for a whole cycle has its floor and no demand to
    set beside it (asked None, not nan)."""
    s = summarize_run(run_simulation(load_scenario(gait="doggo", duration_s=0.3,
                                                   closure="ball"), progress=False))
    a = s["any_controller"]
    assert a["floor_Nm"] is None and a["phases"]["doggo"]["status"] == "unknown"
    s = summarize_run(run_simulation(load_scenario(gait="bound", duration_s=0.3,
                                                   closure="ball"), progress=False))
    a = s["any_controller"]
    assert a["floor_Nm"] > 0.0 and a["asked_Nm"] is None and a["controller_cost"] is None


@pytest.mark.slow
def test_a_trot_faster_than_the_motors_turn_is_this_paths_failing():
    """At 1.5 Hz the trot's path asks a joint beyond the motors' no-load speed (its fastest is
    about 1.37 Hz): that is this path's property, not every path's, so the failing verdict
    blames this controller (its path), and says why."""
    s = summarize_run(run_simulation(load_scenario(gait="trot", gait_frequency_hz=1.5,
                                                   duration_s=4.5), progress=False))
    a = s["any_controller"]
    assert s["verdict"] in ("fail", "not_achieved") and a["fails_for"] == "this controller"
    assert "no-load speed" in a["why"] and "another path" in a["why"]
