"""A co-design's design: a catalogue motor, a gearbox type and ratio, and other parameters by
dotted path, as the parameters the rest of the toolkit runs with, and as a parameter file.

A design is a plain mapping {"motor": NAME, "gearbox": TYPE, "motor.gear_ratio": N, PATH:
value, ...}. Its parameters are the base's with the catalogue actuator (actuators/catalog.py:
k_t, resistance, bus, currents, rotor and gears' inertia, efficiency) in place of the base's
motor with its own thermal model (actuators/catalog.bldc_motor: the entry's winding limit and time
constant or the catalogue's stated assumptions, its continuous current at that limit) at the
base's ambient, the base's friction kept (the catalogue has none), and the robot's motor mass
robot.motors_kg set to the legs' actuators' mass (so a heavier actuator loads every maneuver).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

from fivebar_drake.actuators.catalog import (BUILT_IN, actuator_mass_kg, bldc_motor, catalog,
                                          gearboxes)
from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.parameter_files import packaged, read_toml
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.envelope.spec import EnvelopeSpec
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.robots.quadruped.config import with_changes
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.simulation.builder import check_run
MOTOR, GEARBOX, RATIO = "motor", "gearbox", "motor.gear_ratio"    # a design's own keys
LINKED = "="            # a variable of paths joined by it sets each to its one value
BUS = "motor.bus_voltage_V"


def gearing(motor: str, ratio: float | None, kind: str | None) -> tuple[float | None, str]:
    """(ratio, gearbox type) of a catalogue motor: its own for a built-in actuator; the given
    type, or (kind None) the lightest type spanning the ratio. ParameterError if none spans it."""
    own = catalog()[motor].built_in_gearbox
    if own is not None:
        return own.ratio.value, BUILT_IN
    if ratio is None:
        raise ParameterError(f"{motor} has no gearbox of its own: give its gear ratio "
                             f"({RATIO})", RATIO)
    if kind is not None:
        gearboxes()[kind].check_ratio(ratio)
        return ratio, kind
    spanning = [k for k, g in gearboxes().items()
                if g.ratio_min.value <= ratio <= g.ratio_max.value]
    if not spanning:
        raise ParameterError(f"gear_ratio = {ratio:g}: no gearbox type spans it", RATIO)
    return ratio, min(spanning, key=lambda k: actuator_mass_kg(motor, ratio, k))


def design_of(values: dict) -> dict:
    """The design of sampled values (motor, gearbox or None, ratio or None, other paths, linked
    paths "a=b" each set to the value): the gearing resolved (gearing); ParameterError if no
    gearbox spans the ratio."""
    ratio, kind = gearing(values[MOTOR], values.get(RATIO), values.get(GEARBOX))
    others = {path: v for k, v in values.items() if k not in (MOTOR, GEARBOX, RATIO)
              for path in k.split(LINKED)}
    return {MOTOR: values[MOTOR], GEARBOX: kind, RATIO: ratio, **others}


def actuator_mass(design: dict) -> float:
    """One actuator's mass (kg): motor and gearbox."""
    built_in = design[GEARBOX] == BUILT_IN
    return actuator_mass_kg(design[MOTOR], None if built_in else design[RATIO],
                            design[GEARBOX])


def design_params(base: Params, design: dict) -> Params:
    """The base parameters with the design (module docstring); ParameterError naming the field
    for an impossible one."""
    built_in = design[GEARBOX] == BUILT_IN
    others = {k: v for k, v in design.items() if k not in (MOTOR, GEARBOX, RATIO, BUS)}
    motor = bldc_motor(design[MOTOR], None if built_in else design[RATIO], design[GEARBOX],
                       bus_voltage_V=design.get(BUS),
                       coulomb_friction_Nm=base.motor.coulomb_friction_Nm,
                       viscous_friction_Nm_s=base.motor.viscous_friction_Nm_s,
                       **({"ambient_C": base.motor.ambient_C}
                          if getattr(base.motor, "ambient_C", None) is not None else {}))
    count = base.robot.legs * len(MOTORS)
    return with_changes(dataclasses.replace(base, motor=motor),
                        {**others, "robot.motors_kg": count * actuator_mass(design)})


def design_envelope(spec: EnvelopeSpec, design: dict | None) -> EnvelopeSpec:
    """The envelope spec with every maneuver's parameters those of the design (None: the spec
    as it is, the default design), each checked as simulate checks a run (ParameterError)."""
    if design is None:
        return spec
    maneuvers = []
    for m in spec.maneuvers:
        params = design_params(m.params, design)
        check_run(m.scenario, params)
        maneuvers.append(dataclasses.replace(m, params=params))
    return dataclasses.replace(spec, maneuvers=tuple(maneuvers))


def design_name(design: dict | None) -> str:
    """A design in a few words: motor, gearing, the other parameters."""
    if design is None:
        return "the default design"
    gear = (f"built-in {design[RATIO]:g}:1" if design[GEARBOX] == BUILT_IN else
            f"{design[RATIO]:.2f}:1 {design[GEARBOX]}")
    rest = "".join(f", {k} = {v:.4g}" for k, v in design.items()
                   if k not in (MOTOR, GEARBOX, RATIO))
    return f"{design[MOTOR]} at {gear}{rest}"


def base_file(spec: EnvelopeSpec) -> Path:
    """The parameter file the spec's maneuvers start from (its config, else the packaged)."""
    return Path(spec.maneuvers[0].scenario.params_file or packaged("default.toml"))


def write_parameter_file(spec: EnvelopeSpec, design: dict, path: Path) -> Path:
    """The design's parameter file (TOML, the base file's layout and comments-free values):
    the base file's tables with the design's fields and its whole [motor] section."""
    tables = read_toml(base_file(spec))
    params = design_params(spec.maneuvers[0].params, design)
    for key, value in design.items():
        if key not in (MOTOR, GEARBOX, RATIO, BUS):
            *sections, name = key.split(".")
            table = tables
            for section in sections:
                table = table[section]
            table[name] = value
    tables["robot"]["motors_kg"] = params.robot.motors_kg
    tables["motor"] = {f.name: getattr(params.motor, f.name)
                       for f in dataclasses.fields(params.motor)
                       if getattr(params.motor, f.name) is not None}
    head = (f"# The co-design's recommended design: {design_name(design)}\n"
            f"# (the base parameter file {base_file(spec).name} with its catalogue actuator)\n")
    return write_atomic(path, head + toml_text(tables))


def toml_text(tables: dict, prefix: str = "") -> str:
    """TOML of nested tables of numbers, strings, booleans and lists of them."""
    lines, nested = [], []
    for key, value in tables.items():
        if isinstance(value, dict):
            nested.append((key, value))
        else:
            lines.append(f"{key} = {_value(value)}")
    text = "\n".join(lines) + ("\n" if lines else "")
    for key, value in nested:
        name = f"{prefix}{key}"
        body = toml_text(value, name + ".")
        text += f"\n[{name}]\n{body}" if any(not isinstance(v, dict) for v in value.values()) \
            else body
    return text


def _value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, str):
        return json.dumps(value)
    return repr(value)
