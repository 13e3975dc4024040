"""The quadruped's leg control law, compiled: one controller tick of FootLegController.

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). The torque vector (8) is in the plant's actuation order. The law (see
systems.FootLegController for the whole description):

- swing: joint PD to the closed-form IK (knees out) of the target, moved by the catch reflex, with
  the full model's inverse dynamics of the target's motion (links' M q'' + c + G, reflected rotor
  inertia) as feed-forward;
- stance: the links' weight plus -J_F^T F with the ground forces F that produce the body wrench
  (height, forward speed, roll, pitch) at least weighted norm, F_z >= 0, inside the friction cone;
- support on measured contact (support_weights): a foot takes load only once it is on the
  ground, measured by its mean normal ground force over the last controller period above
  CONTACT_LOAD_SHARE of its standing load (an ideal foot-force sensor: the plant's
  generalized contact forces on the joints B and D through J_P^-T, contact_force_plane);
  its weight w rises from that contact over the load transfer time, never before it;
  a swing foot that has been in the air and lands before its schedule joins the support the
  same way (early touchdown), and its swing target never enters the body's targets;
- the stance feet's ground forces F come from a stage, the stance law (stance_laws.py; the
  default, ground_forces, is the virtual model above): the law is compiled in its own module and
  called between the plan (leg_plan) and the torques (leg_torques), so swapping it recompiles
  nothing and every kernel stays cached on disk;
- each leg blends the swing command and the links' weight with its weight w and adds the push
  -J_F^T F in full: the ground forces' least-squares split is already weighted by w (a foot
  with w -> 0 gets none), so the feet on the ground deliver the whole wrench at every w
  (blending the push by w again lost force mid transfer: 11 % of the weight with one foot
  leaving a standing robot), once their weights' sum reaches the schedule's (up to one foot's
  worth); below it, after a flight or at a landing, they deliver that share of it, so the first
  feet down are not handed the whole landing at once.
"""

from __future__ import annotations

from typing import NamedTuple
import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.gaits import reference_parts, smoothstep
from fivebar_drake.core.rotation import body_rotation, wrap
from fivebar_drake.mechanisms.fivebar import (bias_at, coriolis_at, foot_from, forward_pose,
                                              inverse_pose, link_jacobians_at, mass_matrix_at,
                                              pose_jacobians, static_at)
from fivebar_drake.robots.quadruped.plant import StateIndices


MOMENT_LEVER_M = 0.1       # the wrench fit weighs a moment like a force at this lever
CONTACT_LOAD_SHARE = 0.05  # a foot is on the ground when its measured normal force exceeds this
#                            share of its standing load m g / legs (0.8 N on the default robot):
#                            above the mean of a grazing swing foot over a period, far below a
#                            foot taking load
SUPPORT_FIELDS = 4         # per leg (support_weights): on, early, since (s), aloft (s)
NOT_DUE = 1e9              # "since" of a foot out of the support and not due in it
FOREVER_S = 1e9            # "since" of a foot that stood before the run began
SEARCH_SPEED_M_S = 0.3     # a foot due on the ground and not on it reaches down at this speed
AIRBORNE_S = 0.01          # a swing foot is in the air once unloaded this long (the contact
#                            chatters for a few ms at lift-off)


class ControlGains(NamedTuple):
    """Gains of the law (SI). Swing: joint PD kp (N*m/rad), kd (N*m*s/rad). Body (virtual
    model): height kz (N/m), dz (N*s/m); forward speed dx (N*s/m); roll and pitch k_att
    (N*m/rad, per axis), d_att (N*m*s/rad, per axis)."""

    kp: float
    kd: float
    kz: float
    dz: float
    dx: float
    k_att: np.ndarray
    d_att: np.ndarray


