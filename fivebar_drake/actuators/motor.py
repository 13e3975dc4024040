"""The geared actuator: its parameters (a BLDC motor from motor-side data, BldcMotor, or a plain
torque-speed line, LineMotor), the output envelope derived from them in one place (the compiled
law ActuatorLaw / torque_limits), the motor model's step (motor_step; the Drake block is
simulation/motor_model.MotorModel) and the classification of clipped commands.

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
- Beyond the no-load speed the back-EMF exceeds V_bus / sqrt(3): at least
  ((k_t / 1.5) w_m - V_bus / sqrt(3)) / R flows against the motion, so both bounds brake and the
  motor cannot coast; beyond the speed where that current reaches the peak current the drive
  cannot hold its limit and both bounds are that current (current_limits, torque_limits).
- Each operating point is judged in its own quadrant (quadrant_peak, quadrant_loads): driving
  (torque and speed of one sign, or standing) against N eta tau_m(I_peak), braking against
  N tau_m(I_peak) / eta.
- Copper loss 1.5 R i^2 (three phases of amplitude i).
Changing gear_ratio keeps the motor-side data: output torque x N eta, speed / N, reflected
rotor inertia x N^2, everywhere.

LineMotor is the same law with a normalised "current" (stall current 1, peak current 1): the
motoring torque falls on a straight line from the stall torque to the no-load speed and goes on
into braking beyond it (as a DC motor's), braking is held at the stall torque below it. It has no
electrical or thermal model.

The Drake block (simulation/motor_model.MotorModel) applies the law at every plant step at the
joint's mean speed over the step (held_torque, motor_step: the block's docstring says why and
how).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.parameter_files import build_section
from fivebar_drake.core.validation import (MAX_GEAR_RATIO, MAX_ROTOR_INERTIA_KG_M2,
                                           MAX_SPEED_RAD_S, MAX_TORQUE_NM, ParameterError,
                                           check_number, require)


# Bounds, as loose as the others (validation.py): they catch a slip (milliohms as ohms, minutes
# as seconds, Kelvin as Celsius), not a design.
MAX_TORQUE_CONSTANT_NM_A = 10.0     # motor side; a large servo is ~1 N m/A
MIN_TORQUE_CONSTANT_NM_A = 1e-4     # the smallest hobby outrunners are ~2e-3 N m/A
MAX_RESISTANCE_OHM = 1000.0         # a small hobby motor's winding is ~10 ohm
MIN_RESISTANCE_OHM = 1e-4           # a large QDD motor's phase is ~0.02 ohm
MAX_BUS_VOLTAGE_V = 1000.0          # legged robots run 12-100 V
MIN_BUS_VOLTAGE_V = 1.0             # no motor drive runs on less (a single Li-ion cell: 3.7 V)
MAX_CURRENT_A = 10_000.0            # the largest QDD drives take ~100 A
MIN_CURRENT_A = 1e-3                # a milliamp turns no leg (the smallest drives give ~1 A)
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
FORCED_SPEED_FACTOR = 2.0         # max_applied_torque_Nm: the forced braking up to this x no-load


class ActuatorLaw(NamedTuple):
    """The actuator as plain numbers for the compiled law (SI). Motor side: kt (N*m per unit
    current), resistance (ohm), phase_voltage (V, the largest phase amplitude), back_emf
    (V*s/rad), peak_current; table_current / table_torque (the torque-current curve; empty:
    kt i), rotor_inertia (kg*m^2). Output side: gear (N), efficiency (eta), coulomb (N*m),
    viscous (N*m*s/rad)."""

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
    rotor_inertia: float


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
def current_limits(law, speed):
    """(highest, lowest) signed q-axis current (A; LineMotor: a fraction of its stall current)
    the drive can hold at output speed `speed` (rad/s). The voltage equation with the inductance
    neglected and no d-axis current (which would only use voltage): v_q = R i + e, back-EMF
    e = back_emf N w, |v_q| <= phase_voltage; and |i| <= peak_current wherever the voltage
    allows it. Beyond the no-load speed (e > phase_voltage) both currents brake: the back-EMF
    drives at least (e - phase_voltage) / R against the motion (regeneration), so the motor cannot
    coast; beyond (phase_voltage + R peak_current) / (back_emf N) that least current exceeds the
    peak current, which the drive then cannot hold: both limits are that current."""
    e = law.back_emf * law.gear * speed
    hi = min((law.phase_voltage - e) / law.resistance, law.peak_current)
    lo = max((-law.phase_voltage - e) / law.resistance, -law.peak_current)
    if hi < lo:
        if speed > 0.0:
            lo = hi
        else:
            hi = lo
    return hi, lo


@jit
def output_torque(law, current, speed):
    """Output torque (N*m) of a signed current at output speed `speed` (rad/s): N tau_m(|i|)
    with the current's sign, through the gearbox: x eta driving (torque and speed of one sign, or
    standing), / eta braking (the gearbox's losses help the motor hold the load)."""
    tau = law.gear * motor_torque(law, abs(current))
    if current < 0.0:
        tau = -tau
    return tau * law.efficiency if tau * speed >= 0.0 else tau / law.efficiency


@jit
def torque_limits(law, speed):
    """(upper, lower) output torque (N*m) the actuator can deliver at output speed `speed`
    (rad/s): the currents of current_limits through the gearbox (output_torque). Below the
    no-load speed the interval holds 0 (driving up to the envelope, braking up to the peak
    current); beyond it both bounds brake (module docstring)."""
    hi, lo = current_limits(law, speed)
    return output_torque(law, hi, speed), output_torque(law, lo, speed)


@jit
def quadrant_peak(law, torque, speed):
    """The peak-current output torque (N*m, > 0) of the quadrant of an output torque at an
    output speed: driving (torque and speed of one sign, or standing) N eta tau_m(I_peak),
    braking N tau_m(I_peak) / eta."""
    peak = law.gear * motor_torque(law, law.peak_current)
    return peak * law.efficiency if torque * speed >= 0.0 else peak / law.efficiency


@jit
def quadrant_loads(law, torque, speed):
    """Per operating point (flat arrays of output torque N*m and speed rad/s): |torque| over the
    peak-current torque of its own quadrant (quadrant_peak: 1 is the peak current, driving or
    braking), and whether it brakes (torque against the motion)."""
    load, braking = np.empty(torque.size), np.zeros(torque.size, dtype=np.bool_)
    for k in range(torque.size):
        load[k] = abs(torque[k]) / quadrant_peak(law, torque[k], speed[k])
        braking[k] = torque[k] * speed[k] < 0.0
    return load, braking


@jit
def friction_torque(law, speed):
    """Output-side friction (N*m) opposing the motion at output speed `speed` (rad/s):
    Coulomb tau_c clamp(w / FRICTION_SMOOTHING_RAD_S, -1, 1) plus viscous b w."""
    slip = min(max(speed / FRICTION_SMOOTHING_RAD_S, -1.0), 1.0)
    return law.coulomb * slip + law.viscous * speed


@jit
def friction_array(law, speed):
    """friction_torque over a flat array of speeds."""
    out = np.empty(speed.size)
    for k in range(speed.size):
        out[k] = friction_torque(law, speed[k])
    return out


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
    """Per operating point (flat arrays of output torque N*m and speed rad/s) within the peak
    current of its quadrant: the ratio of the largest speed at which the envelope still gives
    that torque in that quadrant to |speed| (inf standing; nan beyond the peak current, which is
    the torque check's), and whether the point lies outside the envelope. Driving at current i
    the back-EMF may reach the phase voltage less R i: top = (V - R i) / (back_emf N); braking it
    may exceed it by R i at most (beyond, it forces more braking than asked):
    top = (V + R i) / (back_emf N)."""
    margin, outside = np.empty(torque.size), np.zeros(torque.size, dtype=np.bool_)
    for k in range(torque.size):
        t, w = torque[k], speed[k]
        cap = quadrant_peak(law, t, w)
        if abs(t) > cap * (1.0 + PEAK_TOLERANCE):
            margin[k] = np.nan
            continue
        up, lo = torque_limits(law, w)
        slack = cap * PEAK_TOLERANCE
        outside[k] = t > up + slack or t < lo - slack
        if w == 0.0:
            margin[k] = np.inf
            continue
        driving = t * w >= 0.0
        factor = law.efficiency if driving else 1.0 / law.efficiency
        i = motor_current(law, abs(t) / (law.gear * factor))
        volts = law.phase_voltage - law.resistance * i if driving else \
            law.phase_voltage + law.resistance * i
        margin[k] = volts / (law.back_emf * law.gear) / abs(w)
    return margin, outside


@jit
def torque_margins(law, torque, speed):
    """Per operating point (flat arrays, N*m and rad/s): the ratio of the torque the envelope
    gives at that speed in the direction of the torque to the torque (>= 1 inside), or, where
    the back-EMF forces braking on that side (beyond the no-load speed), the torque over that
    least braking when it is less (below 1: it brakes less than the voltage forces); 0 where the
    envelope gives nothing in that direction, inf for a zero torque inside the envelope. Below 1
    exactly where the point lies outside the envelope."""
    out = np.empty(torque.size)
    for k in range(torque.size):
        t = torque[k]
        up, lo = torque_limits(law, speed[k])
        if t > 0.0:
            m = up / t
            if lo > 0.0:
                m = min(m, t / lo)
        elif t < 0.0:
            m = lo / t
            if up < 0.0:
                m = min(m, t / up)
        else:
            m = np.inf if lo <= 0.0 <= up else 0.0
        out[k] = max(m, 0.0)
    return out


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
        """Bound on the torque the motor model puts on a joint (N*m; the plant's effort limit,
        which the MotorModel's output respects too): the applied torque braking at
        FORCED_SPEED_FACTOR times the no-load speed, where the back-EMF forces more braking than
        the peak current (torque_limits) and friction adds to it. A joint driven faster is a
        crash, not a motion: the plant clips its torque there, and the record says so."""
        w = FORCED_SPEED_FACTOR * self.no_load_speed_rad_s
        return float(-torque_limits(self.law, w)[0] + friction_torque(self.law, w))

    @property
    def forced_current_speed_rad_s(self) -> float:
        """Output speed (rad/s) beyond which the current the back-EMF forces (braking) exceeds
        the peak current: (V + R I_peak) / (back_emf N)."""
        law = self.law
        return ((law.phase_voltage + law.resistance * law.peak_current)
                / (law.back_emf * law.gear))

    def limits(self, speed_rad_s) -> tuple[np.ndarray, np.ndarray]:
        """(upper, lower) output torque (N*m) at output speeds (rad/s, any shape)."""
        speed = np.asarray(speed_rad_s, dtype=float)
        up, lo = limits_array(self.law, _flat(speed))
        return up.reshape(speed.shape), lo.reshape(speed.shape)

    def torque_limit(self, speed_rad_s) -> np.ndarray:
        """Largest driving torque (N*m) at output speeds |speed_rad_s| (rad/s) up to the no-load
        speed: the envelope's driving quadrant (negative beyond: the least braking the back-EMF
        forces there, with its sign)."""
        return self.limits(np.abs(np.asarray(speed_rad_s, dtype=float)))[0]

    def friction(self, speed_rad_s) -> np.ndarray:
        """Output-side friction (N*m) at output speeds (rad/s, any shape): friction_torque, the
        law the MotorModel applies (the torque the motor delivers = the joint's torque +
        friction)."""
        speed = np.asarray(speed_rad_s, dtype=float)
        return friction_array(self.law, _flat(speed)).reshape(speed.shape)

    def delivered_torque(self, joint_torque_Nm, speed_rad_s) -> np.ndarray:
        """The torque the motor must deliver (N*m) for joint torques at joint speeds (arrays of
        one shape): the joint's torque plus the friction it overcomes (friction), the
        MotorModel's law read backwards: the closed form's operating points."""
        return np.asarray(joint_torque_Nm, dtype=float) + self.friction(speed_rad_s)

    def quadrant_loads(self, torque_Nm, speed_rad_s) -> tuple[np.ndarray, np.ndarray]:
        """(|torque| over its quadrant's peak-current torque, braking) per operating point
        (arrays of one shape): quadrant_loads."""
        torque = np.asarray(torque_Nm, dtype=float)
        speed = np.broadcast_to(np.asarray(speed_rad_s, dtype=float), torque.shape)
        load, braking = quadrant_loads(self.law, _flat(torque), _flat(speed))
        return load.reshape(torque.shape), braking.reshape(torque.shape)

    def torque_margins(self, torque_Nm, speed_rad_s) -> np.ndarray:
        """The envelope's torque at each point's speed in the direction of its torque over that
        torque (arrays of one shape; below 1 exactly outside the envelope): torque_margins."""
        torque = np.asarray(torque_Nm, dtype=float)
        speed = np.broadcast_to(np.asarray(speed_rad_s, dtype=float), torque.shape)
        return torque_margins(self.law, _flat(torque), _flat(speed)).reshape(torque.shape)

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
                self.gear_ratio, f"gives {peak:g} N·m and {no_load:g} rad/s at the output, "
                f"beyond {MAX_TORQUE_NM:g} N·m or {MAX_SPEED_RAD_S:g} rad/s")
        at_speed = self.coulomb_friction_Nm + self.viscous_friction_Nm_s * no_load
        require(at_speed < peak, "motor.coulomb_friction_Nm", self.coulomb_friction_Nm,
                f"with viscous_friction_Nm_s the friction at the no-load speed is {at_speed:g} "
                f"N·m, not below the peak output torque {peak:g} N·m: the motor could not turn")


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
        require(self.model == "bldc", "motor.model", self.model,
                f"one of {list(MODELS)}" if self.model not in MODELS else
                f"this [motor] gives a bldc motor's fields; a {self.model} motor is described "
                "by other ones (fivebar_drake/data/default.toml's notes): write its [motor] "
                "section in a parameter file (--config) rather than change the model alone")
        for name, low, high in (
                ("torque_constant_Nm_per_A", MIN_TORQUE_CONSTANT_NM_A, MAX_TORQUE_CONSTANT_NM_A),
                ("bus_voltage_V", MIN_BUS_VOLTAGE_V, MAX_BUS_VOLTAGE_V),
                ("peak_current_A", MIN_CURRENT_A, MAX_CURRENT_A)):
            check_number(f"motor.{name}", getattr(self, name), low, high)
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
            coulomb=float(self.coulomb_friction_Nm), viscous=float(self.viscous_friction_Nm_s),
            rotor_inertia=float(self.rotor_inertia_kg_m2)))
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
        """The one continuous rating: continuous_current_A if given, else the thermal model's;
        never above the thermal model's (a winding held beyond its limit is never rated
        continuous); None without either."""
        thermal = self.thermal_continuous_current_A if self.has_thermal_model else None
        if self.continuous_current_A is None:
            return thermal
        return self.continuous_current_A if thermal is None else min(self.continuous_current_A,
                                                                     thermal)

    @property
    def continuous_torque_Nm(self) -> float | None:
        """Output torque (driving) at the continuous current (None without one)."""
        i = self.rated_continuous_current_A
        return None if i is None else self.gear_ratio * self.gear_efficiency * float(
            motor_torque(self.law, i))

    def copper_loss_W(self, current_A):
        """Copper loss (W) at current amplitudes (A): 1.5 R i^2."""
        return DQ_POWER * self.winding_resistance_ohm * np.square(current_A)

    def electrical_power_W(self, torque_Nm, speed_rad_s) -> np.ndarray:
        """Electrical power (W; negative: regenerated) the drive draws for output torques at
        output speeds (arrays of one shape): the copper loss 1.5 R i^2 and the back-EMF's
        k_t N w i, the current signed as the torque (the voltage law of current_limits)."""
        torque = np.asarray(torque_Nm, dtype=float)
        current = self.currents(torque, speed_rad_s) * np.sign(torque)
        return self.copper_loss_W(current) + (self.torque_constant_Nm_per_A * self.gear_ratio
                                              * np.asarray(speed_rad_s) * current)

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
            coulomb=float(self.coulomb_friction_Nm), viscous=float(self.viscous_friction_Nm_s),
            rotor_inertia=float(self.rotor_inertia_kg_m2)))
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


