"""Drive sizing: the demand of a joint's torque (or force) and speed history (peak and RMS
torque, peak speed, peak power through an efficiency), the seed's motor-power rule, and the
ball-screw formulas of seed 002 section 2.3.2 (eq. 2.85-2.97). SI unless a name says otherwise."""

from __future__ import annotations

import math
import numpy as np

RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


def demand(t, torque, speed, efficiency: float) -> dict:
    """Per-joint demand of histories torque, speed (n, joints) sampled at times t (n,) s:
    peak |torque|, RMS torque (time-weighted, trapezoids), peak |speed|, peak output power
    max |torque * speed| (W) and the drive's input power at that efficiency (W)."""
    t, torque, speed = (np.asarray(v, dtype=float) for v in (t, torque, speed))
    power = np.abs(torque * speed)
    mean_sq = np.trapezoid(torque**2, t, axis=0) / (t[-1] - t[0])
    return {"peak": np.max(np.abs(torque), axis=0), "rms": np.sqrt(mean_sq),
            "peak_speed": np.max(np.abs(speed), axis=0), "peak_power_W": power.max(axis=0),
            "input_power_W": power.max(axis=0) / efficiency,
            "peak_time_s": t[np.argmax(np.abs(torque), axis=0)]}


def motor_power_kW(torque_Nm, speed_rpm, efficiency, constant=9550.0):
    """The seed's motor power W = tau n / (constant mu) in kW (eq. 2.82; 9550 ~ 60000/2pi)."""
    return torque_Nm * speed_rpm / (constant * efficiency)


def axial_force(mass_kg, acceleration_m_s2, gravity_m_s2):
    """Axial force (N) lifting a mass with an upward acceleration: m (a + g) (eq. 2.85)."""
    return mass_kg * (acceleration_m_s2 + gravity_m_s2)


def screw_torque(force_N, ball_circle_m, lead_angle_rad, friction_angle_rad):
    """Torque (N*m) at the nut for an axial force: Fa Dtb tan(gamma + phi) / 2 (eq. 2.86)."""
    return force_N * ball_circle_m * math.tan(lead_angle_rad + friction_angle_rad) / 2.0


def screw_force(torque_Nm, ball_circle_m, lead_angle_rad, friction_angle_rad):
    """Axial force (N) a nut torque drives: eq. 2.86 solved for Fa."""
    return 2.0 * torque_Nm / (ball_circle_m * math.tan(lead_angle_rad + friction_angle_rad))


def nut_speed_rpm(speed_m_s, starts, lead_m):
    """Nut speed (rpm) for a screw speed: 60 v / (Z p) (eq. 2.87)."""
    return 60.0 * speed_m_s / (starts * lead_m)


def core_diameter_min(force_N, allowable_stress_Pa):
    """Smallest thread core diameter (m) in tension with 1.3 for torsion (eq. 2.91)."""
    return math.sqrt(4 * 1.3 * force_N / (math.pi * allowable_stress_Pa))


def groove_offset(groove_radius_m, ball_diameter_m, contact_angle_rad):
    """Groove centre to ball centre c = (r1 - db/2) cos(beta) (m) (eq. 2.92)."""
    return (groove_radius_m - ball_diameter_m / 2) * math.cos(contact_angle_rad)


def ball_circle_diameter(core_m, groove_radius_m, offset_m):
    """Diameter through the ball centres Dtb = d1 + 2 (r1 - c) (m) (eq. 2.93)."""
    return core_m + 2 * (groove_radius_m - offset_m)


def lead_angle(lead_m, ball_circle_m):
    """gamma = atan(p / (pi Dtb)) (rad) (eq. 2.94)."""
    return math.atan(lead_m / (math.pi * ball_circle_m))


def ball_count(ball_circle_m, turns, ball_diameter_m):
    """Balls in the working turns pi Dtb K / db - 1 (eq. 2.95)."""
    return math.pi * ball_circle_m * turns / ball_diameter_m - 1


def friction_angle(rolling_friction_m, core_m, contact_angle_rad):
    """Equivalent rolling friction angle atan(2 f / (d1 sin beta)) (rad) (eq. 2.97)."""
    return math.atan(2 * rolling_friction_m / (core_m * math.sin(contact_angle_rad)))


def screw_efficiency(lead_angle_rad, friction_angle_rad):
    """Rotation to translation efficiency tan(gamma) / tan(gamma + phi)."""
    return math.tan(lead_angle_rad) / math.tan(lead_angle_rad + friction_angle_rad)
