"""The tracking controller (simulation/tracking.py) on the Drake Diagram: the bound, the jump and
the drop tracked against the foot/leg controller's, and the scenarios it refuses."""

import pytest

from fivebar_drake.core.validation import ParameterError
from fivebar_drake.optimal.gait_floor import gait_floor
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.simulation.scenario import load_scenario


def worst_p99(summary):
    return max(m["demand_p99_Nm"] for motors in summary["legs"].values()
               for m in motors.values())


@pytest.mark.slow
def test_the_tracked_bound_asks_less_than_the_foot_leg_controllers():
    """4 s of the default bound, tracked from the ramp's start (takeover 0, blended in over a
    period): the run is achieved, no motor at its peak current and none on its voltage line
    more than 0.1 % of the time (an earlier issue asked every clipped fraction 0; with the
    floor's force in full from touchdown, which the bound at its top speed needs, the front A
    motors touch their voltage line for 3 of 4,000 samples), its worst demand p99 lies below
    the foot/leg controller's on the same bound, and no lower than the bound's floor."""
    runs = {kind: summarize_run(run_simulation(load_scenario(
        gait="bound", duration_s=4.0, controller={"kind": kind, **extra}), progress=False))
        for kind, extra in (("tracking", {"takeover": 0.0}), ("foot_leg", {}))}
    tracked = runs["tracking"]
    assert tracked["verdict"] != "not_achieved"
    assert all(m["clipped_peak_fraction"] == 0.0 and m["clipped_line_fraction"] <= 0.001
               for motors in tracked["legs"].values() for m in motors.values())
    assert worst_p99(tracked) < worst_p99(runs["foot_leg"])
    a = tracked["any_controller"]
    assert a["floor_Nm"] <= a["asked_Nm"]


@pytest.mark.slow
def test_the_tracked_trot_is_achieved_without_a_yaw_wrench():
    """The default trot, tracked: achieved, no motor at a limit more than 1 % of the time, and
    its worst demand p99 at most 2x the floor. On a diagonal pair a pitch moment has no other
    lever than the two feet pushing apart along x (a yaw couple): the feedback's split held
    no yaw row, and its least-norm answer to a steady pitch error was a yaw couple of ~30 N per
    foot that saturated a rear motor 12.8 % of the time (NOT ACHIEVED, asked 4.2x the floor)."""
    summary = summarize_run(run_simulation(load_scenario(
        gait="trot", duration_s=4.5, controller={"kind": "tracking"}), progress=False))
    assert summary["verdict"] != "not_achieved", summary["answer"]
    assert all(m["clipped_peak_fraction"] + m["clipped_line_fraction"] <= 0.01
               for motors in summary["legs"].values() for m in motors.values())
    a = summary["any_controller"]
    assert a["floor_Nm"] <= a["asked_Nm"] <= 2.0 * a["floor_Nm"]


@pytest.mark.slow
@pytest.mark.parametrize("gait, duration_s", [("jump", 2.6), ("drop", 2.0)])
def test_the_tracked_jump_and_drop_ask_less_than_the_foot_leg_controllers(simulated, gait,
                                                                           duration_s):
    """The packaged 60 mm jump and 0.1 m drop, tracked (the optimal push, the least-torque
    catch): achieved, each phase asking at least its floor (a floor is a floor) and less than
    the foot/leg controller asks on the same maneuver (the session's run of it)."""
    tracked = summarize_run(run_simulation(load_scenario(
        gait=gait, duration_s=duration_s, controller={"kind": "tracking"}), progress=False))
    alone = summarize_run(simulated(gait=gait, duration_s=duration_s))
    assert tracked["verdict"] in ("pass", "warn", "fail")
    for phase, p in tracked["any_controller"]["phases"].items():
        assert p["floor_Nm"] <= p["asked_Nm"] < alone["any_controller"]["phases"][phase]["asked_Nm"]


@pytest.mark.parametrize("fields, field", [
    ({"gait": "seed_ellipse"}, "scenario.gait"),
    ({"gait": "stand_up"}, "scenario.gait"),
    ({"gait": "bound", "phases_rad": [0.0, 0.0, 0.0, 0.0]}, "scenario.phases_rad")])
def test_it_refuses_what_it_cannot_track(fields, field):
    """A path without a floor, or phases other than the gait's own: refused when the scenario
    is checked (before anything runs), naming the field."""
    with pytest.raises(ParameterError) as err:
        load_scenario(controller={"kind": "tracking"}, **fields)
    assert err.value.field == field


def test_the_plan_is_the_floors_motion():
    """The controller's plan at the floor's knots is the floor's forces and pitch."""
    from fivebar_drake.optimal.gait_floor import whole_body
    from fivebar_drake.simulation.tracking import Plan
    scenario = load_scenario(gait="bound", controller={"kind": "tracking"})
    params = scenario.load_params()
    floor = gait_floor(params, scenario.gait)
    plan = Plan(floor, params, scenario.gait.stance_speed(params.gait), whole_body(params)[1])
    for k in (0, 7, 30):
        forces, body = plan.at(floor.t[k] + 3 * params.gait.period_s)
        assert forces == pytest.approx(floor.force_N[:, k], abs=1e-9)
        assert body[3] == pytest.approx(floor.pitch_rad[k], abs=1e-12)


def test_a_tracked_drop_beyond_what_any_stroke_absorbs_is_judged_not_a_crash(tmp_path, capsys):
    """A drop from 0.35 m with the tracking controller (its landing stroke absorbs 250 mm; even
    the whole reach gives way): the catch plan takes the soonest stop over the whole reach, the
    run happens and is judged (the legs give way: not achieved, exit 1, every file written),
    never an internal error (issue 44: IndexError in CatchPlan)."""
    import json

    from fivebar_drake.cli import main

    scenario = tmp_path / "drop.yaml"
    scenario.write_text("gait: {kind: drop, height_m: 0.35}\ncontroller: {kind: tracking}\n"
                        "duration_s: 1.6\n")
    assert main(["simulate", "--scenario", str(scenario), "--out", str(tmp_path / "run")]) == 1
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["verdict"] in ("not_achieved", "insufficient")
    assert "internal error" not in capsys.readouterr().err
