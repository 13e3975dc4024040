"""The catalogue of real actuators (data/actuators.yaml) and the gearbox model by type
(data/gearboxes.yaml), read as untrusted data (core/yaml_files.py) and turned into the package's
BldcMotor (actuators/motor.py).

A catalogue motor (CatalogMotor) holds motor-side figures in BldcMotor's conventions: k_t per A
of q-axis current (amplitude-invariant), the phase resistance, the rated bus voltage, the peak
and continuous q-axis current, the rotor inertia and the mass; an actuator with a gearbox inside
(Mini Cheetah, CubeMars AK) names its ratio and type (BuiltInGearbox), its mass being the whole
actuator's. A Gearbox type spans a range of ratios with an efficiency, a mass that grows with the
actuator's peak output torque and the inertia of its own moving parts seen at the motor shaft
(a fraction of the rotor's). Every figure (Figure) carries its source and, where it was not read
as published, how it was converted, assumed or could not be re-checked.

bldc_motor(motor, gear_ratio, gearbox) is the actuator the rest of the toolkit uses;
actuator_mass_kg(motor, gear_ratio, gearbox) its mass, motor and gearbox. Errors are
ParameterError naming the file, the entry and the field (motors.<entry>.<field>.value).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import re
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Mapping

from fivebar_drake.core.files import read_input_text
from fivebar_drake.actuators.motor import (DQ_POWER, MAX_BUS_VOLTAGE_V, MAX_CURRENT_A,
                                      MAX_RESISTANCE_OHM, MAX_THERMAL_TIME_CONSTANT_S,
                                      MAX_TORQUE_CONSTANT_NM_A, MAX_WINDING_LIMIT_C,
                                      MIN_RESISTANCE_OHM, PHASE_VOLTAGE_OF_BUS, BldcMotor)
from fivebar_drake.core.parameter_files import check_keys, packaged
from fivebar_drake.core.validation import (MAX_GEAR_RATIO, MAX_MASS_KG, MAX_ROTOR_INERTIA_KG_M2,
                                           MAX_SPEED_RAD_S, MAX_TORQUE_NM, ParameterError,
                                           check_number, require)
from fivebar_drake.core.yaml_files import load_yaml

ACTUATORS_FILE = "actuators.yaml"
GEARBOXES_FILE = "gearboxes.yaml"
BUILT_IN = "built_in"            # bldc_motor's gearbox for an actuator's own gearbox
NAME_PATTERN = re.compile(r"[a-z0-9_]{1,64}")
MAX_TEXT = 2000                  # characters of a name, source or note: a paragraph, not a file
MAX_KV_RPM_PER_V = 100_000.0     # the smallest hobby motors are ~10 000 rpm/V
MAX_GEARBOX_KG_PER_NM = 1.0      # an industrial gearhead is ~0.06 kg per N*m
RATIO_MATCH = 1e-9               # relative: a requested ratio this close to a built-in one is it
KV_TO_KT = math.sqrt(3.0) / 2.0 * 60.0 / (2.0 * math.pi)   # k_t = KV_TO_KT / KV (8.2699)

FIGURE_NOTES = ("converted", "assumed", "unverified")
MOTOR_FIGURES = {   # name -> (low, high, low_open): check_number's bounds of the value
    "torque_constant_Nm_per_A": (0.0, MAX_TORQUE_CONSTANT_NM_A, True),
    "phase_resistance_ohm": (MIN_RESISTANCE_OHM, MAX_RESISTANCE_OHM, False),
    "bus_voltage_V": (0.0, MAX_BUS_VOLTAGE_V, True),
    "peak_current_A": (0.0, MAX_CURRENT_A, True),
    "continuous_current_A": (0.0, MAX_CURRENT_A, True),
    "rotor_inertia_kg_m2": (0.0, MAX_ROTOR_INERTIA_KG_M2, True),
    "mass_kg": (0.0, MAX_MASS_KG, True),
}
OPTIONAL_MOTOR_FIGURES = {"kv_rpm_per_V": (0.0, MAX_KV_RPM_PER_V, True),
                          "winding_limit_C": (0.0, MAX_WINDING_LIMIT_C, True),
                          "thermal_time_constant_s": (0.0, MAX_THERMAL_TIME_CONSTANT_S, True)}
# The thermal model of an entry that publishes none (bldc_motor), stated assumptions: the winding
# limit of the package's default motor (data/default.toml: below class F insulation with margin
# for hot spots), the continuous current rated at that limit in a RATED_AMBIENT_C room, and a
# time constant under a third of the default's 400 s (small outrunners without a heat sink heat
# in minutes: a shorter one is the conservative side for a duty cycle's peak)
ASSUMED_WINDING_LIMIT_C = 120.0
RATED_AMBIENT_C = 25.0
ASSUMED_TIME_CONSTANT_S = 120.0
OUTPUT_FIGURES = {   # published_output: the maker's figures after the gearbox
    "peak_torque_Nm": (0.0, MAX_TORQUE_NM, True),
    "continuous_torque_Nm": (0.0, MAX_TORQUE_NM, True),
    "no_load_speed_rad_s": (0.0, MAX_SPEED_RAD_S, True),
}
MOTOR_TEXT = ("name", "used_in")
GEARBOX_FIGURES = {
    "ratio_min": (1.0, MAX_GEAR_RATIO, False),
    "ratio_max": (1.0, MAX_GEAR_RATIO, False),
    "efficiency": (0.0, 1.0, True),
    "mass_base_kg": (0.0, MAX_MASS_KG, False),
    "mass_per_Nm_kg": (0.0, MAX_GEARBOX_KG_PER_NM, False),
    "input_inertia_fraction": (0.0, 1.0, False),
}


@dataclass(frozen=True)
class Figure:
    """One catalogue figure (SI): its value, its source, and where it was not read as published,
    the formula it was converted by, the assumption it is, or why it could not be re-checked."""

    value: float
    source: str
    converted: str | None = None
    assumed: str | None = None
    unverified: str | None = None


@dataclass(frozen=True)
class BuiltInGearbox:
    """An actuator's own gearbox: its type (a gearboxes.yaml name), its ratio, its efficiency
    (None: the type's) and which side of it the maker's figures are on (text)."""

    type: str
    ratio: Figure
    sides: str
    efficiency: Figure | None = None


@dataclass(frozen=True)
class CatalogMotor:
    """A catalogue entry: motor-side figures in BldcMotor's conventions (module docstring), its
    built-in gearbox if it has one, and the maker's output-side figures (published_output: name
    -> Figure, after the gearbox) to compare with."""

    key: str
    name: str
    used_in: str
    torque_constant_Nm_per_A: Figure
    phase_resistance_ohm: Figure
    bus_voltage_V: Figure
    peak_current_A: Figure
    continuous_current_A: Figure
    rotor_inertia_kg_m2: Figure
    mass_kg: Figure
    kv_rpm_per_V: Figure | None = None
    winding_limit_C: Figure | None = None
    thermal_time_constant_s: Figure | None = None
    built_in_gearbox: BuiltInGearbox | None = None
    published_output: Mapping[str, Figure] = dataclasses.field(
        default_factory=lambda: MappingProxyType({}))
    package_assumption: bool = False

    def figures(self) -> dict[str, Figure]:
        """Every figure of the entry by its dotted name (as errors name them)."""
        out = {name: getattr(self, name) for name in (*MOTOR_FIGURES, *OPTIONAL_MOTOR_FIGURES)
               if getattr(self, name) is not None}
        if self.built_in_gearbox is not None:
            out["built_in_gearbox.ratio"] = self.built_in_gearbox.ratio
            if self.built_in_gearbox.efficiency is not None:
                out["built_in_gearbox.efficiency"] = self.built_in_gearbox.efficiency
        out.update({f"published_output.{k}": v for k, v in self.published_output.items()})
        return out


@dataclass(frozen=True)
class Gearbox:
    """A gearbox type (gearboxes.yaml): the ratios it spans, its efficiency, its mass
    (mass_base_kg + mass_per_Nm_kg * the actuator's peak output torque) and the inertia of its
    moving parts at the motor shaft as a fraction of the rotor's."""

    key: str
    name: str
    ratio_min: Figure
    ratio_max: Figure
    efficiency: Figure
    mass_base_kg: Figure
    mass_per_Nm_kg: Figure
    input_inertia_fraction: Figure

    def figures(self) -> dict[str, Figure]:
        return {name: getattr(self, name) for name in GEARBOX_FIGURES}

    def mass_kg(self, peak_output_torque_Nm: float) -> float:
        """The gearbox's mass (kg) for an actuator of this peak output torque (N*m)."""
        return self.mass_base_kg.value + self.mass_per_Nm_kg.value * float(peak_output_torque_Nm)

    def check_ratio(self, gear_ratio) -> float:
        """gear_ratio as a float if this type spans it; ParameterError naming gear_ratio."""
        return check_number("gear_ratio", gear_ratio, self.ratio_min.value, self.ratio_max.value,
                            why=f"the range of a {self.key} gearbox (gearboxes.yaml)")


# -- reading ---------------------------------------------------------------------------------

def _text(table: dict, key: str, where: str) -> str:
    value = table[key]
    require(isinstance(value, str) and value.strip() != "" and len(value) <= MAX_TEXT,
            f"{where}.{key}", value, f"must be a non-empty text of at most {MAX_TEXT} characters")
    return value


def _figure(table, where: str, bounds: tuple) -> Figure:
    """A {value, source[, converted | assumed | unverified]} table as a Figure."""
    check_keys(table, where, ("value", "source", *FIGURE_NOTES), ("value", "source"))
    low, high, low_open = bounds
    value = check_number(f"{where}.value", table["value"], low, high, low_open=low_open)
    notes = {key: _text(table, key, where) for key in FIGURE_NOTES if key in table}
    return Figure(value=value, source=_text(table, "source", where), **notes)


def _figures(table: dict, where: str, specs: dict, required: bool = True) -> dict:
    return {name: _figure(table[name], f"{where}.{name}", bounds)
            for name, bounds in specs.items() if required or name in table}


def _entries(data, section: str) -> dict:
    """The named entries of the file's one top-level section."""
    require(isinstance(data, dict), "file", type(data).__name__,
            f"must be a table with the one key {section!r}")
    check_keys(data, "file", (section,))
    entries = data[section]
    require(isinstance(entries, dict) and entries, section, entries,
            "must be a table of named entries")
    for name in entries:
        require(isinstance(name, str) and NAME_PATTERN.fullmatch(name) is not None,
                f"{section}.{name}", name, "an entry's name: lower-case letters, digits and _")
    return entries


def _built_in(table, where: str, gearbox_types) -> BuiltInGearbox:
    check_keys(table, where, ("type", "ratio", "sides", "efficiency"), ("type", "ratio", "sides"))
    kind = table["type"]
    require(kind in gearbox_types, f"{where}.type", kind, f"one of {sorted(gearbox_types)}")
    return BuiltInGearbox(
        type=kind, ratio=_figure(table["ratio"], f"{where}.ratio", (1.0, MAX_GEAR_RATIO, False)),
        sides=_text(table, "sides", where),
        efficiency=(_figure(table["efficiency"], f"{where}.efficiency", (0.0, 1.0, True))
                    if "efficiency" in table else None))


def motor_from_dict(key: str, table, gearbox_types) -> CatalogMotor:
    """One catalogue entry (motors.<key>) as a CatalogMotor, every field checked; gearbox_types:
    the gearbox type names a built-in gearbox may name."""
    where = f"motors.{key}"
    allowed = (*MOTOR_TEXT, *MOTOR_FIGURES, *OPTIONAL_MOTOR_FIGURES, "built_in_gearbox",
               "published_output", "package_assumption")
    check_keys(table, where, allowed, (*MOTOR_TEXT, *MOTOR_FIGURES))
    figures = _figures(table, where, MOTOR_FIGURES)
    figures.update(_figures(table, where, OPTIONAL_MOTOR_FIGURES, required=False))
    assumption = table.get("package_assumption", False)
    require(isinstance(assumption, bool), f"{where}.package_assumption", assumption,
            "must be true or false")
    built_in = (_built_in(table["built_in_gearbox"], f"{where}.built_in_gearbox", gearbox_types)
                if "built_in_gearbox" in table else None)
    published = table.get("published_output", {})
    check_keys(published, f"{where}.published_output", OUTPUT_FIGURES, ())
    require(not published or built_in is not None, f"{where}.published_output",
            sorted(published), "output-side figures need the gearbox they were measured through: "
            "only an actuator with built_in_gearbox has them")
    motor = CatalogMotor(
        key=key, name=_text(table, "name", where), used_in=_text(table, "used_in", where),
        built_in_gearbox=built_in, package_assumption=assumption,
        published_output=MappingProxyType(
            _figures(published, f"{where}.published_output", OUTPUT_FIGURES, required=False)),
        **figures)
    peak, continuous = motor.peak_current_A.value, motor.continuous_current_A.value
    require(continuous <= peak, f"{where}.continuous_current_A.value", continuous,
            f"must be at most peak_current_A ({peak:g} A)")
    stall = motor.bus_voltage_V.value * PHASE_VOLTAGE_OF_BUS / motor.phase_resistance_ohm.value
    require(peak <= stall, f"{where}.peak_current_A.value", peak,
            f"the bus drives at most V_bus / sqrt(3) / R = {stall:.4g} A through the standing "
            "winding: check bus_voltage_V and phase_resistance_ohm")
    return motor


def gearbox_from_dict(key: str, table) -> Gearbox:
    """One gearbox type (gearboxes.<key>) as a Gearbox, every field checked."""
    where = f"gearboxes.{key}"
    check_keys(table, where, ("name", *GEARBOX_FIGURES))
    gearbox = Gearbox(key=key, name=_text(table, "name", where),
                      **_figures(table, where, GEARBOX_FIGURES))
    require(gearbox.ratio_min.value <= gearbox.ratio_max.value, f"{where}.ratio_max.value",
            gearbox.ratio_max.value, f"must be at least ratio_min ({gearbox.ratio_min.value:g})")
    return gearbox


def _read(path, what: str, build):
    """build(the file's data) for a YAML file; every ParameterError names the file."""
    path = Path(path)
    data = load_yaml(read_input_text(path, what), str(path))
    try:
        return build(data)
    except ParameterError as err:
        raise err.located(path) from None


def load_gearboxes(path=None) -> Mapping[str, Gearbox]:
    """The gearbox types of a gearboxes.yaml (None: the packaged one), by name."""
    def build(data):
        return {key: gearbox_from_dict(key, table)
                for key, table in _entries(data, "gearboxes").items()}
    return MappingProxyType(_read(path or packaged(GEARBOXES_FILE), "gearbox file", build))


def load_catalog(path=None, gearbox_types=None) -> Mapping[str, CatalogMotor]:
    """The motors of an actuators.yaml (None: the packaged one), by name; gearbox_types: the type
    names a built-in gearbox may name (None: the packaged gearboxes.yaml's)."""
    types = tuple(gearboxes()) if gearbox_types is None else tuple(gearbox_types)

    def build(data):
        return {key: motor_from_dict(key, table, types)
                for key, table in _entries(data, "motors").items()}
    return MappingProxyType(_read(path or packaged(ACTUATORS_FILE), "actuator catalogue", build))


@functools.lru_cache(maxsize=1)
def gearboxes() -> Mapping[str, Gearbox]:
    """The packaged gearbox types, by name (read once)."""
    return load_gearboxes()


@functools.lru_cache(maxsize=1)
def catalog() -> Mapping[str, CatalogMotor]:
    """The packaged actuator catalogue, by name (read once)."""
    return load_catalog()


# -- the actuator ----------------------------------------------------------------------------

def _entry(motor) -> CatalogMotor:
    if isinstance(motor, CatalogMotor):
        return motor
    entries = catalog()
    require(motor in entries, "motor", motor, f"one of the catalogue's {sorted(entries)}")
    return entries[motor]


def _gearing(motor: CatalogMotor, gear_ratio, gearbox) -> tuple[float, float, Gearbox, bool]:
    """(ratio, efficiency, gearbox type, built in) of a motor behind a gearbox: a type name or
    Gearbox from gearboxes.yaml for a bare motor, BUILT_IN for an actuator's own gearbox (ratio
    None or its own)."""
    types = gearboxes()
    own = motor.built_in_gearbox
    if own is not None:
        ratio = own.ratio.value
        require(gearbox in (None, BUILT_IN), "gearbox", gearbox,
                f"{motor.key} has a {ratio:g}:1 {own.type} built in: use gearbox {BUILT_IN!r}")
        if gear_ratio is not None:
            given = check_number("gear_ratio", gear_ratio, 1.0, MAX_GEAR_RATIO)
            require(abs(given - ratio) <= RATIO_MATCH * ratio, "gear_ratio", gear_ratio,
                    f"{motor.key}'s gearbox is built in at {ratio:g}:1")
        kind = types[own.type]
        return ratio, (own.efficiency or kind.efficiency).value, kind, True
    if isinstance(gearbox, Gearbox):
        kind = gearbox
    else:
        require(isinstance(gearbox, str) and gearbox in types, "gearbox", gearbox,
                f"{motor.key} has no gearbox of its own: one of {sorted(types)}")
        kind = types[gearbox]
    return kind.check_ratio(gear_ratio), kind.efficiency.value, kind, False


def bldc_motor(motor, gear_ratio=None, gearbox=None, *, bus_voltage_V=None,
               coulomb_friction_Nm: float = 0.0, viscous_friction_Nm_s: float = 0.0,
               ambient_C: float = RATED_AMBIENT_C) -> BldcMotor:
    """The package's BldcMotor of a catalogue motor (a CatalogMotor or its name) behind a
    gearbox: a gearboxes.yaml type (its name or Gearbox) at gear_ratio within its range, or
    BUILT_IN (or None) for an actuator's own gearbox (gear_ratio None or its own). k_t, the
    phase resistance, the peak and continuous current are the catalogue's; the bus is the
    entry's rated one unless bus_voltage_V is given; the efficiency is the gearbox's; the rotor
    inertia includes the gearbox's moving parts (J_rotor (1 + input_inertia_fraction)), so the
    reflected inertia at the output is N^2 of that. The thermal model is the entry's own: its
    winding limit and time constant (ASSUMED_WINDING_LIMIT_C, ASSUMED_TIME_CONSTANT_S where it
    publishes none) and the thermal resistance at which its continuous current holds the winding
    at that limit in a RATED_AMBIENT_C room, run at ambient_C. The catalogue gives no friction
    (the joint's and the gearbox's belong to the robot): pass the robot's. ParameterError
    naming the field."""
    entry = _entry(motor)
    ratio, efficiency, kind, _ = _gearing(entry, gear_ratio, gearbox)
    bus = entry.bus_voltage_V.value if bus_voltage_V is None else bus_voltage_V
    limit = (entry.winding_limit_C or Figure(ASSUMED_WINDING_LIMIT_C, "")).value
    tau = (entry.thermal_time_constant_s or Figure(ASSUMED_TIME_CONSTANT_S, "")).value
    loss = DQ_POWER * entry.phase_resistance_ohm.value * entry.continuous_current_A.value ** 2
    return BldcMotor(
        torque_constant_Nm_per_A=entry.torque_constant_Nm_per_A.value,
        winding_resistance_ohm=entry.phase_resistance_ohm.value,
        bus_voltage_V=bus, peak_current_A=entry.peak_current_A.value,
        continuous_current_A=entry.continuous_current_A.value,
        gear_ratio=ratio, gear_efficiency=efficiency,
        rotor_inertia_kg_m2=entry.rotor_inertia_kg_m2.value
        * (1.0 + kind.input_inertia_fraction.value),
        coulomb_friction_Nm=coulomb_friction_Nm, viscous_friction_Nm_s=viscous_friction_Nm_s,
        thermal_resistance_K_W=(limit - RATED_AMBIENT_C) / loss, thermal_time_constant_s=tau,
        winding_limit_C=limit, ambient_C=ambient_C)


def actuator_mass_kg(motor, gear_ratio=None, gearbox=None) -> float:
    """The actuator's mass (kg): an actuator with its gearbox built in, its own (the catalogue's
    mass is the whole actuator's); a bare motor, its mass plus the gearbox type's at the
    actuator's peak output torque (driving, at stall: N eta k_t I_peak)."""
    entry = _entry(motor)
    ratio, efficiency, kind, built_in = _gearing(entry, gear_ratio, gearbox)
    if built_in:
        return entry.mass_kg.value
    peak = ratio * efficiency * entry.torque_constant_Nm_per_A.value * entry.peak_current_A.value
    return entry.mass_kg.value + kind.mass_kg(peak)


def kt_from_kv(kv_rpm_per_V: float) -> float:
    """k_t (N*m per A of q-axis current) of a KV (rpm per V of line-to-line peak back-EMF):
    (sqrt(3)/2) * 60 / (2 pi KV), ODrive's 8.27 / KV; the back-EMF (k_t / 1.5) w per phase then
    reaches V / sqrt(3) at KV * V rpm."""
    return KV_TO_KT / check_number("kv_rpm_per_V", kv_rpm_per_V, 0.0, MAX_KV_RPM_PER_V,
                                   low_open=True)
