"""The vertical jump as an optimal-control problem of one leg: the highest jump the legs and
motors allow (the ceiling) and the least peak motor torque that reaches a height (the floor),
for any controller.

Model. A vertical jump of all four legs in phase is symmetric: each leg carries a quarter of
the robot (m_q: a quarter of the body and payload plus its own links), the body does not pitch
or roll (its centre of mass between the hips), and the leg's foot stays where it stands (no
slip). One degree of freedom remains: the hip's height u above the foot point (u = -y of the
foot in the leg plane, x = x_center). Along it the package's own closed-form IK (knees out,
[limits] held) gives q(u), q'(u) = J_F^-1 (0, -1) and q''(u) (second-order differences on a
fine grid). With the hip's speed w = u' and acceleration b = u'' (x = w^2):

    tau = (M(q) + N^2 J_rotor) q'' + c(q, q') + G(q) (1 + b/g) - J_F^T F

with q' = q_u w, q'' = q_u b + q_uu x (the links' and the rotors' inertia and the links' weight
in the hip's accelerating frame, the package's own M, c, G) and the ground force from Newton's
law on the quarter robot: F_y = m_q (g + b) + Y_uu x + Y_u b, F_x = X_uu x + X_u b, X, Y the
links' first moments about the hip (the body does not move sideways: the links' horizontal
motion is all the foot must push). So tau = alpha b + beta x + gamma, affine in (b, x), as are
F_x and F_y. What is neglected: the body's pitch (the centre of mass is between the hips), the
foot's rolling (a point foot), the contact's compliance (rigid ground) and the bushing's gap.

Each motor's delivered torque tau + friction(omega), omega = q_u w, must lie within the
actuator's envelope at omega (both quadrants, Motor.limits) and, for the floor, within +-T;
the foot stays on the ground (F_y >= 0) inside the friction cone (|F_x| <= mu F_y).

The ceiling: in the phase plane x(u) the acceleration bound b <= b_max(u, x) holds for every
admissible motion, so integrating x' = 2 b_max(u, x) from rest gives the largest speed at every
u (the comparison lemma): the highest jump takes off where its centre of mass's apex, z_com +
v_com^2 / 2g, is highest. The floor of a jump to a height: the least T whose ceiling reaches
it (bisection; the ceiling grows with T). A linear program over the same grid (Drake's
MathematicalProgram: tau linear in x and x') gives the floor within the torque box alone, a
second method for the same number where the envelope does not bind.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fivebar_drake.gaits import Jump as JumpPath, Landing
from fivebar_drake.actuators.motor import Motor, friction_torque, torque_limits
from fivebar_drake.core.compiled import jit
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import (KNEES_OUT, LINK_NAMES, held_force, limit_tests,
                                              link_coms, past_any)
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.params import Params

GRID_POINTS = 1500        # nodes along the stroke: the ceiling changes by < 0.1 mm from 750
FLOOR_TOLERANCE_NM = 1e-3  # the floor's bisection stops within this of the least torque
MARGIN_M = 1e-3           # the stroke stays this far inside the leg's limits


@dataclass(frozen=True)
class Stroke:
    """The leg along a vertical push, on a grid of the hip's height u (n,) above the foot point
    (m): joint angles q (n, 2) rad and dq/du (n, 2) rad/m; tau = alpha b + beta x + gamma
    (n, 2) N*m with b = u'' (m/s^2), x = u'^2 (m^2/s^2); the ground force F_x = fx @ (b, x),
    F_y = fy @ (b, x, 1) (n, 2) and (n, 3) N; the quarter robot's centre of mass above the hip
    com_m (n,) and its rate com_u (n,) (d com / du); the quarter mass m_q (kg), gravity g, the
    foot's friction mu and the motor."""

    u: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    gamma: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    com_m: np.ndarray
    com_u: np.ndarray
    m_q: float
    g: float
    mu: float
    motor: Motor


def quarter_mass_kg(params: Params, payload_kg: float = 0.0) -> float:
    """A quarter of the robot with its payload (kg): the robot's total mass holds the legs."""
    return (params.robot.total_mass_kg + payload_kg) / params.robot.legs


