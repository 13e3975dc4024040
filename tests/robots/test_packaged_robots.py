"""The robots packaged beside default.toml from published numbers (a Stanford-Doggo-style and a
Minitaur-style robot, coaxial hips): they load, `analyze --config` and `simulate --config` run
on them out of the box, and the published figures they list are computed from their data by
independent closed forms."""

import json

import pytest

from fivebar_drake.cli import main
from fivebar_drake.core.parameter_files import packaged
from fivebar_drake.robots.quadruped.config import load_params
from fivebar_drake.robots.quadruped.published import compare_published
from style_rules import report_violations

ROBOTS = ("doggo", "minitaur")


def test_published_figures_against_closed_forms():
    doggo, minitaur = (load_params(packaged(f"{r}.toml")) for r in ROBOTS)
    # coaxial leg, foot at E: straight below the hips the extension runs from lower - upper
    # (knees folded) to lower + upper (stretched)
    (row,) = compare_published(doggo)
    assert row["figure"] == "extension_range_m"
    assert row["computed"] == pytest.approx([0.162 - 0.09, 0.162 + 0.09], abs=3e-5)
    assert row["published"] == [0.08, 0.25] and not row["reproduced"]
    rows = {r["figure"]: r for r in compare_published(minitaur)}
    assert set(rows) == {"peak_output_torque_Nm", "no_load_speed_rad_s"}
    assert rows["peak_output_torque_Nm"]["computed"] == pytest.approx(3.5)   # the table's end
    assert rows["peak_output_torque_Nm"]["reproduced"]
    # the no-load speed of PyBullet's DC model, V / k_dc = 16 / 0.0954, reached by the BLDC
    # model's phase limit V/sqrt(3) against the back-EMF (k_t/1.5) w with k_t = sqrt(3)/2 k_dc
    assert rows["no_load_speed_rad_s"]["computed"] == pytest.approx(16.0 / 0.0954, rel=1e-9)
    assert rows["no_load_speed_rad_s"]["reproduced"]
    assert all(r["source"] for r in rows.values())


@pytest.mark.parametrize("robot", ROBOTS)
def test_analyze_and_simulate_run_out_of_the_box(robot, tmp_path, capsys):
    config = str(packaged(f"{robot}.toml"))
    assert main(["analyze", "--config", config, "--gait", "trot", "--out",
                 str(tmp_path / "a")]) == 0, capsys.readouterr().err
    report = json.loads((tmp_path / "a" / "report.json").read_text())
    home = report["force_capability"]["home_pose"]
    assert home["knees_forward"] is None and home["knees_back"] is None   # coaxial: knees meet
    assert home["knees_out"]["max_vertical_N"] > 0
    assert "## Published figures" in (tmp_path / "a" / "report.md").read_text()
    assert report_violations(tmp_path / "a" / "report.md") == []
    code = main(["simulate", "--config", config, "--duration", "1.6", "--out",
                 str(tmp_path / "s")])
    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert code in (0, 1) and summary["verdict"] in ("pass", "warn", "fail", "insufficient",
                                                       "marginal")
    assert summary["max_loop_gap_m"] < 1e-4          # the coaxial loops stay closed
