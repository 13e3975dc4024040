"""A periodic gait's floor with the body in motion: the least peak motor torque with which any
controller carries the robot through a trot, a bound or a pronk (the trot path's family) at its
speed, period and duty factor, the body free to surge, heave and pitch (and to fly, where no
foot is down).

Model (sagittal rigid body, fixed contact schedule and footholds). The centre of mass moves in
the x-z plane (x forward, z up) and the body pitches by theta about +y (y left: a positive theta
lowers the nose; within max_pitch_rad); it neither rolls nor yaws. Its motion repeats every
period at the gait's mean forward speed. Each leg's foot is down during the path's stance (its phase and duty factor) at a
fixed foothold: where the path puts it at mid-stance with the body on its nominal course (steady
speed, the gait's height, level). The ground forces on the feet that are down are free in the
leg planes, (F_x, F_z) per foot with F_z >= 0 inside the friction cone, zero on the others, and
move the body: m x'' = sum F_x, m z'' = sum F_z - m g, I theta'' = sum (r_z F_x - r_x F_z)
(r from the centre of mass to the foot), the roll and yaw moments zero. Each stance leg's motor
torques are its links' weight less J_F^T F at the pose the body's position and pitch give it
(the package's IK, J_F and G; the force turned into the pitched leg plane).

The floor: sequential linear programming (Drake's MathematicalProgram, Clp). The accelerations
are knot-wise constant, the positions and velocities their exact integrals; each program
linearises the pitch moment and the torques (finite differences over the body's position and
pitch) about the last trajectory inside a trust region that shrinks every iteration, and
minimises the peak torque (thermal: the sum of the squared stance torques). The result is a
dynamically consistent trajectory (its pitch-balance residual reported) and the least found: a
local optimum of a non-convex problem, not a proven global bound. Neglected, so the floor lies
below what the gait needs: the swing legs' torques, the links' and rotors' inertia in stance
(the joints move at the stance speeds only), the contact's compliance; the links' weight is
taken level (cos theta ~ 1 to 1e-3 at the few degrees of pitch).
"""

from __future__ import annotations

import dataclasses
import math
import pickle
from dataclasses import dataclass

import numpy as np
from scipy import sparse

from fivebar_drake.gaits import Trot, evaluate, foot_path
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, limit_tests, link_coms, past_any
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.legs import LEGS, hip_positions
from fivebar_drake.robots.quadruped.config import with_gait, with_path_defaults
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.sdf import body_height, body_mass_properties

KINDS = ("trot", "walk", "bound", "pronk")
KNOTS = 48              # samples over a period
ITERATIONS = 60         # linear programs at most
TRUST_M = 0.01          # trust region: the centre of mass's position per knot (m)
TRUST_RAD = math.radians(2.0)   # and the pitch (rad)
SHRINK = 0.3            # the trust region's factor where a program no longer improves by
PROGRESS = 1e-4         # this fraction of its cost
TRUST_END_M = 2e-5      # converged: the trust region below this
STEP_M, STEP_RAD = 1e-5, 1e-5   # finite differences of the torques
CACHE_SIZE = 64
SPEED_STEPS = 6         # bisection steps of the fastest gait's frequency
SPEED_SAMPLES = 2000    # samples of a period for the path's fastest joint
# ASSUMPTION: the body pitches by at most this share of the tilt an achieved run may have
# (checks.achieved_max_tilt_deg) either way, leaving the rest to a controller's tracking error
# (left free, the bound's floor falls on and on as the body rocks by tens of degrees, on swing
# legs that would hit the ground)
PITCH_SHARE = 0.5


def max_pitch_rad(params: Params) -> float:
    """The floor's bound on the body's pitch either way (rad): PITCH_SHARE of the tilt an
    achieved run may have."""
    return math.radians(PITCH_SHARE * params.checks.achieved_max_tilt_deg)


