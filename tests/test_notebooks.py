"""Every notebook in notebooks/ runs top to bottom without errors (outputs are not kept), and the
figures a notebook prints are the reports' (the same functions, the same units)."""

import json
import re
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOKS = sorted((Path(__file__).parent.parent / "notebooks").glob("*.ipynb"))
SIMULATING = {"review_recording.ipynb", "design_study.ipynb"}   # simulations of several seconds


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """run(path): the notebook executed once in a folder of its own (with MPLBACKEND=Agg, and
    TMPDIR there, so that what it writes to a temporary folder stays for the test to read):
    (its cells with their outputs, its printed text, the folder)."""
    done = {}

    def run(path: Path):
        if path.name not in done:
            nb = nbformat.read(path, as_version=4)
            assert not any(cell.get("outputs") for cell in nb.cells), \
                f"{path.name} is committed with outputs"
            folder = tmp_path_factory.mktemp(path.stem)
            with pytest.MonkeyPatch.context() as mp:
                mp.setenv("MPLBACKEND", "Agg")
                mp.setenv("TMPDIR", str(folder))        # a notebook's scratch folder in its own
                NotebookClient(nb, timeout=600, kernel_name="python3",
                               resources={"metadata": {"path": str(folder)}}).execute()
            text = "".join(o.get("text", "") for c in nb.cells for o in c.get("outputs", []))
            done[path.name] = (nb, text, folder)
        return done[path.name]

    return run


def test_there_are_notebooks():
    assert NOTEBOOKS


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.name in SIMULATING
                                  else p for p in NOTEBOOKS], ids=lambda p: p.name)
def test_notebook_runs(path, executed):
    nb, text, _ = executed(path)
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.get("output_type") == "error"]
    assert not errors
    assert "Worker process still alive" not in text


def test_torque_analysis_prints_the_reports_figures(executed):
    """The verdicts and the winding temperatures torque_analysis.ipynb prints are report.json's
    (what report.md states), to the digits printed: a current where thermal_margin wants one."""
    _, text, folder = executed(NOTEBOOKS[0].parent / "torque_analysis.ipynb")
    report = json.loads((folder / "analysis" / "report.json").read_text())
    checked = 0
    for model, motors in report["results"].items():
        for motor, r in motors.items():
            c = r["checks"]
            verdict = (f"{model:>9} {motor}: .*verdict {c['verdict'].upper()}, decided by the "
                       f"{c['deciding_check']} check \\(SF {c['torque']['sf']:.2f}")
            assert re.search(verdict, text), verdict
            checked += 1
    for model, motors in report["thermal"]["models"].items():
        for motor, v in motors.items():
            line = (f"{model:>9} {motor}: RMS {v['rms_torque_Nm']:.3f} N·m at the output = "
                    f"{v['rms_current_A']:.3f} A, steady winding {v['steady_state_C']:.1f} °C, "
                    f"margin {v['margin_K']:.1f} K")
            assert line in text, line
            checked += 1
    assert checked == 3 * 2 + 2 * 2


@pytest.mark.slow
def test_design_study_prints_its_reports_figures(executed):
    """The figures design_study.ipynb prints are those of the reports its runs wrote: the example
    sweep's fastest passing point (sweep.md's, as `make demo` writes it), each simulated point's
    worst motor, SF and verdict (points.csv, the run's summary.json worst motor) and the
    envelope's answer (envelope.json)."""
    import csv

    _, text, folder = executed(NOTEBOOKS[0].parent / "design_study.ipynb")
    (work,) = folder.glob("design_study_*")
    sweep_md = (work / "sweep_example" / "sweep.md").read_text()
    point, speed, sf = re.search(r"the fastest passing: point (\d+), ([\d.]+) m/s, worst SF "
                                 r"(\d+\.\d+)", sweep_md).groups()
    hz, gear = re.search(rf"Point {point}: gait.frequency_hz = ([\d.]+), gait.a_m = [\d.]+, "
                         r"motor.gear_ratio = ([\d.]+)\.", sweep_md).groups()
    assert (f"fastest design where every motor passes: point {point}, gear {float(gear):g}:1 at "
            f"{float(hz):g} Hz, {speed} m/s, worst SF {sf}") in text
    with open(work / "simulated" / "points.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2
    for r in rows:
        line = (f"gear ratio {r['motor.gear_ratio']}: {r['status']}, worst motor "
                f"{r['worst_motor']}, demand p99 {float(r['worst_demand_Nm']):.2f} N·m, SF "
                f"{float(r['worst_safety_factor']):.2f}; verdict {r['worst_verdict'].upper()}")
        assert line in text, line
    envelope = json.loads((work / "envelope" / "envelope.json").read_text())
    assert envelope["answer"] in text
