"""Gear-ratio trade for one motor (Stanford Doggo's method): keep the motor (its motor-side data:
actuators/motor.with_gear) and change the gear ratio N. At the output the envelope's torque scales by
N (times the gearbox efficiency driving, over it braking), its speeds by 1 / N, and the rotor adds
N^2 J_r q'' to each joint's torque. The safety factor at N is the least ratio, over the cycle and
the motors, of the torque the envelope gives at the joint speed in the direction of the torque
the motor must deliver (the joint's torque, the rotor's and the output friction:
Motor.delivered_torque) to that torque (Motor.torque_margins: each sample in its own quadrant)."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np
from scipy.optimize import minimize_scalar

from fivebar_drake.actuators.motor import Motor, with_gear
from fivebar_drake.core.validation import ParameterError


RATIO_RANGE = (1.0, 100.0)   # gear ratios searched (a direct drive to a two-stage planetary)
GRID_POINTS = 200            # log-spaced ratios of the grid; the best one is then refined
# the readings of the safety factor shown side by side: (torque-speed line, reflected inertia)
EFFECTS = {"peak only": (False, False), "torque-speed line": (True, False),
           "reflected inertia": (False, True), "both": (True, True)}


def safety_factors(motor: Motor, load_Nm, qd, qdd, ratios, speed_line: bool = True,
                   rotor: bool = True) -> np.ndarray:
    """Safety factor (r, m) of each motor m at gear ratios (r,), for the joint torques load_Nm
    (n, m) N*m of the linkage at joint rates qd (rad/s) and accelerations qdd (rad/s^2), (n, m):
    the least over the samples of the envelope's torque at qd in the direction of the torque
    the motor delivers (load + N^2 J_r qdd if rotor, + friction) over it (Motor.torque_margins)
    if speed_line, else the peak-current torque of each sample's quadrant over it (1 / the
    largest of Motor.quadrant_loads); 0 at a ratio where the motor cannot turn against the
    output friction (a fast motor geared down little)."""
    qd, qdd = np.asarray(qd, dtype=float), np.asarray(qdd, dtype=float)
    out = []
    for r in np.asarray(ratios, dtype=float).ravel():
        try:
            m = with_gear(motor, r)
        except ParameterError:     # at this ratio the motor cannot turn against the friction
            out.append(np.zeros(np.shape(load_Nm)[-1]))
            continue
        need = m.delivered_torque(np.asarray(load_Nm) + (r**2 * motor.rotor_inertia_kg_m2 * qdd
                                                         if rotor else 0.0), qd)
        if speed_line:
            out.append(np.min(m.torque_margins(need, qd), axis=0))
        else:
            out.append(1.0 / np.maximum(np.max(m.quadrant_loads(need, qd)[0], axis=0), 1e-300))
    return np.array(out)


@dataclass(frozen=True)
class GearTrade:
    """The gear-ratio search, both effects: ratios (r,) and safety factors (r, motors), the best
    ratio (the worst motor's safety factor largest) and its safety factor, and the safety
    factor at the motor's own ratio."""

    ratios: np.ndarray
    safety: np.ndarray
    best_ratio: float
    best_safety: float
    current_safety: float


def gear_trade(motor: Motor, load_Nm, qd, qdd) -> GearTrade:
    """Search RATIO_RANGE (a log grid of GRID_POINTS, then a bounded scalar search between the
    grid neighbours of the best point) for the ratio maximising the worst motor's safety factor
    with both effects (safety_factors)."""
    ratios = np.geomspace(*RATIO_RANGE, GRID_POINTS)
    safety = safety_factors(motor, load_Nm, qd, qdd, ratios)

    def worst(r):
        return float(np.min(safety_factors(motor, load_Nm, qd, qdd, [r])))

    k = int(np.argmax(np.min(safety, axis=1)))
    lo, hi = ratios[max(k - 1, 0)], ratios[min(k + 1, GRID_POINTS - 1)]
    found = minimize_scalar(lambda r: -worst(r), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-9 * hi})
    best = float(found.x) if -found.fun >= worst(ratios[k]) else float(ratios[k])
    return GearTrade(ratios=ratios, safety=safety, best_ratio=best, best_safety=worst(best),
                     current_safety=worst(motor.gear_ratio))
