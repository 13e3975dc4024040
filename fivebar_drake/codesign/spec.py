"""A co-design's specification (SPEC.yaml): what may change, what every design must pass, what
to minimise and how much to spend.

    variables:                   # the design space
      motor: [default_assumed, tmotor_mn5212_kv340]   # catalogue names (data/actuators.yaml)
      gearbox: [single_stage_planetary]   # optional: gearbox types (data/gearboxes.yaml);
                                          # default: the lightest type that spans the ratio
      motor.gear_ratio: [4.0, 12.0]       # a range [low, high] (continuous) or a list
      leg.ce_m: [0.135, 0.145, 0.155]     # any dotted parameter path, as a sweep's
      leg.ac_m=leg.bd_m: [0.07, 0.11]     # paths joined by '=': one value for all of them
    requirements:
      envelope: envelope_demo.yaml  # an envelope spec (file or mapping): its maneuvers, duty
                                    # cycle and base parameter file (its `config`)
      accept: pass                  # every check of every motor of every maneuver: pass, or warn
      step_check: true              # the simulations judged with their step check (each run
                                    # again at half the plant step: a marginal verdict fails)
      never_at_limit: true          # and no motor at its torque or voltage limit, no leg at a
                                    # joint or extension limit, in any sample
      actuator_mass: {equal_to: 0.266, within: 0.02}   # the actuator's mass (motor and
                                    # gearbox) within 2 % of a mass (kg) or of a design's
                                    # ({motor: NAME, gearbox: TYPE, motor.gear_ratio: N})
      simulate_max_jump: true       # each simulated design's max-effort jump simulated too
                                    # (optimal --simulate's), its measured apex the simulated
                                    # max_jump_height_m
      top_speed_m_s: {bound: 1.0}   # a gait's top speed for any controller (optimal/
                                    # top_speed.py) at least this (m/s; trot, bound, pronk):
                                    # predicted, then verified: each simulated design's gait
                                    # at its top speed tracked, achieved at this speed
    compare:                        # optional: designs simulated beside the default design,
      - {motor: odrive_d5065_270kv, motor.gear_ratio: 8.0}   # e.g. the obvious fix
    objectives: [actuator_mass_kg, max_jump_height_m]   # the first decides; default the mass;
                        # also peak_electrical_power_W[:MANEUVER], cost_of_transport:MANEUVER,
                        # top_speed_m_s:GAIT (trot, bound or pronk)
    budget: {trials: 40, finalists: 3, seed: 0}

A built-in actuator (CubeMars AK, Mini Cheetah) keeps its own gearbox and ratio: for it the
gear ratio and gearbox variables do not apply. Relative paths are taken from the spec file's
folder.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

from fivebar_drake.codesign.designs import (GEARBOX, LINKED, MOTOR, RATIO, actuator_mass,
                                           design_of, design_params, gearing)
from fivebar_drake.actuators.catalog import catalog, gearboxes
from fivebar_drake.core.files import read_input_text
from fivebar_drake.core.validation import MAX_MASS_KG, ParameterError, check_number, require
from fivebar_drake.core.yaml_files import load_spec_file
from fivebar_drake.envelope.spec import EnvelopeSpec, spec_from_dict as envelope_from_dict
from fivebar_drake.optimal.gait_floor import KINDS
from fivebar_drake.optimal.top_speed import GAITS as SPEED_GAITS
from fivebar_drake.robots.quadruped.config import with_changes
from fivebar_drake.sweep.spec import Varied

KEYS = ("variables", "requirements", "objectives", "budget", "compare")
OBJECTIVES = {"actuator_mass_kg": "minimize", "max_jump_height_m": "maximize",
              "peak_electrical_power_W": "minimize", "cost_of_transport": "minimize",
              "top_speed_m_s": "maximize"}
ON_MANEUVER = ("peak_electrical_power_W", "cost_of_transport")  # NAME:MANEUVER (a gait's)
ON_GAIT = ("top_speed_m_s",)                                     # NAME:GAIT (SPEED_GAITS)
GAITS = KINDS                                   # the gaits whose floors predict them
ACCEPT = {"pass": ("pass",), "warn": ("pass", "warn")}
FLAGS = ("step_check", "never_at_limit", "simulate_max_jump")
MASS = "actuator mass"            # the mass band's row beside the maneuvers (predict.py)
TOP_SPEED = "top speed {}"        # a required top speed's row, by its gait (predict.py)
MAX_TOP_SPEED_M_S = 100.0         # the fastest top speed a spec may require
MAX_WITHIN = 0.5                  # the widest mass band: +-50 %
BUDGET = {"trials": (1, 100_000), "finalists": (1, 100), "seed": (0, 2**31 - 1)}
DEFAULT_BUDGET = {"trials": 40, "finalists": 3, "seed": 0}


@dataclass(frozen=True)
class CodesignSpec:
    """The checked spec: the catalogue motors and gearbox types to choose from (gearboxes empty:
    the lightest type spanning the ratio), the other varied parameters (sweep.spec.Varied: a
    list, or a range with num None: continuous), the requirements (an EnvelopeSpec and the
    verdicts accepted), the objectives in order, the budget and the source file."""

    motors: tuple[str, ...]
    gearboxes: tuple[str, ...]
    vary: tuple[Varied, ...]
    envelope: EnvelopeSpec
    accept: tuple[str, ...]
    objectives: tuple[str, ...]
    trials: int
    finalists: int
    seed: int
    step_check: bool = False
    never_at_limit: bool = False
    simulate_max_jump: bool = False
    mass_band: tuple[float, float] | None = None     # (kg, relative half-width)
    top_speeds: tuple[tuple[str, float], ...] = ()  # (gait, least top speed m/s) required
    compare: tuple[dict, ...] = ()
    text: str = field(default="", compare=False)
    source: str = field(default="", compare=False)

    @property
    def directions(self) -> list[str]:
        return [OBJECTIVES[o.split(":")[0]] for o in self.objectives]

    def fingerprint(self) -> str:
        """A hash of everything that decides the search and its result: the spec's text and the
        maneuvers' parameters (so editing the spec or a file it names makes another study)."""
        data = {"text": self.text, "maneuvers": [repr(dataclasses.astuple(m.params)) + repr(
            m.scenario) for m in self.envelope.maneuvers]}
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()