@dataclass(frozen=True)
class GaitFloor:
    """The floor (N*m: the least peak motor torque of the stance legs; thermal: the worst
    motor's RMS torque of the least copper loss) and the motion that has it, at the knots' times
    t (s): the centre of mass's x (forward, less the mean speed's course), z (above its nominal
    height) in m and the pitch theta (rad); the feet's forces (legs, knots, 2) N (x forward,
    z up; zero in swing); the legs' motor torques and joint speeds (legs, knots, 2) N*m, rad/s
    (zero in swing); the floor with the body
    held on its course, level (N*m; None where no forces balance it so: a single pair down);
    whether the mean height was free; the worst motor's RMS current over the period (A, the motor
    law at the stance joint speeds, zero in swing; nan without a thermal model); the largest
    pitch-moment residual of the linearisation (N*m) beside the largest moment the feet apply
    (N*m); the programs solved; the body's pitch inertia (kg*m^2) and mass (kg)."""

    floor_Nm: float
    t: np.ndarray
    x_m: np.ndarray
    z_m: np.ndarray
    pitch_rad: np.ndarray
    force_N: np.ndarray
    torque_Nm: np.ndarray
    speed_rad_s: np.ndarray
    level_Nm: float | None
    free_height: bool
    rms_current_A: float
    moment_residual_Nm: float
    moment_scale_Nm: float
    programs: int
    pitch_inertia_kg_m2: float
    mass_kg: float


def whole_body(params: Params, payload_kg: float = 0.0) -> tuple[float, float, float]:
    """(mass kg, centre of mass height above the body origin m, pitch inertia about the centre of
    mass kg*m^2) of the robot standing on its gait's home pose (mass_centre)."""
    mass, _, z_c, pitch = mass_centre(params, payload_kg)
    return mass, z_c, pitch


def mass_centre(params: Params, payload_kg: float = 0.0) -> tuple[float, float, float, float]:
    """(mass kg, centre of mass x (forward) and height above the body origin m, pitch inertia
    about the centre of mass kg*m^2) of the robot standing on its gait's home pose: the body
    (box and motors, sdf.body_mass_properties), the legs' links as point masses at their
    centres of mass, the payload as a point mass at the body origin."""
    body_kg, com, inertia = body_mass_properties(params)
    leg = params.fivebar_leg
    pose = leg.inverse(np.array([params.gait.x_center_m, params.gait.y_home_m]), KNEES_OUT)
    coms = link_coms(leg.geometry, params.links, pose)           # (4, 2) leg plane: x back, y up
    link_kg = np.array([link.mass_kg for link in params.links.values()])
    points, masses = [], []
    for hip in hip_positions(params).values():
        for (px, py), m in zip(coms, link_kg):
            points.append((hip[0] - px, hip[2] + py))
            masses.append(m)
    points, masses = np.array(points), np.array(masses)
    mass = body_kg + masses.sum() + payload_kg
    x_c = (body_kg * com[0] + masses @ points[:, 0]) / mass
    z_c = (body_kg * com[2] + masses @ points[:, 1]) / mass
    pitch = (inertia[1, 1] + body_kg * ((com[0] - x_c) ** 2 + (com[2] - z_c) ** 2)
             + masses @ ((points[:, 0] - x_c) ** 2 + (points[:, 1] - z_c) ** 2)
             + payload_kg * (x_c ** 2 + z_c ** 2))
    return float(mass), float(x_c), float(z_c), float(pitch)


class Schedule:
    """The gait's contact schedule and footholds over the knots of a period: stance (legs,
    knots) bool; each foothold's x (legs, knots) in m along the ground relative to the nominal
    centre of mass at that knot's time (nan in swing); the hips (legs, 3) m in the body frame;
    the mean speed (m/s)."""

    def __init__(self, params: Params, path, t):
        gait = params.gait
        beta = 1.0 - path.stance_start(gait)
        phases = np.array([path.leg_phase(leg) for leg in LEGS])
        u = np.mod(t[None, :] / gait.period_s + phases[:, None] / (2 * math.pi), 1.0)
        self.stance = u >= 1.0 - beta
        sigma = np.where(self.stance, (u - (1.0 - beta)) / beta, np.nan)
        self.speed = path.stance_speed(gait)
        self.period = gait.period_s
        self.hips = np.array([hip_positions(params)[leg] for leg in LEGS])
        # the foot's leg-plane x runs from x_c - a to x_c + a (backwards in the body): at
        # mid-stance it is x_c behind the hip, the body on its course
        leg_x = gait.x_center_m - gait.a_m + 2.0 * gait.a_m * sigma
        self.foothold = self.hips[:, [0]] - leg_x


