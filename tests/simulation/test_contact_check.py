"""The contact check (pipeline.run_contact_check, verdicts.rules.contact_check): the run again
with the foot contact softer and stiffer, the band of the worst safety factor and of every
event figure, a verdict the contact decides marginal."""

import pytest

from fivebar_drake.verdicts.checks import Checks
from fivebar_drake.verdicts.rules import contact_check, contact_checked_verdict
from fivebar_drake.pipeline import (CONTACT_FACTORS, run_contact_check, run_simulation,
                                    summarize_run)
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.simulation.summary_text import markdown

CHECKS = Checks(sf_pass=2.0, sf_warn=1.5)


def summary(sf, verdict="warn", peak=3.0):
    return {"legs": {"FL": {"A": {"safety_factor": sf}, "B": {"safety_factor": 9.0}}},
            "verdict": verdict, "deciding_check": "torque", "contact": {"stiffness_N_m": 1e6},
            "landing": {"peak_torque_Nm": peak, "planned": {}}, "jump": None}


def test_a_band_across_a_threshold_or_a_verdict_that_moves_is_marginal():
    far = contact_check(summary(1.7), "warn", {"softer": summary(1.72), "stiffer": summary(1.68)},
                        CHECKS)
    assert not far["marginal"] and far["worst_sf_band"] == [1.68, 1.72]
    assert far["events"]["landing"]["peak_torque_Nm"] == [3.0, 3.0]
    near = contact_check(summary(1.52), "warn", {"softer": summary(1.55),
                                                 "stiffer": summary(1.49, "fail", 3.4)}, CHECKS)
    assert near["marginal"] and near["events"]["landing"]["peak_torque_Nm"] == [3.0, 3.4]
    assert contact_checked_verdict("warn", near) == "marginal"
    flips = contact_check(summary(1.7), "not_achieved",
                          {"softer": summary(1.7, "warn"), "stiffer": summary(1.7, "warn")},
                          CHECKS)
    assert contact_checked_verdict("not_achieved", flips) == "marginal"
    assert "achieved with softer, stiffer contact and not with nominal" in flips["why"]


@pytest.mark.slow
def test_the_jumps_contact_check_reports_its_bands():
    """The default jump with the contact check: each variant ran with its stiffness, every band
    holds the run's own figure, and summary.md says so."""
    record = run_simulation(load_scenario(gait="jump", duration_s=2.8), progress=False)
    contacts = run_contact_check(record, progress=False)
    k = record.params.body.foot_stiffness_N_m
    assert {label: r.params.body.foot_stiffness_N_m for label, r in contacts.items()} == {
        label: f * k for label, f in CONTACT_FACTORS.items()}
    s = summarize_run(record, contacts=contacts)
    c = s["contact_check"]
    assert set(c["verdicts"]) == {"nominal", *CONTACT_FACTORS}
    lo, hi = c["events"]["landing"]["peak_torque_Nm"]
    assert lo <= s["landing"]["peak_torque_Nm"] <= hi
    lo, hi = c["worst_sf_band"]
    assert lo <= c["worst_sf"]["nominal"] <= hi
    assert "contact check (foot stiffness" in markdown(s, record.params)
