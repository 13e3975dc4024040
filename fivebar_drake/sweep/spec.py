"""A sweep's specification (SPEC.yaml) and the design points it names.

    fidelity: analysis          # or simulation
    sampling: grid              # or random / latin_hypercube, with samples: N and seed: S
    vary:
      gait.frequency_hz: [0.5, 1.0, 2.0]          # a list of values
      gait.a_m: {range: [0.04, 0.06], num: 2}     # a range: num values on a grid, else sampled
    config: my_robot.toml       # base parameter file (default: the packaged one)
    scenario: trot.yaml         # base scenario of simulation points (default: the built-in one)
    gait: seed_ellipse          # foot path of analysis points (default: seed_ellipse)
    model: full_trot            # load model of analysis points (default: full_trot; or full)
    duration_s: 4.5             # simulated time of simulation points (default: the scenario's)
    step_check: false           # simulation points: run each again at half its plant step
    plot: [gait.frequency_hz, gait.a_m]   # the verdict map's axes (default: the first two)

Relative paths are taken from the spec file's folder. Lists may hold numbers or strings (e.g.
`closure` for simulation points, a scenario field); a range is continuous. grid: every
combination of the lists and the ranges' num values (numpy.linspace). random: `samples`
points, each value drawn uniformly from a list or a range. latin_hypercube: `samples` points,
one stratum per point along every varied parameter (scipy.stats.qmc.LatinHypercube; a list is
split into equal strata). A parameter is a dotted path of the parameter file
(robots/quadruped/config.with_changes) or, for simulation points, a field of the scenario
(`scenario.closure`, `scenario.duration_s`, ...).
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fivebar_drake.analysis.design_points import MODELS
from fivebar_drake.gaits import PATHS
from fivebar_drake.core.variants import known
from fivebar_drake.core.files import read_input_text
from fivebar_drake.core.validation import check_number, require
from fivebar_drake.core.yaml_files import load_spec_file

FIDELITIES = ("analysis", "simulation")
SAMPLINGS = ("grid", "random", "latin_hypercube")
MAX_POINTS = 1_000_000


@dataclass(frozen=True)
class Varied:
    """One varied parameter: a list of values, or a range [low, high] with num grid values."""

    path: str
    values: tuple = ()
    low: float | None = None
    high: float | None = None
    num: int | None = None
    integer: bool = False      # an integer parameter's range (the co-design samples integers)

    def grid(self) -> list:
        if self.values:
            return list(self.values)
        return [float(v) for v in np.linspace(self.low, self.high, self.num)]

    def draw(self, u: np.ndarray) -> list:
        """Values at the quantiles u in [0, 1): the list's value of that stratum, or the
        range's point."""
        if self.values:
            return [self.values[min(int(x * len(self.values)), len(self.values) - 1)] for x in u]
        return [float(self.low + x * (self.high - self.low)) for x in u]


@dataclass(frozen=True)
class SweepSpec:
    """The validated spec (see the module's docstring); config and scenario as absolute paths."""

    fidelity: str
    sampling: str
    vary: tuple[Varied, ...]
    samples: int | None = None
    seed: int = 0
    config: str | None = None
    scenario: str | None = None
    gait: str = "seed_ellipse"
    model: str = "full_trot"
    duration_s: float | None = None
    step_check: bool = False
    plot: tuple[str, ...] = ()
    source: str = field(default="", compare=False)

    @property
    def names(self) -> list[str]:
        return [v.path for v in self.vary]

    def points(self) -> list[dict]:
        """The design points, in a fixed order: {dotted path: value}."""
        if self.sampling == "grid":
            return [dict(zip(self.names, combo))
                    for combo in itertools.product(*(v.grid() for v in self.vary))]
        rng = np.random.default_rng(self.seed)
        if self.sampling == "random":
            u = rng.random((self.samples, len(self.vary)))
        else:
            from scipy.stats import qmc
            u = qmc.LatinHypercube(d=len(self.vary), seed=rng).random(self.samples)
        columns = [v.draw(u[:, j]) for j, v in enumerate(self.vary)]
        return [dict(zip(self.names, row)) for row in zip(*columns)]

    def fingerprint(self) -> str:
        """A hash of everything that decides the points and their results (not the plot): the
        spec's fields and the text of every file they name, the parameter file a scenario
        names included (so editing any of them makes another sweep)."""
        data = dataclasses.asdict(dataclasses.replace(self, plot=()))
        data.pop("source")
        for key, path in self.input_files().items():
            data[key + "_text"] = read_input_text(path, key.replace("_", " "))
        return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()

    def input_files(self) -> dict[str, Path]:
        """The files the sweep reads besides the spec: config, scenario and the scenario's
        params_file (relative to the scenario's folder)."""
        files = {key: Path(getattr(self, key)) for key in ("config", "scenario")
                 if getattr(self, key)}
        if self.scenario:
            from fivebar_drake.simulation.scenario import read_scenario_file

            named = read_scenario_file(self.scenario).get("params_file")
            if isinstance(named, str) and named:
                files["scenario_params_file"] = Path(self.scenario).parent / named
        return files