class LawConstants(NamedTuple):
    """Everything the law needs, as plain numbers and arrays (SI). Plant indices: state
    (plant.StateIndices, the robot layout's). Robot: hips_m (legs, 3) and com_m (3,) in
    the body frame, mass_kg, plane (3, 3) = R_body_plane. Leg: geom (LegGeometry.core),
    com_fraction, masses, izz (4,) of the links, gravity, reflected_inertia (N^2 J_rotor).
    Gains (ControlGains). Feet: foot_radius_m, friction mu; stand_offset_m: the body height
    with the feet at leg-plane y = 0 (sdf.body_height(params, 0); it drops as y rises). Catch
    reflex: catch_gain, catch_rate_s, catch_limit_m (the step height); touchdown: early-touchdown
    detection on; support (3,) m/s^2: minus the plant's gravity in the world (the slope's frame),
    what the feet must give the body's mass (the links' weight is taken along the body's -z);
    contact_N: the measured normal force (N) above which a foot is on the ground; transfer_s:
    the time (s) over which a foot takes up its load from contact."""

    state: StateIndices
    hips_m: np.ndarray
    com_m: np.ndarray
    mass_kg: float
    plane: np.ndarray
    geom: tuple
    com_fraction: np.ndarray
    masses: np.ndarray
    izz: np.ndarray
    gravity: float
    reflected_inertia: float
    gains: ControlGains
    foot_radius_m: float
    stand_offset_m: float
    mu: float
    catch_gain: float
    catch_rate_s: float
    catch_limit_m: float
    touchdown: bool
    support: np.ndarray
    contact_N: float
    transfer_s: float


@jit
def _solve2(m, b0, b1, x):
    """x (2,) with m x = (b0, b1) for a (2, 2) matrix m."""
    det = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    x[0] = (m[1, 1] * b0 - m[0, 1] * b1) / det
    x[1] = (m[0, 0] * b1 - m[1, 0] * b0) / det


@jit
def feet_body(k, fx, fy):
    """Foot points (legs, 3) in the body frame from leg-plane feet (legs,)."""
    out = k.hips_m.copy()
    for leg in range(out.shape[0]):
        for i in range(3):
            out[leg, i] += k.plane[i, 0] * fx[leg] + k.plane[i, 1] * fy[leg]
    return out


@jit
def catch_offset(k, state, r_wb):
    """Swing foot target offsets (legs, 2) in m: a swing foot under a hip that the body's
    rotation sinks at dz' (m/s) reaches catch_gain catch_rate dz' further down (up under a rising
    hip), limited to the step height, so the foot on the side the body falls to lands a little
    early and catches it. The hip's drop itself needs no reflex: every target is put on the
    ground as it is (leg_plan)."""
    out = np.zeros((k.hips_m.shape[0], 2))
    if k.catch_gain == 0.0:
        return out
    w0 = k.state.nq + k.state.body_v
    for leg in range(out.shape[0]):
        h = k.hips_m[leg]
        hx, hy = (r_wb[0, 0] * h[0] + r_wb[0, 1] * h[1] + r_wb[0, 2] * h[2],
                  r_wb[1, 0] * h[0] + r_wb[1, 1] * h[1] + r_wb[1, 2] * h[2])
        dz_dot = state[w0] * hy - state[w0 + 1] * hx        # (omega x r)_z
        out[leg, 1] = min(max(k.catch_gain * k.catch_rate_s * dz_dot,
                              -k.catch_limit_m), k.catch_limit_m)
    return out


@jit
def contact_force_plane(bx, by, dx, dy, px, py, tau_b, tau_d):
    """The ground force (F_x, F_y) in N, leg plane, at the contact point P (m) on link DE from
    the generalized contact forces (N*m) on the joints B and D of the tree (the loop is cut at
    E): tau_B = (P - B)_perp . F, tau_D = (P - D)_perp . F, perp turning +90 deg about the
    hinge; B and D in m. NaN where P lies on the line BD (no solution)."""
    a00, a01, a10, a11 = by - py, px - bx, dy - py, px - dx
    det = a00 * a11 - a01 * a10
    return (a11 * tau_b - a01 * tau_d) / det, (a00 * tau_d - a10 * tau_b) / det


@jit
def foot_loads(k, state, contact_tau):
    """The measured normal ground force (legs,) in N (world z) on each foot from the plant
    state (nx,) and the mean generalized contact forces (nv,) of the last controller period."""
    r_wp = body_rotation(state[k.state.body_q:k.state.body_q + 4]) @ k.plane
    down_x, down_y = -k.foot_radius_m * r_wp[2, 0], -k.foot_radius_m * r_wp[2, 1]
    out = np.empty(k.state.q_index.shape[0])
    for leg in range(out.shape[0]):
        _, _, dx, dy, _, _, fx, fy = forward_pose(k.geom, state[k.state.q_index[leg, 0]],
                                                  state[k.state.q_index[leg, 1]], 1.0, True)
        f_x, f_y = contact_force_plane(k.geom[2], k.geom[3], dx, dy, fx + down_x, fy + down_y,
                                       contact_tau[k.state.contact_v_index[leg, 0]],
                                       contact_tau[k.state.contact_v_index[leg, 1]])
        out[leg] = r_wp[2, 0] * f_x + r_wp[2, 1] * f_y
    return out