RESPONSE_FLOOR = 0.01   # a change of the applied torque below this share of the driving peak
#                         measures no joint response (MotorModel: the response is kept)
BISECTIONS = 60         # at most this many steps of the held torque's solve (held_torque)
SOLVE_TOLERANCE = 1e-10  # N*m: the held torque's solve stops within this
MEMORY = 7              # per joint: speed, applied torque, the one before, acceleration, the
#                         acceleration not due to the motor, response, predicted speed (motor_step)
TRUST = (0.5, 0.01)     # a step's prediction holds if it missed the speed reached by at most
#                         this share of the speed's change plus this share of the no-load speed


@jit
def _delivered(law, command, speed):
    """The command clamped to the envelope at output speed `speed` (torque_limits)."""
    up, lo = torque_limits(law, speed)
    return min(max(command, lo), up)


@jit
def step_mean(law, command, start, end):
    """(delivered, applied) torque (N*m) averaged over a step whose joint speed goes evenly from
    `start` to `end` (rad/s): the command clamped to the envelope, less the friction, at the
    step's mean speed; where the speed passes 0 within the step (the joint stops and turns),
    each part at its own mean speed, weighted by its time (the envelope and the Coulomb friction
    change quadrant at standstill)."""
    if start * end < 0.0:
        before = start / (start - end)
        d0, d1 = _delivered(law, command, 0.5 * start), _delivered(law, command, 0.5 * end)
        f0, f1 = friction_torque(law, 0.5 * start), friction_torque(law, 0.5 * end)
        delivered = command if d0 == command and d1 == command else \
            before * d0 + (1.0 - before) * d1
        return delivered, delivered - (before * f0 + (1.0 - before) * f1)
    mean = 0.5 * (start + end)
    delivered = _delivered(law, command, mean)
    return delivered, delivered - friction_torque(law, mean)


