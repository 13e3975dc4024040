"""Every mechanism of the catalog is a study keeping one contract (studies/base.py), and the
command line runs them all one way: an option of one study's own is refused for the others
before anything is written."""

import pytest

from fivebar_drake import catalog
from fivebar_drake.cli import main
from fivebar_drake.studies.base import Study

OWN = [("analyze", "--gait", "trot"), ("analyze", "--set", "motor.gear_ratio=11.5"),
       ("simulate", "--scenario", "s.yaml"), ("simulate", "--gait", "trot"),
       ("simulate", "--closure", "ball"), ("simulate", "--set", "motor.gear_ratio=11.5"),
       ("simulate", "--step-check", None)]


@pytest.mark.parametrize("name", catalog.mechanisms())
def test_every_mechanism_is_a_study(name):
    study = catalog.study(name)
    assert isinstance(study, Study)
    assert study.ANALYSIS_FILES and "report.json" in study.ANALYSIS_FILES
    assert study.SIMULATION_FILES[-1] == "summary.json"
    assert catalog.default_out(name, "analyze") != catalog.default_out(name, "simulate")


@pytest.mark.parametrize("name", [m for m in catalog.mechanisms() if m != catalog.FIVEBAR])
@pytest.mark.parametrize("command, option, value", OWN)
def test_an_option_of_another_study_is_refused(name, command, option, value, tmp_path, capsys):
    assert option not in catalog.study(name).OPTIONS
    out = tmp_path / "out"
    argv = [command, "--mechanism", name, option, *([value] if value else []), "--out", str(out)]
    assert main(argv) == 2
    shown = [value] if option == "--set" else True if value is None else value
    assert (f"command line: {option} = {shown}: applies to --mechanism {catalog.FIVEBAR} only, "
            f"not to {name}") in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("name", [m for m in catalog.mechanisms() if m != catalog.FIVEBAR])
def test_a_stop_request_ends_every_run_early_and_its_files_are_written(name, tmp_path):
    """A signal during another mechanism's simulation stops the stepping within a slice
    (core.interrupts.advance): what was simulated is written and said so (exit 130/143)."""
    study = catalog.study(name)
    plan = study.load_simulation(None, None)
    calls = []

    def stop():
        calls.append(1)
        return "SIGTERM" if len(calls) >= 3 else ""

    record = study.simulate(plan.inputs, False, stop)
    written = study.write_simulation(record, tmp_path)
    assert "interrupted by SIGTERM" in written.interrupted and "wrote what was" in \
        written.interrupted
    assert [p.name for p in written.files][-1] == "summary.json"
    assert all(p.exists() for p in written.files)


@pytest.mark.parametrize("name, duration", [("ballscrew_leg", "0.0005"), ("scara", "1e-300"),
                                            ("parallel4", "1e9")])
def test_durations_are_bounded_by_plant_steps(name, duration, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["simulate", "--mechanism", name, "--duration", duration, "--out", str(out)]) == 2
    assert "plant steps" in capsys.readouterr().err and not out.exists()