def load_codesign_spec(path: str | Path) -> CodesignSpec:
    """Read and check SPEC.yaml (ParameterError naming the file and the field)."""
    path = Path(path)
    spec = load_spec_file(path, "co-design spec", spec_from_dict)
    return dataclasses.replace(spec, text=read_input_text(path, "co-design spec"))


def spec_from_dict(data, folder: Path, source: str = "") -> CodesignSpec:
    """CodesignSpec from the YAML's mapping; relative files are taken from folder."""
    require(isinstance(data, dict), "SPEC", type(data).__name__, f"must be a mapping of {KEYS}")
    unknown = sorted(set(data) - set(KEYS))
    require(not unknown, unknown[0] if unknown else "", unknown,
            f"unknown key(s); the keys are {list(KEYS)}")
    variables = data.get("variables")
    require(isinstance(variables, dict), "variables", variables,
            "must map `motor` (a list of catalogue names) and dotted parameter paths to a list "
            "or a range [low, high]")
    require(MOTOR in variables, "variables.motor", "missing",
            "is required: a list of catalogue names (fivebar_drake/data/actuators.yaml), e.g. "
            "[default_assumed] for the design's own motor")
    motors = _names("variables.motor", variables[MOTOR], catalog())
    kinds = (_names("variables.gearbox", variables[GEARBOX], gearboxes())
             if GEARBOX in variables else ())
    vary = tuple(_varied(str(k), v) for k, v in variables.items() if k not in (MOTOR, GEARBOX))
    envelope, accept, flags, band, speeds = _requirements(data.get("requirements"), folder,
                                                          source)
    base = envelope.maneuvers[0].params
    vary = tuple(_applies(v, base, motors, kinds) for v in vary)
    _buildable(motors, kinds, vary)
    for v in vary:                  # each path and value alone against the base parameters
        for value in (v.values or (v.low, v.high)):
            try:
                with_changes(envelope.maneuvers[0].params,
                             dict.fromkeys(v.path.split(LINKED), value))
            except ParameterError as err:
                raise ParameterError(f"variables.{v.path} = {value!r}: {err.message}",
                                     f"variables.{v.path}") from None
    objectives = _objectives(data.get("objectives", ["actuator_mass_kg"]), envelope)
    require(not flags["simulate_max_jump"] or "max_jump_height_m" in objectives,
            "requirements.simulate_max_jump", True, "needs the objective max_jump_height_m")
    budget = data.get("budget", {})
    require(isinstance(budget, dict) and set(budget) <= set(BUDGET), "budget", budget,
            f"must be a mapping of {list(BUDGET)}")
    counts = {k: check_number(f"budget.{k}", budget.get(k, DEFAULT_BUDGET[k]), *BUDGET[k],
                              integer=True) for k in BUDGET}
    compare = _compare(data.get("compare", []), envelope)
    return CodesignSpec(motors=motors, gearboxes=kinds, vary=vary, envelope=envelope,
                        accept=ACCEPT[accept], objectives=tuple(objectives), source=source,
                        compare=compare, mass_band=band, top_speeds=speeds, **flags, **counts)