def reach(params: Params) -> tuple[float, float]:
    """The hip heights (m) above the foot point (x_center below the hip) the leg reaches within
    its [limits] and its IK, MARGIN_M inside: (deepest crouch, fullest extension)."""
    leg = params.fivebar_leg
    u = np.linspace(0.01, leg.geometry.ce_m + leg.geometry.ac_m + leg.geometry.ef_m, 4001)
    feet = np.stack([np.full_like(u, params.gait.x_center_m), -u], -1)
    pose = leg.inverse(feet, KNEES_OUT, strict=False)
    ok = np.isfinite(pose.q).all(-1) & ~past_any(limit_tests(params.leg, pose), u.shape)
    if not ok.any():
        raise ParameterError("no hip height puts the foot under the hip within [limits]",
                             "limits", "parameter file")
    inside = u[ok]
    return float(inside.min() + MARGIN_M), float(inside.max() - MARGIN_M)


def stroke(params: Params, u0: float, u1: float, payload_kg: float = 0.0,
           points: int = GRID_POINTS) -> Stroke:
    """The Stroke from hip height u0 to u1 (m above the foot point)."""
    leg, g = params.fivebar_leg, params.robot.gravity_m_s2
    u = np.linspace(u0, u1, points)
    feet = np.stack([np.full_like(u, params.gait.x_center_m), -u], -1)
    pose = leg.inverse(feet, KNEES_OUT)
    jf = leg.tool_jacobian(pose)                                   # (n, 2, 2)
    dq = np.linalg.solve(jf, np.broadcast_to([0.0, -1.0], u.shape + (2,))[..., None])[..., 0]
    ddq = np.gradient(dq, u, axis=0, edge_order=2)
    inertia = leg.mass_matrix(pose) + params.motor.reflected_inertia_kg_m2 * np.eye(2)
    coriolis = leg.bias_torques(pose, dq)                          # c(q, q_u), times x
    model = full_model(params)
    weight = leg.static_torques(
        type(model)(**{**model.__dict__, "foot_load_N": 0.0}), pose)   # G(q), links alone
    masses = np.array([params.links[n].mass_kg for n in LINK_NAMES])
    moments = np.einsum("l,nlk->nk", masses, link_coms(params.leg, params.links, pose))
    m_u = np.gradient(moments, u, axis=0, edge_order=2)            # (X_u, Y_u)
    m_uu = np.gradient(m_u, u, axis=0, edge_order=2)
    m_q = quarter_mass_kg(params, payload_kg)
    fx = np.stack([m_u[:, 0], m_uu[:, 0]], -1)
    fy = np.stack([m_q + m_u[:, 1], m_uu[:, 1], np.full_like(u, m_q * g)], -1)
    jt = np.swapaxes(jf, -1, -2)                                   # J_F^T

    def push(f):                                                   # J_F^T (F_x, F_y)
        return np.einsum("nij,nj->ni", jt, f)

    alpha = (np.einsum("nij,nj->ni", inertia, dq) + weight / g
             - push(np.stack([fx[:, 0], fy[:, 0]], -1)))
    beta = (np.einsum("nij,nj->ni", inertia, ddq) + coriolis
            - push(np.stack([fx[:, 1], fy[:, 1]], -1)))
    gamma = weight - push(np.stack([np.zeros_like(u), fy[:, 2]], -1))
    com = moments[:, 1] / m_q                  # the links' part; the body's is at the hip
    return Stroke(u, pose.q, dq, alpha, beta, gamma, fx, fy, com, m_u[:, 1] / m_q, m_q, g,
                  params.body.foot_friction, params.motor)


@jit
def _bounded(low, high, c1, c0):
    """(low, high, infeasible) of the acceleration interval after the row c1 b <= c0."""
    if c1 > 0:
        return low, min(high, c0 / c1), False
    if c1 < 0:
        return max(low, c0 / c1), high, False
    return low, high, c0 < 0


