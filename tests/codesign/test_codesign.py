"""The co-design (`fivebar-drake codesign`): a small co-design on a running Dask scheduler (a
local cluster started here) whose recommended design passes its simulated envelope (read back
from the finalist's envelope.json), is the lightest finalist that does, and whose parameter
file runs `analyze` and `simulate`; predicted figures set beside the simulated ones as the
envelopes report them; an interrupted search resumed into the same folder giving the trials of
an uninterrupted one; a finished co-design run again into its folder simulating nothing and
giving the same design; a spec no candidate meets (exit 1, the requirement and the best margin
named); bad specs refused (exit 2, the field named, nothing written)."""

import csv
import json
import math
import re

import numpy as np
import pytest

from fivebar_drake.cli import main
from fivebar_drake.codesign import search as search_module
from fivebar_drake.codesign.designs import design_params
from fivebar_drake.codesign.run import corrections, next_finalist
from fivebar_drake.codesign.spec import load_codesign_spec
from fivebar_drake.actuators.catalog import actuator_mass_kg, catalog
from fivebar_drake.robots.quadruped.config import load_params
from style_rules import report_violations

ENVELOPE = """\
    scenario: {stand_s: 0.2, ramp_s: 0.5}
    maneuvers:
      - {name: trot, gait: trot, gait_frequency_hz: 2.0, gait_a_m: 0.03, duration_s: 2.2}
"""
DROP = "      - {name: drop, gait: {kind: drop, height_m: 0.05}, duration_s: 1.2}\n"
SPEC = """\
variables:
  motor: [tmotor_mn5212_kv340, cubemars_ak80_9]
  motor.gear_ratio: [8.0, 12.0]
requirements:
  accept: warn
  envelope:
""" + ENVELOPE + DROP + "budget: {trials: 6, finalists: 2}\n"
SEARCH_ONLY = """\
variables:
  motor: [default_assumed, tmotor_mn5212_kv340, maxon_ec45_flat_70w_24v]
  motor.gear_ratio: [4.0, 14.0]
  leg.ce_m: [0.135, 0.145, 0.155]
requirements:
  envelope:
""" + ENVELOPE + "budget: {trials: 9, seed: 3}\n"
NOBODY = """\
variables:
  motor: [maxon_ec45_flat_70w_24v]
  motor.gear_ratio: [4.0, 5.0]
requirements:
  envelope:
""" + ENVELOPE + "budget: {trials: 4}\n"
ACCEPT = ("pass", "warn")


def write(folder, text, name="spec.yaml"):
    path = folder / name
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def codesign(tmp_path_factory):
    """The small co-design through the command line on a running scheduler (a local cluster of
    2 process workers started here): (exit code, its folder, design.json)."""
    from dask.distributed import LocalCluster

    import fivebar_drake.codesign.dossier as dossier

    folder = tmp_path_factory.mktemp("codesign")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, pytest.MonkeyPatch.context() as patch:
        patch.setattr(dossier, "SHEET_GAITS", ("pronk",))     # one top speed: 7 s, not 40
        code = main(["codesign", str(write(folder, SPEC)), "--out", str(folder / "out"),
                     "--scheduler", cluster.scheduler_address])
    return code, folder / "out", json.loads((folder / "out" / "design.json").read_text())


def test_the_reports_keep_the_style_guide(codesign):
    """design.md, and each finalist's envelope.md and summary.md (docs/output_style.md)."""
    assert report_violations(codesign[1]) == []


def envelope_sfs(folder) -> dict:
    """Per maneuver: the worst motor's safety factor and the verdict, from envelope.json."""
    report = json.loads((folder / "envelope.json").read_text())
    return {name: (min(m["checks"]["torque"]["sf"] for m in e["motors"].values()), e["verdict"])
            for name, e in report["maneuvers"].items()}


def test_the_recommended_design_passes_in_simulation_and_is_the_lightest_that_does(codesign):
    code, out, report = codesign
    assert code == 0 and report["recommended"] is not None
    first = (out / "design.md").read_text().splitlines()[0]
    assert first.startswith(f"Recommended: {report['recommended']['name']}: ")
    mass = {f["key"]: actuator_mass_kg(f["design"]["motor"], f["design"]["motor.gear_ratio"],
                                       f["design"]["gearbox"]) for f in report["finalists"]}
    passing = {key for key in mass if all(v in ACCEPT for _, v in envelope_sfs(
        out / "finalists" / key).values())}
    assert report["recommended"]["key"] == min(passing, key=mass.get)
    assert {f["key"] for f in report["finalists"] if f["simulated"]["passes"]} == passing
    for key in ("default", *mass):
        assert (out / "finalists" / key / "drop" / "run.rrd").is_file()


