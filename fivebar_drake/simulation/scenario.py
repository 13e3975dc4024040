"""Simulation scenario: what to simulate and how, as a dataclass loadable from YAML.

Units: s, m, rad, N*m. A YAML file names any subset of the fields, e.g.

    duration_s: 5.0
    closure: ball
    gait_frequency_hz: 1.5

Every field is checked on load (type, finite, within its bounds; the file and field named in
the error); the checks that need the parameters and the plant's time step are in
builder.check_run.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional
from pydrake.multibody.plant import MultibodyPlantConfig
from pydrake.systems.analysis import SimulatorConfig

from fivebar_drake.core.drake_configs import check_simulator_config, config_fields
from fivebar_drake.core.files import read_input_text
from fivebar_drake.core.variants import known
from fivebar_drake.gaits import PATHS, FootPath, Trot
from fivebar_drake.core.validation import (MAX_LENGTH_M, MAX_MASS_KG, ParameterError,
                                           check_number, require)
from fivebar_drake.core.yaml_files import load_yaml
from fivebar_drake.optimal.top_speed import GAITS as SPEED_GAITS
from fivebar_drake.robots.quadruped.config import load_params, with_path_defaults
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.closure import CLOSURES, Closure, CompliantBushing
from fivebar_drake.robots.quadruped.plant import default_plant_config
from fivebar_drake.robots.quadruped.legs import LEGS, path_phases
from fivebar_drake.simulation import tracking  # noqa: F401  (registers the tracking controller)
from fivebar_drake.simulation.systems import CONTROLLERS, MIN_TIME_STEP_S, Controller, FootLeg


# Bounds of the scenario's values, each with the reason it exists.
MAX_LOG_ROWS = 500_000            # recorded intervals kept in memory, ~6 kB each (measured) from the
#                                   recorder to the recording: ~3 GB; 1000 s at the default 2 ms
MAX_LOOP_GAP_M = 1e-3             # 1 % of a link: a looser loop is not the 5-bar's kinematics
MIN_LOOP_GAP_M = 1e-8             # a floor for any closure and step (the explicit bushing's step
#                                   ~ sqrt(gap) is ~2 us here, near MIN_TIME_STEP_S); the compliant
#                                   bushing's own bound, where SAP stops keeping gap = F / k
#                                   (near-rigid; ~ step^2: 1.7 um at 1 ms for the packaged robot),
#                                   is checked with the design (closure.min_loop_gap)
MAX_PHASE_RAD = 2 * math.pi       # a gait phase is an angle of the cycle: one turn either way
MAX_SLOPE_DEG = 45.0              # tan 45 deg = 1: beyond any foot friction (body.foot_friction 0.8)


def default_simulator_config() -> SimulatorConfig:
    """Run as fast as possible; publish only where a system asks."""
    return SimulatorConfig(target_realtime_rate=0.0, publish_every_time_step=False)


DRAKE_CONFIGS = {"plant_config": MultibodyPlantConfig, "simulator_config": SimulatorConfig}
# the variant fields' base classes and registries; a controller's fields are also scenario fields,
# today's flat names (ALIASES), and its errors name them so
REGISTRIES = {FootPath: PATHS, Closure: CLOSURES, Controller: CONTROLLERS}
ALIASES = tuple(f.name for f in dataclasses.fields(FootLeg))
DEFAULT_CONFIGS = {MultibodyPlantConfig: default_plant_config,
                   SimulatorConfig: default_simulator_config}
def _doc(default, doc: str, factory=None):
    """A Scenario field with its default (or default factory) and its description (README)."""
    if factory is not None:
        return field(default_factory=factory, metadata={"doc": doc})
    return field(default=default, metadata={"doc": doc})


@dataclass
class Scenario:
    """What to simulate and how; each field's description is in its metadata["doc"]."""

    duration_s: float = _doc(8.0, "simulated time from t = 0")
    gait: FootPath = _doc(None, f"foot path, one of {', '.join(PATHS)} (gaits/), by "
                                "kind (its defaults) or as {kind: KIND, FIELD: value, ...} (trot: "
                                "duty_factor, null = the parameter file's); {kind: trot, bound "
                                "or pronk, speed_m_s: max}: the gait at its top speed for any "
                                "controller (top_speed), with duty_factor: D its top speed "
                                "at that duty factor, with share: S that path at S of its "
                                "speed (top_speed_share)", factory=Trot)
    top_speed: bool = _doc(False, "run the gait at its top speed for any controller "
                                  "(optimal/top_speed.py: its duty factor (the path's where it "
                                  "has one), stride, frequency and swing shape; written gait: "
                                  "{kind: KIND, speed_m_s: max})")
    top_speed_share: float = _doc(1.0, "with top_speed: the top speed's path at this share of "
                                       "its frequency, so of its speed (its stride, duty factor "
                                       "and swing shape kept), in (0, 1]; written gait: {kind: "
                                       "KIND, speed_m_s: max, share: S}")
    closure: Closure = _doc(None, f"loop closure, one of {', '.join(CLOSURES)} "
                                  "(robots/quadruped/closure.py)", factory=CompliantBushing)
    time_step_s: float = _doc(0.0, "plant step; 0 = derived (bushing, ball: 1 ms; bushing_rpy: "
                                   "its stability bound)")
    target_loop_gap_m: float = _doc(4e-6, "the bushing's design loop gap under the trot's load")
    controller: Controller = _doc(None, f"leg controller, one of {', '.join(CONTROLLERS)} "
                                        "(simulation/systems.py, simulation/tracking.py), by kind or as a mapping; its "
                                        "fields (below) may also be given at the top level",
                                  factory=FootLeg)
    motor_period_s: float = _doc(0.001, "update period of the motor model")
    load_transfer_s: float = _doc(0.04, "time over which a foot takes up or gives off its load "
                                        "at touchdown and lift-off")
    stand_s: float = _doc(0.5, "standing time before the gait starts")
    ramp_s: float = _doc(1.0, "time over which the foot path grows to full size")
    phases_rad: Optional[list[float]] = _doc(
        None, "gait phase of FL, FR, RL, RR; null = the gait's own (trot: 0, pi, pi, 0; walk: "
              "a crawl, a quarter cycle apart; bound: front, rear half a cycle apart; pronk and "
              "the maneuvers: all 0)")
    payload_kg: float = _doc(0.0, "mass added to the body (a rigid payload)")
    payload_offset_m: list[float] = _doc(None, "the payload's centre in the body frame (x "
                                               "forward, y left, z up) from the body's centre",
                                         factory=lambda: [0.0, 0.0, 0.0])
    slope_deg: float = _doc(0.0, "ground slope, walking up it: gravity tilted by it in the plant "
                                 "(the ground stays z = 0; heights and tilt are relative to the "
                                 "slope)")
    log_period_s: float = _doc(0.002, "interval of the recorded means (measured every plant "
                                      "step)")
    pose_rate_hz: float = _doc(50.0, "rate of the 3-D poses in the recording")
    params_file: str = _doc("", "parameter file (TOML), relative to the scenario file's folder; "
                                "\"\" = the packaged one; --config overrides it")
    gait_a_m: Optional[float] = _doc(None, "override of the parameter file's gait.a_m")
    gait_b_m: Optional[float] = _doc(None, "override of gait.b_m")
    gait_y_home_m: Optional[float] = _doc(None, "override of gait.y_home_m")
    gait_frequency_hz: Optional[float] = _doc(None, "override of gait.frequency_hz")
    gait_duty_factor: Optional[float] = _doc(None, "override of gait.duty_factor")
    plant_config: MultibodyPlantConfig = _doc(
        None, "Drake's MultibodyPlantConfig (fields as a mapping, over this default); its "
              "time_step comes from the closure design (time_step_s)",
        factory=default_plant_config)
    simulator_config: SimulatorConfig = _doc(
        None, "Drake's SimulatorConfig of the run (fields as a mapping, over this default)",
        factory=default_simulator_config)

    def __getstate__(self) -> dict:
        """Picklable: Drake's configs travel as their fields."""
        return {**self.__dict__, **{name: config_fields(getattr(self, name))
                                    for name in DRAKE_CONFIGS}}

    def __eq__(self, other) -> bool:
        """Field by field, Drake's configs by their fields."""
        return isinstance(other, Scenario) and self.__getstate__() == other.__getstate__()

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update({**state, **{name: kind(**state[name])
                                          for name, kind in DRAKE_CONFIGS.items()}})

    def replaced(self, **changes) -> Scenario:
        """A copy with fields changed (not validated); today's flat controller fields (ALIASES)
        change the controller's (ParameterError if a controller mapping gives one too)."""
        flat = {k: changes.pop(k) for k in list(changes) if k in ALIASES}
        gait = changes.get("gait")
        if isinstance(gait, dict) and "speed_m_s" in gait:
            speed = gait["speed_m_s"]
            require(speed == "max", "scenario.gait.speed_m_s", speed,
                    "max (the gait's top speed for any controller) is the one speed a gait takes "
                    "by name; set a speed by gait_a_m and gait_frequency_hz")
            others = sorted(set(gait) - {"kind", "speed_m_s", "duty_factor", "share"})
            require(not others, "scenario.gait", gait, f"at its top speed the optimum sets the "
                    f"path's shape: no {', '.join(others)} beside speed_m_s: max (duty_factor: "
                    f"the top speed at that duty factor; share: that path at a share of its "
                    f"speed)")
            changes["top_speed_share"] = gait.get("share", 1.0)
            # no duty factor: searched (a bound's or pronk's default is not the search's)
            changes["gait"] = {"kind": gait.get("kind")}
            if gait.get("kind") in SPEED_GAITS:
                changes["gait"]["duty_factor"] = gait.get("duty_factor")
            changes["top_speed"] = True
        scenario = dataclasses.replace(self, **changes)
        if flat:
            controller = scenario.controller
            if isinstance(controller, Controller):
                controller = {"kind": controller.kind, **dataclasses.asdict(controller)}
            elif isinstance(controller, dict):
                for key, value in flat.items():
                    require(key not in controller, f"scenario.{key}", value,
                            f"given twice: also scenario.controller.{key} = "
                            f"{controller.get(key)!r}")
            else:
                controller = {"kind": controller}
            scenario.controller = {**controller, **flat}
        return scenario

    def validate(self) -> None:
        """Check every field (type, finite, bounds; ParameterError naming the first bad field,
        its value and what is allowed) and store numbers as the field's type."""
        kinds = typing.get_type_hints(Scenario)
        for f in dataclasses.fields(self):
            setattr(self, f.name, _typed(f"scenario.{f.name}", kinds[f.name],
                                         getattr(self, f.name)))
        number = check_number
        number("scenario.log_period_s", self.log_period_s, MIN_TIME_STEP_S)
        number("scenario.duration_s", self.duration_s, self.log_period_s,
               why="at least one recorded interval of scenario.log_period_s")
        number("scenario.duration_s", self.duration_s, high=MAX_LOG_ROWS * self.log_period_s,
               why=f"at most {MAX_LOG_ROWS:g} recorded intervals of scenario.log_period_s = "
                   f"{self.log_period_s:g} s are kept in memory")
        number("scenario.stand_s", self.stand_s, 0.0)
        number("scenario.ramp_s", self.ramp_s, 0.0)
        number("scenario.pose_rate_hz", self.pose_rate_hz, 0.0, low_open=True)
        number("scenario.time_step_s", self.time_step_s, 0.0)
        if self.time_step_s:
            number("scenario.time_step_s", self.time_step_s, MIN_TIME_STEP_S,
                   why="0 = derived; nothing in the robot needs a finer step")
        number("scenario.target_loop_gap_m", self.target_loop_gap_m, MIN_LOOP_GAP_M,
               MAX_LOOP_GAP_M)
        number("scenario.motor_period_s", self.motor_period_s, MIN_TIME_STEP_S,
               self.controller.control_period_s, why="the motor model samples every command of "
                                                     "the controller (scenario.control_period_s)")
        number("scenario.load_transfer_s", self.load_transfer_s, 0.0)
        number("scenario.top_speed_share", self.top_speed_share, 0.0, 1.0, low_open=True)
        require(self.top_speed or self.top_speed_share == 1.0, "scenario.top_speed_share",
                self.top_speed_share, "a share of a top speed, so only with one (gait: {kind: "
                                      "KIND, speed_m_s: max, share: S}); 1 otherwise")
        if self.top_speed:
            require(self.gait.kind in SPEED_GAITS, "scenario.gait.kind", self.gait.kind,
                    f"speed_m_s: max is searched for {', '.join(SPEED_GAITS)}")
            for f in dataclasses.fields(self):
                if f.name.startswith("gait_"):
                    require(getattr(self, f.name) is None, f"scenario.{f.name}",
                            getattr(self, f.name), "at its top speed (gait speed_m_s: max) the "
                            "optimum sets the gait's stride, frequency and duty factor")
        used = self.gait.gait_fields()
        for f in dataclasses.fields(self):      # an override the path never reads does nothing
            name = f.name[len("gait_"):]
            if f.name.startswith("gait_") and getattr(self, f.name) is not None:
                require(name in used, f"scenario.{f.name}", getattr(self, f.name),
                        f"the {self.gait.kind} path does not read gait.{name}"
                        + (f" (set its own: gait: {{kind: {self.gait.kind}, {name}: ...}})"
                           if name in {g.name for g in dataclasses.fields(self.gait)} else ""))
        require(self.phases_rad is None or self.gait.periodic
                or list(self.phases_rad) == list(path_phases(self.gait)), "scenario.phases_rad",
                self.phases_rad, f"a {self.gait.kind} moves all legs together: no phases")
        if self.phases_rad is None:
            self.phases_rad = list(path_phases(self.gait))
        require(len(self.phases_rad) == len(LEGS), "scenario.phases_rad", self.phases_rad,
                f"needs {len(LEGS)} values ({', '.join(LEGS)})")
        for i, phase in enumerate(self.phases_rad):
            number(f"scenario.phases_rad[{i}]", phase, -MAX_PHASE_RAD, MAX_PHASE_RAD)
        number("scenario.payload_kg", self.payload_kg, 0.0, MAX_MASS_KG)
        require(len(self.payload_offset_m) == 3, "scenario.payload_offset_m",
                self.payload_offset_m, "needs 3 values (x, y, z) in m")
        for i, value in enumerate(self.payload_offset_m):
            number(f"scenario.payload_offset_m[{i}]", value, -MAX_LENGTH_M, MAX_LENGTH_M)
        number("scenario.slope_deg", self.slope_deg, -MAX_SLOPE_DEG, MAX_SLOPE_DEG,
               why="steeper, the feet slip at any friction this robot has")
        self.controller.check_scenario(self)
        check_simulator_config(self.simulator_config, "scenario.simulator_config")

    def load_params(self) -> Params:
        """The parameter file with this scenario's gait overrides, else the foot path's own
        (FootPath.gait_defaults) (validated: reachable gait)."""
        params = load_params(self.params_file or None)
        overrides = {f.name[len("gait_"):]: getattr(self, f.name) for f in dataclasses.fields(self)
                     if f.name.startswith("gait_") and getattr(self, f.name) is not None}
        try:
            return with_path_defaults(params, self.gait, **overrides)
        except ParameterError as err:
            given = ", ".join(f"gait_{k} = {v!r}" for k, v in
                              {**self.gait.gait_defaults, **overrides}.items())
            raise ParameterError(f"scenario {given} overriding the parameter file: "
                                 f"{err.message}", err.field) from None

