"""First-order winding temperature of a motor held at an RMS current (Minitaur's "thermal cost
of force"): the copper loss P = 1.5 R i_rms^2 (actuators/motor.py) heats the winding towards
T_ambient + P R_th with the time constant tau_th,
T(t) = T_ambient + P R_th (1 - exp(-t / tau_th)),
which reaches the limit T_limit at t = -tau_th ln(1 - (T_limit - T_ambient) / (P R_th)) if
P R_th > T_limit - T_ambient, never otherwise. The cycle-average loss is exact for i^2 R
(mean of i^2 = i_rms^2); the ripple within a cycle is a fraction ~ period / (2 pi tau_th) of
the rise and is left out. A loss that changes over time (a duty cycle of maneuvers) is
solved exactly for a loss held over each interval (winding_rise)."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.actuators.motor import BldcMotor


@dataclass(frozen=True)
class Thermal:
    """Per RMS current (arrays of its shape): copper loss (W), steady-state winding temperature
    (deg C), margin to the limit at steady state (K, negative beyond it) and the time from
    ambient to the limit (s, inf if never)."""

    loss_W: np.ndarray
    steady_C: np.ndarray
    margin_K: np.ndarray
    time_to_limit_s: np.ndarray


def rms_current(motor: BldcMotor, torque_Nm, speed_rad_s, axis=0) -> np.ndarray:
    """RMS motor current (A) of output torques at output speeds sampled evenly in time (arrays
    of one shape), over `axis` (Motor.currents: driving through the gearbox's losses)."""
    return np.sqrt(np.mean(np.square(motor.currents(torque_Nm, speed_rad_s)), axis=axis))


def thermal_margin(motor: BldcMotor, rms_current_A) -> Thermal:
    """The motor's winding at RMS currents rms_current_A (A, a number or an array), starting at
    ambient (module docstring)."""
    current = np.asarray(rms_current_A, dtype=float)
    loss, rise = motor.copper_loss_W(current), motor.steady_winding_C(current) - motor.ambient_C
    allowed = motor.winding_limit_C - motor.ambient_C
    with np.errstate(divide="ignore"):
        fraction = np.where(rise > allowed, allowed / np.where(rise > 0, rise, 1.0), 1.0)
        time = np.where(rise > allowed, -motor.thermal_time_constant_s * np.log1p(-fraction),
                        np.inf)
    return Thermal(loss_W=loss, steady_C=motor.ambient_C + rise, margin_K=allowed - rise,
                   time_to_limit_s=time)


def winding_temperature(motor: BldcMotor, rms_current_A, t_s) -> np.ndarray:
    """Winding temperature (deg C) at times t_s (s) after starting at ambient, for each RMS
    current: shape rms.shape + t.shape."""
    steady = thermal_margin(motor, rms_current_A).steady_C
    rise = np.asarray(steady)[..., None] - motor.ambient_C
    return motor.ambient_C + rise * -np.expm1(-np.asarray(t_s, dtype=float)
                                             / motor.thermal_time_constant_s)


def winding_rise(motor: BldcMotor, loss_W, dt_s, rise0_K=0.0) -> np.ndarray:
    """Winding temperature rise above ambient (K) at the end of each interval for copper losses
    loss_W (W, intervals along axis 0, any shape after it) each held over its interval dt_s
    (s, (intervals,)), from rise0_K: the first-order model solved exactly for a held loss,
    r_k = a_k r_(k-1) + (1 - a_k) R_th P_k with a_k = exp(-dt_k / tau_th)."""
    loss = np.asarray(loss_W, dtype=float)
    decay = np.exp(-np.asarray(dt_s, dtype=float) / motor.thermal_time_constant_s)
    out, rise = np.empty_like(loss), np.asarray(rise0_K, dtype=float)
    for k in range(loss.shape[0]):
        rise = decay[k] * rise + (1.0 - decay[k]) * motor.thermal_resistance_K_W * loss[k]
        out[k] = rise
    return out