def test_the_recommended_design_has_its_dossier(codesign):
    """dossier/: the design's SDF (Drake parses it strictly, the design's mass), its MJCF
    (MuJoCo loads it, the same mass) and its spec sheet, whose requirements per motor are its
    simulated envelope's largest demand and RMS current, read here from envelope.json."""
    import mujoco
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    from fivebar_drake.codesign.designs import design_params
    from fivebar_drake.codesign.spec import load_codesign_spec

    _, out, report = codesign
    r = report["recommended"]
    folder = out / "dossier"
    spec = load_codesign_spec(out.parent / "spec.yaml")
    mass = design_params(spec.envelope.maneuvers[0].params, r["design"]).robot.total_mass_kg
    plant = MultibodyPlant(0.001)
    parser = Parser(plant)
    parser.SetStrictParsing()
    parser.AddModels(folder / "quadruped.sdf")
    plant.Finalize()
    assert plant.CalcTotalMass(plant.CreateDefaultContext()) == pytest.approx(mass, rel=1e-9)
    model = mujoco.MjModel.from_xml_path(str(folder / "quadruped.xml"))
    assert model.body_mass.sum() == pytest.approx(mass, rel=1e-9)
    sheet = (folder / "spec_sheet.md").read_text()
    assert sheet.splitlines()[2].startswith(f"**Answer:** Recommended: {r['name']}")
    envelope = json.loads((out / "finalists" / r["key"] / "envelope.json").read_text())
    for motor in "AB":
        checks = [e["motors"][motor]["checks"] for e in envelope["maneuvers"].values()]
        torque = max(c["torque"]["torque_Nm"] for c in checks)
        current = max(c["thermal"]["rms_current_A"] for c in checks)
        row = next(line for line in sheet.splitlines() if line.startswith(f"| {motor} | "))
        cells = [c.strip() for c in row.split("|")[1:-1]]
        assert float(cells[1]) == pytest.approx(torque, abs=0.005)
        assert float(cells[7]) == pytest.approx(current, abs=0.005)
        vendor = next(row for row in csv.DictReader((folder / "requirements.csv").open())
                      if row["motor"] == motor)
        assert float(vendor["peak_torque_asked_Nm"]) == pytest.approx(torque, rel=1e-3)
        assert float(vendor["largest_rms_current_A"]) == pytest.approx(current, rel=1e-3)
    assert "pronk top speed" in sheet
    assert "(margins.png)" in sheet and (folder / "margins.png").stat().st_size > 10_000
    assert len(sheet.splitlines()[2]) <= 200


def test_the_spec_sheet_overlays_both_designs_operating_points(codesign):
    """dossier/operating_points.png draws the default design's and the recommended design's
    operating points (their envelopes' operating_points.npz), whose largest demand per motor is
    each maneuver's summary.json peak; the spec sheet shows the picture."""
    from fivebar_drake.envelope.plots import load_points

    _, out, report = codesign
    folder = out / "dossier"
    assert "(operating_points.png)" in (folder / "spec_sheet.md").read_text()
    assert (folder / "operating_points.png").stat().st_size > 10_000
    for key in ("default", report["recommended"]["key"]):
        points = load_points(out / "finalists" / key / "operating_points.npz")
        for name, (speed, demand) in points.items():
            legs = json.loads((out / "finalists" / key / name / "summary.json").read_text())["legs"]
            for j, motor in enumerate("AB"):
                assert speed[j].shape == demand[j].shape and demand[j].size > 100
                assert np.abs(demand[j]).max() == max(ms[motor]["demand_peak_Nm"]
                                                      for ms in legs.values())


