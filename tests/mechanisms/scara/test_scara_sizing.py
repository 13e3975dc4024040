"""The drive-sizing formulas against the seed's worked numbers (section 2.3.2) and the demand
statistics against hand values."""

import math

import numpy as np
import pytest

from fivebar_drake.mechanisms.scara import sizing as sz


def test_motor_power_rule():
    # eq. 2.82: 206 * 75 / (9550 * 0.9) = 1.80 kW; and 9550 is 60000 / 2 pi to 0.01 %
    assert sz.motor_power_kW(206, 75, 0.9) == pytest.approx(1.7976, abs=1e-4)
    assert sz.motor_power_kW(1.0, 1.0, 1.0) == pytest.approx(2 * math.pi / 60000, rel=1e-4)


def test_ball_screw_chain_with_the_seeds_numbers():
    assert sz.axial_force(4.0, 44.13, 9.81) == pytest.approx(215.76)
    assert sz.axial_force(24.0, 44.13, 9.81) == pytest.approx(1294.56)
    g, f = math.radians(17.0), math.radians(0.035)
    assert sz.screw_torque(215.76, 0.02602, g, f) == pytest.approx(0.86, abs=5e-3)
    assert sz.screw_force(sz.screw_torque(100.0, 0.026, g, f), 0.026, g, f) == pytest.approx(100)
    assert sz.nut_speed_rpm(2.78, 1, 0.025) == pytest.approx(6672)
    assert sz.core_diameter_min(1295, 262e6) * 1e3 == pytest.approx(2.86, abs=5e-3)
    c = sz.groove_offset(0.00153, 0.003, math.radians(45))
    assert c * 1e3 == pytest.approx(0.03 * math.sqrt(0.5))
    assert sz.ball_circle_diameter(0.023, 0.00153, 0.00002) * 1e3 == pytest.approx(26.02)
    assert math.degrees(sz.lead_angle(0.025, 0.02602)) == pytest.approx(17.0, abs=0.01)
    assert sz.ball_count(0.02602, 2.3, 0.003) == pytest.approx(61.67, abs=0.01)
    assert math.degrees(sz.friction_angle(5e-6, 0.023, math.radians(45))) == pytest.approx(
        0.035, abs=5e-4)
    assert 0.9 * sz.screw_efficiency(g, f) == pytest.approx(0.898, abs=5e-4)


def test_screw_torque_is_the_work_balance():
    # without friction, T * 2 pi = Fa * lead (one turn): eq. 2.86 with phi = 0
    lead, dtb = 0.025, 0.026
    t = sz.screw_torque(300.0, dtb, sz.lead_angle(lead, dtb), 0.0)
    assert t * 2 * math.pi == pytest.approx(300.0 * lead)


def test_demand_statistics():
    t = np.linspace(0, 1, 100001)
    tau = np.stack([np.sin(2 * np.pi * t), 2 * np.ones_like(t)], 1)
    w = np.stack([np.ones_like(t), 3 * t], 1)
    d = sz.demand(t, tau, w, 0.5)
    assert d["peak"] == pytest.approx([1, 2], abs=1e-8)
    assert d["rms"] == pytest.approx([math.sqrt(0.5), 2], abs=1e-6)
    assert d["peak_speed"] == pytest.approx([1, 3])
    assert d["peak_power_W"] == pytest.approx([1, 6], abs=1e-8)
    assert d["input_power_W"] == pytest.approx([2, 12], abs=1e-8)
