"""Gaits, controllers and closures as typed variants: the registered gaits give what the code
before them gave (tests/data/before_variants.npz, saved from it: the default trot's and the seed
ellipse's foot references at 301 times over 4.5 s; the controller's commands of before are gone
with the law they came from, changed on purpose by issue 28: support on measured contact), a
scenario names them by kind or as a mapping, and a gait registered in a test alone runs through
the pipeline."""

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, NamedTuple

import numpy as np
import pytest
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.core.compiled import jit
from fivebar_drake.gaits import PATHS, FootPath, SeedEllipse, Trot, register_path
from fivebar_drake.core.rotation import tilt_deg
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.pipeline import run_simulation
from fivebar_drake.robots.quadruped.plant import standing_height
from fivebar_drake.simulation.builder import check_run
from fivebar_drake.robots.quadruped.closure import Ball
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.simulation.gait_source import GaitSource
from fivebar_drake.simulation.systems import FootLeg

BEFORE = np.load(Path(__file__).parent.parent / "data" / "before_variants.npz")

# The saved arrays come from another machine: the compiled laws may be built there with fused
# multiply-adds or other vector widths, which move the last bits (measured: at most 1.3e-14 on
# values of order 1, AMD EPYC with AVX-512 against the machine that saved them). A change of a
# formula moves them by far more than 1e-9 (m, m/s, N·m), so that is the tolerance.
ACROSS_MACHINES = dict(rtol=1e-10, atol=1e-9)


def gait_source(scenario, params):
    """The scenario's gait source, added to a fresh builder as the simulation adds it."""
    return GaitSource.add_to(DiagramBuilder(), params.gait, scenario.gait, scenario.phases_rad,
                             scenario.stand_s, scenario.ramp_s, scenario.load_transfer_s)


@pytest.mark.parametrize("gait", ["trot", "seed_ellipse"])
def test_registered_gaits_give_the_references_of_before(params, gait):
    """Targets, velocities, accelerations and stance weights of all legs, standing, ramping and
    walking, to the last bits a CPU may change (ACROSS_MACHINES)."""
    source = gait_source(load_scenario(gait=gait), params)
    now = np.array([source.references(t) for t in BEFORE["t"]])
    np.testing.assert_allclose(now, BEFORE[f"references_{gait}"], **ACROSS_MACHINES)


def test_a_gait_by_kind_or_as_a_mapping(tmp_path):
    assert load_scenario().gait == Trot() and str(Trot()) == "trot"
    path = tmp_path / "s.yaml"
    path.write_text("gait: {kind: trot, duty_factor: 0.7}\n")
    gait = load_scenario(path).gait
    assert gait == Trot(duty_factor=0.7) and str(gait) == "trot(duty_factor=0.7)"
    for text, message in [("gait: {kind: trot, duty_factor: 1.5}\n",
                           "scenario.gait.duty_factor = 1.5"),
                          ("gait: {kind: trot, stride: 1}\n",
                           "scenario.gait.stride = 1: unknown field; trot has ['duty_factor', "
                           "'swing_reach_m', 'swing_skew_m', 'swing_lift_skew_m']"),
                          ("gait: {duty_factor: 0.7}\n", "a mapping needs the kind"),
                          ("gait: {kind: hop}\n", "scenario.gait = 'hop': allowed")]:
        path.write_text(text)
        with pytest.raises(ParameterError, match=message.replace("[", r"\[").replace("(", r"\(")):
            load_scenario(path)


def test_a_controller_and_a_closure_by_kind_or_as_a_mapping(tmp_path):
    """Today's flat controller fields change the controller's; a field given both ways is
    refused; a closure by kind or as a mapping."""
    path = tmp_path / "s.yaml"
    path.write_text("controller: {kind: foot_leg, swing_bandwidth_hz: 20}\ncatch_gain: 0.5\n"
                    "closure: {kind: ball}\n")
    scenario = load_scenario(path)
    assert scenario.controller == FootLeg(swing_bandwidth_hz=20.0, catch_gain=0.5)
    assert scenario.closure == Ball() and load_scenario(closure="ball").closure == Ball()
    assert load_scenario(swing_bandwidth_hz=20).controller == FootLeg(swing_bandwidth_hz=20.0)
    for text, message in [("controller: {kind: foot_leg, catch_gain: 2}\ncatch_gain: 1\n",
                           "scenario.catch_gain = 1: given twice"),
                          ("controller: {kind: foot_leg, catch_gain: 20}\n",
                           r"scenario.catch_gain = 20.0: must be in \[0, 10\]"),
                          ("controller: pid\n", "scenario.controller = 'pid': allowed"),
                          ("closure: {kind: glue}\n", "scenario.closure = 'glue': allowed")]:
        path.write_text(text)
        with pytest.raises(ParameterError, match=message):
            load_scenario(path)


