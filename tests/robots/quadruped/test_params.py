import re

import pytest

from fivebar_drake.robots.quadruped.config import DEFAULT_PATH, load_params, with_gait
from fivebar_drake.core.validation import ParameterError


def edited(tmp_path, old, new):
    text = DEFAULT_PATH.read_text()
    assert re.search(old, text, flags=re.M), old
    path = tmp_path / "params.toml"
    path.write_text(re.sub(old, new, text, count=1, flags=re.M))
    return path


def test_default_matches_spec(params):
    assert params.robot.weight_share_kg == pytest.approx(1.675)
    assert params.leg.ef_m / params.leg.de_m == pytest.approx(8 / 29)
    assert params.motor.no_load_speed_rad_s == pytest.approx(120 * 2 * 3.141592653589793 / 60)


@pytest.mark.parametrize("old, new, message", [
    (r"^ac_m = 0.105", "ac_m = -0.105", "leg.ac_m = -0.105: must be in (0, 2]"),
    (r"^mass_kg = 0.02056", "mass_kg = 0.0", "links.CE.mass_kg = 0.0: must be in (0, 500]"),
    (r"^com_m = 0.07250", "com_m = 0.2",
     "links.CE.com_m = 0.2: must be in [0, 0.145] (the COM lies on its link)"),
    (r"^izz_kg_m2 = 8.0e-5", "izz_kg_m2 = -1e-5", "links.DE.izz_kg_m2 = -1e-05: must be in [0, "),
    (r"^izz_kg_m2 = 1.0e-5", "izz_kg_m2 = 1.0", "links.BD.izz_kg_m2 = 1.0: must be in [0, "
     "7.02895e-05] (cannot be physical beyond m*c*(L-c)"),
    (r"^y_home_m = -0.200", "y_home_m = -0.400",
     "the foot path leaves the workspace (seed_ellipse path, sample 0 of 241 at t = 0.0000 s): "
     "foot target [60.0, -400.0] mm is out of reach: |BF|"),
    (r"^duty_factor = 0.75", "duty_factor = 1.0", "gait.duty_factor = 1.0: must be in (0, 1)"),
    (r"^samples = 60", "samples = 2", "gait.samples = 2: must be an integer in [3, 10000] (central differences need "
     "neighbours)"),
    (r"^frequency_hz = 1.0", "frequency_hz = 0", "gait.frequency_hz = 0.0: must be in (0, 10]"),
    (r"^sf_warn = 1.5", "sf_warn = 2.5", "checks.sf_warn = 2.5: must be <= checks.sf_pass = 2.0"),
    (r"^b_m = 0.030", "b_m = 0.030\nc_m = 1", "[gait] has unknown key(s) ['c_m']"),
    (r"^b_m = 0.030.*\n", "", "[gait] is missing key(s) ['b_m']"),
    (r"^a_m = 0.060", "a_m = 'wide'", "gait.a_m = 'wide': must be a number"),
    (r"^\[checks\]", "[check]", "sections: unknown ['check'], missing ['checks']"),
    (r"^mass_kg = 0.02488", "mass_kg = [", "not valid TOML"),
])
def test_invalid_parameter_files_are_named(tmp_path, old, new, message):
    with pytest.raises(ParameterError) as err:
        load_params(edited(tmp_path, old, new))
    assert message in str(err.value)


def test_missing_file(tmp_path):
    with pytest.raises(ParameterError, match="nope.toml: parameter file not found"):
        load_params(tmp_path / "nope.toml")


def test_user_file_is_used(tmp_path):
    p = load_params(edited(tmp_path, r"^frequency_hz = 1.0", "frequency_hz = 2.0"))
    assert p.gait.period_s == 0.5


def test_with_gait_validates(params):
    with pytest.raises(ParameterError, match="foot path leaves the workspace"):
        with_gait(params, a_m=0.3)