@jit
def acceleration_bounds(law, alpha, beta, gamma, fx, fy, dq, mu, w, peak_Nm):
    """(least, largest) hip acceleration b (m/s^2) at one node of a Stroke (its alpha, beta,
    gamma (2,), fx (2,), fy (3,), dq (2,) there; mu its foot friction) at hip speed w (m/s;
    > 0 rising, < 0 sinking): every motor's delivered torque within its envelope at its speed
    (law: actuators.motor.ActuatorLaw) and within +-peak_Nm, the foot on the ground inside its
    friction cone; (inf, -inf) where no b is admissible."""
    x = w * w
    low, high = -math.inf, math.inf
    for i in range(2):
        omega = dq[i] * w
        upper, lower = torque_limits(law, omega)
        rest = beta[i] * x + gamma[i] + friction_torque(law, omega)
        low, high, none = _bounded(low, high, alpha[i], min(upper, peak_Nm) - rest)
        if none:
            return math.inf, -math.inf
        low, high, none = _bounded(low, high, -alpha[i], rest - max(lower, -peak_Nm))
        if none:
            return math.inf, -math.inf
    fy_b, fy0 = fy[0], fy[1] * x + fy[2]
    fx_b, fx0 = fx[0], fx[1] * x
    for c1, c0 in ((-fy_b, fy0),                                     # F_y >= 0
                   (fx_b - mu * fy_b, mu * fy0 - fx0),               # F_x <= mu F_y
                   (-fx_b - mu * fy_b, mu * fy0 + fx0)):             # -F_x <= mu F_y
        low, high, none = _bounded(low, high, c1, c0)
        if none:
            return math.inf, -math.inf
    return low, high


@jit
def _push_nodes(law, alpha, beta, gamma, fx, fy, dq, u, mu, peak_Nm):
    """push's sweep up the stroke (arrays of a Stroke): (x = w^2, b) at the nodes reached,
    empty where the motors cannot start it from rest at the first node."""
    n = u.size
    x, b = np.zeros(n), np.zeros(n)
    end = n
    for k in range(n - 1):
        low, high = acceleration_bounds(law, alpha[k], beta[k], gamma[k], fx[k], fy[k], dq[k],
                                        mu, math.sqrt(x[k]), peak_Nm)
        if not high >= low or (k == 0 and high <= 0.0):      # no admissible push from here
            end = 0 if k == 0 else k + 1
            break
        b[k] = high
        x[k + 1] = max(x[k] + 2.0 * high * (u[k + 1] - u[k]), 0.0)
        if x[k + 1] == 0.0:
            end = k + 2
            break
    return x[:end], b[:end]


@jit
def _catch_nodes(law, alpha, beta, gamma, fx, fy, dq, u, mu, touchdown_speed, peak_Nm):
    """catch's sweep down the stroke from its top (arrays of a Stroke): (x = w^2, b, the node
    where the hip stops or -1, the lowest node reached)."""
    n = u.size
    x, b = np.zeros(n), np.zeros(n)
    x[n - 1] = touchdown_speed**2
    stop, last = -1, n - 1
    for k in range(n - 1, 0, -1):
        last = k
        low, high = acceleration_bounds(law, alpha[k], beta[k], gamma[k], fx[k], fy[k], dq[k],
                                        mu, -math.sqrt(x[k]), peak_Nm)
        if not high >= low:
            break                                     # the motors cannot hold it: gives way
        b[k] = high
        x[k - 1] = x[k] - 2.0 * high * (u[k] - u[k - 1])
        if x[k - 1] <= 0.0:
            x[k - 1], stop = 0.0, k - 1
            break
    return x, b, stop, last if stop < 0 else stop


@dataclass(frozen=True)
class Jump:
    """A vertical jump along a Stroke, pushed at the largest acceleration allowed: the nodes up
    to takeoff (node `takeoff`), the hip's speed w (m/s), acceleration b (m/s^2, over the cell
    from each node) and time (s) at each; over each cell before takeoff the motors' torques
    (cells, 2) N*m (joint) and delivered (with friction) at their speeds (cells, 2) rad/s; at takeoff the centre of mass's speed (m/s) and its apex above the crouch,
    above standing (m); the apex of the body (the hip) above standing with the legs held at the
    takeoff pose; the stance time and time to apex (s); which constraint bound the push most
    (per node: "A"/"B" a motor, "friction", "ground")."""

    stroke: Stroke
    takeoff: int
    w: np.ndarray
    b: np.ndarray
    t: np.ndarray
    torque_Nm: np.ndarray
    delivered_Nm: np.ndarray
    speed_rad_s: np.ndarray
    v_com: float
    com_rise_from_crouch_m: float
    com_rise_from_standing_m: float
    body_apex_above_standing_m: float
    stance_s: float
    to_apex_s: float

    @property
    def agility_m_s(self) -> float:
        """Vertical jumping agility (Haldane et al. 2016): the rise of the centre of mass from
        the crouch to the apex over the stance time plus the time to apex."""
        return self.com_rise_from_crouch_m / (self.stance_s + self.to_apex_s)