class Body:
    """The robot's sagittal geometry: feet relative to the hips for a centre of mass offset
    (dx, dz) from its nominal course and a pitch theta, and the stance legs' torque terms."""

    def __init__(self, params: Params, schedule: Schedule, mass: float, com_z: float):
        self.params, self.schedule = params, schedule
        self.legs, self.knots = np.nonzero(schedule.stance)
        gait, b = params.gait, params.body
        self.com_z = com_z
        # the nominal centre of mass's height above the ground (feet at y_home, foot radius)
        self.height = float(body_height(params, gait.y_home_m)) + com_z
        self.feet = np.stack([schedule.foothold[self.legs, self.knots],
                              np.full(self.legs.size, b.foot_radius_m - self.height)], -1)
        self.hip = schedule.hips[self.legs][:, [0, 2]] - np.array([0.0, com_z])
        model = full_model(params)
        self.weight_model = type(model)(**{**model.__dict__, "foot_load_N": 0.0})

    def arms(self, dx, dz):
        """(r_x, r_z) (n,) m from the centre of mass to the stance feet."""
        return (self.feet[:, 0] - dx[self.knots], self.feet[:, 1] - dz[self.knots])

    def poses(self, dx, dz, theta):
        """Leg-plane foot positions (n, 2) of the stance legs for the body's offsets (knots,)."""
        rx, rz = self.arms(dx, dz)
        c, s = np.cos(theta[self.knots]), np.sin(theta[self.knots])
        bx, bz = c * rx - s * rz, s * rx + c * rz               # the foot in the body frame
        return np.stack([-(bx - self.hip[:, 0]), bz - self.hip[:, 1]], -1)

    def terms(self, dx, dz, theta):
        """(weight torques (n, 2) N*m, gain (n, 2, 2): torque = weight + gain @ (F_x, F_z) in
        the world, ok) at the body's offsets; ok False where a pose is out of reach or past
        [limits]."""
        leg = self.params.fivebar_leg
        pose = leg.inverse(self.poses(dx, dz, theta), KNEES_OUT, strict=False)
        if (not np.isfinite(pose.q).all()
                or past_any(limit_tests(self.params.leg, pose), (self.legs.size,)).any()):
            return None, None, False
        jf = leg.tool_jacobian(pose)                                   # (n, 2, 2)
        weight = leg.static_torques(self.weight_model, pose)
        c, s = np.cos(theta[self.knots]), np.sin(theta[self.knots])
        # body-frame force R^T F: (c F_x - s F_z, s F_x + c F_z); leg plane (-f_bx, f_bz);
        # torque = weight - J_F^T f_plane
        plane = np.stack([np.stack([-c, s], -1), np.stack([s, c], -1)], -2)  # (n, 2, 2)
        gain = -np.einsum("nji,njk->nik", jf, plane)
        return weight, gain, True


class Layout:
    """The program's variables, in order: the stance feet's forces (n, 2), then per knot and
    axis (x, z, theta) the accelerations a, positions p and velocities v (knots, 3) each."""

    def __init__(self, n: int, knots: int):
        self.n, self.knots = n, knots
        self.size = 2 * n + 9 * knots

    def force(self, i, axis):
        return 2 * np.asarray(i) + axis

    def a(self, k, axis):
        return 2 * self.n + 3 * np.asarray(k) + axis

    def p(self, k, axis):
        return 2 * self.n + 3 * self.knots + 3 * np.asarray(k) + axis

    def v(self, k, axis):
        return 2 * self.n + 6 * self.knots + 3 * np.asarray(k) + axis


class NoFloorMotion(ParameterError):
    """No motion of the floor balances the gait within the legs' reach, [limits] and the pitch
    bound (a stance held long can topple the body: a faster gait of the same path may
    balance)."""


def _rows(entries, count: int, columns: int):
    """The sparse matrix (count, columns) of the entries (rows, columns, values), arrays that
    broadcast against each other; repeated entries add up."""
    r, c, v = (np.concatenate([np.broadcast_to(np.asarray(e[j], dtype=float if j == 2 else int),
                                               np.broadcast_shapes(*(np.shape(x) for x in e))
                                               ).ravel() for e in entries]) for j in range(3))
    return sparse.csc_matrix((v, (r, c)), shape=(count, columns))