def test_predicted_and_simulated_figures_side_by_side(codesign):
    _, out, report = codesign
    for finalist in report["finalists"]:
        simulated = envelope_sfs(out / "finalists" / finalist["key"])
        rows = {c["maneuver"]: c for c in finalist["comparison"]}
        assert set(rows) == {"trot", "drop"}
        assert rows["trot"]["level"] == "closed form" and rows["drop"]["level"] == "floor"
        for name, row in rows.items():
            assert row["simulated_sf"] == pytest.approx(simulated[name][0])
            difference = row["predicted_sf"] / simulated[name][0] - 1.0
            assert row["flagged"] == (abs(difference) > 0.10)
            flag = "FLAG" if row["flagged"] else ""
            assert re.search(rf"\| {finalist['key']} \| {name} \| .*\| "
                             + re.escape(f"{difference:+.0%} | {flag} |"),
                             (out / "design.md").read_text())
        # the floor bounds what any controller needs: the motors' peak over it is an upper
        # bound on the simulated safety factor
        assert rows["drop"]["predicted_sf"] >= simulated["drop"][0]


def test_the_margins_table_holds_the_default_designs_figures(codesign):
    _, out, _ = codesign
    text = (out / "design.md").read_text()
    for name, (sf, verdict) in envelope_sfs(out / "finalists" / "default").items():
        assert re.search(rf"\| {name} \| verdict \| \w+ \| \| {verdict} \| \|", text)
        assert re.search(rf"\| {name} \| torque \| [\d.]+ \| [\d.]+ \| {sf:.2f} \| "
                         rf"{sf / 1.5:.2f} \|", text)       # sf_warn: warn is accepted


def test_design_toml_is_the_recommended_design_and_runs(codesign, tmp_path):
    _, out, report = codesign
    design = report["recommended"]["design"]
    loaded = load_params(out / "design.toml")
    spec = load_codesign_spec(out.parent / "spec.yaml")
    assert loaded.motor == design_params(spec.envelope.maneuvers[0].params, design).motor
    entry = catalog()[design["motor"]]
    assert loaded.motor.torque_constant_Nm_per_A == entry.torque_constant_Nm_per_A.value
    assert loaded.robot.motors_kg == pytest.approx(8 * actuator_mass_kg(
        design["motor"], design["motor.gear_ratio"], design["gearbox"]))
    assert main(["analyze", "--config", str(out / "design.toml"), "--out",
                 str(tmp_path / "a")]) == 0
    assert main(["simulate", "--config", str(out / "design.toml"), "--duration", "0.3",
                 "--out", str(tmp_path / "s")]) in (0, 1)      # too short for a verdict
    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert summary["completed"] and not summary["error"]


def test_a_rerun_into_the_same_folder_simulates_nothing_and_gives_the_same_design(codesign,
                                                                                monkeypatch):
    import fivebar_drake.codesign.dossier as dossier

    monkeypatch.setattr(dossier, "SHEET_GAITS", ("pronk",))     # as the fixture's run
    _, out, report = codesign
    envelopes = sorted((out / "finalists").glob("*/envelope.json"))
    stamps = [p.stat().st_mtime_ns for p in envelopes]
    assert len(envelopes) == len(report["finalists"]) + 1 >= 2       # and the default design
    assert main(["codesign", str(out.parent / "spec.yaml"), "--out", str(out)]) == 0
    assert [p.stat().st_mtime_ns for p in envelopes] == stamps
    assert json.loads((out / "design.json").read_text()) == report


def test_an_interrupted_search_resumes_to_the_trials_of_an_uninterrupted_one(tmp_path,
                                                                               monkeypatch):
    spec = load_codesign_spec(write(tmp_path, SEARCH_ONLY))
    (tmp_path / "whole").mkdir()
    whole = search_module.search(spec, tmp_path / "whole", progress=False)
    calls, evaluate = [], search_module.evaluate

    def cut_at_the_fifth(spec, values):
        calls.append(values)
        if len(calls) == 5:
            raise KeyboardInterrupt
        return evaluate(spec, values)

    monkeypatch.setattr(search_module, "evaluate", cut_at_the_fifth)
    (tmp_path / "cut").mkdir()
    with pytest.raises(KeyboardInterrupt):
        search_module.search(spec, tmp_path / "cut", progress=False)
    monkeypatch.undo()
    states = [t.state.name for t in search_module.open_study(spec, tmp_path / "cut").trials]
    assert states == ["COMPLETE"] * 4 + ["RUNNING"]
    resumed = search_module.search(spec, tmp_path / "cut", progress=False)

    def trials(study):
        return [(t.params, t.values, t.state.name, t.user_attrs["prediction"]["margin"])
                for t in study.trials]

    assert trials(resumed) == trials(whole) and len(whole.trials) == spec.trials
    assert len({t.params["motor"] for t in whole.trials}) > 1        # it explored
    assert (search_module.best_predicted(resumed, spec)
            == search_module.best_predicted(whole, spec))


