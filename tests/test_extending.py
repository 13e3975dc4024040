"""The manual's extension templates (docs/extending.md), run as a package outside fivebar_drake: its gait, stance
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

EXTENDING = Path(__file__).resolve().parent.parent / "docs" / "extending.md"
MODULES = {"stand_still": "gait", "vertical_only": "stance_law", "hold": "controller",
           "ball_api": "closure", "hop": "hop", "high_jump": "high_jump"}
#            a template's kind -> its module's name


def templates() -> dict[str, str]:
    """The extension templates of docs/extending.md by the kind each registers."""
    blocks = re.findall(r"```python\n(.*?)```", EXTENDING.read_text(), re.S)
    found = {}
    for block in blocks:
        kind = re.search(r'kind: ClassVar\[str\] = "(\w+)"', block).group(1)
        found[kind] = block
    return found


@pytest.fixture(scope="module")
def plugin_path(tmp_path_factory) -> Path:
    """A folder holding the package fivebar_templates (the manual's templates, one module
    each) and its dist-info with the entry points."""
    root = tmp_path_factory.mktemp("plugins")
    package = root / "fivebar_templates"
    package.mkdir()
    (package / "__init__.py").write_text('"""The README\'s templates."""\n')
    found = templates()
    assert set(found) == set(MODULES), f"the manual's templates register {sorted(found)}"
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


def _package(root: Path, name: str, modules: dict[str, str]) -> Path:
    """A plugin package `name` in root: its modules (module name -> code) and a dist-info whose
    entry points name each module."""
    package = root / name
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    for module, code in modules.items():
        (package / f"{module}.py").write_text(textwrap.dedent(code))
    info = root / f"{name}-0.3.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 0.3\n")
    (info / "top_level.txt").write_text(f"{name}\n")      # as pip's RECORD tells it
    (info / "entry_points.txt").write_text("[fivebar_drake.plugins]\n" + "".join(
        f"{module} = {name}.{module}\n" for module in modules))
    return root


HIJACK = """
    from typing import ClassVar
    from dataclasses import dataclass
    from fivebar_drake.gaits import Trot, register_path

    @register_path
    @dataclass(frozen=True)
    class StillTrot(Trot):
        kind: ClassVar[str] = "trot"
        REPLACES
"""


