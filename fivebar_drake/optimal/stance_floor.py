"""A walking gait's stance floor: the least peak motor torque with which any controller carries
the robot through the gait's stances at its speed, period and duty factor (the trot path's
family: trot, walk).

Model. The body moves at constant forward speed without turning (no roll, pitch or yaw); its
height is free: a profile z(t) repeating every period / REPEAT[kind] (the trot's pairs every half
period, the crawl's legs every quarter; its mean and HARMONICS harmonics), which moves every
stance foot's height y = y_home - z(t) in its leg plane. Each leg follows the path's horizontal
stance relative to its hip at its phase (x from x_c - a to x_c + a, the parameter file's stride
and duty factor). The ground forces on the stance feet are free in the leg planes, (F_x, F_z)
per foot with F_z >= 0 inside the friction cone, and balance the body at every knot: the vertical
forces carry m (g + z''), the horizontal ones cancel, and the moments about the centre of mass
(at the body's origin, between the hips; each foot at its hip's position plus its leg-plane
offset, h below the centre of mass) vanish about all three axes: the body's attitude does not
change, so a moment about a diagonal from feet ahead or behind the hips is balanced by the feet,
not by tipping. Each stance leg's motor torques are its links' weight less J_F^T F at its pose
(the package's IK, J_F and G).

The floor: for each height profile a linear program (Drake's MathematicalProgram, Clp) gives the
least peak torque over the forces; Nelder-Mead (scipy) searches the profiles (a local search:
the least found). With thermal, the least copper loss (the sum of the squared stance torques, a
quadratic program) instead. Neglected, so the floor lies below what the gait needs: the swing
legs' torques, the links' inertia in stance, the contact's compliance; a body allowed to rock
could do with less (a controller that lets it tilt is not bounded by this floor). A gait whose
balance needs the body to rotate (the bound: one pair down at a time; the pronk: a flight) has
no floor here (None, with why).
"""

from __future__ import annotations

import functools
import math
import pickle
from dataclasses import dataclass

import numpy as np
from scipy import sparse

from fivebar_drake.core.footpath import Trot, foot_path
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, limit_tests, past_any
from fivebar_drake.optimal.vertical_jump import quarter_mass_kg
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.legs import LEGS, hip_positions
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.sdf import body_height

KNOTS = 48          # samples over a period
HARMONICS = 2       # of the body height's repeating profile
REPEAT = {"trot": 2, "walk": 4}    # the body's height repeats this often a period
# moments the feet need not balance, by kind: a trot's diagonal pair alone cannot hold the pitch
# (feet ahead of or behind the hips: only their midpoint lies under the centre of mass), so the
# body rocks: its floor is a relaxation that leaves the pitch moment to the body's rotation
RELAXED = {"trot": ("pitch",), "walk": ()}
CACHE_SIZE = 64     # designs x paths kept per process


@dataclass(frozen=True)
class StanceFloor:
    """The floor (N*m: the least peak motor torque of the stance legs; with thermal the worst
    motor's RMS torque of the least copper loss) and the gait that has it: the knots' times (s),
    the body height's change z (m), the feet's forces (legs, knots, 2) N (x forward, z up; zero
    in swing), the legs' motor torques (legs, knots, 2) N*m; the floor held level (N*m); whether
    the mean height was free; the worst motor's RMS current over the period (A, the motor law at
    the stance joint speeds, zero in swing; nan without a thermal model); the programs solved."""

    floor_Nm: float
    t: np.ndarray
    z_m: np.ndarray
    force_N: np.ndarray
    torque_Nm: np.ndarray
    constant_height_Nm: float
    free_height: bool
    rms_current_A: float
    programs: int


class Stances:
    """Each leg's stance over the knots of a period: stance (legs, knots) bool, its foot's
    leg-plane x (legs, knots) m (nan in swing), and its hip (legs, 3) m in the body frame."""

    def __init__(self, params: Params, path, t):
        gait = params.gait
        beta = 1.0 - path.stance_start(gait)
        phases = np.array([path.leg_phase(leg) for leg in LEGS])
        u = np.mod(t[None, :] / gait.period_s + phases[:, None] / (2 * math.pi), 1.0)
        self.stance = u >= 1.0 - beta
        sigma = np.where(self.stance, (u - (1.0 - beta)) / beta, np.nan)
        self.x = gait.x_center_m - gait.a_m + 2.0 * gait.a_m * sigma
        self.hips = np.array([hip_positions(params)[leg] for leg in LEGS])
        self.speed = path.stance_speed(gait)


