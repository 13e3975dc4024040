"""The quadruped simulation: loop closure, standing and walking, static comparison, recording,
CLI, bad scenarios."""

import json

import numpy as np
import pytest
from rerun.chunk import RrdReader

from fivebar_drake.cli import main
from fivebar_drake.jacobians import foot_jacobian
from fivebar_drake.kinematics import UnreachableError, forward
from fivebar_drake.recording import read_series
from fivebar_drake.scenario import load_scenario
from fivebar_drake.simulation import simulate, standing_height
from fivebar_drake.summary import signals

TEST_DURATION_S = 3.0   # 0.5 s standing, 1 s ramp, 1.5 s full trot


@pytest.fixture(scope="module")
def runs():
    """The test trot with each closure: closure -> (scenario, params, result, setup, signals)."""
    out = {}
    for closure in ("bushing", "ball"):
        scenario = load_scenario(duration_s=TEST_DURATION_S, closure=closure)
        params = scenario.load_params()
        result, setup = simulate(scenario, params, progress=False)
        out[closure] = scenario, params, result, setup, signals(result, setup, params)
    return out


@pytest.fixture(params=["bushing", "ball"])
def run(request, runs):
    return runs[request.param]


def test_closures_give_the_same_gait_and_comparable_torques(runs):
    (scenario, _, _, _, a), (_, _, _, _, b) = runs["ball"], runs["bushing"]
    assert np.array_equal(a.t_log, b.t_log)
    assert np.allclose(a.command[:1], b.command[:1])             # same start, same gait
    trot = a.t_log >= scenario.stand_s + scenario.ramp_s
    mean_a, mean_b = np.abs(a.applied[trot]).mean(), np.abs(b.applied[trot]).mean()
    assert mean_b == pytest.approx(mean_a, rel=0.15)
    assert np.corrcoef(a.applied.ravel(), b.applied.ravel())[0, 1] > 0.7


def test_loop_gap_below_a_tenth_of_a_millimetre(run):
    scenario, params, result, setup, sig = run
    assert not result.error
    assert np.all(np.isfinite(result.state))
    assert sig.gap.shape == (4, len(result.t_state))
    assert np.max(sig.gap) < 1e-4


def test_robot_stands_and_walks(run):
    scenario, params, result, setup, sig = run
    z0 = standing_height(params)
    assert np.all(np.abs(sig.body_p[:, 2] - z0) < 0.05)        # within 5 cm of standing height
    quat = sig.body_quat / np.linalg.norm(sig.body_quat, axis=1, keepdims=True)
    tilt = np.degrees(np.arccos(1 - 2 * (quat[:, 1] ** 2 + quat[:, 2] ** 2)))
    assert tilt.max() < 30.0                                    # upright
    trot = sig.t_state >= scenario.stand_s + scenario.ramp_s
    p = sig.body_p[trot]
    assert (p[-1, 0] - p[0, 0]) / (sig.t_state[trot][-1] - sig.t_state[trot][0]) > 0.02
    standing = sig.t_state < scenario.stand_s
    assert np.max(np.abs(sig.body_v[standing, 0])) < 0.05       # no snap at t = 0


def test_static_prediction_is_jacobian_transpose_times_contact_force(run):
    """-J_F^T F at one sample, with J_F by finite differences of FK and F rotated by hand."""
    scenario, params, result, setup, sig = run
    k = int(np.argmax(np.abs(sig.foot_force_plane[:, 0, 1])))  # FL under load
    q = sig.q[np.searchsorted(sig.t_state, sig.t_log[k], side="right") - 1, 0]
    h = 1e-7
    jf = np.stack([(forward(params.leg, q + h * e).f - forward(params.leg, q - h * e).f) / (2 * h)
                   for e in np.eye(2)], -1)
    expect = -jf.T @ sig.foot_force_plane[k, 0]
    assert np.allclose(sig.static_contact[k, 0], expect, rtol=1e-6, atol=1e-6)
    assert np.allclose(foot_jacobian(params.leg, forward(params.leg, q)), jf, atol=1e-6)