@jit
def held_torque(law, command, speed, drift, rate, cap):
    """(delivered, applied) torque (N*m) of one plant step: the torque held over the step, for
    a joint at speed `speed` (rad/s) at its start whose speed changes over the step by
    drift + rate * the applied torque (rad/s; rate in rad/s per N*m, 0: the motor's torque is
    not felt within the step). The applied torque u solves u = step_mean(speed, speed + drift +
    rate u): the instantaneous law (the inductance neglected) averaged over a step whose speed
    changes evenly. The right side falls as u grows (the envelope falls as the speed rises, the
    friction rises), so the solution is unique: found in a bracket grown from the torque at the
    start by regula falsi (Illinois), to SOLVE_TOLERANCE. The applied torque is clipped to +-cap
    (the plant's effort limit, Motor.max_applied_torque_Nm)."""
    base = speed + drift
    delivered, u = step_mean(law, command, speed, base)
    if rate > 0.0:
        # g(x) = the step's applied torque for torque x, minus x: decreasing, root wanted
        a, b = -abs(u) - SOLVE_TOLERANCE, abs(u) + SOLVE_TOLERANCE
        ga = step_mean(law, command, speed, base + rate * a)[1] - a
        for _ in range(BISECTIONS):
            if ga >= 0.0:
                break
            a *= 2.0
            ga = step_mean(law, command, speed, base + rate * a)[1] - a
        gb = step_mean(law, command, speed, base + rate * b)[1] - b
        for _ in range(BISECTIONS):
            if gb <= 0.0:
                break
            b *= 2.0
            gb = step_mean(law, command, speed, base + rate * b)[1] - b
        side = 0
        u = 0.5 * (a + b)
        for _ in range(BISECTIONS):
            if b - a <= SOLVE_TOLERANCE or ga == gb:
                break
            u = (a * gb - b * ga) / (gb - ga)
            if not a < u < b:
                u = 0.5 * (a + b)
            gu = step_mean(law, command, speed, base + rate * u)[1] - u
            if abs(gu) <= SOLVE_TOLERANCE:
                break
            if gu > 0.0:
                a, ga = u, gu
                if side == 1:
                    gb *= 0.5
                side = 1
            else:
                b, gb = u, gu
                if side == -1:
                    ga *= 0.5
                side = -1
        delivered, u = step_mean(law, command, speed, base + rate * u)
    return delivered, min(max(u, -cap), cap)


