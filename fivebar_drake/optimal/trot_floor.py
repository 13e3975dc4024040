"""The trot's torque floor: the least peak motor torque with which any controller carries the
robot through the trot's stance at its speed and period.

Model. A trot at constant forward speed: the diagonal pairs (FL, RR) and (FR, RL) alternate, so
by symmetry the body neither rolls (each pair's support line passes through the centre of mass)
nor pitches (front and rear feet of a pair carry equal loads: the centre of mass between the
hips), and the second pair repeats the first half a period later. The stance feet follow the
trot path's horizontal stance (x from x_c - a to x_c + a at constant speed, relative to the hip,
the parameter file's stride and duty factor); the body's height is free: a half-period-periodic
profile z(t) (its mean and HARMONICS harmonics), which moves the stance feet's height y = y_home
- z(t) in the leg plane. The feet's vertical forces are free too, each >= 0, summing to the
robot's weight and its vertical acceleration: 2 F_1(t) + 2 F_1(t + T/2) = m (g + z''(t)) (F_1:
a foot of the first pair; horizontal forces zero at constant speed). Each stance leg's motor
torques are its links' weight less J_F^T (0, F_1) at its pose (the package's IK, J_F and G).

The floor: the least T over the height profile (Nelder-Mead, scipy) of the least peak torque
over the forces (a linear program in Drake's MathematicalProgram, Clp, for each profile).
Neglected, so the floor lies below what any real trot needs: the swing legs' torques (the other
motors of the robot at that instant), the links' inertia in stance, the contact's compliance;
the friction cone is not binding (no horizontal force).
"""

from __future__ import annotations

import functools
import math
import pickle
from dataclasses import dataclass

import numpy as np

from fivebar_drake.core.footpath import Trot, foot_path
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, limit_tests, past_any
from fivebar_drake.optimal.vertical_jump import quarter_mass_kg
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.params import Params

KNOTS = 80          # samples over a period (even: the second pair at half a period)
HARMONICS = 2       # of the body height's half-period profile
CACHE_SIZE = 64     # designs x paths kept per process


@dataclass(frozen=True)
class TrotFloor:
    """The floor (N*m, the least peak motor torque of a stance leg) and the trot that has it:
    the times (s) of the knots over a period, the body height's change z (m) and the vertical
    force on a first-pair foot F_1 (N) at each, that leg's motor torques (knots, 2) N*m (zero in
    swing); the floor at constant height (N*m) beside it; whether the mean height was free; the
    worst motor's RMS current over the period (A; the motor law at the stance joint speeds,
    zero in swing; nan without a thermal model); the programs solved."""

    floor_Nm: float
    t: np.ndarray
    z_m: np.ndarray
    force_N: np.ndarray
    torque_Nm: np.ndarray
    constant_height_Nm: float
    free_height: bool
    rms_current_A: float
    programs: int


def _stance(params: Params, path) -> tuple[np.ndarray, np.ndarray, float]:
    """(cycle phases u (KNOTS,), stance mask of a first-pair leg, its stance foot x (m) relative
    to the hip at each knot, nan in swing) of the trot path."""
    gait = params.gait
    u = np.arange(KNOTS) / KNOTS
    beta = path.beta(gait) if hasattr(path, "beta") else 1.0 - path.stance_start(gait)
    stance = u >= 1.0 - beta
    sigma = np.where(stance, (u - (1.0 - beta)) / beta, np.nan)
    return u, stance, gait.x_center_m - gait.a_m + 2.0 * gait.a_m * sigma


