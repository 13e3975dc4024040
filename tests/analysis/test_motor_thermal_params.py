"""The motor's thermal parameters in the parameter file are validated like the others: the error
names the file, the field, the value and the allowed range."""

import re

import pytest

from fivebar_drake.core.validation import ParameterError
from fivebar_drake.robots.quadruped.config import DEFAULT_PATH, load_params

CASES = {
    "continuous above peak": ("ambient_C = 25.0", "ambient_C = 25.0\ncontinuous_current_A = 6.0",
                              "motor.continuous_current_A = 6.0: must be in (0, "
                              "3.35889] (at most peak_current_A)"),
    "no torque constant": ("torque_constant_Nm_per_A = 0.20674833578317203",
                           "torque_constant_Nm_per_A = 0",
                           "motor.torque_constant_Nm_per_A = 0.0: must be in [0.0001, 10]"),
    "milliohms as ohms": ("winding_resistance_ohm = 2.0", "winding_resistance_ohm = 1000.5",
                          "motor.winding_resistance_ohm = 1000.5: must be in [0.0001, 1000]"),
    "negative thermal resistance": ("thermal_resistance_K_W = 15.0",
                                    "thermal_resistance_K_W = -8.0",
                                    "motor.thermal_resistance_K_W = -8.0: must be in (0, 1000]"),
    "time constant not a number": ("thermal_time_constant_s = 400.0",
                                   "thermal_time_constant_s = 'long'",
                                   "motor.thermal_time_constant_s = 'long': must be a number"),
    "limit below ambient": ("winding_limit_C = 120.0", "winding_limit_C = 20.0",
                            "motor.winding_limit_C = 20.0: must be in (25, 300] (above "
                            "motor.ambient_C)"),
    "kelvin as celsius": ("ambient_C = 25.0", "ambient_C = 298.15",
                          "motor.ambient_C = 298.15: must be in [-60, 100]"),
}


@pytest.mark.parametrize("old, new, message", CASES.values(), ids=CASES.keys())
def test_bad_thermal_value(tmp_path, old, new, message):
    text = DEFAULT_PATH.read_text()
    assert re.search(rf"^{re.escape(old)}", text, re.M), old
    bad = tmp_path / "bad.toml"
    bad.write_text(re.sub(rf"^{re.escape(old)}", new, text, flags=re.M))
    with pytest.raises(ParameterError) as err:
        load_params(bad)
    assert str(err.value).startswith(f"{bad}: {message}")
    assert err.value.field == message.split(" =")[0]


def test_missing_thermal_key(tmp_path):
    bad = tmp_path / "old.toml"
    bad.write_text(re.sub(r"^ambient_C = .*$", "", DEFAULT_PATH.read_text(), flags=re.M))
    with pytest.raises(ParameterError, match=r"motor = .*: the thermal model needs all of"):
        load_params(bad)
    none = tmp_path / "none.toml"
    none.write_text(re.sub(r"^(thermal_resistance_K_W|thermal_time_constant_s|winding_limit_C|"
                           r"ambient_C) = .*$", "", DEFAULT_PATH.read_text(), flags=re.M))
    with pytest.raises(ParameterError, match="the quadruped's verdict needs a BLDC motor"):
        load_params(none)
