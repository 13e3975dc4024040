"""report.json is always written and holds no NaN: over a set of geometries (coaxial and offset
hips, asymmetric links, the foot at E or offset), every number is finite or null, and a null
says why (issue 21's output-finiteness sweep)."""

import json
import math
import re

import pytest

from fivebar_drake.cli import main
from fivebar_drake.robots.quadruped.config import DEFAULT_PATH

# leg keys changed from the packaged default (m); hips at +-spacing / 2
GEOMETRIES = {
    "default (offset hips, offset foot)": {},
    "coaxial, equal links, foot at E (Doggo-like)": {"motor_a_m": [0.0, 0.0],
                                                    "motor_b_m": [0.0, 0.0], "ac_m": 0.09,
                                                    "bd_m": 0.09, "ce_m": 0.162, "de_m": 0.162,
                                                    "ef_m": 0.0},
    "coaxial, offset foot": {"motor_a_m": [0.0, 0.0], "motor_b_m": [0.0, 0.0]},
    "asymmetric links": {"ac_m": 0.1, "bd_m": 0.11, "ce_m": 0.14, "de_m": 0.15},
    "foot at E, offset hips": {"ef_m": 0.0},
}


def _numbers(value, path=""):
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _numbers(v, f"{path}.{k}")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _numbers(v, f"{path}[{i}]")
    else:
        yield path, value


@pytest.mark.parametrize("name", GEOMETRIES)
def test_report_is_written_and_finite(name, tmp_path, capsys):
    text = DEFAULT_PATH.read_text()
    for key, value in GEOMETRIES[name].items():
        text, n = re.subn(rf"^{key} = .*$", f"{key} = {value}", text, count=1, flags=re.M)
        assert n == 1, key
    config = tmp_path / "leg.toml"
    config.write_text(text)
    assert main(["analyze", "--config", str(config), "--out", str(tmp_path / "out")]) == 0, \
        capsys.readouterr().err
    raw = (tmp_path / "out" / "report.json").read_text()
    assert "NaN" not in raw and "Infinity" not in raw
    report = json.loads(raw)
    for path, value in _numbers(report):
        assert value is None or not isinstance(value, float) or math.isfinite(value), path
    home = report["force_capability"]
    for mode, figures in home["home_pose"].items():
        assert (figures is None) == (mode in home["home_pose_null_why"]), mode
    assert None not in home["support_ranking"]
    if name.startswith("coaxial, equal"):
        # two modes put both knees on one point: no assembly, never offered
        assert sorted(home["home_pose_null_why"]) == ["knees_back", "knees_forward"]
        assert all("coincide" in why for why in home["home_pose_null_why"].values())


def test_the_report_answers_first():
    """Issue 32: report.md's first paragraph is the answer: each motor's verdict and deciding
    check for the trot-loaded full model and the seed's model, as report.json has them."""
    from fivebar_drake.analysis.report import markdown
    from fivebar_drake.analysis.torques import analyze
    from fivebar_drake.robots.quadruped.config import load_params

    an = analyze(load_params(None))
    text = markdown(an)
    first = text.split("\n\n")[1]
    assert " N m" not in text and "N*m" not in text          # one spelling: N·m
    assert first.startswith("**Answer:**")
    for model in ("full_trot", "seed"):
        for motor in ("A", "B"):
            c = an.results["results"][model][motor]["checks"]
            assert (f"{motor} {c['verdict'].upper()} by the {c['deciding_check']} check "
                    f"(SF {c['torque']['sf']:.2f})") in first