def test_a_plugin_cannot_hijack_a_kind_unless_it_says_so(tmp_path):
    """A plugin registering the built-in trot is refused at load, exit 2 naming both classes
    and its entry point; one that says it replaces the trot runs, and summary.json records
    where the trot came from (module, distribution and version, entry point, what it replaced).
    Without plugins (--no-plugins, or FIVEBAR_DRAKE_NO_PLUGINS=1) the built-in runs."""
    hijack = _package(tmp_path / "a", "hijack", {"trot": HIJACK.replace("REPLACES", "")})
    done = run(hijack, "-m", "fivebar_drake", "simulate", "--duration", "0.3", "--out", "x",
               cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert ("registered twice" in done.stderr and "fivebar_drake.gaits.trot.Trot" in done.stderr
            and "hijack.trot.StillTrot" in done.stderr and "entry point trot" in done.stderr)
    assert not (tmp_path / "x").exists()
    for flag, env in ((["--no-plugins"], {}), ([], {"FIVEBAR_DRAKE_NO_PLUGINS": "1"})):
        done = subprocess.run([sys.executable, "-m", "fivebar_drake", *flag, "simulate",
                               "--duration", "0.3", "--out", "plain"], capture_output=True,
                              text=True, cwd=tmp_path, timeout=600,
                              env={**os.environ, **env, "PYTHONPATH": str(hijack)})
        assert done.returncode in (0, 1), done.stderr          # 0.3 s: no verdict (exit 1)
        ran = json.loads((tmp_path / "plain" / "summary.json").read_text())["ran"]
        assert ran["origins"]["gait"]["module"] == "fivebar_drake.gaits.trot.Trot"
        assert ran["origins"]["gait"]["distribution"].startswith("fivebar_drake ")
    asked = _package(tmp_path / "b", "hijack", {"trot": HIJACK.replace(
        "REPLACES", "replaces: ClassVar[bool] = True")})
    done = run(asked, "-m", "fivebar_drake", "simulate", "--gait", "trot", "--duration", "0.3",
               "--out", "y", cwd=tmp_path)
    assert done.returncode in (0, 1), done.stderr
    gait = json.loads((tmp_path / "y" / "summary.json").read_text())["ran"]["origins"]["gait"]
    assert gait == {"module": "hijack.trot.StillTrot", "distribution": "hijack 0.3",
                    "entry_point": "trot = hijack.trot",
                    "replaces": "fivebar_drake.gaits.trot.Trot"}


def test_a_plugin_that_exits_at_import_is_refused_naming_it(tmp_path):
    root = _package(tmp_path, "quitter", {"bye": "raise SystemExit(0)\n"})
    done = run(root, "-m", "fivebar_drake", "analyze", "--out", "z", cwd=tmp_path)
    assert done.returncode == 2
    assert "entry point bye = quitter.bye" in done.stderr and "exits at import" in done.stderr


def test_the_docs_options_table_holds_with_a_plugin_installed(plugin_path):
    """The package's own tests pass with a plugin installed: the options table leaves a
    plugin's kinds out, so the reference page's is current in a process that loaded the templates."""
    done = run(plugin_path, "-c", "from fivebar_drake.cli import parser, options_markdown; "
               "parser(); print(options_markdown())")
    assert done.returncode == 0, done.stderr
    page = (EXTENDING.parent / "reference" / "options.md").read_text()
    assert done.stdout.rstrip("\n") in page
    assert "stand_still" in run(plugin_path, "-m", "fivebar_drake", "simulate", "--help").stdout


def test_a_maneuver_with_its_own_floor_and_one_without(plugin_path, tmp_path):
    """The templates' two maneuvers simulated through the command line: the high jump's need is
    its registered floors (push-off driving, landing braking); the hop, a Jump subclass that
    registers none, has no floor (unknown), never the vertical jump's."""
    floors = {}
    for kind in ("high_jump", "hop"):
        done = run(plugin_path, "-m", "fivebar_drake", "simulate", "--gait", kind,
                   "--duration", "2.8", "--out", kind, cwd=tmp_path)
        assert done.returncode in (0, 1), done.stderr
        summary = json.loads((tmp_path / kind / "summary.json").read_text())
        assert summary["ran"]["gait"]["kind"] == kind
        floors[kind] = summary["any_controller"]
    high = floors["high_jump"]["phases"]
    assert high["push-off"]["status"] == "floor" and high["push-off"]["floor_Nm"] > 0
    assert high["landing"]["limit_Nm"] > high["push-off"]["limit_Nm"]
    hop = floors["hop"]
    assert hop["floor_Nm"] is None and hop["phases"] == {"hop": {
        "status": "unknown", "floor_Nm": None, "limit_Nm": high["push-off"]["limit_Nm"],
        "asked_Nm": hop["phases"]["hop"]["asked_Nm"]}}


NAN_GAIT = """
    from dataclasses import dataclass
    from typing import ClassVar, NamedTuple

    from fivebar_drake.core.compiled import jit
    from fivebar_drake.gaits import FootPath, register_path


    class Home(NamedTuple):
        x: float
        y: float


    @jit
    def broken_point(c, u):            # a NaN from a quarter of the cycle on
        x = c.x if u < 0.25 else c.x * float("nan")
        return x, c.y, 0.0, 0.0, 0.0, 0.0, True


    @register_path
    @dataclass(frozen=True)
    class Broken(FootPath):
        kind: ClassVar[str] = "broken_path"
        point: ClassVar = staticmethod(broken_point)

        def constants(self, gait):
            return Home(gait.x_center_m, gait.y_home_m)

        def stance_start(self, gait):
            return 0.0

        def stance_speed(self, gait):
            return 0.0
"""


def test_a_plugin_path_that_gives_nan_is_refused_at_load(tmp_path):
    """A plugin's path whose point function gives NaN part of the way ran until 0.5 s and
    stopped with a raw solver message (exit 1, issue 44): refused before the run, exit 2,
    naming the path and the time, nothing written."""
    root = _package(tmp_path, "nanpath", {"broken": NAN_GAIT})
    done = run(root, "-m", "fivebar_drake", "simulate", "--gait", "broken_path",
               "--duration", "2", "--out", "x", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "the broken_path path gives a value that is not a number" in done.stderr
    assert not (tmp_path / "x").exists()