def body_apexes(s: Stroke, w: np.ndarray, standing_u: float) -> np.ndarray:
    """The body's (the hip's) apex above standing (m) of a takeoff at each of the stroke's
    first w.size nodes with the hip rising at w (m/s) there, the legs held at the takeoff pose
    in flight: the whole rises with the centre of mass, at w (1 + com_u)."""
    n = w.size
    return s.u[:n] + (w * (1.0 + s.com_u[:n])) ** 2 / (2.0 * s.g) - standing_u


def push(s: Stroke, standing_u: float, peak_Nm: float = math.inf) -> Jump | None:
    """The highest jump along the stroke (module docstring), torques within +-peak_Nm too;
    None if the motors cannot start it from rest at the crouch."""
    x, b = _push_nodes(s.motor.law, s.alpha, s.beta, s.gamma, s.fx, s.fy, s.dq, s.u, s.mu,
                       float(peak_Nm))
    if not x.size:
        return None
    w = np.sqrt(x)
    v_com = w * (1.0 + s.com_u[:w.size])
    z_com = s.u[:w.size] + s.com_m[:w.size]
    apex = z_com + v_com**2 / (2.0 * s.g)
    k = int(np.argmax(apex))
    if k == 0:
        return None
    dt = np.diff(s.u[:k + 1]) * 2.0 / np.maximum(w[:k] + w[1:k + 1], 1e-12)
    t = np.concatenate([[0.0], np.cumsum(dt)])
    omega = s.dq[:k] * w[:k, None]          # each cell's push, from its first node
    tau = s.alpha[:k] * b[:k, None] + s.beta[:k] * x[:k, None] + s.gamma[:k]
    com_stand = standing_u + float(np.interp(standing_u, s.u, s.com_m))
    return Jump(s, k, w[:k + 1], b[:k + 1], t, tau, tau + s.motor.friction(omega), omega,
                float(v_com[k]), float(apex[k] - z_com[0]), float(apex[k] - com_stand),
                float(body_apexes(s, w[:k + 1], standing_u)[k]), float(t[-1]),
                float(v_com[k] / s.g))


def point_mass_bound(params: Params, u0: float, u1: float, standing_u: float,
                     payload_kg: float = 0.0, points: int = GRID_POINTS) -> tuple[float, float]:
    """An upper bound, by another method, on the jump from hip height u0 (at rest) to u1: the
    quarter robot as a point at the hip on a massless, frictionless leg, pushed at every hip
    height and speed by the largest vertical foot force the motors hold there (their envelope
    at the joint speeds the hip's speed takes, through J_F^T: held_force), integrated over the
    stroke (the comparison lemma again: no motion of this model is faster). The links' inertia
    and weight, the motors' friction and the friction cone only take from the real jump.
    Returns (the largest takeoff speed m/s, the largest apex of the hip above standing m)."""
    leg, g, motor = params.fivebar_leg, params.robot.gravity_m_s2, params.motor
    u = np.linspace(u0, u1, points)
    pose = leg.inverse(np.stack([np.full_like(u, params.gait.x_center_m), -u], -1), KNEES_OUT)
    jf = leg.tool_jacobian(pose)
    rates = np.linalg.solve(jf, np.broadcast_to([0.0, -1.0], u.shape + (2,))[..., None])[..., 0]
    m = quarter_mass_kg(params, payload_kg)
    x = np.zeros(points)
    reached = 1                         # the nodes the hip reaches (from rest at u0)
    for k in range(points - 1):
        upper, lower = motor.limits(rates[k] * math.sqrt(x[k]))
        force = float(held_force(jf[k], upper, lower, np.array([0.0, 1.0])))
        x[k + 1] = max(x[k] + 2.0 * (force / m - g) * (u[k + 1] - u[k]), 0.0)
        if x[k + 1] == 0.0:
            break
        reached = k + 2
    apex = u[:reached] + x[:reached] / (2.0 * g)
    return float(np.sqrt(x.max())), float(apex.max() - standing_u)