UNITS = {"_s": "s", "_m": "m", "_hz": "Hz", "_rad": "rad", "_periods": "controller periods",
         "_kg": "kg", "_deg": "deg"}


def _changed_fields(config) -> str:
    """The fields where a config differs from Drake's default, as YAML flow."""
    drake = config_fields(type(config)())
    changed = {k: v for k, v in config_fields(config).items() if v != drake[k]}
    return "{" + ", ".join(f"{k}: {str(v).lower() if isinstance(v, bool) else v}"
                           for k, v in changed.items()) + "}"


def _field_row(f: dataclasses.Field, kind, default, doc: str) -> str:
    """A row of fields_markdown: the field f of type kind with its default and meaning."""
    shown_kind = {float: "number", int: "integer", bool: "true/false", str: "text"}.get(
        kind, "list of numbers" if kind == list[float] else
        "list of numbers or null" if kind == Optional[list[float]] else
        "kind or mapping" if kind in REGISTRIES else
        "mapping" if kind in DRAKE_CONFIGS.values() else "number or null")
    shown = (_changed_fields(default) if f.name in DRAKE_CONFIGS else
             "null" if default is None else f'"{default}"' if isinstance(default, str) else
             f'"{default.kind}"' if isinstance(default, tuple(REGISTRIES)) else
             str(default).lower() if isinstance(default, bool) else
             "[" + ", ".join(f"{v:.4g}" for v in default) + "]"
             if isinstance(default, list) else f"{default:g}")
    unit = next((u for suffix, u in UNITS.items() if f.name.endswith(suffix)), "")
    return f"| `{f.name}` | {shown_kind} | {shown} | {unit} | {doc} |"


