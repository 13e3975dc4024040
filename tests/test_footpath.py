"""Foot paths: the trot path walks (flat stance at constant speed, touchdown without slip or
vertical speed, continuous velocity), the seed's ellipse is the seed's, loads add up."""

import dataclasses
import json

import numpy as np
import pytest

from fivebar_drake.analysis import analyze
from fivebar_drake.cli import main
from fivebar_drake.footpath import TROT_PHASES_RAD, evaluate, stance_loads

DT = 1e-5


def _gait(params, duty, freq):
    return dataclasses.replace(params.gait, duty_factor=duty, frequency_hz=freq)


GAITS = [(0.75, 1.0), (0.6, 1.0), (0.5, 2.0), (0.85, 0.5)]


@pytest.fixture(params=GAITS, ids=[f"beta{d}-f{f}" for d, f in GAITS])
def gait(request, params):
    return _gait(params, *request.param)


def _fd(x, dt=DT):
    return np.gradient(x, dt, axis=0)


def test_trot_stance_is_flat_at_constant_speed_over_the_stride(gait):
    t = np.arange(0.0, gait.period_s, DT)
    p = evaluate(gait, "trot", t)
    stance = p.stance
    assert np.mean(stance) == pytest.approx(gait.duty_factor, abs=1e-3)
    assert np.all(p.pos[stance, 1] == gait.y_home_m)                       # on the ground line
    speed = 2 * gait.a_m / (gait.duty_factor * gait.period_s)
    vx = np.diff(p.pos[stance, 0]) / DT                                    # finite differences
    assert np.allclose(vx, speed, rtol=1e-6)
    x = p.pos[stance, 0]
    assert x.min() == pytest.approx(gait.x_center_m - gait.a_m, abs=speed * DT * 1.01)
    assert x.max() == pytest.approx(gait.x_center_m + gait.a_m, abs=speed * DT * 1.01)
    assert p.pos[:, 1].max() - gait.y_home_m == pytest.approx(gait.b_m, rel=1e-6)   # step height


def test_trot_touchdown_and_liftoff_match_the_ground(gait):
    """At both ends of the swing: vertical speed 0, horizontal speed = the stance speed."""
    speed = 2 * gait.a_m / (gait.duty_factor * gait.period_s)
    t_sw = (1 - gait.duty_factor) * gait.period_s
    for t_edge in (0.0, t_sw):                        # lift-off at u = 0, touchdown at u = 1 - beta
        t = t_edge + np.array([-2 * DT, -DT, 0.0, DT, 2 * DT])
        pos = evaluate(gait, "trot", t).pos
        v = (pos[2:] - pos[:-2]) / (2 * DT)           # central differences around the edge
        assert np.allclose(v[:, 1], 0.0, atol=1e-6)
        assert np.allclose(v[:, 0], speed, rtol=1e-4)


def test_trot_velocity_is_continuous_and_matches_the_derivatives(gait):
    t = np.arange(0.0, 2 * gait.period_s, DT)          # two cycles: the wrap is covered
    p = evaluate(gait, "trot", t)
    v_fd = _fd(p.pos)
    scale_v = np.abs(p.vel).max()
    assert np.max(np.abs(v_fd[1:-1] - p.vel[1:-1])) < 1e-4 * scale_v
    assert np.max(np.abs(np.diff(v_fd[1:-1], axis=0))) < 1e-3 * scale_v    # no jumps
    a_fd = _fd(p.vel)
    scale_a = np.abs(p.acc).max()
    assert np.isfinite(scale_a) and scale_a < 100.0                        # bounded (m/s^2)
    assert np.max(np.abs(a_fd[1:-1] - p.acc[1:-1])) < 1e-3 * scale_a


def test_seed_ellipse_is_the_seeds(params):
    g = params.gait
    t = np.linspace(0.0, 3.0, 301)
    p = evaluate(g, "seed_ellipse", t)
    w = 2 * np.pi * g.frequency_hz
    assert np.allclose(p.pos[:, 0], g.x_center_m + g.a_m * np.cos(w * t), atol=1e-15)
    assert np.allclose(p.pos[:, 1], g.y_home_m + g.b_m * np.sin(w * t), atol=1e-15)
    clear = np.abs(np.sin(w * t)) > 1e-9                  # off the stance boundaries
    assert np.array_equal(p.stance[clear], np.sin(w * t)[clear] < 0)


@pytest.mark.parametrize("path", ["seed_ellipse", "trot"])
def test_stance_loads_carry_the_weight(params, path):
    t = np.linspace(0.0, 2.0, 2001)
    loads = stance_loads(params.gait, path, t, TROT_PHASES_RAD, 65.0)
    in_stance = np.stack([evaluate(params.gait, path, t, ph).stance for ph in TROT_PHASES_RAD])
    total = loads.sum(0)
    assert np.allclose(total[in_stance.any(0)], 65.0)
    assert np.all(loads[~in_stance] == 0.0)


def test_analysis_on_the_trot_path(params):
    ellipse, trot = analyze(params, "seed_ellipse"), analyze(params, "trot")
    assert trot.samples.path == "trot" and trot.results["path"]["gait"] == "trot"
    a, b = (x.results["results"]["full_trot"]["A"]["peak_torque_Nm"] for x in (ellipse, trot))
    assert a != pytest.approx(b, rel=1e-3)
    # the seed's tables stay the seed's: the default analysis is on the ellipse
    assert analyze(params).results["path"]["gait"] == "seed_ellipse"


def test_analyze_cli_gait(tmp_path, capsys):
    assert main(["analyze", "--gait", "trot", "--out", str(tmp_path)]) == 0
    data = json.loads((tmp_path / "report.json").read_text())
    assert data["path"]["gait"] == "trot"
    printed = capsys.readouterr().out
    assert "full_trot" in printed and printed.index("full_trot") < printed.index(" seed ")
    with pytest.raises(SystemExit) as err:
        main(["analyze", "--gait", "hop", "--out", str(tmp_path)])
    assert err.value.code == 2