def _compare(value, envelope: EnvelopeSpec, field_name: str = "") -> tuple[dict, ...]:
    """The designs to simulate beside the default: each a mapping {motor: NAME, gearbox: TYPE
    (optional), motor.gear_ratio: N, PATH: value}, resolved (designs.design_of) and checked
    against the base parameters."""
    require(isinstance(value, list) and len(value) <= 10, "compare", value,
            "must be a list of at most 10 designs, each {motor: NAME, motor.gear_ratio: N, ...}")
    out = []
    for i, given in enumerate(value):
        where = field_name or f"compare[{i}]"
        require(isinstance(given, dict) and MOTOR in given, where, given,
                "must be a mapping {motor: NAME, gearbox: TYPE (optional), motor.gear_ratio: N, "
                "PATH: value}")
        _names(f"{where}.motor", [given[MOTOR]], catalog())
        if GEARBOX in given:
            _names(f"{where}.gearbox", [given[GEARBOX]], gearboxes())
        for k, v in given.items():
            if k not in (MOTOR, GEARBOX):
                check_number(f"{where}.{k}", v)
        try:
            design = design_of(dict(given))
            design_params(envelope.maneuvers[0].params, design)
        except ParameterError as err:
            raise ParameterError(f"{where}: {err.message}", f"{where}.{err.field}") from None
        out.append(design)
    return tuple(out)


def _objectives(value, envelope: EnvelopeSpec) -> list[str]:
    """The objectives: distinct names of OBJECTIVES; peak_electrical_power_W and
    cost_of_transport over a gait maneuver of the envelope as NAME:MANEUVER (the peak power
    without one: over all its gait maneuvers)."""
    gaits = [m.name for m in envelope.maneuvers if m.scenario.gait.kind in GAITS]
    require(isinstance(value, list) and value and len(set(map(str, value))) == len(value),
            "objectives", value, f"must be a list of distinct names of {list(OBJECTIVES)}")
    for i, o in enumerate(value):
        name, _, maneuver = str(o).partition(":")
        require(name in OBJECTIVES, f"objectives[{i}]", o, f"must be one of {list(OBJECTIVES)}"
                f" ({', '.join(ON_MANEUVER)} optionally as NAME:MANEUVER)")
        if name in ON_GAIT:
            require(maneuver in SPEED_GAITS, f"objectives[{i}]", o,
                    f"{name} is on a gait: {name}:GAIT, GAIT one of {list(SPEED_GAITS)}")
            continue
        which = (f"one of the envelope's gait maneuvers {gaits}" if gaits else
                 "and the envelope has no gait maneuver (trot, walk, bound, pronk)")
        require(not maneuver or name in ON_MANEUVER and maneuver in gaits, f"objectives[{i}]",
                o, f"only {', '.join(ON_MANEUVER)} take a maneuver, {which}")
        require(name != "cost_of_transport" or maneuver, f"objectives[{i}]", o,
                f"cost_of_transport is on a maneuver: cost_of_transport:NAME, {which}")
        require(name != "peak_electrical_power_W" or maneuver or gaits, f"objectives[{i}]", o,
                "the envelope has no gait (trot, walk, bound, pronk) to predict it on")
    return [str(o) for o in value]


