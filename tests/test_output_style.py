"""Issue 32: the output style guide (docs/output_style.md) held over the kinds of report `make
demo` writes. The rules (tests/style_rules.py) are shown to catch each breach on a report written
here; then they are held over reports written cheaply from runs other tests already make (the
2.5 s trot and 2.6 s jump of the session's `simulated`: their summary.md and the comparison of
the two, as `compare` writes it), the default analysis' report.md and the example sweep's
sweep.md (its closed-form points). The demo's other reports are held where their own tests write
them: the design study's design.md with its envelopes' envelope.md and summary.md
(tests/codesign), optimal.md (tests/optimal/test_vertical_jump.py), the envelope's
(tests/envelope/test_envelope.py), the seed studies' report.md (tests/studies) and the packaged
robots' (tests/robots). Here too, cheaply: the demo's gear comparison of two real runs (the
shared 4.5 s trot at 8:1 and one at 11.5:1) and the Doggo- and Minitaur-style robots'
optimal.md (all but its gait floors: their rows are the default robot's code, held in
tests/optimal; the floors would cost 14 s per robot)."""

from pathlib import Path

import pytest

from style_rules import glossary, header_words, report_violations, violations

GOOD = """# A report

**Answer:** RR A FAIL by the torque check: 3.42 N·m against its 3.00 N·m limit (SF 1.41).
Thresholds: SF ≥ 2 pass, ≥ 1.5 warn, else fail.

| leg | motor | demand p99 | SF | verdict |
|---|---|---|---|---|
| RR | A | 3.42 | 1.41 | FAIL |

Winding 79.7 °C, margin 40.3 K, 0.02432 N·m/A, gap 0.0039 mm, speed 0.000 m/s.
"""

BREACHES = {
    "the first line is not the answer": ("**Answer:** RR A FAIL by the torque check:",
                                         "Method: the seed's model; RR A"),
    "without its thresholds": ("Thresholds: SF ≥ 2 pass, ≥ 1.5 warn, else fail.", ""),
    "unit spelled N m": ("3.42 N·m against", "3.42 N m against"),
    "unit spelled N*m": ("3.42 N·m against", "3.42 N*m against"),
    "unit spelled C for °C": ("79.7 °C", "79.7 C"),
    "nan or inf": ("| 3.42 | 1.41 |", "| nan | 1.41 |"),
    "negative zero": ("speed 0.000 m/s", "speed -0.000 m/s"),
    "more than 4 decimals": ("3.42 N·m against", "2.77288 N·m against"),
    "header term not in the glossary": ("| demand p99 |", "| dyn/trot |"),
    "the first line is longer than 200 characters": (
        "(SF 1.41).", "(SF 1.41, " + "each sample against its own quadrant's limit, " * 3 + ")."),
    "a paragraph of 92 words": ("Winding 79.7 °C,", "Winding " + "the seed's model " * 26
                                + "79.7 °C,"),
}


def test_a_report_that_keeps_the_guide_passes(tmp_path):
    path = tmp_path / "report.md"
    path.write_text(GOOD)
    assert violations(path) == []


@pytest.mark.parametrize("rule", list(BREACHES))
def test_each_rule_catches_its_breach(tmp_path, rule):
    good, bad = BREACHES[rule]
    assert good in GOOD
    path = tmp_path / "report.md"
    path.write_text(GOOD.replace(good, bad, 1))
    found = violations(path)
    assert found and all(rule in v for v in found), found


def test_the_glossary_has_the_jargon_the_issue_names():
    terms = glossary()
    for term in ("sf", "p99", "demand", "floor", "any controller", "this controller",
                 "deciding check", "achieved", "seed", "full", "full_trot", "static",
                 "clipped", "insufficient", "not achieved"):
        assert term in terms, term
    assert header_words("peak torque (N·m)") == ["peak", "torque"]      # the unit is no term
    assert header_words("motor.gear_ratio") == []                        # a parameter path


@pytest.fixture(scope="module")
def written(tmp_path_factory, simulated):
    """The folder of the cheap reports: trot/ and jump/ summary.md, comparison.md, analysis/
    report.md, sweep/sweep.md."""
    from fivebar_drake.verdicts.checks import thresholds_text
    from fivebar_drake.pipeline import run_analysis, summarize_run
    from fivebar_drake.analysis.report import write_report
    from fivebar_drake.simulation.comparison import write_comparison
    from fivebar_drake.simulation.summary_text import write_summary
    from fivebar_drake.sweep.engine import base_inputs
    from fivebar_drake.sweep.points import analysis_rows
    from fivebar_drake.sweep.report import summarize_sweep, write_sweep_report
    from fivebar_drake.sweep.spec import load_spec

    out = tmp_path_factory.mktemp("style")
    runs = []
    for gait, duration_s in (("trot", 2.5), ("jump", 2.6)):      # the runs other tests share
        record = simulated(gait=gait, duration_s=duration_s)
        write_summary(summarize_run(record), record.params, out / gait)
        runs.append(out / gait)
    write_comparison(runs, out / "comparison.md")
    analysis = run_analysis()
    write_report(analysis.analysis, out / "analysis", analysis.sampling_error)
    spec = load_spec(Path(__file__).parents[1] / "fivebar_drake" / "data" / "sweep_example.yaml")
    params, _ = base_inputs(spec)
    rows = analysis_rows(params, (spec.gait, spec.model), list(enumerate(spec.points())))
    rows = [{k: str(v) for k, v in r.items()} for r in rows]
    (out / "sweep").mkdir()
    write_sweep_report(summarize_sweep(rows, spec.names, params.checks.sf_pass), spec.names,
                       spec.fidelity, (out / "sweep"), thresholds_text(params.checks))
    return out


