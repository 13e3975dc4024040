"""The ball-screw leg study: Drake's projected static torques against the closed form, the command
line end to end (analyze and simulate), bad input, and report.json's seed claims against hand
calculations."""

import dataclasses
import json
import math

import numpy as np
import pytest

from fivebar_drake import catalog
from fivebar_drake.cli import main
from fivebar_drake.mechanisms.ballscrew_leg import load_params
from fivebar_drake.core.rerun_files import read_series
from fivebar_drake.studies.ballscrew_leg.model import build_model
from style_rules import report_violations

REQUIRED_IDS = {"ratio_max_s1_0.02", "ratio_min_s1_0.02", "ratio_max_s1_0.05",
                "ratio_s1_0.07_vs_0.05"}
FIELDS = {"id", "claim", "seed_value", "computed_value", "unit", "reading", "reproduced"}


@pytest.fixture(scope="module")
def bs_params():
    return load_params()


@pytest.mark.parametrize("lever", [0.02, 0.05, 0.07])
def test_drake_static_torques_match_the_closed_form_over_the_squat(bs_params, lever):
    """Bench rig, the foot load as an external force: the screw motor torque (lossless screw)
    within 1 % of F lead / (2 pi), F from the knee torque 700 N x l2 sin q1 by virtual work."""
    model = build_model(bs_params, lever, "bench")
    q1 = np.radians(np.linspace(1.0, 85.0, 43))
    pose = model.leg.points(q1, -2 * q1)
    drake = model.static_torques(model.positions(pose), (0.0, 700.0))
    q2l = np.sqrt(0.04 + lever**2 - 2 * 0.2 * lever * np.cos(2 * q1))
    knee = 140.0 * np.sin(q1)
    force = knee / (0.2 * lever * np.sin(-2 * q1) / q2l)
    screw = force * 0.005 / (2 * math.pi)
    assert np.all(np.abs(drake[:, 1] / screw - 1.0) < 0.01)
    assert np.all(np.abs(drake[:, 0]) < 0.01 * np.abs(knee).max())      # hip: 0 in the squat


def test_drake_static_torques_off_the_squat(bs_params):
    """Any pose, any foot force: Drake's projection against -J^T F of the seed's Jacobian."""
    model = build_model(bs_params, 0.05, "bench")
    rng = np.random.default_rng(3)
    q = np.column_stack([rng.uniform(-0.8, 1.2, 20), rng.uniform(0.16, 0.24, 20)])
    pose = model.leg.forward(q)
    force = np.array([150.0, 700.0])
    drake = model.static_torques(model.positions(pose), force)
    closed = model.leg.static_torques(force, pose)
    assert np.allclose(drake[:, 0], closed[:, 0], rtol=0.01, atol=1e-9)
    assert np.allclose(drake[:, 1], closed[:, 1] * 0.005 / (2 * math.pi), rtol=0.01, atol=1e-9)


def test_squat_rig_carries_the_load_through_the_pinned_foot(bs_params):
    """The simulated rig (carriage of 700 N / g on a rail, foot pinned, gravity): with near
    massless links its static screw torque is the closed form's for 700 N."""
    s = dataclasses.replace(bs_params.simulation, thigh_mass_kg=1e-6, shank_mass_kg=1e-6,
                            screw_mass_kg=1e-6, nut_mass_kg=1e-6)
    params = dataclasses.replace(bs_params, simulation=s)
    model = build_model(params, 0.05, "squat")
    q1 = np.radians([10.0, 30.0, 50.0, 70.0])
    pose = model.leg.points(q1, -2 * q1)
    drake = model.static_torques(model.positions(pose, -pose.f[:, 1]))[:, 0]
    closed = model.leg.static_torques((0.0, 700.0), pose)[:, 1] * 0.005 / (2 * math.pi)
    assert np.allclose(drake, closed, rtol=0.01)


def test_catalog_knows_the_study():
    assert "ballscrew_leg" in catalog.mechanisms() and catalog.can_simulate("ballscrew_leg")