def fields_markdown() -> str:
    """The README's table of the scenario fields: name, type, default, unit, meaning; the
    default controller's fields after the controller's row."""
    kinds, defaults = typing.get_type_hints(Scenario), Scenario()
    rows = ["| field | type | default | unit | meaning |", "|---|---|---|---|---|"]
    for f in dataclasses.fields(Scenario):
        rows.append(_field_row(f, kinds[f.name], getattr(defaults, f.name), f.metadata["doc"]))
        if f.name == "controller":
            knobs = defaults.controller
            inner = typing.get_type_hints(type(knobs))
            rows += [_field_row(g, inner[g.name], getattr(knobs, g.name),
                                f"{knobs.kind}: {g.metadata['doc']}")
                     for g in dataclasses.fields(knobs)]
    return "\n".join(rows)


def _variant(name: str, base: type, value):
    """The variant (core/variants.py) of a field of type base, checked (Variant.check): value is
    a variant, a kind of its registry (REGISTRIES) or a mapping {kind: KIND, FIELD: value, ...}
    (each field typed as in _typed)."""
    if isinstance(value, base):
        value.check(_prefix(name, type(value)))
        return value
    registry = REGISTRIES[base]
    fields = value if isinstance(value, dict) else {"kind": value}
    require("kind" in fields, name, value, f"a mapping needs the kind, one of {list(registry)}")
    kind = fields["kind"]
    require(isinstance(kind, str) and known(registry, kind), name, kind,
            f"allowed {list(registry)}")
    cls = registry[kind]
    prefix = _prefix(name, cls)
    names, hints = [f.name for f in dataclasses.fields(cls)], typing.get_type_hints(cls)
    for key in fields:
        require(key == "kind" or key in names, f"{prefix}.{key}", fields[key],
                f"unknown field; {kind} has {names}")
    variant = cls(**{key: _typed(f"{prefix}.{key}", hints[key], item)
                     for key, item in fields.items() if key != "kind"})
    variant.check(prefix)
    return variant