def test_simulate_cli_writes_outputs_and_recording(tmp_path, capsys):
    out = tmp_path / "sim"
    assert main(["simulate", "--duration", "1.0", "--closure", "ball", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "rerun" in printed and str(out.resolve()) in printed
    summary = json.loads((out / "summary.json").read_text())
    for key in ("max_loop_gap_m", "real_time_factor", "closure", "duration_s"):
        assert key in summary
    assert summary["closure"] == "ball" and summary["duration_s"] == pytest.approx(1.0)
    for leg in ("FL", "FR", "RL", "RR"):
        for motor in ("A", "B"):
            m = summary["legs"][leg][motor]
            for key in ("peak_torque_Nm", "rms_torque_Nm", "static_torque_Nm",
                        "dynamic_to_static_ratio", "safety_factor", "verdict",
                        "saturated_fraction", "peak_speed_rad_s"):
                assert key in m, (leg, motor, key)
            assert 0 <= m["saturated_fraction"] <= 1 and m["peak_torque_Nm"] > 0
    for name in ("summary.md", "sim_torques.png", "sim_motion.png"):
        assert (out / name).stat().st_size > 1000
    check_recording(out / "run.rrd", summary)


def rows(path, entity):
    chunks = RrdReader(path).stream().filter(content=entity, is_static=False).to_chunks()
    return sum(c.num_rows for c in chunks)


def check_recording(path, summary):
    assert path.stat().st_size > 10_000
    reader = RrdReader(path)
    steps = rows(path, "/loop_gap/FL")
    assert steps == pytest.approx(1.0 / 0.001, abs=2)           # every 1 ms plant step
    assert rows(path, "/joints/RR/B/speed") == steps
    samples = rows(path, "/torque/FL/A/applied")
    assert samples == pytest.approx(1.0 / 0.002, abs=2)         # log period 2 ms
    for entity in ("/torque/RR/B/commanded", "/torque/RR/B/static_contact",
                   "/torque/RR/B/static_seed", "/torque/RR/B/limit_pos", "/contact/FL/normal"):
        assert rows(path, entity) == samples, entity
    frames = rows(path, "/world/body")
    assert frames == pytest.approx(1.0 * 50, abs=2)             # 3-D poses at 50 Hz
    for leg in ("FL", "FR", "RL", "RR"):
        assert rows(path, f"/world/legs/{leg}") == frames
    assert rows(path, "/body/height") == steps
    _, gap = read_series(path, "/loop_gap/FL")                 # binned, peaks kept
    assert gap.max() == pytest.approx(summary["max_loop_gap_per_leg_m"]["FL"], rel=1e-12)
    t, applied = read_series(path, "/torque/FL/A/applied")
    assert len(t) == samples and np.all(np.diff(t) > 0)
    peak = summary["legs"]["FL"]["A"]["peak_torque_Nm"]
    assert np.max(np.abs(applied[t >= summary["trot_window_s"][0]])) == pytest.approx(peak)
    assert reader.blueprints()                                  # the blueprint is in the file


@pytest.mark.parametrize("args, message", [
    (["--closure", "glue"], "scenario.closure = 'glue': allowed ['bushing', 'ball']"),
    (["--duration", "-1"], "scenario.duration_s = -1.0: must be > 0"),
])
def test_bad_scenarios_fail_clearly(tmp_path, capsys, args, message):
    assert main(["simulate", *args, "--out", str(tmp_path)]) == 2
    assert message in capsys.readouterr().err


def test_unreachable_gait_in_scenario_file(tmp_path, capsys):
    path = tmp_path / "far.yaml"
    path.write_text("gait_y_home_m: -0.35\nduration_s: 1.0\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path)]) == 2
    assert "gait leaves the workspace: foot target [60.0, -350.0] mm is out of reach" in \
        capsys.readouterr().err


def test_unknown_scenario_key(tmp_path, capsys):
    path = tmp_path / "typo.yaml"
    path.write_text("durration_s: 1.0\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path)]) == 2
    assert "durration_s" in capsys.readouterr().err


def test_bushing_time_step_beyond_stability_is_refused(tmp_path, capsys):
    path = tmp_path / "coarse.yaml"
    path.write_text("time_step_s: 0.0005\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path)]) == 2
    assert "scenario.time_step_s = 0.0005: the bushing (k = 8.48e+06 N/m" in capsys.readouterr().err


def test_failed_run_keeps_what_was_simulated(tmp_path, capsys, monkeypatch):
    """A run that fails midway still writes its summary, plots and recording, and exits 1."""
    from fivebar_drake import systems

    original = systems.FootIKController.command
    calls = []

    def failing(self, targets, velocities, state):
        calls.append(1)
        if len(calls) > 150:                                    # t = 0.3 s at 500 Hz
            raise UnreachableError("foot target out of reach (injected)")
        return original(self, targets, velocities, state)

    monkeypatch.setattr(systems.FootIKController, "command", failing)
    out = tmp_path / "sim"
    assert main(["simulate", "--duration", "1.0", "--closure", "ball", "--out", str(out)]) == 1
    assert "stopped early: foot target out of reach (injected)" in capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is False and 0.25 < summary["duration_s"] < 0.35
    assert (out / "run.rrd").stat().st_size > 10_000 and (out / "sim_torques.png").exists()
