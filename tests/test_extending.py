"""The README's extension templates, run as a package outside fivebar_drake: its gait, stance
law, controller and closure blocks become the modules of a package in a temporary folder,
registered by entry points of the group fivebar_drake.plugins (a dist-info folder on the path,
as pip installs one) and simulated through the command line in fresh processes; a swapped
stance law leaves every compiled law cached (a second process's first controller tick)."""

import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"
MODULES = {"stand_still": "gait", "vertical_only": "stance_law", "hold": "controller",
           "ball_api": "closure"}                 # a template's kind -> its module's name


def templates() -> dict[str, str]:
    """The README's extension templates by the kind each registers."""
    text = README.read_text()
    section = text[text.index("**Extending:"):text.index("A **mechanism** is a folder")]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    found = {}
    for block in blocks:
        kind = re.search(r'kind: ClassVar\[str\] = "(\w+)"', block).group(1)
        found[kind] = block
    return found


@pytest.fixture(scope="module")
def plugin_path(tmp_path_factory) -> Path:
    """A folder holding the package fivebar_templates (the README's templates, one module
    each) and its dist-info with the entry points."""
    root = tmp_path_factory.mktemp("plugins")
    package = root / "fivebar_templates"
    package.mkdir()
    (package / "__init__.py").write_text('"""The README\'s templates."""\n')
    found = templates()
    assert set(found) == set(MODULES), f"the README's templates register {sorted(found)}"
    for kind, code in found.items():
        (package / f"{MODULES[kind]}.py").write_text(code)
    info = root / "fivebar_templates-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fivebar-templates\n"
                                   "Version: 0.1\n")
    (info / "entry_points.txt").write_text("[fivebar_drake.plugins]\n" + "".join(
        f"{kind} = fivebar_templates.{module}\n" for kind, module in MODULES.items()))
    return root


def run(plugin_path: Path, *args, cwd=None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(plugin_path), os.environ.get("PYTHONPATH", "")])}
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, env=env,
                          cwd=cwd, timeout=600)


def test_the_command_line_offers_the_plugins_kinds(plugin_path):
    help_text = run(plugin_path, "-m", "fivebar_drake", "simulate", "--help").stdout
    choices = re.sub(r"\s+", "", help_text)
    assert "stand_still" in choices and "ball_api" in choices
    assert "stand_still" not in re.sub(r"\s+", "", run(plugin_path.parent, "-m", "fivebar_drake",
                                                       "simulate", "--help").stdout)


def test_the_templates_simulate_through_the_command_line(plugin_path, tmp_path):
    """The template gait with the template stance law in the default controller and the
    template closure: the robot stands on its own law; the same run closed by the package's own
    ball constraint (the same constraint, declared in the SDF) gives the same torques."""
    scenario = {"gait": "stand_still", "closure": "ball_api", "stance_law": "vertical_only",
                "stand_s": 0.0, "ramp_s": 0.0, "duration_s": 3.2}
    (tmp_path / "s.yaml").write_text(json.dumps(scenario))
    done = run(plugin_path, "-m", "fivebar_drake", "simulate", "--scenario", "s.yaml",
               "--out", "run", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    ran = summary["ran"]
    assert ran["gait"]["kind"] == "stand_still" and ran["closure"]["kind"] == "ball_api"
    assert ran["controller"]["stance_law"] == "vertical_only"
    assert summary["completed"] and summary["max_tilt_deg"] < 2.0
    assert summary["max_loop_gap_m"] < 1e-3
    done = run(plugin_path, "-m", "fivebar_drake", "simulate", "--scenario", "s.yaml",
               "--closure", "ball", "--out", "ball", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    ball = json.loads((tmp_path / "ball" / "summary.json").read_text())
    for leg, motors in ball["legs"].items():      # one constraint, two ways to declare it
        for motor, m in motors.items():
            theirs = summary["legs"][leg][motor]["rms_torque_Nm"]
            assert theirs == pytest.approx(m["rms_torque_Nm"], rel=1e-3)


def test_the_template_controller_runs_through_the_command_line(plugin_path, tmp_path):
    (tmp_path / "s.yaml").write_text(json.dumps({
        "gait": "stand_still", "closure": "ball", "controller": {"kind": "hold"},
        "stand_s": 0.0, "ramp_s": 0.0, "duration_s": 3.2}))
    done = run(plugin_path, "-m", "fivebar_drake", "simulate", "--scenario", "s.yaml",
               "--out", "run", cwd=tmp_path)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["ran"]["controller"]["kind"] == "hold", done.stderr
    assert summary["controller_gains"] is None and summary["completed"]
    (tmp_path / "b.yaml").write_text(json.dumps({"controller": {"kind": "hold",
                                                                "stiffness_Nm_rad": -1}}))
    bad = run(plugin_path, "-m", "fivebar_drake", "simulate", "--scenario", "b.yaml",
              cwd=tmp_path)
    assert bad.returncode == 2
    assert "scenario.controller.stiffness_Nm_rad = -1" in bad.stderr


FIRST_TICK = textwrap.dedent("""
    import time
    import numpy as np
    from fivebar_drake.simulation.builder import build_diagram, check_run
    from fivebar_drake.simulation.scenario import load_scenario
    from fivebar_drake.robots.quadruped.plant import set_standing_pose
    scenario = load_scenario(stance_law="vertical_only", closure="ball")
    params = scenario.load_params()
    diagram, setup = build_diagram(scenario, params, check_run(scenario, params))
    context = diagram.CreateDefaultContext()
    plant_context = setup.plant.GetMyMutableContextFromRoot(context)
    set_standing_pose(setup.plant, plant_context, setup.instance, setup.layout.legs, params)
    state = setup.plant.GetPositionsAndVelocities(plant_context)
    references = diagram.GetSubsystemByName("gait_source").references(1.0)
    start = time.perf_counter()
    torques = setup.controller.command(references, state)
    print(time.perf_counter() - start, np.all(np.isfinite(torques)))
""")


def test_a_swapped_stance_law_keeps_the_compiled_laws_cached(plugin_path, tmp_path):
    """The first process may compile the plugin's law (and cache it on disk beside it); a
    second process's first tick loads every law from the cache: well under a second (about 23 s
    when a law is passed as a function argument, which numba cannot cache)."""
    (tmp_path / "tick.py").write_text(FIRST_TICK)
    for _ in range(2):
        done = run(plugin_path, str(tmp_path / "tick.py"))
        assert done.returncode == 0, done.stderr
    seconds, finite = done.stdout.split()
    assert finite == "True" and float(seconds) < 0.5
