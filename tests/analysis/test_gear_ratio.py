"""The gear-ratio trade against closed-form optima: with the torque-speed line alone the safety
factor tau_m N (1 - w N / w_m0) / T peaks at N = w_m0 / (2 w); with the rotor alone
tau_m N / (T + N^2 J a) peaks at N = sqrt(T / (J a))."""

import dataclasses

import numpy as np
import pytest

from fivebar_drake.analysis.gear_ratio import gear_trade, safety_factors


@pytest.fixture()
def motor(params):
    return dataclasses.replace(params.motor, rotor_inertia_kg_m2=2e-6)


def test_speed_limited_optimum(motor):
    tau_m, w_m0 = motor.peak_torque_Nm / motor.gear_ratio, motor.no_load_speed_rad_s * 8
    n = 50
    load, qd, qdd = np.full((n, 2), 1.0), np.full((n, 2), 2.0), np.zeros((n, 2))
    qd[:, 1] = 1.0                                    # motor B slower: A decides
    g = gear_trade(motor, load, qd, qdd)
    assert g.best_ratio == pytest.approx(w_m0 / 4.0, rel=1e-6)
    assert g.best_safety == pytest.approx(tau_m * w_m0 / 8.0, rel=1e-9)
    assert g.current_safety == pytest.approx(motor.peak_torque_Nm * (1 - 2.0 / 12.566370614359172),
                                             rel=1e-12)


def test_inertia_limited_optimum(motor):
    tau_m = motor.peak_torque_Nm / motor.gear_ratio
    j, a, t = motor.rotor_inertia_kg_m2, 1000.0, 1.0
    load, qd, qdd = np.full((3, 2), t), np.zeros((3, 2)), np.full((3, 2), a)
    g = gear_trade(motor, load, qd, qdd)
    assert g.best_ratio == pytest.approx(np.sqrt(t / (j * a)), rel=1e-6)
    assert g.best_safety == pytest.approx(tau_m / (2 * np.sqrt(t * j * a)), rel=1e-9)


def test_readings_at_the_current_ratio(params):
    """Without the rotor the torque-speed reading is the analysis' torque-speed margin, and
    without either effect the seed's safety factor."""
    from fivebar_drake.analysis.torques import analyze

    an = analyze(params)
    tb, s = an.torques["full"], an.samples
    r = an.results["results"]["full"]
    for flags, key in (((True, False), "torque_speed_margin"), ((False, False), "safety_factor")):
        sf = safety_factors(params.motor, tb.total, s.qd, s.qdd, [params.motor.gear_ratio], *flags)
        np.testing.assert_allclose(sf[0], [r["A"][key], r["B"][key]], rtol=1e-12)
    assert an.metrics.gear.current_safety <= min(r["A"]["torque_speed_margin"],
                                                 r["B"]["torque_speed_margin"])
