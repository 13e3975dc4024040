"""A duty envelope's specification (SPEC.yaml): the maneuvers, each a named scenario (a gait kind
and scenario fields over the base scenario), and a duty cycle.

    config: my_robot.toml        # parameter file (default: the packaged one)
    scenario: base.yaml          # base scenario of every maneuver: a file or a mapping of
                                 # scenario fields (default: the built-in scenario)
    duration_s: 10.0             # simulated time of each maneuver that does not give its own
    maneuvers:
      - {name: trot_1hz, gait: trot}
      - {name: trot_fast, gait: trot, gait_frequency_hz: 1.5}
      - {name: jump, gait: jump, duration_s: 3.0, contact_check: true}   # run again with the
                                 # foot contact softer and stiffer (simulate --contact-check)
    duty_cycle:                  # optional: maneuvers one after the other, each for a time
      - {maneuver: trot_1hz, duration_s: 300}
      - {maneuver: trot_fast, duration_s: 60}

A maneuver's keys other than `name` and `contact_check` are scenario fields (simulation/scenario.py, README), so a
new gait kind or scenario field is a maneuver as soon as it exists. Every maneuver is checked as
`simulate` checks a run (its scenario, its parameters, builder.check_run) before anything runs;
relative paths are taken from the spec file's folder.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from fivebar_drake.core.validation import ParameterError, check_number, require
from fivebar_drake.core.yaml_files import load_spec_file
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.builder import check_run
from fivebar_drake.simulation.scenario import Scenario, field_names, load_scenario

DATA = Path(__file__).resolve().parent.parent / "data"
DEFAULT_SPEC = DATA / "envelope_default.yaml"
KEYS = ("config", "scenario", "duration_s", "maneuvers", "duty_cycle")
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}")   # a maneuver's name is its folder's name
MAX_MANEUVERS = 100          # each is a whole simulation (seconds to minutes of wall time)
MAX_DUTY_STEPS = 1000
MAX_DUTY_CYCLE_S = 86_400.0  # a day of operation: 200 of the default winding's time constants


@dataclass(frozen=True)
class Maneuver:
    """A maneuver: its name, the scenario fields the spec gives it (over the base scenario),
    the checked scenario and parameters it runs with, and whether its run is step-checked (run
    again at half the plant step, as `simulate --step-check`; set by the co-design) and
    contact-checked (run again with the foot contact softer and stiffer, as `simulate
    --contact-check`: the maneuver's `contact_check: true`)."""

    name: str
    changes: dict
    scenario: Scenario
    params: Params
    step_check: bool = False
    contact_check: bool = False


@dataclass(frozen=True)
class DutyStep:
    """A step of the duty cycle: a maneuver (its name) repeated for duration_s (s)."""

    maneuver: str
    duration_s: float


@dataclass(frozen=True)
class EnvelopeSpec:
    """The checked spec: its maneuvers (in the spec's order), the duty cycle (empty: none) and
    the file it came from."""

    maneuvers: tuple[Maneuver, ...]
    duty_cycle: tuple[DutyStep, ...]
    source: str = field(default="", compare=False)


def load_envelope_spec(path: str | Path | None = None) -> EnvelopeSpec:
    """Read and check SPEC.yaml (None: the packaged default); ParameterError naming the file,
    the field (`maneuvers[i]...`, `duty_cycle[i]...`), the value and what is allowed."""
    path = Path(path) if path is not None else DEFAULT_SPEC
    return load_spec_file(path, "envelope spec", spec_from_dict)


def spec_from_dict(data, folder: Path, source: str = "") -> EnvelopeSpec:
    """EnvelopeSpec from the YAML's mapping; relative files are taken from folder."""
    require(isinstance(data, dict), "SPEC", type(data).__name__,
            f"must be a mapping of {list(KEYS)}")
    unknown = sorted(set(data) - set(KEYS))
    require(not unknown, unknown[0] if unknown else "", unknown,
            f"unknown key(s); the keys are {list(KEYS)}")
    config = _file(data.get("config"), "config", folder)
    base = _base_scenario(data.get("scenario"), folder)
    duration = data.get("duration_s")
    if duration is not None:
        check_number("duration_s", duration, 0.0, low_open=True)
    listed = data.get("maneuvers")
    require(isinstance(listed, list) and 1 <= len(listed) <= MAX_MANEUVERS, "maneuvers",
            listed, f"must be a list of 1 .. {MAX_MANEUVERS} maneuvers, each a mapping "
            "{name: NAME, gait: KIND, FIELD: value, ...}")
    maneuvers = []
    for i, item in enumerate(listed):
        maneuver = _maneuver(i, item, base, duration, config, folder)
        require(all(m.name != maneuver.name for m in maneuvers), f"maneuvers[{i}].name",
                maneuver.name, "given to two maneuvers; each maneuver needs its own name (the "
                "name of its output folder)")
        if maneuvers:
            require(maneuver.params.motor == maneuvers[0].params.motor,
                    f"maneuvers[{i}].params_file", maneuver.scenario.params_file, "gives "
                    f"another motor than maneuver {maneuvers[0].name!r}: an envelope is of one "
                    "motor")
        maneuvers.append(maneuver)
    return EnvelopeSpec(tuple(maneuvers), _duty_cycle(data.get("duty_cycle"), maneuvers),
                        source)


def _file(value, key: str, folder: Path) -> str | None:
    """The absolute path of a file the spec names (None if not given)."""
    if value is None:
        return None
    require(isinstance(value, str) and (folder / value).is_file(), key, value,
            f"must name an existing file (relative to {folder})")
    return str((folder / value).resolve())


def _base_scenario(value, folder: Path) -> tuple[str | None, dict]:
    """(scenario file or None, scenario fields) every maneuver starts from."""
    if isinstance(value, dict):
        names = field_names()
        for key in value:
            require(key in names, f"scenario.{key}", value[key],
                    f"unknown field; the fields are {names}")
        return None, value
    return _file(value, "scenario", folder), {}


def _maneuver(i: int, item, base: tuple[str | None, dict], duration, config,
              folder: Path) -> Maneuver:
    """The maneuver maneuvers[i], checked as simulate checks a run; its errors name the
    maneuver and the field where it was given: the maneuver's own (maneuvers[i].FIELD), the
    spec's scenario (scenario.FIELD) or its duration_s (those of a file it reads name that
    file)."""
    where = f"maneuvers[{i}]"
    require(isinstance(item, dict) and isinstance(item.get("name"), str), where, item,
            "must be a mapping with a name, e.g. {name: trot_fast, gait: trot, "
            "gait_frequency_hz: 1.5}")
    name = item["name"]
    require(NAME.fullmatch(name) is not None, f"{where}.name", name,
            "must be 1 to 64 letters, digits, '_' or '-', starting with a letter or a digit "
            "(it names the maneuver's output folder)")
    changes = {k: v for k, v in item.items() if k not in ("name", "contact_check")}
    contact = item.get("contact_check", False)
    require(isinstance(contact, bool), f"{where}.contact_check", contact,
            "must be true or false (run again with the foot contact softer and stiffer)")
    names = field_names()
    for key in changes:
        require(key in names, f"{where}.{key}", changes[key],
                f"unknown field; a maneuver gives its name and scenario fields {names}")
    fields = {**base[1], **({"duration_s": duration} if duration is not None else {}),
              **changes}
    if isinstance(fields.get("params_file"), str) and fields["params_file"]:
        fields["params_file"] = str(folder / fields["params_file"])
    if config is not None:
        fields["params_file"] = config
    try:
        scenario = load_scenario(base[0], **fields)
        params = scenario.load_params()
        check_run(scenario, params)
    except ParameterError as err:
        if err.source not in ("", "command line", "built-in scenario"):
            raise                           # the base scenario's file or a parameter file
        inner = err.field[len("scenario."):] if err.field.startswith("scenario.") else ""
        key = inner.split(".")[0].split("[")[0]
        if key and key not in changes and key in base[1]:        # from the spec's scenario
            field_ = f"scenario.{inner}"
        elif key == "duration_s" and "duration_s" not in changes and duration is not None:
            field_ = "duration_s"                                # the spec's own duration
        else:
            field_ = f"{where}.{inner}" if inner else where
        message = (field_ + err.message[len(err.field):] if inner and
                   err.message.startswith(err.field) else f"{where}: {err.message}")
        raise ParameterError(f"{message} (maneuver {name!r})", field_) from None
    return Maneuver(name, changes, scenario, params, contact_check=contact)


def _duty_cycle(steps, maneuvers: list[Maneuver]) -> tuple[DutyStep, ...]:
    """The duty cycle's steps, each naming a maneuver of the spec."""
    if steps is None:
        return ()
    names = [m.name for m in maneuvers]
    require(isinstance(steps, list) and 1 <= len(steps) <= MAX_DUTY_STEPS, "duty_cycle", steps,
            f"must be a list of 1 .. {MAX_DUTY_STEPS} steps, each {{maneuver: NAME, "
            "duration_s: S}")
    out = []
    for i, step in enumerate(steps):
        where = f"duty_cycle[{i}]"
        require(isinstance(step, dict) and set(step) == {"maneuver", "duration_s"}, where,
                step, "must be a mapping {maneuver: NAME, duration_s: S}")
        require(step["maneuver"] in names, f"{where}.maneuver", step["maneuver"],
                f"names no maneuver of the spec; they are {names}")
        duration = check_number(f"{where}.duration_s", step["duration_s"], 0.0,
                                MAX_DUTY_CYCLE_S, low_open=True)
        out.append(DutyStep(step["maneuver"], duration))
    total = sum(s.duration_s for s in out)
    check_number("duty_cycle (total duration_s)", total, 0.0, MAX_DUTY_CYCLE_S,
                 why="a day of operation")
    return tuple(out)

