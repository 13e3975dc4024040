"""The sweep under hostile input (issue 23): every bad spec, output folder, scheduler or resumed
table is refused with exit 2 and a message naming the file or option, before anything is
written; tables that do not belong to the sweep are recognised; plots cost no call per point."""

import csv
import json
import os

import pytest

from fivebar_drake.cli import main
from fivebar_drake.robots.quadruped.config import DEFAULT_PATH
from fivebar_drake.sweep.engine import finished_points, run_sweep
from fivebar_drake.sweep.spec import load_spec

SPEC = "vary:\n  gait.frequency_hz: [0.5, 1.0]\n  motor.gear_ratio: [8.0, 10.0]\n"


def write(tmp_path, text, name="spec.yaml"):
    path = tmp_path / name
    path.write_text(text) if isinstance(text, str) else path.write_bytes(text)
    return path


def refused(capsys, argv, *words):
    """main(argv) exits 2 with one message holding every word."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    for word in words:
        assert word in err, err
    return err


@pytest.mark.parametrize("text, words", [
    ("vary:\n" + "".join(f"  gait.p{i}: {{range: [0.0, 1.0], num: 1000000}}\n" for i in range(4)),
     ["points = 1000000000000000000000000", "[1, 1000000]"]),
    (SPEC + "plot: 5\n", ["plot = 5"]),
    (SPEC + "plot: [gait.a_m]\n", ["plot"]),
    ("vary:\n  motor.nonsense: [1.0]\n", ["motor.nonsense", "spec.yaml"]),
    ("vary:\n  gait.frequency_hz: [500.0]\n", ["gait.frequency_hz", "spec.yaml"]),
    ("vary: {gait.a_m: [0.04]}\nvary: {gait.a_m: [0.05]}\n", ["written twice"]),
    ("a: &x [1, 2]\nvary: {gait.a_m: *x}\n", ["aliases"]),
    (SPEC + "fidelity: simulation\nstep_check: 5\n", ["step_check = 5", "true or false"]),
    (SPEC + "step_check: true\n", ["step_check", "simulation points"]),
])
def test_bad_specs_exit_2_and_write_nothing(tmp_path, capsys, text, words):
    spec, out = write(tmp_path, text), tmp_path / "out"
    refused(capsys, ["sweep", str(spec), "--out", str(out), "--workers", "1"], *words)
    assert not out.exists()


def test_spec_that_is_not_utf8_or_not_a_file(tmp_path, capsys):
    refused(capsys, ["sweep", str(write(tmp_path, b"vary: {gait.a_m: [\xff]}\n"))], "not UTF-8")
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    refused(capsys, ["sweep", str(fifo)], "not a regular file")


def test_numbers_read_as_in_scenarios(tmp_path):
    spec = load_spec(write(tmp_path, "vary:\n  motor.viscous_friction_Nm_s: [1e-9, 2e-3]\n"))
    assert [p["motor.viscous_friction_Nm_s"] for p in spec.points()] == [1e-9, 2e-3]


@pytest.mark.parametrize("out, words", [("file", ["is a file"]), ("/sys/x", ["cannot create"])])
def test_bad_output_folder(tmp_path, capsys, out, words):
    target = write(tmp_path, "x", "file") if out == "file" else out
    refused(capsys, ["sweep", str(write(tmp_path, SPEC)), "--out", str(target)], *words)


@pytest.fixture
def quick_refusal(monkeypatch):
    """The sweep's client retries a refused connection until its timeout (10 s) before it gives
    up; 1 s here, the same failure (OSError "Timed out trying to connect") sooner."""
    import dask.distributed

    class QuickClient(dask.distributed.Client):
        def __init__(self, address=None, *args, timeout=None, **kwargs):
            super().__init__(address, *args, timeout="1s", **kwargs)

    monkeypatch.setattr(dask.distributed, "Client", QuickClient)


@pytest.mark.parametrize("address", ["garbage", "http://127.0.0.1:1", "tcp://127.0.0.1",
                                     "tcp://127.0.0.1:1"])
def test_bad_scheduler_writes_nothing(tmp_path, capsys, address, quick_refusal):
    """Refused naming --scheduler; the output folders the check made, every level of a new
    nested --out, are gone again (issue 33's twelfth class: only the last level was)."""
    out = tmp_path / "new" / "a" / "b"
    refused(capsys, ["sweep", str(write(tmp_path, SPEC)), "--out", str(out), "--scheduler",
                     address], "--scheduler")
    assert not (tmp_path / "new").exists()


def test_workers_bounded(tmp_path, capsys):
    refused(capsys, ["sweep", str(write(tmp_path, SPEC)), "--workers", "1000"], "--workers",
            "per core")


def test_resume_recognises_what_is_not_its_own(tmp_path, capsys, shared_client):
    spec = load_spec(write(tmp_path, SPEC))
    out = tmp_path / "out"
    first = run_sweep(spec, out, client=shared_client, progress=False)
    assert len(first.rows) == 4
    table = (out / "points.csv").read_text()
    lines = table.splitlines(keepends=True)
    header, rows = lines[0], lines[1:]
    # a duplicate, a point the sweep does not have, a non-integer point, extra cells, a row
    # whose values are not its point's, a line cut short: all dropped, their points recomputed
    alien = rows[1].replace("0.5", "0.75", 1)
    bad = [rows[0], rows[0], "7" + rows[1][1:], "x" + rows[2][1:], rows[3].rstrip("\n") + ",9\n",
           alien, rows[2][:10]]
    (out / "points.csv").write_text(header + "".join(bad))
    again = run_sweep(spec, out, client=shared_client, progress=False)
    assert [int(r["point"]) for r in again.rows] == [0, 1, 2, 3]
    assert again.computed == 3 and again.dropped == 6
    assert (out / "points.csv").read_text() == table
    assert finished_points(spec, out) == (4, 4)
    for name, text, words in (("points.csv", b"\x00\xff\xfe", "not UTF-8"),
                              ("points.csv", "a,b\n1,2\n", "header"),
                              ("sweep.json", '{"finger', "not valid JSON"),
                              ("sweep.json", "[1, 2]", "not a sweep record")):
        saved = (out / name).read_bytes()
        write(out, text, name)
        refused(capsys, ["sweep", str(tmp_path / "spec.yaml"), "--out", str(out)], words, name)
        (out / name).write_bytes(saved)


def test_a_changed_params_file_named_by_the_scenario_is_another_sweep(tmp_path, capsys):
    write(tmp_path, DEFAULT_PATH.read_text(), "robot.toml")
    write(tmp_path, "params_file: robot.toml\n", "scenario.yaml")
    spec = load_spec(write(tmp_path, "fidelity: simulation\nscenario: scenario.yaml\n"
                           "vary:\n  gait.frequency_hz: [1.0]\n"))
    before = spec.fingerprint()
    write(tmp_path, DEFAULT_PATH.read_text().replace("structure_kg = 1.62", "structure_kg = 1.7"),
          "robot.toml")
    assert spec.fingerprint() != before


def test_verdict_map_costs_no_call_per_point(tmp_path, monkeypatch):
    """5000 points draw with one scatter call per outcome, not one per point."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.axes import Axes

    from fivebar_drake.sweep.plots import write_sweep_plots

    calls = []
    original = Axes.scatter
    monkeypatch.setattr(Axes, "scatter", lambda self, *a, **k: calls.append(1) or original(
        self, *a, **k))
    rows = [{"point": str(i), "a": str(i % 100), "b": str(i // 100), "status": "ok",
             "worst_verdict": ("pass", "warn", "fail")[i % 3], "worst_safety_factor": "2.0",
             "speed_m_s": "0.1"} for i in range(5000)]
    write_sweep_plots(rows, ("a", "b"), "analysis", 2.0, tmp_path)
    assert len(calls) <= 4
    with open(tmp_path / "verdict_map.png", "rb") as f:
        assert f.read(4) == b"\x89PNG"


def test_table_rows_are_point_order(tmp_path, shared_client):
    spec = load_spec(write(tmp_path, SPEC))
    result = run_sweep(spec, tmp_path / "o", client=shared_client, progress=False)
    with open(result.table, newline="") as f:
        assert [int(r["point"]) for r in csv.DictReader(f)] == [0, 1, 2, 3]
    assert json.loads((tmp_path / "o" / "sweep.json").read_text())["fingerprint"]