def torque_floor(s: Stroke, standing_u: float, rise_m: float) -> tuple[float, Jump]:
    """The least peak motor torque (N*m, delivered) with which the stroke's highest jump
    lifts the body rise_m above its standing height (its apex with the legs held at the
    takeoff pose: the jump maneuver's height_m, as the simulation measures it), within the
    envelope too, and that jump (bisection to FLOOR_TOLERANCE_NM). ParameterError naming the
    ceiling if no torque the motors have reaches it."""
    best = push(s, standing_u)
    if best is None or best.body_apex_above_standing_m < rise_m:
        reached = ("the motors cannot lift the crouched robot" if best is None else
                   f"the highest jump rises {best.body_apex_above_standing_m * 1e3:.1f} mm")
        raise ParameterError(f"{rise_m * 1e3:.1f} mm above standing: beyond what the motors "
                             f"allow on this stroke ({reached})", "height_m")
    low, high, found = 0.0, float(np.abs(best.delivered_Nm).max()), best
    while high - low > FLOOR_TOLERANCE_NM:
        mid = 0.5 * (low + high)
        jump = push(s, standing_u, mid)
        if jump is not None and jump.body_apex_above_standing_m >= rise_m:
            high, found = mid, jump
        else:
            low = mid
    return high, found


def push_stroke(params: Params, path: JumpPath, payload_kg: float = 0.0) -> Stroke:
    """The Stroke of a jump maneuver's push (gaits.Jump): from its crouch, crouch_m
    above the standing line, to its takeoff, extension_m below it."""
    standing = -params.gait.y_home_m
    return stroke(params, standing - path.crouch_m, standing + path.extension_m, payload_kg)


def maneuver_push(params: Params, path: JumpPath, payload_kg: float = 0.0) -> Jump:
    """The optimal push of a jump maneuver (gaits.Jump; its height_m the apex above
    standing, m): the push of least peak torque that reaches height_m (torque_floor), or the
    highest (push) where none does. ParameterError if the motors cannot start it from the
    crouch."""
    standing, s = -params.gait.y_home_m, push_stroke(params, path, payload_kg)
    highest = push(s, standing)
    if highest is None:
        raise ParameterError("the motors cannot lift the crouched robot", "crouch_m")
    if highest.body_apex_above_standing_m < path.height_m:
        return highest
    return torque_floor(s, standing, path.height_m)[1]


def landing_stroke(params: Params, path: Landing, payload_kg: float = 0.0) -> Stroke:
    """The Stroke a maneuver's landing (gaits.Landing: a jump's or a drop's) stops the
    body within: its landing_stroke_m up to its touchdown pose, extension_m below standing."""
    top = -params.gait.y_home_m + path.extension_m
    return stroke(params, top - path.landing_stroke_m, top, payload_kg)


def box_floor_lp(s: Stroke, standing_u: float, rise_m: float) -> tuple[float, str]:
    """(The least peak joint torque (N*m), the solver that found it) of a jump along the whole
    stroke (taking off at its end) that lifts the body rise_m above standing (as torque_floor),
    within the torque box alone (no friction, no speed limit), with the foot on the ground
    inside its friction cone: a linear program in x = u'^2 over the grid (Drake's MathematicalProgram; tau is linear in x and
    x'). A second method: where the envelope does not bind, torque_floor's jump taking off at
    the stroke's end has the same floor."""
    from pydrake.solvers import MathematicalProgram, Solve

    n = s.u.size
    prog = MathematicalProgram()
    x = prog.NewContinuousVariables(n, "x")
    peak = prog.NewContinuousVariables(1, "peak")[0]
    prog.AddBoundingBoxConstraint(0.0, 0.0, x[0])
    prog.AddBoundingBoxConstraint(0.0, np.inf, x)
    du = np.diff(s.u)
    for k in range(n - 1):
        b = (x[k + 1] - x[k]) / (2.0 * du[k])
        for i in range(2):
            tau = s.alpha[k, i] * b + s.beta[k, i] * x[k] + s.gamma[k, i]
            prog.AddLinearConstraint(tau <= peak)
            prog.AddLinearConstraint(tau >= -peak)
        fy = s.fy[k, 0] * b + s.fy[k, 1] * x[k] + s.fy[k, 2]
        fx = s.fx[k, 0] * b + s.fx[k, 1] * x[k]
        prog.AddLinearConstraint(fy >= 0.0)
        prog.AddLinearConstraint(fx <= s.mu * fy)
        prog.AddLinearConstraint(-fx <= s.mu * fy)
    # the body's apex, the legs held at the takeoff pose (the last node): the hip rises with
    # the centre of mass after takeoff, (w (1 + com_u))^2 / 2g
    need = standing_u + rise_m - s.u[-1]
    prog.AddLinearConstraint(x[-1] * (1.0 + s.com_u[-1]) ** 2 / (2.0 * s.g) >= need)
    prog.AddLinearCost(peak)
    result = Solve(prog)
    if not result.is_success():
        raise RuntimeError(f"the linear program failed: {result.get_solution_result()} "
                           f"({result.get_solver_id().name()})")
    return float(result.GetSolution(peak)), result.get_solver_id().name()