def _names(where: str, value, known) -> tuple[str, ...]:
    require(isinstance(value, list) and value and all(v in known for v in value)
            and len(set(value)) == len(value), where, value,
            f"must be a list of distinct names of {sorted(known)}")
    return tuple(value)


def _varied(path: str, value) -> Varied:
    """A list of numbers, or a range [low, high] (low < high), of a dotted parameter path (or
    of several joined by LINKED, which take the same value)."""
    where = f"variables.{path}"
    paths = path.split(LINKED)
    require(all(paths) and len(set(paths)) == len(paths)
            and (len(paths) == 1 or not {MOTOR, GEARBOX, RATIO} & set(paths)),
            where, path, f"paths joined by {LINKED!r} must be distinct parameter paths")
    numbers = isinstance(value, list) and value and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
    require(bool(numbers), where, value, "must be a range [low, high] or a list of numbers, "
            "e.g. [4.0, 12.0] (two numbers: a range)")
    for i, v in enumerate(value):
        check_number(f"{where}[{i}]", v)
    if len(value) == 2:
        require(value[0] < value[1], where, value, "a range [low, high] needs low < high (a "
                "list of values has three or more, or one)")
        return Varied(path, low=value[0], high=value[1])
    return Varied(path, values=tuple(value))


def _buildable(motors: tuple, kinds: tuple, vary: tuple) -> None:
    """ParameterError (before any search) where no design of the space can be built: no listed
    motor has its gearbox built in, and no gear ratio the space gives (its list, or a range
    sampled at 64 points) fits a listed (or any) gearbox type."""
    if any(catalog()[m].built_in_gearbox is not None for m in motors):
        return
    ratio = next((v for v in vary if RATIO in v.path.split(LINKED)), None)
    require(ratio is not None, "variables", sorted({MOTOR, *(v.path for v in vary)}),
            f"no listed motor has a gearbox of its own: vary {RATIO} too")
    ratios = ratio.values or [ratio.low + (ratio.high - ratio.low) * i / 63 for i in range(64)]
    for motor in motors:
        for kind in kinds or (None,):
            for value in ratios:
                try:
                    gearing(motor, float(value), kind)
                    return
                except ParameterError:
                    continue
    spans = ", ".join(f"{k} {g.ratio_min.value:g}..{g.ratio_max.value:g}"
                      for k, g in gearboxes().items() if not kinds or k in kinds)
    raise ParameterError(f"variables.{ratio.path} = {list(ratio.values) or [ratio.low, ratio.high]}"
                         f": no design of the space can be built: no gear ratio it gives fits a "
                         f"gearbox type ({spans})", f"variables.{ratio.path}")


def _applies(v: Varied, base, motors: tuple, kinds: tuple) -> Varied:
    """The variable if every design can take it, as the parameter's type (an integer parameter's
    range sampled as integers, its values kept as given); ParameterError naming it where the
    design itself sets the parameter (the catalogue motor's fields, the actuators' mass) or no
    listed motor takes it (a gear ratio where every motor has its gearbox built in)."""
    where = f"variables.{v.path}"
    for path in v.path.split(LINKED):
        require(path == RATIO or not path.startswith("motor."), where, path,
                "the catalogue motor sets the motor's fields: vary `motor` (and its "
                f"{RATIO}) instead")
        require(path != "robot.motors_kg", where, path, "the design sets the motors' mass "
                "from its actuators (motor and gearbox): vary `motor` instead")
    if RATIO in v.path.split(LINKED) and not kinds:
        require(any(catalog()[m].built_in_gearbox is None for m in motors), where, v.path,
                f"every listed motor ({', '.join(motors)}) has its gearbox built in at its own "
                "ratio, which the design keeps: list a bare motor or drop the variable")
    current = base
    for part in v.path.split(LINKED)[0].split("."):
        current = getattr(current, part, None)
    if isinstance(current, int) and not isinstance(current, bool):
        given = v.values or (v.low, v.high)
        require(all(float(x).is_integer() for x in given), where, list(given),
                f"{v.path} is an integer (now {current}): give whole numbers")
        return dataclasses.replace(v, values=tuple(int(x) for x in v.values),
                                   low=None if v.low is None else int(v.low),
                                   high=None if v.high is None else int(v.high), integer=True)
    return v