def test_a_duty_factor_of_the_gait_changes_its_stance(params):
    """The trot's own duty_factor overrides the parameter file's; its stance and speed are the
    formulas of before, to the bit."""
    tight = load_scenario(gait={"kind": "trot", "duty_factor": 0.6}).gait
    g = params.gait
    for path, beta in [(tight, 0.6), (Trot(), g.duty_factor)]:
        assert path.stance_start(g) == 1.0 - beta
        assert path.stance_speed(g) == 2.0 * g.a_m / (beta * g.period_s)
    assert SeedEllipse().stance_speed(g) == 2.0 * g.a_m / (0.5 * g.period_s)


class Home(NamedTuple):
    """The home point (m)."""

    x: float
    y: float


@jit
def home_point(c, u):
    """At home, at rest, in stance, whatever the phase."""
    return c.x, c.y, 0.0, 0.0, 0.0, 0.0, True


class StandStill(FootPath):
    """Holds every foot at home: all stance, no speed (y_m: the home's height, None = the
    parameter file's)."""

    point: ClassVar = staticmethod(home_point)
    y_m: ClassVar = None

    def constants(self, gait):
        return Home(gait.x_center_m, gait.y_home_m if self.y_m is None else self.y_m)

    def stance_start(self, gait):
        return 0.0

    def stance_speed(self, gait):
        return 0.0


def toy_gait(kind: str, y_m=None):
    """A StandStill registered as `kind` for one test (removed after it)."""
    cls = register_path(dataclass(frozen=True)(type(kind, (StandStill,),
                                                     {"kind": kind, "y_m": y_m})))
    yield cls
    del PATHS[kind]


@pytest.fixture
def stand_still():
    """A toy gait registered for the test alone (and removed after it)."""
    yield from toy_gait("stand_still")


def test_a_gait_registered_alone_runs_through_the_pipeline(params, stand_still):
    """The toy gait, by kind in a scenario: the robot stays standing where it stood."""
    record = run_simulation(load_scenario(gait="stand_still", duration_s=1.5, closure="ball"),
                            progress=False)
    assert record.completed and isinstance(record.scenario.gait, stand_still)
    state, body = record.table["state"], record.layout.state.body_q
    height, xy = state[:, body + 6], state[:, body + 4:body + 6]
    assert np.abs(height - standing_height(params)).max() < 5e-3
    assert np.abs(xy - xy[0]).max() < 5e-3
    assert tilt_deg(state[:, body:body + 4]).max() < 1.0


def test_analyze_simulate_and_a_sweep_run_the_same_path(tmp_path):
    """A path's own gait fields (the bound's 2 Hz and a = 30 mm) apply alike to analyze,
    simulate and a sweep's base; a --set or a scenario's gait_* override goes over them."""
    from fivebar_drake.studies.fivebar_leg import load_analysis
    from fivebar_drake.sweep.engine import base_inputs
    from fivebar_drake.sweep.spec import load_spec

    bound = load_scenario(gait="bound").load_params().gait
    assert (bound.frequency_hz, bound.a_m) == (2.0, 0.03)
    analysed = load_analysis(None, "bound").inputs[0].gait
    assert (analysed.frequency_hz, analysed.a_m) == (bound.frequency_hz, bound.a_m)
    assert load_analysis(None, "bound", ["gait.frequency_hz=1.5"]).inputs[0].gait.frequency_hz \
        == 1.5
    assert load_scenario(gait="bound", gait_frequency_hz=1.5).load_params().gait.frequency_hz \
        == 1.5
    spec = tmp_path / "s.yaml"
    spec.write_text("fidelity: analysis\ngait: bound\nvary:\n  motor.gear_ratio: [8, 10]\n")
    params, _ = base_inputs(load_spec(spec))
    assert (params.gait.frequency_hz, params.gait.a_m) == (2.0, 0.03)


@pytest.fixture
def far_away():
    """A toy gait whose feet stand 1 m below the hips, beyond any leg's reach."""
    yield from toy_gait("far_away", -1.0)


def test_a_gait_out_of_reach_breaks_only_its_own_runs(far_away, tmp_path):
    """Registering a gait never makes a parameter file fail to load (the packaged robots
    included); the command that runs it refuses it, naming it (exit 2)."""
    from fivebar_drake.robots.quadruped.config import load_params
    from fivebar_drake.studies.fivebar_leg import load_analysis

    for name in (None, "doggo", "minitaur"):
        load_params(None if name is None else
                    Path(__file__).parents[2] / "fivebar_drake" / "data" / f"{name}.toml")
    with pytest.raises(ParameterError, match="out of|outside|reach") as err:
        load_analysis(None, "far_away")
    assert err.value.source == "command line (--gait far_away)"
    with pytest.raises(ParameterError, match="out of|outside|reach"):
        check_run(load_scenario(gait="far_away"), load_params())