@dataclass(frozen=True)
class Catch:
    """A landing along a Stroke, braked at the largest deceleration allowed from touchdown at
    the stroke's top node: the node where the hip comes to rest (`stop`, None: it does not
    within the stroke), the distance it sank (m), the time (s), and over each cell the motors'
    joint and delivered torques (cells, 2) N*m at their speeds (cells, 2) rad/s, each cell's
    from its upper node; the hip's speed w (m/s, <= 0) at the nodes from the lowest (the stop)
    to the top."""

    stroke: Stroke
    stop: int | None
    sink_m: float
    duration_s: float
    torque_Nm: np.ndarray
    delivered_Nm: np.ndarray
    speed_rad_s: np.ndarray
    w: np.ndarray


def catch(s: Stroke, touchdown_speed: float, peak_Nm: float = math.inf) -> Catch:
    """The landing that stops soonest (the comparison lemma, sinking: the largest upward
    acceleration at every state leaves the least speed at every height) from the hip sinking at
    touchdown_speed (m/s) at the stroke's top; torques within +-peak_Nm too. The foot's impact
    is not modelled: the hip keeps its speed through it (the links' momentum lost at impact
    would help; the floor is that much too high)."""
    n = s.u.size
    x, b, stop, first = _catch_nodes(s.motor.law, s.alpha, s.beta, s.gamma, s.fx, s.fy, s.dq,
                                     s.u, s.mu, float(touchdown_speed), float(peak_Nm))
    stop = None if stop < 0 else stop
    cells = slice(first + 1, n)
    w = -np.sqrt(x)
    omega = s.dq[cells] * w[cells, None]
    tau = s.alpha[cells] * b[cells, None] + s.beta[cells] * x[cells, None] + s.gamma[cells]
    dt = np.diff(s.u[first:]) * 2.0 / np.maximum(-(w[first:-1] + w[first + 1:]), 1e-12)
    return Catch(s, stop, float(s.u[-1] - s.u[first]), float(dt.sum()), tau,
                 tau + s.motor.friction(omega), omega, w[first:])


def landing_floor(s: Stroke, touchdown_speed: float) -> tuple[float, Catch]:
    """The least peak motor torque (N*m, delivered) with which the legs stop the hip within
    the stroke from touchdown_speed (m/s) at its top, within the envelope (braking: the speeds
    are negative), and that landing (bisection). ParameterError if the motors cannot stop it
    within the stroke (the legs give way)."""
    best = catch(s, touchdown_speed)
    if best.stop is None:
        raise ParameterError(f"a touchdown at {touchdown_speed:.2f} m/s: the legs cannot stop "
                             f"the body within {(s.u[-1] - s.u[0]) * 1e3:.0f} mm of stroke "
                             "(they give way)", "landing_stroke_m")
    low, high, found = 0.0, float(np.abs(best.delivered_Nm).max()), best
    while high - low > FLOOR_TOLERANCE_NM:
        mid = 0.5 * (low + high)
        trial = catch(s, touchdown_speed, mid)
        if trial.stop is not None:
            high, found = mid, trial
        else:
            low = mid
    return high, found


def highest_drop(s: Stroke, tolerance_m_s: float = 1e-3) -> float:
    """The largest touchdown speed (m/s) at the stroke's top that the legs stop within it
    (bisection on catch)."""
    low, high = 0.0, 1.0
    while catch(s, high).stop is not None:
        low, high = high, 2.0 * high
    while high - low > tolerance_m_s:
        mid = 0.5 * (low + high)
        low, high = (mid, high) if catch(s, mid).stop is not None else (low, mid)
    return low


