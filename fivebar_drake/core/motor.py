"""The geared motor: its parameters and torque-speed line (Motor), the Drake motor model built from
C++ primitives (MotorModel) and the classification of clipped commands."""

from __future__ import annotations

from dataclasses import dataclass
import math
import numpy as np
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.primitives import (AffineSystem, Demultiplexer, Gain, MatrixGain, Multiplexer,
                                        Saturation, ZeroOrderHold)

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.validation import (MAX_GEAR_RATIO, MAX_ROTOR_INERTIA_KG_M2,
                                           MAX_SPEED_RAD_S, MAX_TORQUE_NM, check_number, require)


# Bounds of the thermal parameters, as loose as the others (validation.py): they catch a slip
# (milliohms as ohms, minutes as seconds, Kelvin as Celsius), not a design.
MAX_TORQUE_CONSTANT_NM_A = 10.0     # motor side; a large servo is ~1 N m/A
MAX_RESISTANCE_OHM = 1000.0         # a small hobby motor's winding is ~10 ohm
MAX_THERMAL_RESISTANCE_K_W = 1000.0  # a bare 20 mm motor is ~20 K/W
MAX_THERMAL_TIME_CONSTANT_S = 1e5   # a large motor's housing: about an hour
MIN_AMBIENT_C, MAX_AMBIENT_C = -60.0, 100.0
MAX_WINDING_LIMIT_C = 300.0         # above the class C insulation rating (220 C)


@jit
def torque_speed_line(peak_Nm, no_load_rad_s, speed_rad_s):
    """Largest motoring torque (N*m) at a joint speed (rad/s, a number or an array): the linear
    torque-speed line peak (1 - |w| / w_0), zero beyond the no-load speed w_0."""
    return peak_Nm * np.minimum(np.maximum(1.0 - np.abs(speed_rad_s) / no_load_rad_s, 0.0), 1.0)


THERMAL_FIELDS = ("continuous_torque_Nm", "torque_constant_Nm_A", "winding_resistance_ohm",
                  "thermal_resistance_K_W", "thermal_time_constant_s", "winding_limit_C",
                  "ambient_C")