def _prefix(name: str, cls: type) -> str:
    """What a variant's field errors name it by: "scenario" for a controller whose fields are
    all flat scenario fields (ALIASES: the default controller's), else the field itself (e.g.
    scenario.controller: a new controller's knob can only be given in its mapping)."""
    flat = issubclass(cls, Controller) and {f.name for f in dataclasses.fields(cls)} <= set(ALIASES)
    return "scenario" if flat else name


def _typed(name: str, kind, value):
    """value checked against a field's type (a number of a float field as a float; a Drake
    config from the mapping of its fields, over the field's default; a variant by its kind or
    as a mapping, _variant)."""
    if kind in REGISTRIES:
        return _variant(name, kind, value)
    if kind in DRAKE_CONFIGS.values():
        if isinstance(value, kind):
            return value
        require(isinstance(value, dict), name, value, f"must be a mapping of {kind.__name__} "
                f"fields {[f.name for f in kind.__fields__]}")
        types = {f.name: f.type for f in kind.__fields__}
        fields = config_fields(DEFAULT_CONFIGS[kind]())
        for key, item in value.items():
            require(key in types, f"{name}.{key}", item,
                    f"unknown field; {kind.__name__} has {list(types)}")
            fields[key] = _typed(f"{name}.{key}", types[key], item)
        return kind(**fields)
    if kind is float:
        return check_number(name, value)
    if kind is int:
        return check_number(name, value, integer=True)
    if kind is bool:
        require(isinstance(value, bool), name, value, "must be true or false")
        return value
    if kind is str:
        require(isinstance(value, str), name, value, "must be text")
        return value
    if kind == Optional[list[float]]:
        return None if value is None else _typed(name, list[float], value)
    if kind == list[float]:
        require(isinstance(value, (list, tuple)), name, value, "must be a list of numbers")
        return [check_number(f"{name}[{i}]", v) for i, v in enumerate(value)]
    return None if value is None else check_number(name, value)       # Optional[float]