def _height(coefficients, t, period: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(z, z', z'') of the half-period profile: mean plus harmonics (cos, sin pairs)."""
    w = 4.0 * math.pi / period
    z, zd, zdd = np.full_like(t, coefficients[0]), np.zeros_like(t), np.zeros_like(t)
    for k in range(1, len(coefficients) // 2 + 1):
        c, s = coefficients[2 * k - 1], coefficients[2 * k]
        phase = k * w * t
        z += c * np.cos(phase) + s * np.sin(phase)
        zd += k * w * (s * np.cos(phase) - c * np.sin(phase))
        zdd -= (k * w) ** 2 * (c * np.cos(phase) + s * np.sin(phase))
    return z, zd, zdd


def _peak(params: Params, x, stance, z, zdd, mass: float, rms: bool = False):
    """(least peak torque N*m, F_1 (KNOTS,), torques (KNOTS, 2), the stance leg's joint Jacobians
    J_F (stance, 2, 2)) for the height profile by the linear program; with rms, the least
    total squared stance torque over the period (the copper loss, a quadratic program on the
    same constraints), valued as the worst motor's RMS torque; (inf, None, None, None) where a
    stance pose is out of reach or past [limits], or the feet would have to pull."""
    from pydrake.solvers import MathematicalProgram, Solve

    leg, g = params.fivebar_leg, params.robot.gravity_m_s2
    feet = np.stack([x[stance], params.gait.y_home_m - z[stance]], -1)
    pose = leg.inverse(feet, KNEES_OUT, strict=False)
    if (not np.isfinite(pose.q).all()
            or past_any(limit_tests(params.leg, pose), (int(stance.sum()),)).any()):
        return math.inf, None, None, None
    jf = leg.tool_jacobian(pose)                                  # (stance, 2, 2)
    model = full_model(params)
    weight = leg.static_torques(type(model)(**{**model.__dict__, "foot_load_N": 0.0}), pose)
    prog = MathematicalProgram()
    force = prog.NewContinuousVariables(KNOTS, "F")
    peak = None if rms else prog.NewContinuousVariables(1, "peak")[0]
    prog.AddBoundingBoxConstraint(0.0, np.inf, force)
    swing = np.flatnonzero(~stance)
    prog.AddBoundingBoxConstraint(0.0, 0.0, force[swing])
    half = KNOTS // 2
    for j in range(half):
        prog.AddLinearEqualityConstraint(2.0 * force[j] + 2.0 * force[j + half]
                                         == mass * (g + zdd[j]))
    for n, j in enumerate(np.flatnonzero(stance)):
        for i in range(2):
            tau = weight[n, i] - jf[n, 1, i] * force[j]          # -J_F^T (0, F)
            if rms:
                prog.AddQuadraticCost(tau * tau / KNOTS)
            else:
                prog.AddLinearConstraint(tau <= peak)
                prog.AddLinearConstraint(tau >= -peak)
    if not rms:
        prog.AddLinearCost(peak)
    result = Solve(prog)
    if not result.is_success():
        return math.inf, None, None, None
    f = result.GetSolution(force)
    torque = np.zeros((KNOTS, 2))
    torque[stance] = weight - jf[:, 1, :] * f[stance, None]
    value = (float(np.sqrt(np.mean(torque**2, axis=0)).max()) if rms
             else float(result.GetSolution(peak)))
    return value, f, torque, jf


def trot_floor(params: Params, path=None, payload_kg: float = 0.0,
               free_height: bool = False, thermal: bool = False) -> TrotFloor:
    """The trot path's (default the parameter file's trot) torque floor (module docstring):
    the body's mean height the gait's own (its stance feet at y_home) unless free_height, where
    any mean height within the leg's reach and [limits] is allowed (a straighter leg holds the
    weight with less torque). thermal: the thermal floor instead, the least copper loss (the
    sum of the stance torques squared over the period, swing torques taken as zero), floor_Nm
    its worst motor's RMS torque and rms_current_A its RMS current. Cached per process by
    (design, path, payload, free_height, thermal): a sweep's or an envelope's runs of one
    design ask once (~1 s)."""
    return _cached(pickle.dumps((params, foot_path(path or Trot()), float(payload_kg),
                                 bool(free_height), bool(thermal))))


@functools.lru_cache(maxsize=CACHE_SIZE)
def _cached(key: bytes) -> TrotFloor:
    return _solve(*pickle.loads(key))


def _solve(params: Params, path, payload_kg: float, free_height: bool,
           thermal: bool) -> TrotFloor:
    """trot_floor, computed."""
    from scipy.optimize import minimize

    period = params.gait.period_s
    t = np.arange(KNOTS) / KNOTS * period
    _, stance, x = _stance(params, path)
    mass = 4.0 * quarter_mass_kg(params, payload_kg)
    count = [0]

    def full(free):
        return free if free_height else np.concatenate([[0.0], free])

    def cost(free):
        count[0] += 1
        z, _, zdd = _height(full(free), t, period)
        return _peak(params, x, stance, z, zdd, mass, thermal)[0]

    start = np.zeros(2 * HARMONICS + (1 if free_height else 0))
    constant = cost(start)
    best = minimize(cost, start, method="Nelder-Mead",
                    options={"initial_simplex": np.vstack([start, 0.005 * np.eye(len(start))]),
                             "xatol": 1e-5, "fatol": 1e-4, "maxiter": 400})
    z, zd, zdd = _height(full(best.x), t, period)
    floor, force, torque, jf = _peak(params, x, stance, z, zdd, mass, thermal)
    current = math.nan
    if jf is not None and params.motor.has_thermal_model:
        # the stance leg's joint speeds: its foot moves at the stance speed along x and at -z'
        speed = np.zeros((KNOTS, 2))
        feet = np.stack([np.full(int(stance.sum()), path.stance_speed(params.gait)),
                         -zd[stance]], -1)
        speed[stance] = np.linalg.solve(jf, feet[..., None])[..., 0]
        current = float(np.sqrt(np.mean(params.motor.currents(torque, speed) ** 2, axis=0)).max())
    return TrotFloor(floor, t, z, force, torque, constant, free_height, current, count[0] + 1)