@dataclass(frozen=True)
class Motor:
    """Geared hip motor. Torque (N*m), speed (rad/s) and the continuous torque rating at the
    gearbox output; rotor inertia (kg*m^2) and torque constant (N*m/A) on the motor side; the
    winding: resistance (ohm), thermal resistance (K/W) and time constant (s) to ambient,
    temperature limit and ambient (deg C). The thermal fields (THERMAL_FIELDS) are given all
    together or not at all (None: a motor without a thermal model, e.g. a drive of another
    mechanism)."""

    peak_torque_Nm: float
    gear_ratio: float
    no_load_speed_rad_s: float
    rotor_inertia_kg_m2: float
    coulomb_friction_Nm: float
    viscous_friction_Nm_s: float
    continuous_torque_Nm: float | None = None
    torque_constant_Nm_A: float | None = None
    winding_resistance_ohm: float | None = None
    thermal_resistance_K_W: float | None = None
    thermal_time_constant_s: float | None = None
    winding_limit_C: float | None = None
    ambient_C: float | None = None

    def __post_init__(self):
        for name, high in (("peak_torque_Nm", MAX_TORQUE_NM), ("gear_ratio", MAX_GEAR_RATIO),
                           ("no_load_speed_rad_s", MAX_SPEED_RAD_S)):
            check_number(f"motor.{name}", getattr(self, name), 0.0, high, low_open=True)
        check_number("motor.rotor_inertia_kg_m2", self.rotor_inertia_kg_m2, 0.0,
                     MAX_ROTOR_INERTIA_KG_M2)
        check_number("motor.coulomb_friction_Nm", self.coulomb_friction_Nm, 0.0, MAX_TORQUE_NM)
        check_number("motor.viscous_friction_Nm_s", self.viscous_friction_Nm_s, 0.0, MAX_TORQUE_NM)
        at_speed = self.coulomb_friction_Nm + self.viscous_friction_Nm_s * self.no_load_speed_rad_s
        require(at_speed < self.peak_torque_Nm, "motor.coulomb_friction_Nm",
                self.coulomb_friction_Nm, f"with viscous_friction_Nm_s the friction at the no-load "
                f"speed is {at_speed:g} N m, not below peak_torque_Nm = {self.peak_torque_Nm:g}: "
                "the motor could not turn")
        given = [name for name in THERMAL_FIELDS if getattr(self, name) is not None]
        require(len(given) in (0, len(THERMAL_FIELDS)), "motor", given,
                f"the thermal model needs all of {list(THERMAL_FIELDS)} or none")
        if self.has_thermal_model:
            self._check_thermal()

    @property
    def has_thermal_model(self) -> bool:
        return self.continuous_torque_Nm is not None

    def _check_thermal(self) -> None:
        check_number("motor.continuous_torque_Nm", self.continuous_torque_Nm, 0.0,
                     self.peak_torque_Nm, low_open=True, why="at most peak_torque_Nm")
        for name, high in (("torque_constant_Nm_A", MAX_TORQUE_CONSTANT_NM_A),
                           ("winding_resistance_ohm", MAX_RESISTANCE_OHM),
                           ("thermal_resistance_K_W", MAX_THERMAL_RESISTANCE_K_W),
                           ("thermal_time_constant_s", MAX_THERMAL_TIME_CONSTANT_S)):
            check_number(f"motor.{name}", getattr(self, name), 0.0, high, low_open=True)
        check_number("motor.ambient_C", self.ambient_C, MIN_AMBIENT_C, MAX_AMBIENT_C)
        check_number("motor.winding_limit_C", self.winding_limit_C, self.ambient_C,
                     MAX_WINDING_LIMIT_C, low_open=True, why="above motor.ambient_C")

    def torque_limit(self, speed_rad_s):
        """Largest motoring torque (N*m) at joint speeds (rad/s, array): torque_speed_line."""
        return torque_speed_line(self.peak_torque_Nm, self.no_load_speed_rad_s,
                                 np.asarray(speed_rad_s, dtype=float))

    @property
    def reflected_inertia_kg_m2(self) -> float:
        """Rotor inertia seen at the output, N^2 J_rotor."""
        return self.gear_ratio**2 * self.rotor_inertia_kg_m2

    @property
    def thermal_continuous_torque_Nm(self) -> float:
        """Output torque whose copper loss (tau / (N k_t))^2 R holds the winding at its limit in
        steady state: N k_t sqrt((T_limit - T_ambient) / (R R_th))."""
        return self.gear_ratio * self.torque_constant_Nm_A * math.sqrt(
            (self.winding_limit_C - self.ambient_C)
            / (self.winding_resistance_ohm * self.thermal_resistance_K_W))

FRICTION_SMOOTHING_RAD_S = 0.05   # Coulomb friction reaches its full value at this joint speed
PEAK_TOLERANCE = 1e-12            # relative: a delivered torque this close to the peak is at it


