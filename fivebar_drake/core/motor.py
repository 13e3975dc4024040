"""The geared actuator: its parameters (a BLDC motor from motor-side data, BldcMotor, or a plain
torque-speed line, LineMotor), the output envelope derived from them in one place (the compiled
law ActuatorLaw / torque_limits), the Drake motor model (MotorModel) and the classification of
clipped commands.

Conventions (BldcMotor; see README "The actuator"):
- k_t (N*m/A) multiplies the q-axis current i of the amplitude-invariant dq transform, which is
  the amplitude of the sinusoidal phase current; the motor torque is k_t i, or the optional
  torque-current table (saturation) at i.
- Power balance 1.5 e_q i = k_t i w_m gives the q-axis back-EMF e_q = (k_t / 1.5) w_m (V per
  motor rad/s, phase amplitude); the winding resistance R is the phase resistance; the inverter
  gives phase amplitudes up to V_bus / sqrt(3) (space-vector modulation, linear range).
- Driving (torque and speed of one sign): R i + (k_t / 1.5) w_m <= V_bus / sqrt(3) and
  i <= peak_current_A, so the output torque N eta tau_m(i) is flat up to the corner speed and then
  falls to zero at the no-load speed sqrt(3)/2 V_bus / (k_t N). Braking: the back-EMF helps
  (R i - (k_t / 1.5) w_m <= V_bus / sqrt(3)); the current the motor regenerates is taken by the
  bus (a battery), and the gearbox's losses help the motor hold the load: tau_out = N tau_m / eta.
- Copper loss 1.5 R i^2 (three phases of amplitude i).
Changing gear_ratio keeps the motor-side data: output torque x N eta, speed / N, reflected
rotor inertia x N^2, everywhere.

LineMotor is the same law with a normalised "current" (stall current 1, peak current 1): the
motoring torque falls on a straight line from the stall torque to the no-load speed, braking is
held at the stall torque. It has no electrical or thermal model.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from pydrake.systems.framework import LeafSystem

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.parameter_files import build_section
from fivebar_drake.core.validation import (MAX_GEAR_RATIO, MAX_ROTOR_INERTIA_KG_M2,
                                           MAX_SPEED_RAD_S, MAX_TORQUE_NM, ParameterError,
                                           check_number, require)


# Bounds, as loose as the others (validation.py): they catch a slip (milliohms as ohms, minutes
# as seconds, Kelvin as Celsius), not a design.
MAX_TORQUE_CONSTANT_NM_A = 10.0     # motor side; a large servo is ~1 N m/A
MAX_RESISTANCE_OHM = 1000.0         # a small hobby motor's winding is ~10 ohm
MIN_RESISTANCE_OHM = 1e-4           # a large QDD motor's phase is ~0.02 ohm
MAX_BUS_VOLTAGE_V = 1000.0          # legged robots run 12-100 V
MAX_CURRENT_A = 10_000.0            # the largest QDD drives take ~100 A
MAX_THERMAL_RESISTANCE_K_W = 1000.0  # a bare 20 mm motor is ~20 K/W
MAX_THERMAL_TIME_CONSTANT_S = 1e5   # a large motor's housing: about an hour
MIN_AMBIENT_C, MAX_AMBIENT_C = -60.0, 100.0
MAX_WINDING_LIMIT_C = 300.0         # above the class C insulation rating (220 C)
MAX_TABLE_POINTS = 1000

DQ_POWER = 1.5                      # amplitude-invariant dq: P = 1.5 (v_d i_d + v_q i_q)
PHASE_VOLTAGE_OF_BUS = 1.0 / math.sqrt(3.0)   # SVPWM linear range: phase amplitude / V_bus
MODELS = ("bldc", "torque_speed_line")
THERMAL_FIELDS = ("thermal_resistance_K_W", "thermal_time_constant_s", "winding_limit_C",
                  "ambient_C")
FRICTION_SMOOTHING_RAD_S = 0.05   # Coulomb friction reaches its full value at this joint speed
PEAK_TOLERANCE = 1e-12            # relative: a delivered torque this close to the peak is at it
ENVELOPE_SAMPLES = 64             # report.json's motor.envelope


class ActuatorLaw(NamedTuple):
    """The actuator as plain numbers for the compiled law (SI). Motor side: kt (N*m per unit
    current), resistance (ohm), phase_voltage (V, the largest phase amplitude), back_emf
    (V*s/rad), peak_current; table_current / table_torque (the torque-current curve; empty:
    kt i). Output side: gear (N), efficiency (eta), coulomb (N*m), viscous (N*m*s/rad)."""

    gear: float
    efficiency: float
    kt: float
    resistance: float
    phase_voltage: float
    back_emf: float
    peak_current: float
    table_current: np.ndarray
    table_torque: np.ndarray
    coulomb: float
    viscous: float


@jit
def motor_torque(law, current):
    """Motor-side torque (N*m) at a current (>= 0): the table, or kt * current."""
    if law.table_current.size:
        return np.interp(current, law.table_current, law.table_torque)
    return law.kt * current


@jit
def motor_current(law, torque):
    """Current for a motor-side torque (>= 0, N*m): the inverse of motor_torque."""
    if law.table_current.size:
        return np.interp(torque, law.table_torque, law.table_current)
    return torque / law.kt


@jit
def torque_limits(law, speed):
    """(upper, lower) output torque (N*m) the actuator can deliver at output speed `speed`
    (rad/s): the current each direction of torque may draw under the voltage and the peak
    current, through the gearbox (x N eta driving, x N / eta braking). Module docstring."""
    w = law.gear * speed
    up = min(max((law.phase_voltage - law.back_emf * w) / law.resistance, 0.0), law.peak_current)
    lo = min(max((law.phase_voltage + law.back_emf * w) / law.resistance, 0.0), law.peak_current)
    up_factor = law.efficiency if speed >= 0.0 else 1.0 / law.efficiency
    lo_factor = law.efficiency if speed <= 0.0 else 1.0 / law.efficiency
    return (law.gear * up_factor * motor_torque(law, up),
            -law.gear * lo_factor * motor_torque(law, lo))


@jit
def limits_array(law, speed):
    """torque_limits over a flat array of speeds: (upper, lower) arrays."""
    up, lo = np.empty(speed.size), np.empty(speed.size)
    for k in range(speed.size):
        up[k], lo[k] = torque_limits(law, speed[k])
    return up, lo


@jit
def currents_array(law, torque, speed):
    """Motor current (A, >= 0) that delivers output torques `torque` at output speeds `speed`
    (flat arrays): driving through the gearbox's losses (tau / (N eta)), braking helped by them
    (tau eta / N)."""
    out = np.empty(torque.size)
    for k in range(torque.size):
        driving = torque[k] * speed[k] >= 0.0
        factor = law.efficiency if driving else 1.0 / law.efficiency
        out[k] = motor_current(law, abs(torque[k]) / (law.gear * factor))
    return out


@jit
def speed_margins(law, torque, speed):
    """Per operating point (flat arrays of output torque N*m and speed rad/s): the ratio of the
    largest speed at which the envelope still gives |torque| to |speed| for driving points within
    the peak current (inf for braking or standing points; nan beyond the peak current, which is
    the torque check's), and whether the point lies outside the envelope (within the peak
    current: on its speed side)."""
    margin, outside = np.empty(torque.size), np.zeros(torque.size, dtype=np.bool_)
    peak_motor = motor_torque(law, law.peak_current)
    for k in range(torque.size):
        t, w = torque[k], speed[k]
        driving = t * w >= 0.0
        cap = law.gear * peak_motor * (law.efficiency if driving else 1.0 / law.efficiency)
        if abs(t) > cap * (1.0 + PEAK_TOLERANCE):
            margin[k] = np.nan
            continue
        up, lo = torque_limits(law, w)
        outside[k] = t > up * (1.0 + PEAK_TOLERANCE) or t < lo * (1.0 + PEAK_TOLERANCE)
        margin[k] = np.inf
        if t * w > 0.0:                         # driving: the back-EMF limits the speed
            i = motor_current(law, abs(t) / (law.gear * law.efficiency))
            top = (law.phase_voltage - law.resistance * i) / (law.back_emf * law.gear)
            margin[k] = top / abs(w)
    return margin, outside


def _flat(values: np.ndarray) -> np.ndarray:
    """values as a flat, C-contiguous, writable float array: the one array type the compiled
    laws are called with (a read-only view, e.g. np.broadcast_to's, would load a second
    compiled variant)."""
    return np.require(np.ravel(values), dtype=float, requirements=["C", "W"])


class Motor:
    """What every actuator gives (output side, SI): peak_torque_Nm (driving, at stall),
    no_load_speed_rad_s, reflected_inertia_kg_m2, the envelope (torque_limit, limits), currents
    and the compiled law (law). Subclasses: BldcMotor, LineMotor."""

    gear_ratio: float
    gear_efficiency: float
    rotor_inertia_kg_m2: float
    coulomb_friction_Nm: float
    viscous_friction_Nm_s: float

    @property
    def law(self) -> ActuatorLaw:
        raise NotImplementedError

    @property
    def has_thermal_model(self) -> bool:
        return False

    @property
    def peak_torque_Nm(self) -> float:
        """Output torque at stall, driving (N*m)."""
        return float(torque_limits(self.law, 0.0)[0])

    @property
    def braking_peak_torque_Nm(self) -> float:
        """Largest output torque braking (N*m): at the peak current through the gearbox's
        losses (N tau_m / eta)."""
        law = self.law
        return law.gear / law.efficiency * float(motor_torque(law, law.peak_current))

    @property
    def no_load_speed_rad_s(self) -> float:
        """Output speed at which the driving torque reaches zero (rad/s)."""
        law = self.law
        return law.phase_voltage / (law.back_emf * law.gear)

    @property
    def reflected_inertia_kg_m2(self) -> float:
        """Rotor inertia seen at the output, N^2 J_rotor."""
        return self.gear_ratio**2 * self.rotor_inertia_kg_m2

    @property
    def max_applied_torque_Nm(self) -> float:
        """Bound on the torque the motor model puts on a joint at up to the no-load speed."""
        return (self.braking_peak_torque_Nm + self.coulomb_friction_Nm
                + self.viscous_friction_Nm_s * self.no_load_speed_rad_s)

    def limits(self, speed_rad_s) -> tuple[np.ndarray, np.ndarray]:
        """(upper, lower) output torque (N*m) at output speeds (rad/s, any shape)."""
        speed = np.asarray(speed_rad_s, dtype=float)
        up, lo = limits_array(self.law, _flat(speed))
        return up.reshape(speed.shape), lo.reshape(speed.shape)

    def torque_limit(self, speed_rad_s) -> np.ndarray:
        """Largest driving torque (N*m) at output speeds |speed_rad_s| (rad/s): the envelope's
        driving quadrant."""
        return self.limits(np.abs(np.asarray(speed_rad_s, dtype=float)))[0]

    def envelope(self, samples: int = ENVELOPE_SAMPLES) -> dict:
        """The driving quadrant at the output from 0 to the no-load speed: speed_rad_s and
        max_torque_Nm lists (report.json's motor.envelope)."""
        speed = np.linspace(0.0, self.no_load_speed_rad_s, samples)
        return {"speed_rad_s": speed.tolist(), "max_torque_Nm": self.torque_limit(speed).tolist()}

    def currents(self, torque_Nm, speed_rad_s) -> np.ndarray:
        """Motor current (A; LineMotor: a fraction of its stall current) for output torques at
        output speeds (arrays of one shape)."""
        torque = np.asarray(torque_Nm, dtype=float)
        speed = np.broadcast_to(np.asarray(speed_rad_s, dtype=float), torque.shape)
        return currents_array(self.law, _flat(torque), _flat(speed)).reshape(torque.shape)

    def speed_margins(self, torque_Nm, speed_rad_s) -> tuple[np.ndarray, np.ndarray]:
        """(speed margin, outside the envelope on its speed side) per operating point (arrays
        of one shape): speed_margins."""
        torque = np.asarray(torque_Nm, dtype=float)
        speed = np.broadcast_to(np.asarray(speed_rad_s, dtype=float), torque.shape)
        m, out = speed_margins(self.law, _flat(torque), _flat(speed))
        return m.reshape(torque.shape), out.reshape(torque.shape)

    def _check_fields(self) -> None:
        """The fields every actuator has, before the law is built from them."""
        check_number("motor.gear_ratio", self.gear_ratio, 0.0, MAX_GEAR_RATIO, low_open=True)
        check_number("motor.gear_efficiency", self.gear_efficiency, 0.0, 1.0, low_open=True)
        check_number("motor.rotor_inertia_kg_m2", self.rotor_inertia_kg_m2, 0.0,
                     MAX_ROTOR_INERTIA_KG_M2)
        check_number("motor.coulomb_friction_Nm", self.coulomb_friction_Nm, 0.0, MAX_TORQUE_NM)
        check_number("motor.viscous_friction_Nm_s", self.viscous_friction_Nm_s, 0.0,
                     MAX_TORQUE_NM)

    def _check_output(self) -> None:
        """The output side the law gives: within bounds, and able to turn against friction."""
        peak, no_load = self.peak_torque_Nm, self.no_load_speed_rad_s
        require(peak <= MAX_TORQUE_NM and no_load <= MAX_SPEED_RAD_S, "motor.gear_ratio",
                self.gear_ratio, f"gives {peak:g} N m and {no_load:g} rad/s at the output, "
                f"beyond {MAX_TORQUE_NM:g} N m or {MAX_SPEED_RAD_S:g} rad/s")
        at_speed = self.coulomb_friction_Nm + self.viscous_friction_Nm_s * no_load
        require(at_speed < peak, "motor.coulomb_friction_Nm", self.coulomb_friction_Nm,
                f"with viscous_friction_Nm_s the friction at the no-load speed is {at_speed:g} "
                f"N m, not below the peak output torque {peak:g} N m: the motor could not turn")


@dataclass(frozen=True)
class BldcMotor(Motor):
    """A brushless motor behind a gearbox, from motor-side data (module docstring): k_t
    (N*m/A, q-axis), phase resistance (ohm), bus voltage (V), peak current (A), optional
    continuous current (A), gear ratio and efficiency, rotor inertia (kg*m^2, motor side),
    output-side friction (N*m, N*m*s/rad), an optional torque-current table (motor side, A and
    N*m, from (0, 0), increasing, reaching the peak current) and an optional first-order thermal
    model of the winding (THERMAL_FIELDS: K/W, s, deg C; all or none)."""

    torque_constant_Nm_per_A: float
    winding_resistance_ohm: float
    bus_voltage_V: float
    peak_current_A: float
    gear_ratio: float
    gear_efficiency: float
    rotor_inertia_kg_m2: float
    coulomb_friction_Nm: float
    viscous_friction_Nm_s: float
    continuous_current_A: float | None = None
    current_table_A: tuple | None = None
    torque_table_Nm: tuple | None = None
    thermal_resistance_K_W: float | None = None
    thermal_time_constant_s: float | None = None
    winding_limit_C: float | None = None
    ambient_C: float | None = None
    model: str = "bldc"

    def __post_init__(self):
        require(self.model == "bldc", "motor.model", self.model, f"one of {list(MODELS)}")
        for name, high in (("torque_constant_Nm_per_A", MAX_TORQUE_CONSTANT_NM_A),
                           ("bus_voltage_V", MAX_BUS_VOLTAGE_V),
                           ("peak_current_A", MAX_CURRENT_A)):
            check_number(f"motor.{name}", getattr(self, name), 0.0, high, low_open=True)
        check_number("motor.winding_resistance_ohm", self.winding_resistance_ohm,
                     MIN_RESISTANCE_OHM, MAX_RESISTANCE_OHM)
        self._check_fields()
        self._check_table()
        object.__setattr__(self, "_law", ActuatorLaw(
            gear=float(self.gear_ratio), efficiency=float(self.gear_efficiency),
            kt=float(self.torque_constant_Nm_per_A), resistance=float(self.winding_resistance_ohm),
            phase_voltage=self.bus_voltage_V * PHASE_VOLTAGE_OF_BUS,
            back_emf=self.torque_constant_Nm_per_A / DQ_POWER,
            peak_current=float(self.peak_current_A),
            table_current=np.array(self.current_table_A or (), dtype=float),
            table_torque=np.array(self.torque_table_Nm or (), dtype=float),
            coulomb=float(self.coulomb_friction_Nm), viscous=float(self.viscous_friction_Nm_s)))
        self._check_output()
        stall = self._law.phase_voltage / self.winding_resistance_ohm
        require(stall >= self.peak_current_A, "motor.peak_current_A", self.peak_current_A,
                f"the bus drives at most V_bus / sqrt(3) / R = {stall:.4g} A through the "
                "standing winding: the peak current is never reached (lower it, or check "
                "bus_voltage_V and winding_resistance_ohm)")
        if self.continuous_current_A is not None:
            check_number("motor.continuous_current_A", self.continuous_current_A, 0.0,
                         self.peak_current_A, low_open=True, why="at most peak_current_A")
        given = [name for name in THERMAL_FIELDS if getattr(self, name) is not None]
        require(len(given) in (0, len(THERMAL_FIELDS)), "motor", given,
                f"the thermal model needs all of {list(THERMAL_FIELDS)} or none")
        if self.has_thermal_model:
            for name, high in (("thermal_resistance_K_W", MAX_THERMAL_RESISTANCE_K_W),
                               ("thermal_time_constant_s", MAX_THERMAL_TIME_CONSTANT_S)):
                check_number(f"motor.{name}", getattr(self, name), 0.0, high, low_open=True)
            check_number("motor.ambient_C", self.ambient_C, MIN_AMBIENT_C, MAX_AMBIENT_C)
            check_number("motor.winding_limit_C", self.winding_limit_C, self.ambient_C,
                         MAX_WINDING_LIMIT_C, low_open=True, why="above motor.ambient_C")

    def _check_table(self) -> None:
        i, tau = self.current_table_A, self.torque_table_Nm
        require((i is None) == (tau is None), "motor.torque_table_Nm", tau,
                "give current_table_A and torque_table_Nm together, or neither")
        if i is None:
            return
        for name, values in (("current_table_A", i), ("torque_table_Nm", tau)):
            require(isinstance(values, tuple) and 2 <= len(values) <= MAX_TABLE_POINTS,
                    f"motor.{name}", values, f"a list of 2 .. {MAX_TABLE_POINTS} numbers")
            for k, v in enumerate(values):
                check_number(f"motor.{name}[{k}]", v, 0.0, MAX_CURRENT_A if name[0] == "c"
                             else MAX_TORQUE_NM)
            require(values[0] == 0.0 and all(b > a for a, b in zip(values, values[1:])),
                    f"motor.{name}", list(values), "must start at 0 and increase strictly")
        require(len(i) == len(tau), "motor.torque_table_Nm", list(tau),
                f"one torque per current of current_table_A ({len(i)})")
        require(i[-1] >= self.peak_current_A, "motor.current_table_A", list(i),
                f"must reach peak_current_A = {self.peak_current_A:g}")

    @property
    def law(self) -> ActuatorLaw:
        return self._law

    @property
    def has_thermal_model(self) -> bool:
        return self.thermal_resistance_K_W is not None

    @property
    def thermal_continuous_current_A(self) -> float:
        """Current whose copper loss 1.5 R i^2 holds the winding at its limit in steady state."""
        return math.sqrt((self.winding_limit_C - self.ambient_C)
                         / (DQ_POWER * self.winding_resistance_ohm * self.thermal_resistance_K_W))

    @property
    def rated_continuous_current_A(self) -> float | None:
        """continuous_current_A if given, else the thermal model's (None without either)."""
        if self.continuous_current_A is not None:
            return self.continuous_current_A
        return self.thermal_continuous_current_A if self.has_thermal_model else None

    @property
    def continuous_torque_Nm(self) -> float | None:
        """Output torque (driving) at the continuous current (None without one)."""
        i = self.rated_continuous_current_A
        return None if i is None else self.gear_ratio * self.gear_efficiency * float(
            motor_torque(self.law, i))

    def copper_loss_W(self, current_A):
        """Copper loss (W) at current amplitudes (A): 1.5 R i^2."""
        return DQ_POWER * self.winding_resistance_ohm * np.square(current_A)

    def steady_winding_C(self, rms_current_A):
        """Winding temperature (deg C) reached at an RMS current (A) held for ever: ambient +
        copper loss x thermal resistance."""
        return self.ambient_C + self.copper_loss_W(rms_current_A) * self.thermal_resistance_K_W


@dataclass(frozen=True)
class LineMotor(Motor):
    """A plain torque-speed line (a file must ask for it: model = "torque_speed_line"): the
    motor-side stall torque (N*m) and no-load speed (rad/s) behind a gearbox; driving torque
    N eta tau_s (1 - N w / w_0), braking held at N tau_s / eta. No electrical or thermal
    model."""

    model: str
    motor_stall_torque_Nm: float
    motor_no_load_speed_rad_s: float
    gear_ratio: float
    rotor_inertia_kg_m2: float
    coulomb_friction_Nm: float
    viscous_friction_Nm_s: float
    gear_efficiency: float = 1.0

    def __post_init__(self):
        require(self.model == "torque_speed_line", "motor.model", self.model,
                f"one of {list(MODELS)}")
        check_number("motor.motor_stall_torque_Nm", self.motor_stall_torque_Nm, 0.0,
                     MAX_TORQUE_NM, low_open=True)
        check_number("motor.motor_no_load_speed_rad_s", self.motor_no_load_speed_rad_s, 0.0,
                     MAX_SPEED_RAD_S * MAX_GEAR_RATIO, low_open=True)
        self._check_fields()
        object.__setattr__(self, "_law", ActuatorLaw(
            gear=float(self.gear_ratio), efficiency=float(self.gear_efficiency),
            kt=float(self.motor_stall_torque_Nm), resistance=1.0, phase_voltage=1.0,
            back_emf=1.0 / self.motor_no_load_speed_rad_s, peak_current=1.0,
            table_current=np.zeros(0), table_torque=np.zeros(0),
            coulomb=float(self.coulomb_friction_Nm), viscous=float(self.viscous_friction_Nm_s)))
        self._check_output()

    @property
    def law(self) -> ActuatorLaw:
        return self._law

    @property
    def continuous_torque_Nm(self) -> None:
        return None


OLD_LINE_KEYS = ("peak_torque_Nm", "no_load_speed_rad_s", "continuous_torque_Nm",
                 "torque_constant_Nm_A")


def build_motor(table, section: str = "motor") -> Motor:
    """The [motor] table of a parameter file as a BldcMotor (model = "bldc", the default) or a
    LineMotor (model = "torque_speed_line"); ParameterError naming the key otherwise."""
    require(isinstance(table, dict), f"[{section}]", table, "must be a table of keys")
    model = table.get("model", "bldc")
    require(model in MODELS, f"{section}.model", model, f"one of {list(MODELS)}")
    old = [key for key in OLD_LINE_KEYS if key in table]
    if old and model == "bldc":
        raise ParameterError(
            f"{section}.{old[0]}: [{section}] now describes the actuator from motor-side data "
            "(torque_constant_Nm_per_A, winding_resistance_ohm, bus_voltage_V, peak_current_A, "
            "gear_ratio, gear_efficiency, ...; see fivebar_drake/data/default.toml); for a plain "
            "torque-speed line write model = \"torque_speed_line\" with motor_stall_torque_Nm "
            "and motor_no_load_speed_rad_s at the motor shaft", f"{section}.{old[0]}")
    return build_section(BldcMotor if model == "bldc" else LineMotor, table, section)


def with_gear(motor: Motor, gear_ratio: float) -> Motor:
    """The same motor behind another gearbox ratio (motor-side data kept)."""
    return dataclasses.replace(motor, gear_ratio=float(gear_ratio))


@jit
def motor_step(law, command, speed, out):
    """One sample of the motor model: out = (command, delivered, applied) (3 n) from the
    commanded torques and the joint speeds (n, output side): the command clamped to the
    envelope at the speed (torque_limits), less the friction tau_c clamp(w / w_s, -1, 1) + b w."""
    n = command.size
    for k in range(n):
        up, lo = torque_limits(law, speed[k])
        delivered = min(max(command[k], lo), up)
        slip = min(max(speed[k] / FRICTION_SMOOTHING_RAD_S, -1.0), 1.0)
        out[k], out[n + k] = command[k], delivered
        out[2 * n + k] = delivered - law.coulomb * slip - law.viscous * speed[k]


class MotorModel(LeafSystem):
    """Commanded torque and joint speed -> torque at the joints, one actuator per joint, values
    at the gearbox output, SI.

    Input ports: "torque_command" (n) N*m, "plant_state" (nx). Every period_s the law
    (motor_step, compiled) is evaluated on the command and the joint speeds and its results are
    held until the next sample (zero-order hold): the delivered torque is the command clamped
    to the actuator's envelope at the joint speed (Motor.limits: current and voltage limits
    through the gearbox), friction (Coulomb, regularised over |w| < FRICTION_SMOOTHING_RAD_S,
    and viscous) opposes the motion. Output ports: "applied_torque" (n) N*m at the joints
    (delivered - friction); "motor_record" (3 n): the sampled command, the delivered torque and
    the applied torque (N*m) (clip_flags classifies the clipping). The rotor's reflected
    inertia N^2 J_rotor is in the plant (<drake:rotor_inertia>, <drake:gear_ratio>), not here."""

    def __init__(self, motor: Motor, v_index_in_state, nx: int, period_s: float):
        super().__init__()
        self._law = motor.law
        self._v_index = np.asarray(v_index_in_state, dtype=np.int64)
        n = self._v_index.size
        self._command = self.DeclareVectorInputPort("torque_command", n)
        self._state = self.DeclareVectorInputPort("plant_state", nx)
        self._record = self.DeclareDiscreteState(3 * n)
        self._applied = self.DeclareDiscreteState(n)
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareStateOutputPort("applied_torque", self._applied)
        self.DeclareStateOutputPort("motor_record", self._record)
        self._out = np.zeros(3 * n)

    def _update(self, context, discrete_state):
        motor_step(self._law, self._command.Eval(context),
                   self._state.Eval(context)[self._v_index], self._out)
        discrete_state.set_value(self._record, self._out)
        discrete_state.set_value(self._applied, self._out[2 * self._v_index.size:])


def clip_flags(motor: Motor, command, delivered) -> tuple[np.ndarray, np.ndarray]:
    """Where the motor clipped the command (arrays of one shape, N*m): (by the peak current,
    by the voltage: the envelope's speed side), boolean. The current limit binds where the
    command exceeds the driving peak torque and the delivered torque sits at it or beyond
    (braking holds more); otherwise a clipped command met the speed side of the envelope."""
    command, delivered = np.asarray(command, dtype=float), np.asarray(delivered, dtype=float)
    clipped = delivered != command
    peak = motor.peak_torque_Nm
    at_peak = clipped & (np.abs(command) > peak) & (np.abs(delivered)
                                                    >= peak * (1.0 - PEAK_TOLERANCE))
    return at_peak, clipped & ~at_peak