def test_a_spec_no_candidate_meets_names_the_requirement_and_the_best_margin(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["codesign", str(write(tmp_path, NOBODY)), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    found = re.search(r"no candidate meets trot (\w+): the best, (.+), reaches a predicted "
                      r"margin of ([\d.]+)", err)
    assert found, err
    report = json.loads((out / "design.json").read_text())
    margins = {c["name"]: c["maneuvers"]["trot"]["margins"][found.group(1)]
               for c in report["candidates"]}
    assert max(margins.values()) < 1.0
    assert found.group(2) == max(margins, key=margins.get)
    assert float(found.group(3)) == pytest.approx(max(margins.values()), abs=0.005)
    assert not (out / "design.toml").exists() and not (out / "finalists").exists()
    assert (out / "design.md").read_text().startswith("No design recommended: no candidate")
    # another spec into the same folder: refused, the journal kept as it was (not appended to)
    journal = (out / "codesign.journal").read_bytes()
    other = write(tmp_path, NOBODY.replace("trials: 4", "trials: 5"), "other.yaml")
    assert main(["codesign", str(other), "--out", str(out)]) == 2
    assert "another co-design" in capsys.readouterr().err
    assert (out / "codesign.journal").read_bytes() == journal
    # a journal cut mid-line (a crash, a full disk): the cut record dropped, resumed to the same
    # answer; a stray line in the middle: exit 2 naming the journal and the line
    (out / "codesign.journal").write_bytes(journal + b'{"op_code": 5, "worker_id": "x", "tr')
    assert main(["codesign", str(write(tmp_path, NOBODY)), "--out", str(out)]) == 1
    assert "was cut short" in capsys.readouterr().err
    lines = (out / "codesign.journal").read_bytes().split(b"\n")
    (out / "codesign.journal").write_bytes(b"\n".join(lines[:2] + [b"stray"] + lines[2:]))
    assert main(["codesign", str(write(tmp_path, NOBODY)), "--out", str(out)]) == 2
    assert "line 3 is not a journal record" in capsys.readouterr().err


@pytest.mark.parametrize("change, words", [
    (("[tmotor_mn5212_kv340, cubemars_ak80_9]", "[tmotor_mn5212, cubemars_ak80_9]"),
     ["variables.motor", "tmotor_mn5212"]),
    (("motor.gear_ratio: [8.0, 12.0]", "motor.gear_ratio: [12.0, 8.0]"),
     ["variables.motor.gear_ratio", "low < high"]),
    (("motor.gear_ratio: [8.0, 12.0]", "leg.ce_mm: [0.1, 0.2]"),
     ["variables.leg.ce_mm", "no such field"]),
    (("motor.gear_ratio: [8.0, 12.0]", "leg.ce_m: [-0.1, 0.2]"), ["variables.leg.ce_m"]),
    (("gait: trot,", "gait: moonwalk,"), ["requirements.envelope.maneuvers[0]", "moonwalk"]),
    (("accept: warn", "accept: fail"), ["requirements.accept"]),
    (("trials: 6", "trials: 0"), ["budget.trials"]),
    (("budget:", "objectives: [speed]\nbudget:"), ["objectives", "speed"]),
    (("motor.gear_ratio: [8.0, 12.0]", "robot.motors_kg: [2.0, 3.0]"),
     ["variables.robot.motors_kg", "vary `motor`"]),
    (("motor.gear_ratio: [8.0, 12.0]", "motor.peak_current_A: [3.0, 4.0]"),
     ["variables.motor.peak_current_A", "catalogue motor"]),
    (("[tmotor_mn5212_kv340, cubemars_ak80_9]", "[cubemars_ak80_9, mit_mini_cheetah]"),
     ["variables.motor.gear_ratio", "built in"]),
    (("motor.gear_ratio: [8.0, 12.0]", "gait.samples: [60.5, 120]"),
     ["variables.gait.samples", "whole numbers"]),
    (("[tmotor_mn5212_kv340, cubemars_ak80_9]\n  motor.gear_ratio: [8.0, 12.0]",
      "[tmotor_mn5212_kv340]\n  gearbox: [single_stage_planetary]\n"
      "  motor.gear_ratio: [500.0, 900.0]"),
     ["variables.motor.gear_ratio", "no design of the space can be built"]),
    (("  motor: [tmotor_mn5212_kv340, cubemars_ak80_9]\n", ""),
     ["variables.motor", "is required", "default_assumed"]),
    (("accept: warn", "accept: warn\n  top_speed_m_s: {gallop: 2.0}"),
     ["requirements.top_speed_m_s", "'trot', 'bound', 'pronk'"]),
    (("accept: warn", "accept: warn\n  top_speed_m_s: {pronk: .nan}"),
     ["requirements.top_speed_m_s.pronk", "finite"]),
    (("accept: warn", "accept: warn\n  top_speed_m_s: {trot: '700 mm/s'}"),
     ["requirements.top_speed_m_s.trot", "a number"]),
    (("budget:", "objectives: [actuator_mass_kg, 'top_speed_m_s:Bound']\nbudget:"),
     ["objectives[1]", "top_speed_m_s:GAIT"]),
])
def test_bad_specs_are_refused_naming_the_field(tmp_path, capsys, change, words):
    spec = write(tmp_path, SPEC.replace(*change))
    assert main(["codesign", str(spec), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert str(spec) in err and all(w in err for w in words), err
    assert not (tmp_path / "out").exists()


def test_a_design_carries_its_actuators_mass_and_motor(tmp_path):
    spec = load_codesign_spec(write(tmp_path, SEARCH_ONLY))
    base = spec.envelope.maneuvers[0].params
    design = {"motor": "odrive_d5065_270kv", "gearbox": "two_stage_timing_belt",
              "motor.gear_ratio": 10.0, "leg.ce_m": 0.15}
    params = design_params(base, design)
    assert params.robot.motors_kg == pytest.approx(
        8 * actuator_mass_kg("odrive_d5065_270kv", 10.0, "two_stage_timing_belt"))
    assert params.leg.ce_m == 0.15 and params.motor.gear_ratio == 10.0
    assert params.motor.gear_efficiency == pytest.approx(0.95**2)
    # its own winding (issue 39), not the base's: its continuous current at its limit
    assert params.motor.thermal_resistance_K_W != base.motor.thermal_resistance_K_W
    assert params.motor.thermal_continuous_current_A == pytest.approx(
        catalog()["odrive_d5065_270kv"].continuous_current_A.value, rel=1e-12)
    assert params.motor.ambient_C == base.motor.ambient_C
    assert math.isclose(params.motor.peak_current_A,
                        catalog()["odrive_d5065_270kv"].peak_current_A.value)



def test_a_prediction_found_optimistic_is_trusted_less_for_the_next_finalist(tmp_path):
    spec = load_codesign_spec(write(tmp_path, SEARCH_ONLY))

    def entry(trial, mass, thermal):
        return {"trial": trial, "name": f"design {trial}", "meets": True, "design": {},
                "objectives": {"actuator_mass_kg": mass},
                "maneuvers": {"trot": {"margins": {"torque": 2.0, "thermal": thermal}}}}

    light, middle, heavy = entry(0, 0.30, 1.02), entry(1, 0.33, 1.05), entry(2, 0.36, 1.20)
    entries = [heavy, middle, light]
    assert next_finalist(spec, entries, set(), {}) is light
    # the lightest fails its thermal check in simulation at 0.92 where 1.02 was predicted
    failed = {"maneuvers": {"trot": {"margins": {"torque": 2.1, "thermal": 0.92}}}}
    factors = corrections([(light, failed)])
    assert factors == {"trot thermal": pytest.approx(0.92 / 1.02)}   # the torque held up
    # 1.05 x 0.90 < 1: the middle design is skipped; 1.20 x 0.90 >= 1
    assert next_finalist(spec, entries, {light["name"]}, factors) is heavy


def test_an_integer_parameter_is_varied_as_integers(tmp_path):
    """gait.samples is an integer: its values stay integers and its range is sampled as
    integers (every value became a float: "60.0 must be an integer")."""
    spec = load_codesign_spec(write(tmp_path, SEARCH_ONLY.replace(
        "leg.ce_m: [0.135, 0.145, 0.155]", "gait.samples: [60, 120]")))
    varied = {v.path: v for v in spec.vary}["gait.samples"]
    assert varied.integer and (varied.low, varied.high) == (60, 120)
    study = search_module.search(spec, tmp_path, progress=False)
    samples = [t.params["gait.samples"] for t in study.trials]
    assert all(isinstance(x, int) and 60 <= x <= 120 for x in samples)
    assert not any("must be an integer" in (t.user_attrs["prediction"].get("error") or "")
                   for t in study.trials)


def test_an_unreachable_scheduler_is_refused_before_any_folder(tmp_path, capsys):
    """codesign --scheduler to an address nothing answers, with a nested --out: exit 2 naming
    --scheduler before the search, no level of the nested folder left (issue 44)."""
    out = tmp_path / "new" / "a" / "b"
    assert main(["codesign", str(write(tmp_path, SPEC)), "--out", str(out), "--scheduler",
                 "tcp://127.0.0.1:9"]) == 2
    assert "--scheduler" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()


def test_the_entry_page_gives_one_answer_and_links_every_output(codesign, tmp_path):
    """`fivebar-drake index` over a folder holding the co-design: the default design's answer
    (its simulated envelope's design_answer) first, the fix as design.md's first line, both at
    most 200 characters; the maneuver table's worst SF and need as envelope.json has them; every
    link and picture of index.html a file in the folder, and every report and recording in the
    folder linked. An empty folder is refused (exit 2), nothing written."""
    import shutil
    from html.parser import HTMLParser

    _, out, report = codesign
    root = tmp_path / "out"
    shutil.copytree(out, root / "codesign")
    assert main(["index", str(root)]) == 0
    text = (root / "index.md").read_text()
    envelope = json.loads((root / "codesign/finalists/default/envelope.json").read_text())
    answer = envelope["design_answer"]["text"]
    assert len(answer) <= 200 and len(report["answer"]) <= 200
    assert answer in text.splitlines()[2]
    assert (out / "design.md").read_text().splitlines()[0] == report["answer"]
    assert f"**Fix:** {report['answer']}" in text
    for name, e in envelope["maneuvers"].items():
        row = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
        sf = min(m["checks"]["torque"]["sf"] for m in e["motors"].values())
        assert f"| {sf:.2f} |" in row
        assert f"| {e['any_controller']['floor_Nm']:.2f} |" in row

    class Targets(HTMLParser):
        found = []

        def handle_starttag(self, tag, attrs):
            self.found += [v for k, v in attrs if k in ("href", "src")]

    page = Targets()
    page.feed((root / "index.html").read_text())
    assert page.found and all((root / t).is_file() for t in page.found), page.found
    outputs = {p.relative_to(root).as_posix() for p in root.rglob("*")
               if p.suffix in (".md", ".rrd") and p.name != "index.md"}
    assert outputs <= set(page.found)
    assert any(t.endswith(".png") for t in page.found)
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["index", str(empty)]) == 2 and list(empty.iterdir()) == []


def test_design_md_sets_each_tracked_top_speed_beside_its_optimum(codesign):
    """design.md's "Top speeds tracked" (codesign.report.markdown): per finalist and gait the
    speed required, the optimum's, the tracked run's mean and its share, the verdict and
    whether it meets the requirement ("(an objective)" where none asks a speed); none without
    a tracked top speed. The run's outcome is set here on the small co-design's report."""
    import copy

    from fivebar_drake.codesign.report import markdown

    _, out, report = codesign
    spec = load_codesign_spec(out.parent / "spec.yaml")
    assert "## Top speeds tracked" not in markdown(spec, report)
    tracked = copy.deepcopy(report)
    finalist = tracked["finalists"][0]
    finalist["simulated"]["top_speeds"] = {
        "bound": {"required_m_s": 0.5, "predicted_m_s": 0.501, "simulated_m_s": 0.49,
                  "verdict": "fail", "achieved": True, "meets": False},
        "pronk": {"required_m_s": None, "predicted_m_s": 0.85, "simulated_m_s": 0.0,
                  "verdict": "not_achieved", "achieved": False, "meets": None}}
    lines = markdown(spec, tracked).splitlines()
    assert "## Top speeds tracked" in lines
    rows = [line for line in lines if line.startswith(f"| {finalist['key']}: ")
            and ("| bound |" in line or "| pronk |" in line)]
    assert rows[0].endswith("| bound | 0.50 | 0.50 | 0.490 | 98% | fail | no |")
    assert rows[1].endswith("| pronk | — | 0.85 | 0.000 | 0% | not_achieved | (an objective) |")