def _program(body: Body, mass: float, inertia: float, g: float, state, forces, trust,
             thermal: bool, free_height: bool):
    """One linear (thermal: quadratic) program about the trajectory `state` (dx, dz, theta
    (knots,) each) and the stance forces `forces` (n, 2): (new state, new forces, predicted
    cost) or None where it fails or a pose is out of reach."""
    from pydrake.solvers import MathematicalProgram, Solve

    st = body.schedule
    knots = st.stance.shape[1]
    dt = st.period / knots
    n = body.legs.size
    weight, gain, ok = body.terms(*state)
    if not ok:
        return None
    tau0 = weight + np.einsum("nij,nj->ni", gain, forces)
    d_tau = []                       # the torques' derivatives over the body's offsets
    for axis, step in ((0, STEP_M), (1, STEP_M), (2, STEP_RAD)):
        moved = [s.copy() for s in state]
        moved[axis] = moved[axis] + step
        w1, g1, ok1 = body.terms(*moved)
        if not ok1:
            return None
        d_tau.append((w1 + np.einsum("nij,nj->ni", g1, forces) - tau0) / step)
    d_tau = np.stack(d_tau, -1)                                       # (n, 2, 3)
    rx, rz = body.arms(state[0], state[1])
    lay = Layout(n, knots)

    ks, nxt = np.arange(knots), (np.arange(knots) + 1) % knots
    entries, rhs = [], [np.zeros(6 * knots)]
    for axis in range(3):      # knot-wise constant accelerations, the motion periodic
        pos, vel = 6 * ks + 2 * axis, 6 * ks + 2 * axis + 1
        entries += [(pos, lay.p(nxt, axis), 1.0), (pos, lay.p(ks, axis), -1.0),
                    (pos, lay.v(ks, axis), -dt), (pos, lay.a(ks, axis), -0.5 * dt * dt),
                    (vel, lay.v(nxt, axis), 1.0), (vel, lay.v(ks, axis), -1.0),
                    (vel, lay.a(ks, axis), -dt)]
    means = (0, 2) if free_height else (0, 1, 2)   # on the course on average: the mean x
    for j, axis in enumerate(means):                # offset and pitch zero (and height)
        entries.append((6 * knots + j, lay.p(ks, axis), 1.0 / knots))
    rhs.append(np.zeros(len(means)))
    # per knot: sum F_x = m ddx, sum F_z = m (g + ddz); the pitch, linearised:
    # sum (r_z F_x - r_x F_z) = I ddtheta, r = foot - com, about (state, forces); roll and yaw:
    # sum y F_z = 0, sum y F_x = 0
    row = 6 * knots + len(means) + 5 * ks                   # each knot's first row
    at = row[body.knots]                                    # each stance sample's knot's
    feet = np.arange(n)
    fx_bar = np.bincount(body.knots, forces[:, 0], knots)
    fz_bar = np.bincount(body.knots, forces[:, 1], knots)
    hip_y = st.hips[body.legs, 1]
    entries += [(at, lay.force(feet, 0), 1.0), (row, lay.a(ks, 0), -mass),
                (at + 1, lay.force(feet, 1), 1.0), (row + 1, lay.a(ks, 1), -mass),
                (at + 2, lay.force(feet, 0), rz), (at + 2, lay.force(feet, 1), -rx),
                (row + 2, lay.p(ks, 0), fz_bar), (row + 2, lay.p(ks, 1), -fx_bar),
                (row + 2, lay.a(ks, 2), -inertia),
                (at + 3, lay.force(feet, 1), hip_y), (at + 4, lay.force(feet, 0), hip_y)]
    rhs.append(np.stack([np.zeros(knots), np.full(knots, mass * g),
                         fz_bar * state[0] - fx_bar * state[1], np.zeros(knots),
                         np.zeros(knots)], -1).ravel())
    rhs = np.concatenate(rhs)
    prog = MathematicalProgram()
    x = prog.NewContinuousVariables(lay.size, "x")
    prog.AddLinearEqualityConstraint(_rows(entries, rhs.size, lay.size), rhs, x)
    mu = body.params.body.foot_friction
    cone = _rows([(feet, lay.force(feet, 0), 1.0), (feet, lay.force(feet, 1), -mu),
                  (n + feet, lay.force(feet, 0), -1.0), (n + feet, lay.force(feet, 1), -mu)],
                 2 * n, lay.size)                    # |F_x| <= mu F_z (so F_z >= 0)
    prog.AddLinearConstraint(cone, np.full(2 * n, -np.inf), np.zeros(2 * n), x)
    centre = np.stack(state, -1).ravel()                # the trust region about the last motion
    radius = np.tile([trust[0], trust[0], trust[1]], knots)
    pitch = np.tile([np.inf, np.inf, max_pitch_rad(body.params)], knots)   # the pitch's bound
    prog.AddBoundingBoxConstraint(np.maximum(centre - radius, -pitch),
                                  np.minimum(centre + radius, pitch),
                                  x[lay.p(0, 0):lay.p(0, 0) + 3 * knots])
    # torques, linear: tau0 + d_tau (offset - state) + gain (F - forces)
    motor_rows = (2 * feet[:, None] + np.arange(2))[..., None]     # (n, 2, 1)
    at_state = np.stack(state, -1)[body.knots]                     # (n, 3)
    torque = _rows([(motor_rows, lay.force(feet, np.arange(2)[:, None, None]).T, gain),
                    (motor_rows, lay.p(body.knots[:, None, None], np.arange(3)), d_tau)],
                   2 * n, lay.size)
    const = np.array([tau0[i, m] - gain[i, m] @ forces[i] - d_tau[i, m] @ at_state[i]
                      for i in range(n) for m in range(2)])
    peak = prog.NewContinuousVariables(1, "peak")
    if thermal:                      # each motor's RMS torque over the period <= peak
        for leg in range(len(LEGS)):
            for m in range(2):
                rows = 2 * np.flatnonzero(body.legs == leg) + m
                a = sparse.vstack([sparse.csc_matrix(([math.sqrt(knots)], ([0], [lay.size])),
                                                     shape=(1, lay.size + 1)),
                                   sparse.hstack([torque[rows], sparse.csc_matrix(
                                       (rows.size, 1))])]).toarray()
                prog.AddLorentzConeConstraint(a, np.concatenate([[0.0], const[rows]]),
                                              np.concatenate([x, peak]))
    else:
        ones = sparse.csc_matrix(np.ones((2 * n, 1)))
        for sign in (1.0, -1.0):
            prog.AddLinearConstraint(sparse.hstack([sign * torque, -ones], format="csc"),
                                     np.full(2 * n, -np.inf), -sign * const,
                                     np.concatenate([x, peak]))
    prog.AddLinearCost([1.0], 0.0, peak)
    result = Solve(prog)
    if not result.is_success():
        return None
    sol = result.GetSolution(x)
    motion = sol[lay.p(0, 0):lay.p(0, 0) + 3 * knots].reshape(knots, 3)
    return tuple(motion.T.copy()), sol[:2 * n].reshape(n, 2), result.get_optimal_cost()