@jit
def foot_clearance(k, fx, fy, state, r_wb):
    """Height (legs,) in m of each foot's lowest point above flat ground at z = 0, from the
    body's pose and the leg-plane feet fx, fy (m): the kinematic estimate."""
    feet_b = feet_body(k, fx, fy)
    out = np.empty(fx.shape[0])
    for leg in range(fx.shape[0]):
        out[leg] = (state[k.state.body_q + 6] + feet_b[leg, 0] * r_wb[2, 0]
                    + feet_b[leg, 1] * r_wb[2, 1] + feet_b[leg, 2] * r_wb[2, 2]
                    - k.foot_radius_m)
    return out


@jit
def support_weights(k, scheduled, descending, loads, memory, t):
    """Each foot's weight in the support (legs,) at time t (s) from its scheduled weight (0 in
    swing), whether its target moves down (legs,) and its measured normal force loads (N);
    memory (legs, SUPPORT_FIELDS) carries per leg (on, early, since, aloft: the time it was
    last loaded) from tick to tick and is updated in place; since: when the foot joined the
    support or, out of it, when its stance was due (NOT_DUE in its swing).

    A foot joins the support when it is measured on the ground (load > contact_N): in its
    scheduled stance (since = now), or, with touchdown detection, in its scheduled swing when
    it has been in the air at least AIRBORNE_S and its target is on the way down (an early
    touchdown). Its weight then rises from contact over transfer_s (smoothstep): min(scheduled,
    rise) in stance, so a foot down on time follows its schedule and a late one takes its load
    from when it lands; an early foot's weight is its rise until its schedule reaches full
    stance. It leaves the support when its schedule returns to swing (lift-off), or when it has
    been unloaded AIRBORNE_S in full stance (it lost the ground: it is due again); a scheduled
    stance foot not on the ground has weight 0."""
    out = np.zeros(scheduled.shape[0])
    for i in range(scheduled.shape[0]):
        on, early, since, aloft = memory[i, 0], memory[i, 1], memory[i, 2], memory[i, 3]
        loaded = loads[i] > k.contact_N
        if scheduled[i] <= 0.0:
            if on > 0.5 and early < 0.5:                     # lift-off by the schedule
                on = 0.0
            if on < 0.5:
                since = NOT_DUE
            if (on < 0.5 and k.touchdown and loaded and descending[i]
                    and t - aloft >= AIRBORNE_S):
                on, early, since = 1.0, 1.0, t
        else:
            if (on > 0.5 and early < 0.5 and scheduled[i] >= 1.0 and not loaded
                    and t - aloft >= AIRBORNE_S):            # lost the ground in full stance
                on, since = 0.0, t
            if on < 0.5:
                since = min(since, t)                        # due from now, or earlier
            if on < 0.5 and loaded:
                on, early, since = 1.0, 0.0, t
            if early > 0.5 and scheduled[i] >= 1.0:
                early = 0.0
        if loaded:
            aloft = t
        if on > 0.5:
            rise = smoothstep((t - since) / k.transfer_s) if k.transfer_s > 0.0 else 1.0
            out[i] = max(scheduled[i], rise) if early > 0.5 else min(scheduled[i], rise)
        memory[i, 0], memory[i, 1], memory[i, 2], memory[i, 3] = on, early, since, aloft
    return out


@jit
def body_targets(k, guides, targets, velocities, accelerations, state, r_wb):
    """The body's targets (height z* m, vertical speed z*' m/s and acceleration z*'' m/s^2 in
    the world, forward speed v_x* m/s in the body frame) from the targets of the feet weighted
    by guides (legs,: the feet on their scheduled stance): height stand_offset - y, vertical
    speed -y', acceleration -y'', forward speed the feet's x'; with no guide, the body's own
    height and speeds (nothing to correct) and no acceleration."""
    w0 = k.state.nq + k.state.body_v
    if guides.sum() <= 0.0:
        v_b = np.ascontiguousarray(r_wb.T) @ state[w0 + 3:w0 + 6]
        return state[k.state.body_q + 6], state[w0 + 5], 0.0, v_b[0]
    share = guides / guides.sum()
    return (k.stand_offset_m - np.sum(share * targets[:, 1]), -np.sum(share * velocities[:, 1]),
            -np.sum(share * accelerations[:, 1]), np.sum(share * velocities[:, 0]))