@pytest.mark.parametrize("report", ["trot/summary.md", "jump/summary.md", "comparison.md",
                                    "analysis/report.md", "sweep/sweep.md"])
def test_the_demos_reports_keep_the_guide(written, report):
    assert (written / report).is_file()
    assert report_violations(written / report) == []


@pytest.mark.parametrize("run", ["trot", "jump"])
def test_a_runs_answer_opens_with_its_verdict(written, run):
    """A gait's and a maneuver's summary.md alike: the answer's first words are the verdict and
    the check that decided it, then the worst motor and its figure (not the figure first)."""
    import json

    s = json.loads((written / run / "summary.json").read_text())
    first = [line for line in (written / run / "summary.md").read_text().splitlines()
             if line.strip()][1]
    if s["verdict"] in ("pass", "warn", "fail"):
        assert first.startswith(f"{s['verdict'].upper()}, decided by the {s['deciding_check']} "
                                f"check: worst motor {s['worst_motor']}, "), first
    else:
        assert first.startswith(("NOT ACHIEVED", "No verdict")), first


@pytest.fixture(scope="module")
def gear_comparison(tmp_path_factory, simulated):
    """The demo's gear_comparison.md (`compare` of the trot at 8:1 and at 11.5:1): the 4.5 s
    ball-closure trot the session shares (tests/simulation/test_simulation.py,
    tests/test_pipeline.py) and the same at 11.5:1 (2.5 s to simulate and summarize)."""
    from fivebar_drake.pipeline import run_simulation, summarize_run
    from fivebar_drake.robots.quadruped.config import load_params
    from fivebar_drake.simulation.comparison import load_summaries, markdown
    from fivebar_drake.simulation.scenario import load_scenario
    from fivebar_drake.simulation.summary_text import write_summary
    from fivebar_drake.studies.fivebar_leg import with_sets

    out = tmp_path_factory.mktemp("gear")
    geared = with_sets(load_params(), ["motor.gear_ratio=11.5"])
    records = {"trot": simulated(duration_s=4.5, closure="ball"),
               "trot_gear_11.5": run_simulation(load_scenario(duration_s=4.5, closure="ball"),
                                                geared, progress=False)}
    for name, record in records.items():
        write_summary(summarize_run(record), record.params, out / name)
    path = out / "gear_comparison.md"
    path.write_text(markdown(load_summaries([out / name for name in records])))
    return path


def test_the_gear_comparison_of_two_real_runs_answers_first(gear_comparison):
    """Issue 32: that the 11.5:1 gearbox turns the torque failure into a speed failure is said
    in the first line, each run's verdict with its deciding check and figure."""
    assert report_violations(gear_comparison) == []
    first = gear_comparison.read_text().split("\n\n")[1]
    assert first.startswith("**Answer:** trot FAIL (torque, SF ")
    assert "trot_gear_11.5 FAIL (speed, " in first and "% beyond the envelope" in first
    assert "moved the limit from the torque check to the speed check" in first


@pytest.mark.parametrize("robot", ["doggo", "minitaur"])
def test_the_packaged_robots_optimal_report_keeps_the_guide(tmp_path, monkeypatch, robot):
    """optimal.md of a Doggo- or Minitaur-style robot (`make demo`'s robots/<robot>/optimal):
    its jump, drop, stand-up and published figures as the command writes them, the gait floors
    left out (monkeypatched to none: 1 s instead of 15 s a robot) and the top speed the trot's
    on one cell of its grid (3 s instead of 30)."""
    import functools

    import fivebar_drake.optimal.report as optimal
    from fivebar_drake.core.parameter_files import packaged
    from fivebar_drake.robots.quadruped.config import load_params

    monkeypatch.setattr(optimal, "KINDS", ())
    monkeypatch.setattr(optimal, "FASTEST", ())
    monkeypatch.setattr(optimal, "top_speed", functools.partial(
        optimal.top_speed, duties=(0.5,), shares=(0.75,)))
    result, _ = optimal.jump_limits(load_params(packaged(f"{robot}.toml")), speed_gaits=("trot",))
    assert result["published"], "a packaged robot's published jump is in its report"
    path = tmp_path / "optimal.md"
    path.write_text(optimal.markdown(result))
    assert path.read_text().splitlines()[2] == result["answer"]
    assert report_violations(path) == []
