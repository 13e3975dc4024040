"""The simulation's limit report: a run that reaches a limit says which leg, which limit, when
first, for how long and how far, checked against the joint positions Drake logged through a
second chain (the D side of each loop with Drake's knee angle, not the motor angles' forward
kinematics); Drake's joint limit holds a knee at its least angle; the default run reaches
none."""

import numpy as np
import pytest

from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.config import check_path, load_params, with_changes
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.simulation.run_statistics import LIMIT_REACHED
from fivebar_drake.simulation.summary_text import markdown

# 0.2 s standing, 0.3 s ramp, one whole trot cycle
SHORT = dict(duration_s=1.5, stand_s=0.2, ramp_s=0.3)
# Within the planned trot (170 .. 209 mm from the hips, knees >= 66.99 deg) but reached by the
# simulated trot, whose stance legs and catch reflex leave the plan (measured 166 mm, 65.3 deg
# without limits)
TOUCHED = {"limits.extension_min_m": 0.1699, "limits.knee_min_deg": 66.8}


def run(params):
    record = run_simulation(load_scenario(**SHORT), params, progress=False)
    assert not record.error
    return record, summarize_run(record)


def logged(record) -> dict[str, np.ndarray]:
    """Per leg (rows, legs): the extension (m) through the D side of the loop, B + BD u(theta_B)
    + (DE + EF) u(theta_B + phi_D), from the hips' midpoint, and the knee angles (deg) 180 -
    |phi| from Drake's knee joints, at the end of each recorded interval."""
    leg, lay = record.params.leg, record.layout
    x = np.stack([record.table["state"][:, lay.indices[name].q] for name in lay.legs], 1)
    ta, tb, pc, pd = np.moveaxis(x, -1, 0)
    u = lambda a: np.stack([np.cos(a), np.sin(a)], -1)  # noqa: E731
    foot = leg.b + leg.bd_m * u(tb) + (leg.de_m + leg.ef_m) * u(tb + pd)
    knee = lambda phi: 180.0 - np.degrees(np.abs(np.arctan2(np.sin(phi), np.cos(phi))))  # noqa
    return {"extension": np.linalg.norm(foot - (leg.a + leg.b) / 2, axis=-1),
            "knee": np.minimum(knee(pc), knee(pd))}


@pytest.fixture(scope="module")
def touched():
    params = with_changes(load_params(), TOUCHED)
    check_path(params, "trot")                        # the trot planned is within the limits
    return run(params)


def test_a_run_that_reaches_limits_names_leg_limit_and_time(touched):
    record, summary = touched
    report, ref, t = summary["limits"], logged(record), record.table["t"]
    assert report["set"] == {"extension_min_m": 0.1699, "knee_min_deg": 66.8, **{
        k: v for k, v in load_params().limits.given.items()
        if k not in ("extension_min_m", "knee_min_deg")}}
    hits = {(h["leg"], h["field"]): h for h in report["hits"]}
    assert {field for _, field in hits} == set(TOUCHED)
    for field, quantity, tol in (("limits.extension_min_m", "extension", LIMIT_REACHED["m"]),
                                 ("limits.knee_min_deg", "knee", LIMIT_REACHED["deg"])):
        bound = TOUCHED[field]
        named = {leg for leg, f in hits if f == field}
        surely = {leg for i, leg in enumerate(record.layout.legs)
                  if ref[quantity][:, i].min() < bound + tol / 2}
        maybe = {leg for i, leg in enumerate(record.layout.legs)
                 if ref[quantity][:, i].min() < bound + 2 * tol}
        assert surely and surely <= named <= maybe, (field, named, surely, maybe)
        for leg in named:
            h, i = hits[(leg, field)], record.layout.legs.index(leg)
            near = np.flatnonzero(ref[quantity][:, i] < bound + 2 * tol)
            assert 0.0 < h["first_t_s"] <= SHORT["duration_s"]
            assert abs(h["first_t_s"] - t[near[0]]) <= 0.02
            assert h["share_of_time"] <= (near.size + 2) / len(t)
    # the extension is no joint's range: the leg goes past it; the knee's is: Drake stops it
    worst = min(h["worst_value"] for (leg, f), h in hits.items() if f == "limits.extension_min_m")
    assert worst < 0.1699 and worst == pytest.approx(ref["extension"].min(), abs=5e-4)
    assert ref["knee"].min() > 66.8 - 0.02
    assert ref["knee"].min() < 66.8 + LIMIT_REACHED["deg"]          # it did reach the stop
    text = markdown(summary, record.params)
    assert "limits reached: " in text and "deg, limits.knee_min_deg)" in text


def test_the_default_run_reaches_no_limit():
    record, summary = run(load_params())
    assert summary["limits"] == {"set": load_params().limits.given, "hits": []}
    ref, lim = logged(record), load_params().limits
    assert ref["extension"].min() > lim.extension_min_m + LIMIT_REACHED["m"]
    assert ref["extension"].max() < lim.extension_max_m - LIMIT_REACHED["m"]
    assert ref["knee"].min() > lim.knee_min_deg + LIMIT_REACHED["deg"]
    assert "limits: none reached (8 set in [limits])" in markdown(summary, record.params)


def test_never_reached_a_limit_covers_every_motor(simulated):
    """The answer's "never reached a limit" speaks for every motor: where the worst motor sat at
    no limit but another did, the answer names that one (the highest jump said "it never
    reached a limit" while its front B motors sat at their voltage limit)."""
    import copy

    from fivebar_drake.simulation.summary_text import answer_details

    record = simulated(duration_s=4.5, closure="ball")
    s = copy.deepcopy(summarize_run(record))
    if s["verdict"] in ("not_achieved", "insufficient"):
        pytest.skip("the shared run has no torque answer")
    for ms in s["legs"].values():
        for m in ms.values():
            m["saturated_fraction"], m["limit_shares"] = 0.0, {}
    assert "no motor reached a limit" in " ".join(answer_details(s, record.params))
    worst = s["worst_motor"].split()
    other = next((leg, name) for leg, ms in s["legs"].items() for name in ms
                 if [leg, name] != worst)
    m = s["legs"][other[0]][other[1]]
    m["saturated_fraction"] = 0.029
    m["limit_shares"] = {"driving_voltage": 0.029}
    text = " ".join(answer_details(s, record.params))
    assert "it never reached a limit" in text
    assert (f"Other motors at a limit (share of the time, each limit in the table): "
            f"{other[0]} {other[1]} 2.9%") in text
