"""First-order winding temperature of a geared motor held at a gait's RMS torque (Minitaur's
"thermal cost of force"): the copper loss P = (tau_rms / (N k_t))^2 R heats the winding towards
T_ambient + P R_th with the time constant tau_th,
T(t) = T_ambient + P R_th (1 - exp(-t / tau_th)),
which reaches the limit T_limit at t = -tau_th ln(1 - (T_limit - T_ambient) / (P R_th)) if
P R_th > T_limit - T_ambient, never otherwise. The cycle-average loss is exact for I^2 R
(mean of tau^2 = tau_rms^2); the ripple within a cycle is a fraction ~ period / (2 pi tau_th) of
the rise and is left out."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.motor import Motor


@dataclass(frozen=True)
class Thermal:
    """Per RMS torque (arrays of its shape): copper loss (W), steady-state winding temperature
    (deg C), margin to the limit at steady state (K, negative beyond it) and the time from
    ambient to the limit (s, inf if never)."""

    loss_W: np.ndarray
    steady_C: np.ndarray
    margin_K: np.ndarray
    time_to_limit_s: np.ndarray


def thermal_margin(motor: Motor, rms_torque_Nm) -> Thermal:
    """The motor's winding at output RMS torques rms_torque_Nm (N*m, a number or an array),
    starting at ambient (module docstring)."""
    rms = np.asarray(rms_torque_Nm, dtype=float)
    current = rms / (motor.gear_ratio * motor.torque_constant_Nm_A)
    loss = current**2 * motor.winding_resistance_ohm
    rise = loss * motor.thermal_resistance_K_W
    allowed = motor.winding_limit_C - motor.ambient_C
    with np.errstate(divide="ignore"):
        fraction = np.where(rise > allowed, allowed / np.where(rise > 0, rise, 1.0), 1.0)
        time = np.where(rise > allowed, -motor.thermal_time_constant_s * np.log1p(-fraction),
                        np.inf)
    return Thermal(loss_W=loss, steady_C=motor.ambient_C + rise, margin_K=allowed - rise,
                   time_to_limit_s=time)


def winding_temperature(motor: Motor, rms_torque_Nm, t_s) -> np.ndarray:
    """Winding temperature (deg C) at times t_s (s) after starting at ambient, for each RMS
    torque: shape rms.shape + t.shape."""
    steady = thermal_margin(motor, rms_torque_Nm).steady_C
    rise = np.asarray(steady)[..., None] - motor.ambient_C
    return motor.ambient_C + rise * -np.expm1(-np.asarray(t_s, dtype=float)
                                             / motor.thermal_time_constant_s)
