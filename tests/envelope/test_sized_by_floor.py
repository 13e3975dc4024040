"""The envelope's sizing for any controller (envelope/report.sized_by_floor): the maneuver whose
need leaves the least safety factor in the quadrant it acts, a maneuver beyond a bound first,
undecided maneuvers and those without a floor named apart and never given a safety factor."""

from fivebar_drake.envelope.report import floor_text, sized_by_floor


def entry(*phases):
    """A maneuver's any_controller from (status, floor, limit) per phase."""
    if phases == ("none",):
        return {"any_controller": None}
    table = {f"p{i}": {"status": st, "floor_Nm": f, "limit_Nm": lim, "asked_Nm": None}
             for i, (st, f, lim) in enumerate(phases)}
    floors = [p["floor_Nm"] for p in table.values()]
    return {"any_controller": {
        "phases": table, "floor_Nm": None if None in floors else max(floors),
        "floor_safety_factor": None if None in floors else
        min(p["limit_Nm"] / p["floor_Nm"] for p in table.values())}}


def test_the_least_safety_factor_in_its_quadrant_sizes_the_motors():
    """A landing's 3.24 N·m against the 6.17 N·m braking limit leaves more than a 2.9 N·m stance
    against the 5 N·m driving limit: the stance sizes the motors, not the larger floor."""
    maneuvers = {"trot": entry(("floor", 2.9, 5.0)), "drop": entry(("floor", 3.24, 6.17)),
                 "bound": entry("none")}
    s = sized_by_floor(maneuvers)
    assert s["maneuver"] == "trot" and s["floor_Nm"] == 2.9
    assert abs(s["safety_factor"] - 5.0 / 2.9) < 1e-12 and s["without_floor"] == ["bound"]


def test_a_maneuver_beyond_a_bound_sizes_them_and_an_undecided_one_does_not():
    s = sized_by_floor({"trot": entry(("floor", 2.46, 5.0)),
                        "jump": entry(("beyond bound", None, 5.0), ("floor", 2.0, 6.17))})
    assert s["maneuver"] == "jump" and s["floor_Nm"] is None and s["safety_factor"] == 0.0
    s = sized_by_floor({"trot": entry(("floor", 2.46, 5.0)),
                        "jump": entry(("undecided", None, 5.0), ("floor", 2.0, 6.17))})
    assert s["maneuver"] == "trot" and s["undecided"] == ["jump"]
    assert "Undecided for any controller" in floor_text(s)
    assert "beyond these motors" not in floor_text(s)


def test_without_any_floor_there_is_no_sizing():
    assert sized_by_floor({"walk": entry("none")}) is None


def answer_of(maneuvers, duty=None):
    """design_answer over maneuvers given as name -> (verdict, deciding check, entry(...)),
    the worst verdict as envelope_report takes it, on the packaged thresholds."""
    from fivebar_drake.envelope.report import design_answer
    from fivebar_drake.robots.quadruped.config import load_params
    from fivebar_drake.verdicts.checks import SEVERITY

    table = {}
    for name, (verdict, check, need) in maneuvers.items():
        need = dict(need)
        if need["any_controller"] and verdict == "fail" and check == "achieved":
            need["any_controller"]["fails_for"] = "any controller"
        table[name] = {"verdict": verdict, "deciding_check": check, **need}
    worst = max((v for v, _, _ in maneuvers.values()),
                key=lambda v: SEVERITY.get(v, 3))
    return design_answer(worst, table, sized_by_floor(table), duty, load_params().checks)


def test_the_designs_answer_names_who_can_do_it_in_one_short_sentence():
    """Each kind of answer from its own case: every maneuver passing carries; a torque failure
    whose need leaves a warning SF asks for a better controller; a need that leaves a failing
    SF is short of margin; a thermal failure is bounded by no need; a maneuver beyond a bound
    is beyond the motors. Each sentence at most 200 characters."""
    ok = ("pass", "torque", entry(("floor", 2.0, 5.0)))
    cases = {
        "carries": {"trot": ok, "jump": ("warn", "torque", entry(("floor", 2.0, 6.17)))},
        "better controller": {"trot": ("fail", "torque", entry(("floor", 3.0, 5.0))),
                              "jump": ok},
        "short of margin": {"trot": ("fail", "torque", entry(("floor", 4.0, 5.0)))},
        "this controller": {"trot": ("fail", "thermal", entry(("floor", 2.0, 5.0)))},
        "beyond": {"trot": ok, "jump": ("fail", "torque",
                                        entry(("beyond bound", None, 5.0)))},
    }
    for kind, maneuvers in cases.items():
        a = answer_of(maneuvers)
        assert a["kind"] == kind, (kind, a)
        assert len(a["text"]) <= 200
    a = answer_of(cases["better controller"])
    assert a["fails"] == ["trot"] and "SF 1.67" in a["text"] and "WARN" in a["text"]
    a = answer_of(cases["short of margin"])
    assert "4.00 N·m" in a["text"] and "SF 1.25" in a["text"]
    assert answer_of(cases["beyond"])["text"].startswith(
        "No: FAIL in 1 of 2 for any controller: jump beyond these motors")
    hot = {"verdict": "fail", "motors": {}}
    assert answer_of({"trot": ok}, duty=hot)["kind"] == "this controller"