def gait_floor(params: Params, path=None, payload_kg: float = 0.0, free_height: bool = False,
               thermal: bool = False) -> GaitFloor | None:
    """The gait's floor (module docstring) for a path of KINDS (default the trot); None for
    another kind. The centre of mass's mean height is the gait's own (its feet at y_home when
    level) unless free_height. The floor does not depend on the motor (only its RMS current
    does, computed here for params.motor): cached per process by the rest of the design, the
    path, payload, free_height and thermal, so the designs of a sweep or a co-design that
    differ only in their motor or gear share it."""
    path = foot_path(path or Trot())
    if path.kind not in KINDS:
        return None
    key = pickle.dumps((params.leg, params.links, params.robot, params.gait, params.body,
                        params.checks.achieved_max_tilt_deg, path, float(payload_kg),
                        bool(free_height), bool(thermal)))
    floor = _FLOORS.get(key)
    if floor is None:
        floor = _solve(params, path, float(payload_kg), bool(free_height), bool(thermal))
        if len(_FLOORS) >= CACHE_SIZE:
            _FLOORS.pop(next(iter(_FLOORS)))              # the oldest
        _FLOORS[key] = floor
    return dataclasses.replace(floor, rms_current_A=_rms_current(params.motor, floor))


_FLOORS: dict[bytes, GaitFloor] = {}     # gait_floor's cache, oldest first