class MotorModel(Diagram):
    """Commanded torque and joint speed -> torque at the joints, built from Drake's C++
    primitives (no Python at run time). Values at the gearbox output, SI.

    Input ports: "torque_command" (n) N*m, "plant_state" (nx). Every period_s the law is
    evaluated on the command and the joint speeds and its results are held until the next
    sample (zero-order hold):
    - the delivered torque is the command clamped to [lower, upper]: motoring (torque and speed
      of the same sign) is limited by the torque-speed line, braking by the peak torque,
      upper = clamp(peak (1 - w / w_0), 0, peak), lower = clamp(-peak (1 + w / w_0), -peak, 0)
      (the line of Motor.torque_limit), as c - max(c - upper, 0) + max(lower - c, 0);
    - friction tau_c clamp(w / w_s, -1, 1) + b w (Coulomb, regularised over |w| < w_s =
      FRICTION_SMOOTHING_RAD_S, and viscous) opposes the motion.
    Output ports: "applied_torque" (n) N*m at the joints (delivered - friction); "motor_record"
    (3 n): the sampled command, the delivered torque and the applied torque (N*m), held between
    samples (clip_flags classifies the clipping). The rotor's reflected inertia N^2 J_rotor is
    in the plant (<drake:rotor_inertia>, <drake:gear_ratio>), not here."""

    def __init__(self, motor: Motor, v_index_in_state, nx: int, period_s: float):
        super().__init__()
        v_index = np.asarray(v_index_in_state)   # state index of each actuator's joint speed
        n, peak, slope = len(v_index), motor.peak_torque_Nm, (motor.peak_torque_Nm
                                                              / motor.no_load_speed_rad_s)
        eye, zero = np.eye(n), np.zeros((n, n))
        b = DiagramBuilder()
        select = np.zeros((n, nx))
        select[np.arange(n), v_index] = 1.0
        speed = b.AddNamedSystem("speed", MatrixGain(select))
        line = b.AddNamedSystem("line", AffineSystem(
            np.zeros((0, 0)), np.zeros((0, n)), np.zeros(0), np.zeros((2 * n, 0)),
            np.vstack([-slope * eye, -slope * eye]), np.r_[np.full(n, peak), np.full(n, -peak)]))
        limits = b.AddNamedSystem("limits", Saturation(np.r_[np.zeros(n), np.full(n, -peak)],
                                                       np.r_[np.full(n, peak), np.zeros(n)]))
        beyond = b.AddNamedSystem("beyond", Multiplexer([n, 2 * n]))        # c, upper, lower
        excess = b.AddNamedSystem("excess", MatrixGain(np.block([[eye, -eye, zero],
                                                                 [-eye, zero, eye]])))
        positive = b.AddNamedSystem("positive", Saturation(np.zeros(2 * n),
                                                           np.full(2 * n, np.inf)))
        slip = b.AddNamedSystem("slip", Gain(1.0 / FRICTION_SMOOTHING_RAD_S, n))
        unit = b.AddNamedSystem("unit", Saturation(-np.ones(n), np.ones(n)))
        terms = b.AddNamedSystem("terms", Multiplexer([n, 2 * n, n, n]))  # c, excess, unit, w
        delivered = np.hstack([eye, -eye, eye, zero, zero])
        friction = np.hstack([zero, zero, zero, motor.coulomb_friction_Nm * eye,
                              motor.viscous_friction_Nm_s * eye])
        law = b.AddNamedSystem("law", MatrixGain(np.vstack([delivered, delivered - friction])))
        record = b.AddNamedSystem("record", Multiplexer([n, 2 * n]))   # c, delivered, applied
        hold = b.AddNamedSystem("hold", ZeroOrderHold(period_s, 3 * n))
        split = b.AddNamedSystem("split", Demultiplexer([n, n, n]))
        b.ExportInput(beyond.get_input_port(0), "torque_command")
        for port in (terms.get_input_port(0), record.get_input_port(0)):
            b.ConnectInput("torque_command", port)
        b.ExportInput(speed.get_input_port(), "plant_state")
        b.Connect(speed.get_output_port(), line.get_input_port())
        b.Connect(line.get_output_port(), limits.get_input_port())
        b.Connect(limits.get_output_port(), beyond.get_input_port(1))
        b.Connect(beyond.get_output_port(), excess.get_input_port())
        b.Connect(excess.get_output_port(), positive.get_input_port())
        b.Connect(speed.get_output_port(), slip.get_input_port())
        b.Connect(slip.get_output_port(), unit.get_input_port())
        for i, source in enumerate((positive, unit, speed), start=1):
            b.Connect(source.get_output_port(), terms.get_input_port(i))
        b.Connect(terms.get_output_port(), law.get_input_port())
        b.Connect(law.get_output_port(), record.get_input_port(1))
        b.Connect(record.get_output_port(), hold.get_input_port())
        b.Connect(hold.get_output_port(), split.get_input_port())
        b.ExportOutput(split.get_output_port(2), "applied_torque")
        b.ExportOutput(hold.get_output_port(), "motor_record")
        b.BuildInto(self)


def clip_flags(motor: Motor, command, delivered) -> tuple[np.ndarray, np.ndarray]:
    """Where the motor clipped the command (arrays of one shape, N*m): (by the peak torque,
    by the torque-speed line), boolean. The peak binds where the command exceeds it and the
    delivered torque sits at it; otherwise a clipped command met the line."""
    command, delivered = np.asarray(command, dtype=float), np.asarray(delivered, dtype=float)
    clipped = delivered != command
    peak = motor.peak_torque_Nm
    at_peak = clipped & (np.abs(command) > peak) & (np.abs(delivered)
                                                    >= peak * (1.0 - PEAK_TOLERANCE))
    return at_peak, clipped & ~at_peak