@jit
def motor_step(law, command, speed, memory, time, cap, out, remembered):
    """The motor model over the plant step starting at time `time` (s): out = (command,
    delivered, applied) (3 n, N*m) from the held commands and the joint speeds (n, output side)
    at the step's start (held_torque), and `remembered` (MEMORY n + 1) what the next step needs.
    memory (MEMORY n + 1), per joint from the step before (started at memory[-1] s, nan: none
    yet): its start speed, its applied torque and the one before, the acceleration over the step
    before it (nan: none), the part of that acceleration the motor's torque did not cause, and
    the joint's response (rad/s^2 per N*m, 0: unknown).
    The response is measured as the change of acceleration over the change of the applied
    torque between two steps (an unchanged load cancels), when that torque changed by at least
    RESPONSE_FLOOR of the driving peak, both changed one way and the ratio is at most
    1 / (N^2 J_rotor) (a joint is never lighter than its rotor: a larger change came from the
    load, e.g. a foot's impact, and measures nothing); the first one, while none is known, as
    acceleration over torque. The acceleration the motor did not cause (the load: gravity, the
    other joints, the ground) is carried into the next step when it kept its sign over the last
    two (the smaller of the two): a steady push persists, an impact does not. A step whose
    speed, predicted with a measured response, missed the speed reached by more than TRUST (a
    foot touching down makes a leg heavy at once) is followed by one at the envelope at its start
    speed. The next step is taken as long as the one before; memory's last entry per joint is the
    speed predicted (nan: no response measured)."""
    n = command.size
    step = time - memory[MEMORY * n]
    no_load = law.phase_voltage / (law.back_emf * law.gear)
    floor = RESPONSE_FLOOR * law.gear * law.efficiency * motor_torque(law, law.peak_current)
    ceiling = np.inf
    if law.rotor_inertia > 0.0:
        ceiling = 1.0 / (law.gear * law.gear * law.rotor_inertia)
    for k in range(n):
        j = MEMORY * k
        start, applied, before = memory[j], memory[j + 1], memory[j + 2]
        accel, load, response = memory[j + 3], memory[j + 4], memory[j + 5]
        predicted = memory[j + 6]
        now, pushed, drift = np.nan, 0.0, 0.0
        # a prediction made with a measured response that missed: the load changed at once
        missed = abs(speed[k] - predicted) > TRUST[0] * abs(speed[k] - start) + TRUST[1] * no_load
        if step > 0.0:
            now = (speed[k] - start) / step
            change = applied - before
            if accel == accel and abs(change) >= floor and 0.0 < (now - accel) / change \
                    <= ceiling:
                response = (now - accel) / change
            elif response == 0.0 and abs(applied) >= floor and 0.0 < now / applied <= ceiling:
                response = now / applied
            pushed = now - response * applied
            if pushed * load > 0.0:
                drift = step * (pushed if abs(pushed) < abs(load) else load)
        rate = step * response if step > 0.0 else 0.0
        out[k] = command[k]
        if missed:
            out[n + k], out[2 * n + k] = held_torque(law, command[k], speed[k], 0.0, 0.0, cap)
        else:
            out[n + k], out[2 * n + k] = held_torque(law, command[k], speed[k], drift, rate, cap)
        remembered[j], remembered[j + 1], remembered[j + 2] = speed[k], out[2 * n + k], applied
        remembered[j + 3], remembered[j + 4], remembered[j + 5] = now, pushed, response
        remembered[j + 6] = speed[k] + drift + rate * out[2 * n + k] if rate > 0.0 else np.nan
    remembered[MEMORY * n] = time


def clip_flags(motor: Motor, command, delivered, speed=None) -> tuple[np.ndarray, np.ndarray]:
    """Where the motor clipped the command (arrays of one shape, N*m): (by the peak current,
    by the voltage), boolean. With the joint speeds (rad/s) the current limit binds where the
    delivered torque draws the peak current in its own quadrant (Motor.currents), and the voltage
    where it draws less (the envelope's speed side) or more (the back-EMF forcing the braking
    current beyond the peak); without them, where the command and the delivered torque reach
    the driving peak torque (the braking peak is larger, and braking is never voltage-limited
    below the no-load speed)."""
    command, delivered = np.asarray(command, dtype=float), np.asarray(delivered, dtype=float)
    clipped = delivered != command
    if speed is None:
        peak = motor.peak_torque_Nm
        at_peak = clipped & (np.abs(command) > peak) & (np.abs(delivered)
                                                        >= peak * (1.0 - PEAK_TOLERANCE))
    else:
        peak = motor.law.peak_current
        current = motor.currents(delivered, np.broadcast_to(speed, delivered.shape))
        at_peak = clipped & (np.abs(current - peak) <= 1e-9 * peak)
    return at_peak, clipped & ~at_peak