def test_analyze_end_to_end(tmp_path):
    assert main(["analyze", "--mechanism", "ballscrew_leg", "--out", str(tmp_path)]) == 0
    study = catalog.study("ballscrew_leg")
    for name in study.ANALYSIS_FILES:
        assert (tmp_path / name).stat().st_size > 0
    report = json.loads((tmp_path / "report.json").read_text())
    claims = report["seed_claims"]
    assert REQUIRED_IDS <= {c["id"] for c in claims}
    assert all(set(c) == FIELDS for c in claims)
    by = {(c["id"], *c["reading"].split(":")[0].split(" / ")): c for c in claims}
    assert len(by) == len(claims)                     # one object per claim and reading
    joint = "joint"
    # hand: the peak ratio is 2 pi eta s1 / lead (the q1 grid is 0.05 deg: within 1e-5)
    for cid, s1, seed in (("ratio_max_s1_0.02", 0.02, 20.0), ("ratio_max_s1_0.05", 0.05, 56.0)):
        c = by[cid, joint, "forward"]
        expected = 2 * math.pi * 0.9 * s1 / 0.005
        assert c["computed_value"] == pytest.approx(expected, rel=1e-5)
        assert c["reproduced"] == (abs(expected - seed) <= 0.05 * seed)
        back = by[cid, joint, "back-driven"]
        assert back["computed_value"] == pytest.approx(2 * math.pi * s1 / (0.9 * 0.005),
                                                       rel=1e-5)
    assert by["ratio_max_s1_0.05", joint, "forward"]["reproduced"]          # 56.55 against 56
    assert not by["ratio_max_s1_0.02", joint, "forward"]["reproduced"]      # 22.62 against 20
    # the minimum over the file's squat sits at its first sample, q1 = 1 deg (hand formula)
    q1 = math.radians(1.0)
    q2l = math.sqrt(0.04 + 0.0004 - 0.008 * math.cos(2 * q1))
    expected_min = 2 * math.pi * 0.9 * 0.2 * 0.02 * math.sin(2 * q1) / (0.005 * q2l)
    low = by["ratio_min_s1_0.02", joint, "forward"]
    assert low["computed_value"] == pytest.approx(expected_min, rel=1e-5)
    vs = by["ratio_s1_0.07_vs_0.05", joint, "forward"]
    assert vs["computed_value"] == pytest.approx(2 * math.pi * 0.9 * 0.07 / 0.005, rel=1e-5)
    assert vs["reproduced"] is False
    # the screw motor needs less torque than the geared motor where the ratio beats 10:1:
    # between the two roots of 2 pi 0.9 0.2 0.05 sin 2q / (0.005 q2l(q)) = 10 (bisection)
    def excess(q):
        return 2 * math.pi * 0.9 * 0.01 * math.sin(2 * q) / (
            0.005 * math.sqrt(0.0425 - 0.02 * math.cos(2 * q))) - 10

    roots = []
    for lo, hi in ((1.0, 20.0), (85.0, 60.0)):          # ends: ratio below 10, then above
        lo, hi = math.radians(lo), math.radians(hi)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if excess(mid) < 0 else (lo, mid)
        roots.append(math.degrees(lo))
    share = abs(roots[1] - roots[0]) / 84.0
    below = by["screw_motor_below_geared_s1_0.05", "forward"]
    assert below["computed_value"] == pytest.approx(share, abs=2 / 1681)
    text = (tmp_path / "report.md").read_text()
    assert "not reproduced" in text and "ratio_min_s1_0.02" in text
    assert report_violations(tmp_path / "report.md") == []


def test_bad_config_names_file_and_field(tmp_path, capsys):
    from fivebar_drake.mechanisms.ballscrew_leg import DEFAULT_PATH

    bad = tmp_path / "bad.toml"
    bad.write_text(DEFAULT_PATH.read_text().replace("lead_m = 0.005", "lead_m = 5"))
    assert main(["analyze", "--mechanism", "ballscrew_leg", "--config", str(bad),
                 "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "screw.lead_m" in err and "5" in err
    bad.write_text(DEFAULT_PATH.read_text().replace("lever_m = 0.05 ", "lever_m = 0.04 "))
    assert main(["simulate", "--mechanism", "ballscrew_leg", "--config", str(bad),
                 "--out", str(tmp_path / "out")]) == 2
    assert "simulation.lever_m" in capsys.readouterr().err
    bad.write_text(DEFAULT_PATH.read_text().replace("stroke_m = 0.06", "stroke_mm = 60"))
    assert main(["analyze", "--mechanism", "ballscrew_leg", "--config", str(bad),
                 "--out", str(tmp_path / "out")]) == 2
    assert "screw.stroke_mm" in capsys.readouterr().err
    # 60 mm of stroke from the straight leg bends the knee to acos(-0.08) for s1 = 0.05 m:
    # the squat can reach q1 = 47.29 deg, not 50
    bad.write_text(DEFAULT_PATH.read_text().replace("q1_bottom_deg = 45.0", "q1_bottom_deg = 50.0"))
    assert main(["simulate", "--mechanism", "ballscrew_leg", "--config", str(bad),
                 "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "simulation.q1_bottom_deg" in err and f"{math.degrees(math.acos(-0.08)) / 2:.2f}" in err
    assert not (tmp_path / "out").exists()            # refused before the folder is touched
    assert main(["simulate", "--mechanism", "ballscrew_leg", "--duration", "-1",
                 "--out", str(tmp_path / "out")]) == 2
    assert "--duration" in capsys.readouterr().err


def test_simulate_end_to_end(tmp_path, bs_params):
    """A short run: standing, then the start of the squat. The recording reads back; while the
    leg stands still the applied torque is Drake's projected static torque (links included)."""
    assert main(["simulate", "--mechanism", "ballscrew_leg", "--duration", "0.4",
                 "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["duration_s"] == pytest.approx(0.4)
    assert max(summary["max_loop_gap_m"].values()) < 1e-4
    assert summary["q1_tracking_error_deg"]["max"] < 0.5
    t, applied = read_series(tmp_path / "run.rrd", "torque/applied")
    assert t[-1] == pytest.approx(0.4) and len(t) == len(np.unique(t))
    model = build_model(bs_params, 0.05, "squat")
    q1 = math.radians(bs_params.simulation.q1_top_deg)
    pose = model.leg.points(q1, -2 * q1)
    static = model.static_torques(model.positions(pose, -pose.f[1])[None])[0, 0]
    standing = (t > 0.1) & (t < bs_params.simulation.hold_s)
    assert np.allclose(applied[standing], static, rtol=0.01)