@jit
def body_attitude(k, state, r_wb):
    """(roll, pitch rad: the body's tilt about its x and y axes; its angular velocity (3,) rad/s
    in the body frame) from the plant state and the body's rotation r_wb (world from body)."""
    w0 = k.state.nq + k.state.body_v
    omega_b = np.ascontiguousarray(r_wb.T) @ state[w0:w0 + 3]
    return (np.arctan2(r_wb[2, 1], r_wb[2, 2]), -np.arcsin(min(max(r_wb[2, 0], -1.0), 1.0)),
            omega_b)


@jit
def ground_forces(k, body, weights, share, fx, fy, state, r_wb):
    """The virtual-model stance law (stance_laws.VirtualModel): ground forces on the feet
    (legs, 2) in N, leg-plane (x, y), from the body wrench in the body frame: F_x = m dx (v_x* - v_x), F_z = m (g + z*'') + kz (z* - z) + dz (z*' - z') (and
    m g's components along the slope: support), M_roll,pitch = -k_att angle - d_att rate, with
    the body's targets body = (z*, z*', z*'', v_x*) (body_targets), split over the feet by their
    weights (legs,), share (0 .. 1) of it."""
    n = weights.shape[0]
    total = weights.sum()
    if total <= 0.0:
        return np.zeros((n, 2))
    w0 = k.state.nq + k.state.body_v
    z = state[k.state.body_q + 6]
    r_bw = np.ascontiguousarray(r_wb.T)
    roll, pitch, omega_b = body_attitude(k, state, r_wb)
    v_w = state[w0 + 3:w0 + 6]
    v_b = r_bw @ v_w
    z_des, vz_des, az_des, vx_des = body
    force_w = np.array([k.mass_kg * k.support[0], k.mass_kg * k.support[1],
                        k.mass_kg * (k.support[2] + az_des) + k.gains.kz * (z_des - z)
                        + k.gains.dz * (vz_des - v_w[2])])
    force_b = r_bw @ force_w
    force_b[0] += k.gains.dx * (vx_des - v_b[0])
    wrench = np.array([force_b[0], force_b[2],
                       -k.gains.k_att[0] * roll - k.gains.d_att[0] * omega_b[0],
                       -k.gains.k_att[1] * pitch - k.gains.d_att[1] * omega_b[1], 0.0])
    sol = split_wrench(k, weights, fx, fy, wrench, 5) * share
    return plane_forces(k, sol[0::2], sol[1::2])


@jit
def split_wrench(k, weights, fx, fy, wrench, rows):
    """The ground forces (2 n,: body-frame x and z per foot) of least weighted norm (weights
    (legs,); a foot of weight 0 gets none) whose net wrench about the centre of mass, in the
    body frame, is the first `rows` of wrench (F_x, F_z, M_roll, M_pitch, M_yaw), moments
    weighed as forces at MOMENT_LEVER_M; the feet at the measured leg-plane fx, fy (legs,)."""
    n = weights.shape[0]
    r = feet_body(k, fx, fy) - k.com_m
    # unknowns per foot: ground force along body x and z; rows: Fx, Fz, Mx, My, Mz
    a = np.zeros((5, 2 * n))
    for i in range(n):
        a[0, 2 * i], a[1, 2 * i + 1] = 1.0, 1.0
        a[2, 2 * i + 1] = r[i, 1]                              # Mx = y Fz
        a[3, 2 * i], a[3, 2 * i + 1] = r[i, 2], -r[i, 0]       # My = z Fx - x Fz
        a[4, 2 * i] = -r[i, 1]                                 # Mz = -y Fx
    scale = np.array([1.0, 1.0, 1.0 / MOMENT_LEVER_M, 1.0 / MOMENT_LEVER_M, 1.0 / MOMENT_LEVER_M])
    sw = np.sqrt(np.repeat(weights, 2))
    fit = np.ascontiguousarray(((a * scale[:, None]) * sw)[:rows])
    return np.linalg.lstsq(fit, np.ascontiguousarray((wrench * scale)[:rows]),
                           rcond=1e-6)[0] * sw