def _requirements(value, folder: Path, source: str) -> tuple:
    """(the envelope spec, the accepted verdict's name, {step_check, never_at_limit,
    simulate_max_jump}, the mass band or None, the required top speeds) of `requirements`."""
    require(isinstance(value, dict) and "envelope" in value and set(value) <= {
        "envelope", "accept", "actuator_mass", "top_speed_m_s", *FLAGS}, "requirements", value,
        "must be a mapping {envelope: FILE or an envelope spec's mapping, accept: pass|warn, "
        "step_check: true|false, never_at_limit: true|false, actuator_mass: {equal_to: KG or "
        "a design, within: FRACTION}, simulate_max_jump: true|false, top_speed_m_s: {GAIT: "
        "M_S}}")
    accept = value.get("accept", "pass")
    require(accept in ACCEPT, "requirements.accept", accept, f"must be one of {list(ACCEPT)}")
    flags = {k: value.get(k, False) for k in FLAGS}
    for k, v in flags.items():
        require(isinstance(v, bool), f"requirements.{k}", v, "must be true or false")
    envelope = _envelope(value["envelope"], folder, source)
    if flags["step_check"]:
        envelope = dataclasses.replace(envelope, maneuvers=tuple(
            dataclasses.replace(m, step_check=True) for m in envelope.maneuvers))
    band = _mass_band(value["actuator_mass"], envelope) if "actuator_mass" in value else None
    return envelope, accept, flags, band, _top_speeds(value.get("top_speed_m_s", {}))


def _top_speeds(value) -> tuple[tuple[str, float], ...]:
    """The required top speeds of requirements.top_speed_m_s: {GAIT: M_S, ...}."""
    where = "requirements.top_speed_m_s"
    require(isinstance(value, dict) and set(value) <= set(SPEED_GAITS), where, value,
            f"must be a mapping of gaits {list(SPEED_GAITS)} to the least top speed (m/s)")
    return tuple((gait, check_number(f"{where}.{gait}", speed, 0.0, MAX_TOP_SPEED_M_S,
                                     low_open=True)) for gait, speed in value.items())


def _mass_band(value, envelope: EnvelopeSpec) -> tuple[float, float]:
    """(the reference actuator mass in kg, the relative half-width) of
    requirements.actuator_mass: {equal_to: KG or a design's mapping, within: FRACTION}."""
    where = "requirements.actuator_mass"
    require(isinstance(value, dict) and set(value) == {"equal_to", "within"}, where, value,
            "must be a mapping {equal_to: KG or a design {motor: NAME, gearbox: TYPE, "
            "motor.gear_ratio: N}, within: FRACTION (e.g. 0.02: +-2 %)}")
    within = check_number(f"{where}.within", value["within"], 0.0, MAX_WITHIN)
    reference = value["equal_to"]
    if isinstance(reference, dict):
        design = _compare([reference], envelope, f"{where}.equal_to")[0]
        return actuator_mass(design), within
    return check_number(f"{where}.equal_to", reference, 0.0, MAX_MASS_KG, low_open=True), within


def _envelope(given, folder: Path, source: str) -> EnvelopeSpec:
    """The envelope spec of `requirements.envelope` (a file name or a mapping)."""
    if isinstance(given, str):
        path = folder / given
        require(path.is_file(), "requirements.envelope", given,
                f"must name an existing envelope spec (relative to {folder})")
        return load_spec_file(path, "envelope spec", envelope_from_dict)
    require(isinstance(given, dict), "requirements.envelope", given,
            "must be a file name or an envelope spec's mapping (maneuvers, duty_cycle, ...)")
    try:
        return envelope_from_dict(given, folder, source)
    except ParameterError as err:
        if err.source:                  # a file the envelope names: its own error
            raise
        raise ParameterError(f"requirements.envelope.{err.message}",
                             f"requirements.envelope.{err.field}") from None
