"""One continuous rating everywhere (issue 33's sixth class): the duty cycle's thermal check
holds the winding's equivalent current to the same continuous current as every maneuver's
thermal check (the datasheet's continuous_current_A when given, else the thermal model's, never
above the thermal model's: a duty cycle never passes a winding above its limit, issue 39)."""

import math

import numpy as np
import pytest

from fivebar_drake.envelope.duty_cycle import DutyTemperature, duty_verdict
from fivebar_drake.robots.quadruped.config import load_params, with_changes


@pytest.mark.parametrize("share", [None, 0.5, 1.4])
def test_the_duty_cycle_uses_the_motors_one_continuous_rating(share):
    params = load_params(None)
    thermal = params.motor.thermal_continuous_current_A
    if share is not None:
        params = with_changes(params, {"motor.continuous_current_A": share * thermal})
    motor = params.motor
    held = (1.1 if share == 1.4 else 0.8) * thermal   # the current the winding saw
    rise = motor.copper_loss_W(held) * motor.thermal_resistance_K_W
    temperature = np.full((2, 4, 2), motor.ambient_C)
    temperature[1] += rise
    duty = duty_verdict(motor, params.checks, DutyTemperature(np.array([0.0, 1e4]), temperature,
                                                              np.array([0.0, 1e4])),
                        ("FL", "FR", "RL", "RR"), ("A", "B"))
    rating = motor.rated_continuous_current_A
    assert rating == (thermal if share is None else min(share, 1.0) * thermal)
    a = duty["motors"]["A"]
    assert a["equivalent_current_A"] == pytest.approx(held, rel=1e-9)
    assert a["margin"] == pytest.approx(rating / held, rel=1e-9)
    assert duty["verdict"] == ("fail" if rating < held else
                               "warn" if rating / held < params.checks.thermal_margin_warn
                               else "pass")
    assert not math.isnan(a["margin"])
    if a["peak_C"] > motor.winding_limit_C:                # a winding above its limit
        assert duty["verdict"] == "fail"
    assert (a["peak_C"] > motor.winding_limit_C) == (share == 1.4)


@pytest.mark.parametrize("share", [None, 0.5])
def test_the_duty_cycles_picture_draws_where_its_verdict_turns(share):
    """duty_cycle.png's threshold lines (envelope.plots.verdict_temperatures) are where
    duty_verdict's thermal check turns: a winding a kelvin under the warn line passes, a kelvin
    over it warns; under the fail line warns, over it fails."""
    from fivebar_drake.envelope.plots import verdict_temperatures

    params = load_params(None)
    if share is not None:
        params = with_changes(params, {"motor.continuous_current_A":
                                       share * params.motor.thermal_continuous_current_A})
    motor = params.motor
    turns = verdict_temperatures(motor, params.checks)
    assert motor.ambient_C < turns["warn"] < turns["fail"] <= motor.winding_limit_C + 1e-9

    def verdict(peak_C):
        temperature = np.full((2, 4, 2), motor.ambient_C)
        temperature[1] = peak_C
        return duty_verdict(motor, params.checks, DutyTemperature(
            np.array([0.0, 1e4]), temperature, np.array([0.0, 1e4])),
            ("FL", "FR", "RL", "RR"), ("A", "B"))["verdict"]

    assert [verdict(turns["warn"] - 1), verdict(turns["warn"] + 1)] == ["pass", "warn"]
    assert [verdict(turns["fail"] - 1), verdict(turns["fail"] + 1)] == ["warn", "fail"]
