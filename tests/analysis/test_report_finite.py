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


def _answer_and_details(text: str) -> tuple[str, str]:
    """report.md's answer (its first line after the title) and the list under it."""
    paragraphs = text.split("\n\n")
    return paragraphs[1], paragraphs[2]


def test_the_report_answers_first():
    """Issue 32: report.md's first line is the answer, at most 200 characters: each motor's
    verdict and torque SF for the trot-loaded full model, then the seed's model, as report.json
    has them; the check that decided each verdict in the answer (the first motor's, the same
    for all) and in the list under it, with the motors and the thresholds."""
    from fivebar_drake.analysis.report import markdown
    from fivebar_drake.analysis.torques import analyze
    from fivebar_drake.core.text import ANSWER_CHARS
    from fivebar_drake.robots.quadruped.config import load_params

    an = analyze(load_params(None))
    text = markdown(an)
    first, details = _answer_and_details(text)
    assert " N m" not in text and "N*m" not in text          # one spelling: N·m
    assert first.startswith("**Answer:**") and "\n" not in first
    assert len(first) <= ANSWER_CHARS
    said = {}
    for model in ("full_trot", "seed"):
        for motor in ("A", "B"):
            c = an.results["results"][model][motor]["checks"]
            assert c["deciding_check"] == "torque"
            said[model, motor] = (f"{motor} {c['verdict'].upper()}"
                                  f"{' by the torque check' if said == {} else ''} "
                                  f"(SF {c['torque']['sf']:.2f})")
    assert first == ("**Answer:** the physically consistent model with the trot's loading: "
                     f"{said['full_trot', 'A']}, {said['full_trot', 'B']}; the seed's model as "
                     f"written: {said['seed', 'A']}, {said['seed', 'B']}.")
    assert "each verdict above is the torque check's" in details
    assert "the seed's estimate" in details.lower()
    assert "5.00 N·m, 12.57 rad/s motors" in details
    assert "Thresholds: SF ≥ 2 pass, ≥ 1.5 warn, else fail." in details


def test_an_answer_whose_checks_differ_names_them():
    """A deciding check other than the torque check is named in the answer (its SF is the
    torque check's) as long as the line keeps to 200 characters; the list under it names every
    motor's."""
    from fivebar_drake.analysis.report import markdown
    from fivebar_drake.analysis.torques import analyze
    from fivebar_drake.core.text import ANSWER_CHARS
    from fivebar_drake.robots.quadruped.config import load_params, with_changes

    an = analyze(with_changes(load_params(None), {"motor.gear_ratio": 11.5}), path="trot")
    r = an.results["results"]
    first, details = _answer_and_details(markdown(an))
    assert len(first) <= ANSWER_CHARS
    assert r["full_trot"]["B"]["checks"]["deciding_check"] == "speed"
    assert f"B {r['full_trot']['B']['checks']['verdict'].upper()} by speed" in first
    decided = "; ".join(f"`{model}` " + ", ".join(
        f"{m} {r[model][m]['checks']['deciding_check']}" for m in ("A", "B"))
        for model in ("full_trot", "seed"))
    assert f"the check that decided each verdict above: {decided}" in details
    r["full_trot"]["A"]["checks"]["deciding_check"] = "thermal"   # three named: too long
    r["seed"]["B"]["checks"]["deciding_check"] = "thermal"
    for model in ("full_trot", "seed"):
        for m in ("A", "B"):
            r[model][m]["checks"]["torque"]["sf"] = 12.345
    first, details = _answer_and_details(markdown(an))
    assert len(first) <= ANSWER_CHARS and " by " not in first
    assert "`full_trot` A thermal, B speed" in details and "B thermal" in details
