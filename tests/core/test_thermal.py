"""The winding-temperature model against a hand-computed step response and a numerical
integration of the heat balance C dT/dt = P - (T - T_ambient) / R_th."""

import dataclasses
import math

import numpy as np
import pytest

from fivebar_drake.actuators.thermal import thermal_margin, winding_temperature


@pytest.fixture()
def motor(params):
    """Round numbers: R = 2 ohm (copper loss 1.5 R i^2 = 3 i^2), R_th = 5 K/W, tau = 100 s,
    20 C ambient, 120 C limit."""
    return dataclasses.replace(params.motor, winding_resistance_ohm=2.0,
                               thermal_resistance_K_W=5.0, thermal_time_constant_s=100.0,
                               ambient_C=20.0, winding_limit_C=120.0)


def test_hand_computed_step_response(motor):
    # 2 A: 12 W, +60 K: never reaches the limit
    # 4 A: 48 W, +240 K: 120 C is reached at t = -100 ln(1 - 100/240) = 100 ln(12/7) s
    th = thermal_margin(motor, np.array([2.0, 4.0]))
    np.testing.assert_allclose(th.loss_W, [12.0, 48.0], rtol=1e-14)
    np.testing.assert_allclose(th.steady_C, [80.0, 260.0], rtol=1e-14)
    np.testing.assert_allclose(th.margin_K, [40.0, -140.0], rtol=1e-14)
    assert th.time_to_limit_s[0] == math.inf
    assert th.time_to_limit_s[1] == pytest.approx(100.0 * math.log(12 / 7), rel=1e-14)
    assert winding_temperature(motor, 4.0, [100.0])[0] == pytest.approx(
        20.0 + 240.0 * (1 - math.exp(-1)), rel=1e-14)
    assert winding_temperature(motor, np.array([2.0, 4.0]), [0.0, 1e6]).tolist() == [
        [20.0, 80.0], [20.0, 260.0]]


def test_against_integrated_heat_balance(motor):
    rms = 3.7
    power = 1.5 * motor.winding_resistance_ohm * rms**2
    capacity = motor.thermal_time_constant_s / motor.thermal_resistance_K_W    # J/K
    dt, temp, t = 1e-3, motor.ambient_C, 0.0
    while temp < motor.winding_limit_C:                       # explicit midpoint steps
        def rate(T):
            return (power - (T - motor.ambient_C) / motor.thermal_resistance_K_W) / capacity
        temp += dt * rate(temp + 0.5 * dt * rate(temp))
        t += dt
    assert float(thermal_margin(motor, rms).time_to_limit_s) == pytest.approx(t, abs=2 * dt)


def test_continuous_rating_is_the_steady_limit(motor):
    # the current that holds the winding exactly at the limit: sqrt(100 K / (3 ohm 5 K/W))
    rating = motor.thermal_continuous_current_A
    assert rating == pytest.approx(math.sqrt(100.0 / 15.0), rel=1e-14)
    th = thermal_margin(motor, [rating * (1 - 1e-9), rating * (1 + 1e-6)])
    assert th.time_to_limit_s[0] == math.inf and np.isfinite(th.time_to_limit_s[1])
    assert float(thermal_margin(motor, 0.0).time_to_limit_s) == math.inf


def test_default_motor_reports(params):
    """The packaged file's continuous rating follows from its thermal values (the file's
    comment): sqrt(95 / (15 * 1.5 * 2)) A, through 8:1 at 0.9."""
    m = params.motor
    assert m.thermal_continuous_current_A == pytest.approx(math.sqrt(95 / 45.0), rel=1e-12)
    assert m.continuous_torque_Nm == pytest.approx(
        8 * 0.9 * m.torque_constant_Nm_per_A * math.sqrt(95 / 45.0), rel=1e-12)