def field_names() -> list[str]:
    """The names a scenario may give: its fields, then the controller's flat ones (ALIASES)."""
    return [f.name for f in dataclasses.fields(Scenario)] + list(ALIASES)


def read_scenario_file(path) -> dict:
    """The fields named in a scenario file (YAML mapping, core/yaml_files: untrusted data);
    ParameterError naming the file."""
    path = Path(path)
    text = read_input_text(path, "scenario file")
    hint = " (a parameter file goes to --config)" if path.suffix == ".toml" else ""
    data = load_yaml(text, str(path), hint)
    if data is None:
        data = {}                                   # an empty file: every default
    if not isinstance(data, dict):
        raise ParameterError(f"must be a mapping of scenario fields (e.g. `duration_s: 5.0`), "
                             f"not a {type(data).__name__}{hint}", source=str(path))
    names = field_names()
    for key in data:
        require(key in names, f"scenario.{key}", data[key],
                f"unknown field; the fields are {names}")
    return data


def source_of(err: ParameterError, path, overrides: dict) -> str:
    """Where a scenario error comes from: the command line for an overridden field, else the
    file (or the built-in scenario)."""
    field = err.field.split("[")[0]
    given = any(field == f"scenario.{k}" or field.startswith(f"scenario.{k}.") for k in overrides)
    return "command line" if given else str(path or "built-in scenario")


def load_scenario(path: "str | Path | None" = None, **overrides) -> Scenario:
    """Scenario from a YAML file (None: defaults) with keyword overrides (from the command
    line; None = not given); validated. A relative params_file in the file is taken relative
    to the file's folder. Errors name the file, or the command line for an override."""
    overrides = {k: v for k, v in overrides.items() if v is not None}
    data = {}
    if path is not None:
        try:
            data = read_scenario_file(path)
        except ParameterError as err:
            raise err.located(path) from None
        if isinstance(data.get("params_file"), str) and data["params_file"]:
            data["params_file"] = str(Path(path).parent / data["params_file"])
    try:
        scenario = Scenario().replaced(**{**data, **overrides})
        scenario.validate()
    except ParameterError as err:
        raise err.located(source_of(err, path, overrides)) from None
    return scenario
