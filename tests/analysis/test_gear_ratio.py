"""The gear-ratio trade against closed-form optima: with a plain torque-speed line alone the
safety factor tau_m N (1 - w N / w_m0) / T peaks at N = w_m0 / (2 w); with the BLDC envelope
N min(I_peak, (V - k_e N w) / R) peaks where the voltage limit meets the peak current when that
lies beyond V / (2 k_e w); with the rotor alone tau_m N / (T + N^2 J a) peaks at
N = sqrt(T / (J a)). T is the torque the motor delivers: the joint's plus the output friction
tau_c + b w (Coulomb at its full value beyond 0.05 rad/s)."""

import dataclasses
import math

import numpy as np
import pytest

from fivebar_drake.analysis.gear_ratio import gear_trade, safety_factors
from fivebar_drake.actuators.motor import LineMotor


@pytest.fixture()
def motor(params):
    return dataclasses.replace(params.motor, rotor_inertia_kg_m2=2e-6)


def test_speed_limited_optimum_of_a_line():
    tau_m, w_m0 = 0.625, 32 * math.pi
    line = LineMotor("torque_speed_line", tau_m, w_m0, 8.0, 2e-6, 0.0, 0.0)
    n = 50
    load, qd, qdd = np.full((n, 2), 1.0), np.full((n, 2), 2.0), np.zeros((n, 2))
    qd[:, 1] = 1.0                                    # motor B slower: A decides
    g = gear_trade(line, load, qd, qdd)
    assert g.best_ratio == pytest.approx(w_m0 / 4.0, rel=1e-6)
    assert g.best_safety == pytest.approx(tau_m * w_m0 / 8.0, rel=1e-9)
    assert g.current_safety == pytest.approx(5.0 * (1 - 2.0 / (4 * math.pi)), rel=1e-12)


def test_speed_limited_optimum_of_the_bldc(motor):
    n = 50
    load, qd, qdd = np.full((n, 2), 1.0), np.full((n, 2), 2.0), np.zeros((n, 2))
    qd[:, 1] = 1.0
    g = gear_trade(motor, load, qd, qdd)
    v, k_e = motor.bus_voltage_V / math.sqrt(3), motor.torque_constant_Nm_per_A / 1.5
    r, i = motor.winding_resistance_ohm, motor.peak_current_A
    corner = (v - r * i) / (k_e * 2.0)
    assert corner > v / (2 * k_e * 2.0)              # the voltage branch falls beyond it
    need = 1.0 + motor.coulomb_friction_Nm + motor.viscous_friction_Nm_s * 2.0   # motor A
    assert g.best_ratio == pytest.approx(corner, rel=1e-6)
    assert g.best_safety == pytest.approx(corner * motor.gear_efficiency
                                          * motor.torque_constant_Nm_per_A * i / need, rel=1e-9)


def test_inertia_limited_optimum(motor):
    tau_m = motor.peak_torque_Nm / motor.gear_ratio       # per unit ratio, through the gearbox
    j, a, t = motor.rotor_inertia_kg_m2, 1000.0, 1.0
    load, qd, qdd = np.full((3, 2), t), np.zeros((3, 2)), np.full((3, 2), a)
    g = gear_trade(motor, load, qd, qdd)
    assert g.best_ratio == pytest.approx(np.sqrt(t / (j * a)), rel=1e-6)
    assert g.best_safety == pytest.approx(tau_m / (2 * np.sqrt(t * j * a)), rel=1e-9)


def test_readings_at_the_current_ratio(params):
    """Without the rotor the torque-speed reading is the analysis' torque-speed margin, and
    without either effect the torque check's safety factor (each sample against its own
    quadrant's peak)."""
    from fivebar_drake.analysis.torques import analyze

    an = analyze(params)
    tb, s = an.torques["full"], an.samples
    r = an.results["results"]["full"]
    for flags, pick in (((True, False), lambda m: m["torque_speed_margin"]),
                        ((False, False), lambda m: m["checks"]["torque"]["sf"])):
        sf = safety_factors(params.motor, tb.total, s.qd, s.qdd, [params.motor.gear_ratio], *flags)
        np.testing.assert_allclose(sf[0], [pick(r["A"]), pick(r["B"])], rtol=1e-12)
    assert an.metrics.gear.current_safety <= min(r["A"]["torque_speed_margin"],
                                                 r["B"]["torque_speed_margin"])


def test_the_verdict_counts_the_reflected_rotor_inertia(params):
    """Issue 33's seventh class: with a heavy rotor (0.01 kg m^2: 0.64 kg m^2 at 8:1) the full
    model's torque check fails, and its safety factor is the gear trade's at the current ratio
    with the rotor added to the links' torque (the trade's own, separate reading); the seed's
    model, which has no rotor, is unchanged by it."""
    from fivebar_drake.analysis.torques import analyze
    from fivebar_drake.robots.quadruped.config import with_changes

    heavy = with_changes(params, {"motor.rotor_inertia_kg_m2": 0.01})
    an, light = analyze(heavy), analyze(params)
    tb, s = an.torques["full"], an.samples
    full = an.results["results"]["full"]
    sf = safety_factors(heavy.motor, tb.joint, s.qd, s.qdd, [heavy.motor.gear_ratio], False, True)
    np.testing.assert_allclose(sf[0], [full["A"]["checks"]["torque"]["sf"],
                                       full["B"]["checks"]["torque"]["sf"]], rtol=1e-12)
    assert max(full[m]["checks"]["torque"]["sf"] for m in "AB") < 1.0
    assert full["A"]["verdict"] == "fail"
    seed, seed_light = an.results["results"]["seed"], light.results["results"]["seed"]
    assert seed["A"]["peak_torque_Nm"] == seed_light["A"]["peak_torque_Nm"]