def _height(coefficients, t, repeat_s: float):
    """(z, z', z'') of the profile repeating every repeat_s: mean plus harmonics."""
    w = 2.0 * math.pi / repeat_s
    z, zd, zdd = np.full_like(t, coefficients[0]), np.zeros_like(t), np.zeros_like(t)
    for k in range(1, len(coefficients) // 2 + 1):
        c, s = coefficients[2 * k - 1], coefficients[2 * k]
        phase = k * w * t
        z += c * np.cos(phase) + s * np.sin(phase)
        zd += k * w * (s * np.cos(phase) - c * np.sin(phase))
        zdd -= (k * w) ** 2 * (c * np.cos(phase) + s * np.sin(phase))
    return z, zd, zdd


def _program(params: Params, st: Stances, z, zdd, mass: float, thermal: bool,
             relaxed: tuple = ()):
    """(the floor's value, forces (legs, knots, 2), torques (legs, knots, 2), J_F of the
    stance poses (stance pairs, 2, 2)) for the height profile: the linear program (least peak)
    or the quadratic one (thermal); (inf, None, None, None) where a stance pose is out of reach
    or past [limits] or no forces balance the body; relaxed: the moments left unbalanced
    (RELAXED)."""
    from pydrake.solvers import MathematicalProgram, Solve

    leg, g, mu = params.fivebar_leg, params.robot.gravity_m_s2, params.body.foot_friction
    legs, knots = np.nonzero(st.stance)
    y_foot = params.gait.y_home_m - z[knots]
    pose = leg.inverse(np.stack([st.x[legs, knots], y_foot], -1), KNEES_OUT, strict=False)
    if (not np.isfinite(pose.q).all()
            or past_any(limit_tests(params.leg, pose), (legs.size,)).any()):
        return math.inf, None, None, None
    jf = leg.tool_jacobian(pose)                                       # (n, 2, 2)
    model = full_model(params)
    weight = leg.static_torques(type(model)(**{**model.__dict__, "foot_load_N": 0.0}), pose)
    n = legs.size                                   # variables: (F_x, F_z) per stance pair
    prog = MathematicalProgram()
    f = prog.NewContinuousVariables(2 * n, "F")
    fx, fz = f[0::2], f[1::2]
    prog.AddBoundingBoxConstraint(0.0, np.inf, fz)
    height = body_height(params, y_foot)                               # centre of mass, m
    body_x = st.hips[legs, 0] - st.x[legs, knots]       # leg-plane x points backwards
    body_y = st.hips[legs, 1]
    balanced = [m for m in ("roll", "pitch", "yaw") if m not in relaxed]
    rows = []                                           # per knot: Fz, Fx, then the moments
    for k in range(z.size):
        at = np.flatnonzero(knots == k)
        if not at.size:
            return math.inf, None, None, None           # a flight: no floor here
        a = np.zeros((5, 2 * n))
        a[0, 2 * at + 1] = 1.0
        a[1, 2 * at] = 1.0
        a[2, 2 * at + 1] = body_y[at]                                   # roll: y F_z
        a[3, 2 * at + 1] = -body_x[at]                                  # pitch: -x F_z - h F_x
        a[3, 2 * at] = -height[at]
        a[4, 2 * at] = -body_y[at]                                      # yaw: -y F_x
        keep = [0, 1] + [2 + ("roll", "pitch", "yaw").index(m) for m in balanced]
        rows.append((a[keep], np.array([mass * (g + zdd[k]), 0.0, 0.0, 0.0, 0.0])[keep]))
    prog.AddLinearEqualityConstraint(sparse.csc_matrix(np.vstack([r[0] for r in rows])),
                                     np.concatenate([r[1] for r in rows]), f)
    cone = sparse.block_diag([np.array([[1.0, -mu], [-1.0, -mu]])] * n, format="csc")
    prog.AddLinearConstraint(cone, np.full(2 * n, -np.inf), np.zeros(2 * n), f)   # |F_x| <= mu F_z
    # torque = weight - J_F^T (F_plane), F_plane = (-F_x, F_z) (leg-plane x backwards)
    blocks = np.stack([jf[:, 0, :], -jf[:, 1, :]], -1)                 # (n, motor, (F_x, F_z))
    gain = sparse.block_diag(list(blocks), format="csc")
    base = weight.ravel()
    if thermal:
        prog.AddQuadraticCost((2.0 * gain.T @ gain / z.size).toarray(),
                              2.0 * gain.T @ base / z.size, f)
    else:
        peak = prog.NewContinuousVariables(1, "peak")
        ones = sparse.csc_matrix(np.ones((2 * n, 1)))
        for sign in (1.0, -1.0):                        # +-torque <= peak
            prog.AddLinearConstraint(sparse.hstack([sign * gain, -ones], format="csc"),
                                     np.full(2 * n, -np.inf), -sign * base,
                                     np.concatenate([f, peak]))
        prog.AddLinearCost([1.0], 0.0, peak)
    result = Solve(prog)
    if not result.is_success():
        return math.inf, None, None, None
    sol = result.GetSolution(f)
    forces = np.zeros(st.stance.shape + (2,))
    forces[legs, knots] = sol.reshape(n, 2)
    torques = np.zeros(st.stance.shape + (2,))
    torques[legs, knots] = (base + gain @ sol).reshape(n, 2)
    value = (float(np.sqrt(np.mean(torques**2, axis=1)).max()) if thermal
             else float(np.abs(torques).max()))
    return value, forces, torques, jf


def stance_floor(params: Params, path=None, payload_kg: float = 0.0,
                 free_height: bool = False, thermal: bool = False) -> StanceFloor | None:
    """The gait's (a trot-family path, default the parameter file's trot) stance floor (module
    docstring); None for a path kind without a floor (REPEAT). The body's mean height is the
    gait's own (its stance feet at y_home) unless free_height (a straighter leg holds the weight
    with less torque). Cached per process by (design, path, payload, free_height, thermal): a
    sweep's or an envelope's runs of one design ask once (about a second)."""
    path = foot_path(path or Trot())
    if path.kind not in REPEAT:
        return None
    return _cached(pickle.dumps((params, path, float(payload_kg), bool(free_height),
                                 bool(thermal))))


@functools.lru_cache(maxsize=CACHE_SIZE)
def _cached(key: bytes) -> StanceFloor:
    return _solve(*pickle.loads(key))


def _solve(params: Params, path, payload_kg: float, free_height: bool,
           thermal: bool) -> StanceFloor:
    """stance_floor, computed."""
    from scipy.optimize import minimize

    period = params.gait.period_s
    t = np.arange(KNOTS) / KNOTS * period
    st = Stances(params, path, t)
    mass = 4.0 * quarter_mass_kg(params, payload_kg)
    repeat = period / REPEAT[path.kind]
    count = [0]

    def full(free):
        return free if free_height else np.concatenate([[0.0], free])

    def cost(free):
        count[0] += 1
        z, _, zdd = _height(full(free), t, repeat)
        return _program(params, st, z, zdd, mass, thermal, RELAXED[path.kind])[0]

    start = np.zeros(2 * HARMONICS + (1 if free_height else 0))
    constant = cost(start)
    best = minimize(cost, start, method="Nelder-Mead",
                    options={"initial_simplex": np.vstack([start, 0.005 * np.eye(len(start))]),
                             "xatol": 1e-5, "fatol": 1e-4, "maxiter": 400})
    z, zd, zdd = _height(full(best.x), t, repeat)
    floor, forces, torques, jf = _program(params, st, z, zdd, mass, thermal,
                                          RELAXED[path.kind])
    current = math.nan
    if jf is not None and params.motor.has_thermal_model:
        legs, knots = np.nonzero(st.stance)      # the stance feet's velocity relative to the hip
        feet = np.stack([np.full(legs.size, st.speed), -zd[knots]], -1)
        speed = np.zeros_like(torques)
        speed[legs, knots] = np.linalg.solve(jf, feet[..., None])[..., 0]
        current = float(np.sqrt(np.mean(params.motor.currents(torques, speed) ** 2,
                                        axis=1)).max())
    return StanceFloor(floor, t, z, forces, torques, constant, free_height, current,
                       count[0] + 1)