@dataclass(frozen=True)
class Need:
    """What any controller needs for one phase of a maneuver (jump_need, landing_need): status
    "floor" (floor_Nm the least peak motor torque of the one-leg model, on the maneuver's
    stroke or, beyond what that stroke allows, on the leg's whole reach: why says which),
    "undecided" (beyond the model's optimum over the whole reach, within the bound by another
    method or where there is none: a controller's run decides) or "beyond bound" (beyond
    point_mass_bound: no motion does it); the stroke's and the whole reach's optimum (m: a
    jump's body apex above standing, a landing's highest drop) and the bound (m, None: none);
    found: the floor's motion (a Jump or a Catch; None without a floor)."""

    status: str
    floor_Nm: float | None
    why: str
    stroke_optimum_m: float | None
    reach_optimum_m: float | None = None
    bound_m: float | None = None
    found: object = None


def _apex(jump: Jump | None) -> float | None:
    """A jump's body apex above standing (m); None for none or one below standing (no jump)."""
    if jump is None or jump.body_apex_above_standing_m <= 0.0:
        return None
    return jump.body_apex_above_standing_m


def jump_need(params: Params, path: JumpPath, payload_kg: float = 0.0) -> Need:
    """The push-off's need for the jump maneuver path (its height_m above standing): the floor
    on its own stroke (push_stroke); beyond that stroke's highest jump, the floor on the leg's
    whole reach (a deeper crouch, a fuller extension); beyond that, undecided up to the point-mass
    bound over the whole reach and beyond bound above it."""
    standing, height = -params.gait.y_home_m, path.height_m
    own = push_stroke(params, path, payload_kg)
    stroke_top = _apex(push(own, standing))
    try:
        floor, found = torque_floor(own, standing, height)
        return Need("floor", floor, "", stroke_top, found=found)
    except ParameterError:
        pass
    u0, u1 = reach(params)
    whole = stroke(params, u0, u1, payload_kg)
    reach_top = _apex(push(whole, standing))
    bound = point_mass_bound(params, u0, u1, standing, payload_kg)[1]
    figures = dict(stroke_optimum_m=stroke_top, reach_optimum_m=reach_top, bound_m=bound)
    mm = height * 1e3
    own_text = ("its stroke cannot start it" if stroke_top is None else
                f"its stroke's highest is {stroke_top * 1e3:.1f} mm")
    try:
        floor, found = torque_floor(whole, standing, height)
        return Need("floor", floor, f"{mm:.1f} mm: {own_text}; the floor is on the leg's whole "
                    f"reach (a deeper crouch and a fuller extension)", **figures, found=found)
    except ParameterError:
        pass
    if height > bound:
        return Need("beyond bound", None, f"{mm:.1f} mm is beyond the bound of "
                    f"{bound * 1e3:.1f} mm (a point mass on massless legs pushed by the motors' "
                    f"envelope over the leg's whole reach): no motion of the legs does it",
                    **figures)
    top = "no jump" if reach_top is None else f"{reach_top * 1e3:.1f} mm"
    return Need("undecided", None, f"{mm:.1f} mm lies between the one-leg model's highest "
                f"jump over the leg's whole reach ({top}) and the bound of {bound * 1e3:.1f} mm "
                "(a point mass on massless legs): undecided, a controller's run decides "
                "(controller: {kind: tracking})", **figures)


def landing_need(params: Params, path: Landing, payload_kg: float = 0.0) -> Need:
    """The landing's need for the maneuver path (a jump's or a drop's): the floor stopping its
    touchdown speed within its landing stroke (landing_stroke, braking); where the legs give way
    there, the floor over the leg's whole reach below the touchdown pose; where they give way
    even there, undecided (no bound by another method for a landing)."""
    speed, g = path.touchdown_speed(params.gait), params.robot.gravity_m_s2
    own = landing_stroke(params, path, payload_kg)
    drop = highest_drop(own) ** 2 / (2.0 * g)
    try:
        floor, found = landing_floor(own, speed)
        return Need("floor", floor, "", drop, found=found)
    except ParameterError as err:
        given_way = err.message
    whole = stroke(params, reach(params)[0], float(own.u[-1]), payload_kg)
    whole_drop = highest_drop(whole) ** 2 / (2.0 * g)
    try:
        floor, found = landing_floor(whole, speed)
        return Need("floor", floor, f"{given_way}; the floor is over the leg's whole reach "
                    f"({(whole.u[-1] - whole.u[0]) * 1e3:.0f} mm)", drop, whole_drop,
                    found=found)
    except ParameterError as err:
        return Need("undecided", None, f"{err.message}, even over the leg's whole reach (the "
                    f"one-leg model's highest drop {whole_drop * 1e3:.0f} mm): undecided, no "
                    "bound by another method", drop, whole_drop)