KEYS = {"fidelity", "sampling", "vary", "samples", "seed", "config", "scenario", "gait",
        "model", "duration_s", "step_check", "plot"}


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate SPEC.yaml (ParameterError naming the file and the field)."""
    path = Path(path)
    return load_spec_file(path, "sweep spec", spec_from_dict)


def spec_from_dict(data, folder: Path, source: str = "") -> SweepSpec:
    """SweepSpec from the YAML's mapping; relative files are taken from folder."""
    require(isinstance(data, dict), "SPEC", type(data).__name__, "must be a mapping of "
            f"{sorted(KEYS)}")
    unknown = sorted(set(data) - KEYS)
    require(not unknown, unknown[0] if unknown else "", unknown, f"unknown key(s); the keys are "
            f"{sorted(KEYS)}")
    fidelity = data.get("fidelity", "analysis")
    require(fidelity in FIDELITIES, "fidelity", fidelity, f"must be one of {list(FIDELITIES)}")
    sampling = data.get("sampling", "grid")
    require(sampling in SAMPLINGS, "sampling", sampling, f"must be one of {list(SAMPLINGS)}")
    vary = data.get("vary")
    require(isinstance(vary, dict) and vary, "vary", vary,
            "must map one or more dotted parameter paths to a list or {range: [low, high], "
            "num: N}")
    varied = tuple(_varied(str(k), v, sampling) for k, v in vary.items())
    samples = data.get("samples")
    if sampling == "grid":
        require(samples is None, "samples", samples, "applies to random and latin_hypercube "
                "sampling; a grid takes every combination")
        count = math.prod(len(v.values) if v.values else v.num for v in varied)   # exact
    else:
        check_number("samples", samples, 1, MAX_POINTS, integer=True,
                     why=f"{sampling} sampling draws this many points")
        count = samples
    check_number("points", count, 1, MAX_POINTS, integer=True,
                 why="the number of design points the sweep names")
    seed = data.get("seed", 0)
    check_number("seed", seed, 0, 2**32 - 1, integer=True)
    gait = data.get("gait", "seed_ellipse")
    require(known(PATHS, gait), "gait", gait, f"must be one of {list(PATHS)}")
    model = data.get("model", MODELS[0])
    require(model in MODELS, "model", model, f"must be one of {list(MODELS)}")
    require(fidelity == "analysis" or "model" not in data, "model", model,
            "applies to analysis points (a simulation has its own loads)")
    duration = data.get("duration_s")
    if duration is not None:
        require(fidelity == "simulation", "duration_s", duration, "applies to simulation points")
        check_number("duration_s", duration, 0.0, 3600.0, low_open=True)
    step_check = data.get("step_check", False)
    require(isinstance(step_check, bool), "step_check", step_check, "true or false")
    require(fidelity == "simulation" or not step_check, "step_check", step_check,
            "applies to simulation points (each is run again at half its plant step)")
    files = {}
    for key in ("config", "scenario"):
        value = data.get(key)
        if value is not None:
            require(isinstance(value, str) and (folder / value).is_file(), key, value,
                    f"must name an existing file (relative to {folder})")
            files[key] = str((folder / value).resolve())
    require(files.get("scenario") is None or fidelity == "simulation", "scenario",
            data.get("scenario"), "applies to simulation points")
    names = [v.path for v in varied]
    plot = data.get("plot") or names[:2]
    plot = [plot] if isinstance(plot, str) else plot
    require(isinstance(plot, list) and 1 <= len(plot) <= 2 and all(p in names for p in plot),
            "plot", data.get("plot"), f"one or two of the varied parameters {names}")
    plot = tuple(plot)
    for v in varied:
        require(fidelity == "simulation" or not v.path.startswith("scenario."), v.path, v.path,
                "scenario fields vary only in simulation sweeps")
    return SweepSpec(fidelity=fidelity, sampling=sampling, vary=varied, samples=samples,
                     seed=seed, gait=gait, model=model, duration_s=duration, step_check=step_check,
                     plot=plot, source=source,
                     **files)


def _varied(path: str, value, sampling: str) -> Varied:
    field_ = f"vary.{path}"
    if isinstance(value, list):
        require(value and all(isinstance(v, (int, float, str)) and not isinstance(v, bool)
                              for v in value), field_, value,
                "must be a non-empty list of numbers or strings")
        return Varied(path, values=tuple(value))
    require(isinstance(value, dict) and set(value) <= {"range", "num"} and "range" in value,
            field_, value, "must be a list or {range: [low, high], num: N}")
    rng = value["range"]
    require(isinstance(rng, list) and len(rng) == 2 and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in rng) and rng[0] <= rng[1],
        f"{field_}.range", rng, "must be [low, high] with low <= high")
    num = value.get("num")
    if sampling == "grid":
        check_number(f"{field_}.num", num, 1, MAX_POINTS, integer=True,
                     why="a grid takes num values of a range")
        require(num == 1 or rng[0] < rng[1], f"{field_}.range", rng,
                "a range of more than one value needs low < high")
    else:
        require(num is None, f"{field_}.num", num, f"{sampling} sampling draws from the range; "
                "num applies to grids")
    return Varied(path, low=float(rng[0]), high=float(rng[1]), num=num)