@jit
def plane_forces(k, fxb, fz):
    """Ground forces given along the body's x and z per foot (legs,) each, pushing (F_z >= 0)
    inside the friction cone (|F_x| <= mu F_z), in the leg planes (legs, 2) N."""
    fz = np.maximum(fz, 0.0)
    fxb = np.minimum(np.maximum(fxb, -k.mu * fz), k.mu * fz)
    out = np.empty((fz.shape[0], 2))
    for j in range(2):      # body (x, 0, z) -> leg plane: F_plane = R_body_plane^T F_body
        out[:, j] = k.plane[0, j] * fxb + k.plane[2, j] * fz
    return out


class LegPlan(NamedTuple):
    """A tick's plan (leg_plan) before the stance feet's ground forces: base (8) N*m in
    actuation order, each leg's swing command and links' weight blended by its weight w; goal
    (legs, 2) m the swing IK targets; what a stance law takes (StanceLaw.forces): body (4,) the
    body's targets (body_targets: z* m, z*' m/s, z*'' m/s^2, v_x* m/s), weights (legs,) the
    feet's support, share (0 .. 1) of the wrench they deliver, fx, fy (legs,) m the measured
    leg-plane feet, r_wb (3, 3) the body's rotation; jf (legs, 2, 2) the foot Jacobians at the
    measured poses (leg_torques)."""

    base: np.ndarray
    goal: np.ndarray
    body: tuple
    weights: np.ndarray
    share: float
    fx: np.ndarray
    fy: np.ndarray
    r_wb: np.ndarray
    jf: np.ndarray


