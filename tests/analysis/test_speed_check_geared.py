"""The closed form's speed check at 11.5:1 on the trot path (issue 28): its operating points are
the torque the motor delivers (joint torque + output friction) at the joint speed, and beyond the
no-load speed the back-EMF forces braking. B's swing passes the no-load speed braking less than
that: the check fails, as the simulation's does (tests/simulation/test_verdict.py), and no line
of report.md contradicts it."""

import math
import re

import numpy as np
import pytest

from fivebar_drake.analysis.report import markdown
from fivebar_drake.analysis.torques import analyze
from fivebar_drake.robots.quadruped.config import with_changes


@pytest.fixture(scope="module")
def geared(params):
    return analyze(with_changes(params, {"motor.gear_ratio": 11.5}), path="trot")


def outside_by_hand(m, tau, w):
    """Samples outside the envelope from the circuit alone: the motor delivers tau + tau_c
    clamp(w / 0.05) + b w; below the no-load speed driving needs R i + (k_t / 1.5) N |w| <=
    V_bus / sqrt(3); beyond it the back-EMF drives at least ((k_t / 1.5) N |w| - V) / R amperes
    against the motion, N k_t i / eta of braking at the output."""
    n, kt, r = m.gear_ratio, m.torque_constant_Nm_per_A, m.winding_resistance_ohm
    v = m.bus_voltage_V / math.sqrt(3)
    delivered = tau + m.coulomb_friction_Nm * np.clip(w / 0.05, -1, 1) + m.viscous_friction_Nm_s * w
    emf = kt / 1.5 * n * np.abs(w)
    driving = delivered * w >= 0
    current = np.abs(delivered) / (n * kt * np.where(driving, m.gear_efficiency,
                                                     1 / m.gear_efficiency))
    forced = (emf - v) / r
    return np.where(emf > v, driving | (current < forced),
                    driving & (r * current + emf > v))


def test_trot_at_11_5_fails_the_speed_check_on_the_back_emf(geared):
    m = geared.params.motor
    r = geared.results["results"]
    for model in ("seed", "full", "full_trot"):
        for j, motor in enumerate("AB"):
            tau, w = geared.torques[model].total[:, j], geared.samples.qd[:, j]
            beyond = outside_by_hand(m, tau, w)
            speed = r[model][motor]["checks"]["speed"]
            assert speed["outside_fraction"] == pytest.approx(np.mean(beyond), abs=1e-12)
    trot_b = r["full_trot"]["B"]
    assert trot_b["checks"]["speed"]["verdict"] == "fail"
    assert trot_b["checks"]["speed"]["outside_fraction"] > geared.params.checks.speed_outside_fail
    # the sample that was 'within' before: it brakes 0.034 N m at 8.924 rad/s, less than the
    # friction it must also overcome and than the 0.38 N m the back-EMF forces there
    w = geared.samples.qd[:, 1]
    k = int(np.argmax(np.abs(w)))
    assert abs(w[k]) > m.no_load_speed_rad_s
    assert abs(geared.torques["full_trot"].total[k, 1]) < m.coulomb_friction_Nm * 2


def test_report_lines_agree_with_the_checks(geared):
    """Each speed-table row: its torque-speed margin below 1 (a sample outside the envelope)
    never sits beside a passing speed check, and its speed check is the verdict table's."""
    md = markdown(geared)
    speed_rows = re.findall(r"^\| ([AB]) \| (\w+) \| [^|]+ \| [^|]+ \| (no|YES) \| [^|]+ \| "
                            r"[^|]+ \| [^|]+ \| ([\d.]+)x \| (PASS|WARN|FAIL) \|$", md, re.M)
    assert len(speed_rows) == 6
    r = geared.results["results"]
    for motor, model, beyond, margin, check in speed_rows:
        c = r[model][motor]["checks"]["speed"]
        assert check == c["verdict"].upper()
        if float(margin) < 1.0:
            assert check != "PASS"
    assert "| B | full_trot | FAIL | speed |" in md