def _rms_current(motor, floor: GaitFloor) -> float:
    """The worst motor's RMS current (A) over the floor's period: the motor law at the stance
    joint speeds, zero in swing; nan without a thermal model."""
    if not motor.has_thermal_model:
        return math.nan
    return float(np.sqrt(np.mean(motor.currents(floor.torque_Nm, floor.speed_rad_s) ** 2,
                                 axis=1)).max())


def _solve(params: Params, path, payload_kg: float, free_height: bool,
           thermal: bool) -> GaitFloor:
    """gait_floor, computed."""
    g = params.robot.gravity_m_s2
    t = np.arange(KNOTS) / KNOTS * params.gait.period_s
    mass, com_z, inertia = whole_body(params, payload_kg)
    schedule = Schedule(params, path, t)
    if not schedule.stance.any(axis=1).all():
        raise ParameterError(f"duty factor {path.beta(params.gait):g}: a foot's stance falls "
                             f"between the floor's {KNOTS} samples of the period (at least "
                             f"1/{KNOTS} of it down)", "gait", "parameter file")
    body = Body(params, schedule, mass, com_z)
    level = np.zeros(KNOTS)
    state, forces = (level, level, level), np.zeros((body.legs.size, 2))
    held = _program(body, mass, inertia, g, state, forces, (0.0, 0.0), thermal, free_height)
    trust, programs, last = np.array([TRUST_M, TRUST_RAD]), 1, math.inf
    while programs < ITERATIONS and trust[0] > TRUST_END_M:
        step = _program(body, mass, inertia, g, state, forces, trust, thermal, free_height)
        programs += 1
        if step is None or not body.terms(*step[0])[2]:  # a pose out of reach: a smaller step
            trust = trust * SHRINK
            continue
        state, forces, cost = step
        if cost > last * (1.0 - PROGRESS):   # no longer improving: tighten (the linearisation
            trust = trust * SHRINK           # converges on the last motion)
        last = min(last, cost)
    if not np.isfinite(last):
        raise NoFloorMotion(f"no {path.kind} motion found within the legs' reach and [limits] "
                             f"(the body's pitch within {math.degrees(max_pitch_rad(params)):g} deg)",
                             "gait", "parameter file")
    torques = _grid(body, _torques(body, state, forces))
    floor = _value(torques, thermal)
    residual, scale = _pitch_residual(body, state, forces, inertia)
    speeds = _joint_speeds(body, state)
    level_floor = None if held is None else _value(_grid(body, _torques(body, *held[:2])),
                                                   thermal)
    return GaitFloor(floor, t, state[0], state[1], state[2], _grid(body, forces), torques,
                     speeds, level_floor, free_height, math.nan, residual, scale, programs,
                     inertia, mass)


def _torques(body: Body, state, forces) -> np.ndarray:
    """The stance legs' motor torques (n, 2) N*m at the motion and forces, exactly."""
    weight, gain, _ = body.terms(*state)
    return weight + np.einsum("nij,nj->ni", gain, forces)


def _grid(body: Body, values) -> np.ndarray:
    """Stance values (n, 2) spread over (legs, knots, 2), zero in swing."""
    out = np.zeros(body.schedule.stance.shape + (2,))
    out[body.legs, body.knots] = values
    return out


def _value(torques, thermal: bool) -> float:
    """The floor of torques (legs, knots, 2): the peak, or the worst motor's RMS."""
    return (float(np.sqrt(np.mean(torques**2, axis=1)).max()) if thermal
            else float(np.abs(torques).max()))


def _joint_speeds(body: Body, state) -> np.ndarray:
    """Motor speeds (legs, knots, 2) rad/s of the stance legs (zero in swing): J_F^-1 times the
    foot's velocity relative to the hip, central differences over the stance's knots
    (one-sided at its ends)."""
    dt = body.schedule.period / state[0].size
    feet = np.full(body.schedule.stance.shape + (2,), np.nan)
    feet[body.legs, body.knots] = body.poses(*state)
    ahead, behind = np.roll(feet, -1, axis=1), np.roll(feet, 1, axis=1)
    velocity = (ahead - behind) / (2 * dt)
    velocity = np.where(np.isnan(ahead), (feet - behind) / dt, velocity)
    velocity = np.where(np.isnan(behind), (ahead - feet) / dt, velocity)
    leg = body.params.fivebar_leg
    jf = leg.tool_jacobian(leg.inverse(feet[body.legs, body.knots], KNEES_OUT))
    speeds = np.zeros_like(feet)
    speeds[body.legs, body.knots] = np.linalg.solve(
        jf, np.nan_to_num(velocity[body.legs, body.knots])[..., None])[..., 0]
    return speeds