@jit
def leg_plan(k, references, state, loads, memory, t):
    """The tick's LegPlan at time t (s) from the foot references (gaits.reference_parts:
    targets, velocities, accelerations (legs, 2) each, scheduled stance weights (legs,)), the
    plant state (nx,) and the feet's measured normal forces (legs,) in N (foot_loads); memory
    (legs, SUPPORT_FIELDS): the feet's support (support_weights), updated in place. A foot due
    in stance that is not yet on the ground reaches down to it (its kinematic clearance,
    foot_clearance) at SEARCH_SPEED_M_S from when it was due. NaN where a target is out of reach
    or the legs cannot close."""
    targets, velocities, accelerations, weights = reference_parts(references)
    n = weights.shape[0]
    r_wb = body_rotation(state[k.state.body_q:k.state.body_q + 4])
    swing, stance, jf_now = np.empty((n, 2)), np.empty((n, 2)), np.empty((n, 2, 2))
    fx, fy = np.empty(n), np.empty(n)
    pts, jac, acc = np.empty((5, 2)), np.empty((5, 2, 2)), np.empty((5, 2))
    jv, jw, jf = np.empty((4, 2, 2)), np.empty((4, 2)), np.empty((2, 2))
    av, aw, af = np.empty((4, 2)), np.empty(4), np.empty(2)
    m, c, weight, foot = np.empty((2, 2)), np.empty(2), np.empty(2), np.empty(2)
    qd_des, qdd_des = np.empty(2), np.empty(2)
    for i in range(n):
        # stance: virtual model, links' weight at the measured pose
        cx, cy, dx, dy, ex, ey, fx[i], fy[i] = forward_pose(
            k.geom, state[k.state.q_index[i, 0]], state[k.state.q_index[i, 1]], 1.0, True)
        pose_jacobians(k.geom, cx, cy, dx, dy, ex, ey, pts, jac)
        link_jacobians_at(k.geom, k.com_fraction, pts, jac, jv, jw)
        foot_from(k.geom, jac[4], jac[3], jf_now[i])
        static_at(k.masses, k.gravity, 0.0, jv, jf_now[i], stance[i], foot)
    scheduled = weights
    weights = support_weights(k, scheduled, velocities[:, 1] < 0.0, loads, memory, t)
    guides = np.where(memory[:, 1] > 0.5, 0.0, weights)      # early feet guide nothing
    body = body_targets(k, guides, targets, velocities, accelerations, state, r_wb)
    goal = targets + catch_offset(k, state, r_wb)
    if guides.sum() > 0.0:   # feet out of the support land on the ground as it is now
        ground = k.stand_offset_m - body[0]            # the stance feet's y with the body at z*
        clearance = foot_clearance(k, targets[:, 0], targets[:, 1], state, r_wb)
        for i in range(n):
            goal[i, 1] += max(targets[i, 1] - ground, 0.0) - clearance[i]
    velocities, accelerations = velocities.copy(), accelerations.copy()
    for i in range(n):
        if scheduled[i] > 0.0 and memory[i, 0] < 0.5:    # due, not down: reach further down
            goal[i, 1] -= SEARCH_SPEED_M_S * (t - memory[i, 2])
        # the target moves by at most the step height (the path's own lift) from its plan:
        # a body far from its height is not followed out of the leg's reach
        goal[i, 1] = min(max(goal[i, 1], targets[i, 1] - k.catch_limit_m),
                         targets[i, 1] + k.catch_limit_m)
        if memory[i, 1] > 0.5:                           # down early: it stays where it is
            goal[i, 0], goal[i, 1] = fx[i], fy[i]
            velocities[i], accelerations[i] = 0.0, 0.0
    for i in range(n):
        qa, qb = state[k.state.q_index[i, 0]], state[k.state.q_index[i, 1]]
        qda, qdb = state[k.state.nq + k.state.v_index[i, 0]], state[k.state.nq + k.state.v_index[i, 1]]
        # swing: IK of the target (moved by the catch reflex, onto the ground as it is, or
        # down to it), its rates and accelerations, inverse-dynamics feed-forward
        ta, tb, cx, cy, dx, dy, ex, ey = inverse_pose(k.geom, goal[i, 0], goal[i, 1], 1.0, 1.0)
        pose_jacobians(k.geom, cx, cy, dx, dy, ex, ey, pts, jac)
        link_jacobians_at(k.geom, k.com_fraction, pts, jac, jv, jw)
        foot_from(k.geom, jac[4], jac[3], jf)
        _solve2(jf, velocities[i, 0], velocities[i, 1], qd_des)
        bias_at(k.geom, k.com_fraction, pts, jac, qd_des[0], qd_des[1], acc, av, aw, af)
        _solve2(jf, accelerations[i, 0] - af[0], accelerations[i, 1] - af[1], qdd_des)
        static_at(k.masses, k.gravity, 0.0, jv, jf, weight, foot)
        mass_matrix_at(k.masses, k.izz, jv, jw, m)
        coriolis_at(k.masses, k.izz, jv, jw, av, aw, c)
        for j, (q_des, q, qd) in enumerate(((ta, qa, qda), (tb, qb, qdb))):
            ff = (m[j, 0] * qdd_des[0] + m[j, 1] * qdd_des[1] + c[j] + weight[j]
                  + k.reflected_inertia * qdd_des[j])
            swing[i, j] = k.gains.kp * wrap(q_des - q) + k.gains.kd * (qd_des[j] - qd) + ff
    # the feet on the ground deliver the share of the wrench the schedule expects of the feet
    # down (all of it once their weights reach the schedule's, up to one foot's worth): the
    # first feet down after a flight or at a landing take it up as their weights rise
    expected = min(scheduled.sum(), 1.0)
    share = min(weights.sum() / expected, 1.0) if expected > 0.0 else min(weights.sum(), 1.0)
    base = np.zeros(2 * n)
    for i in range(n):
        for j in range(2):          # a leg wholly in stance needs no reachable swing target
            swung = (1.0 - weights[i]) * swing[i, j] if weights[i] < 1.0 else 0.0
            base[k.state.actuators[i, j]] = weights[i] * stance[i, j] + swung
    return LegPlan(base, goal, body, weights, share, fx, fy, r_wb, jf_now)


@jit
def leg_torques(actuators, base, jf, forces):
    """(torque command (8) N*m in actuation order, whether it is finite): the plan's base
    (LegPlan) less -J_F^T F of each leg's ground force F (legs, 2) N, in full: the stance law's
    split already gives each foot its share (none at w = 0), so the feet deliver the whole
    wrench while a foot takes up or gives off its load. actuators (legs, 2): the motors'
    indices in actuation order."""
    out = base.copy()
    for i in range(jf.shape[0]):
        for j in range(2):
            out[actuators[i, j]] -= jf[i, 0, j] * forces[i, 0] + jf[i, 1, j] * forces[i, 1]
    return out, np.all(np.isfinite(out))