def _pitch_residual(body: Body, state, forces, inertia: float) -> tuple[float, float]:
    """(the largest |I theta'' - sum (r_z F_x - r_x F_z)| over the knots with the exact arms,
    the largest |moment|) in N*m, theta'' from the pitch's positions: with knot-wise constant
    accelerations theta_{k+1} - 2 theta_k + theta_{k-1} = dt^2 (a_k + a_{k-1}) / 2."""
    knots = state[2].size
    dt = body.schedule.period / knots
    rx, rz = body.arms(state[0], state[1])
    moment = np.bincount(body.knots, rz * forces[:, 0] - rx * forces[:, 1], minlength=knots)
    second = (np.roll(state[2], -1) - 2.0 * state[2] + np.roll(state[2], 1)) / dt**2
    predicted = 0.5 * (moment + np.roll(moment, 1))
    return float(np.abs(inertia * second - predicted).max()), float(np.abs(moment).max())


def within_envelope(params: Params, floor: GaitFloor) -> bool:
    """Whether the floor's stance torques, with the motors' friction at their joint speeds, lie
    inside the actuator's envelope at those speeds in both quadrants."""
    motor = params.motor
    delivered = floor.torque_Nm + motor.friction(floor.speed_rad_s)
    upper, lower = motor.limits(floor.speed_rad_s)
    return bool(np.all((delivered <= upper + 1e-9) & (delivered >= lower - 1e-9)))


def fastest_joint(params: Params, path) -> float:
    """The largest joint speed (rad/s) along the path over a period (SPEED_SAMPLES), from its
    exact foot velocity: J_F^-1 v at each pose."""
    leg, gait = params.fivebar_leg, params.gait
    points = evaluate(gait, path, np.arange(SPEED_SAMPLES) / SPEED_SAMPLES * gait.period_s)
    jf = leg.tool_jacobian(leg.inverse(points.pos, KNEES_OUT))
    return float(np.abs(np.linalg.solve(jf, points.vel[..., None])).max())


def fastest_gait(params: Params, kind: str, payload_kg: float = 0.0) -> dict:
    """The fastest gait of this kind the legs and motors allow for any controller, at its own
    stride and duty factor (the path's gait defaults over the parameter file's): the highest
    frequency (Hz) and speed (m/s) whose floor (gait_floor) lies inside the envelope at its
    stance joint speeds (within_envelope) and whose path keeps every joint, swing included,
    below the motors' no-load speed (the path scaled in time: joint speeds grow with the
    frequency, so that limit is f * no-load / the fastest joint at f, fastest_joint). Bisection (SPEED_STEPS)
    up from the gait's own frequency (the floor grows with the frequency); limited_by names what stopped it ("speed", "torque", or
    "its own frequency": the gait itself does not pass, frequency nan)."""
    base = with_path_defaults(params, kind)
    path, f0 = foot_path(kind), base.gait.frequency_hz
    joint = fastest_joint(base, path)
    top = f0 * params.motor.no_load_speed_rad_s / joint

    def passes(f: float) -> bool:
        try:
            return within_envelope(base, gait_floor(with_gait(base, frequency_hz=f), path,
                                                    payload_kg))
        except ParameterError:
            return False

    low, limited = f0, "torque"
    if not passes(low):
        low, limited = math.nan, "its own frequency"
    elif passes(top):
        low, limited = top, "speed"
    else:
        high = top
        for _ in range(SPEED_STEPS):
            middle = 0.5 * (low + high)
            low, high = (middle, high) if passes(middle) else (low, middle)
    speed = path.stance_speed(with_gait(base, frequency_hz=low).gait) if low == low else math.nan
    return {"frequency_hz": low, "speed_m_s": speed, "limited_by": limited,
            "speed_limit_frequency_hz": top, "gait_frequency_hz": f0,
            "gait_speed_m_s": path.stance_speed(base.gait)}
