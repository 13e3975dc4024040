"""The quadruped's leg control law, compiled: one controller tick of FootLegController.

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). The torque vector (8) is in the plant's actuation order. The law (see
systems.FootLegController for the whole description):

- swing: joint PD to the closed-form IK (knees out) of the target, moved by the catch reflex, with
  the full model's inverse dynamics of the target's motion (links' M q'' + c + G, reflected rotor
  inertia) as feed-forward;
- stance: the links' weight plus -J_F^T F with the ground forces F that produce the body wrench
  (height, forward speed, roll, pitch) at least weighted norm, F_z >= 0, inside the friction cone;
- each leg blends the swing command and the links' weight with its stance weight w (raised by
  early touchdown) and adds the push -J_F^T F in full: the ground forces' least-squares split
  is already weighted by w (a foot with w -> 0 gets none), so the feet deliver the whole
  wrench at every w (blending the push by w again lost force mid transfer: 11 % of the weight
  with one foot leaving a standing robot).
"""

from __future__ import annotations

from typing import NamedTuple
import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.rotation import body_rotation, wrap
from fivebar_drake.mechanisms.fivebar import (bias_at, coriolis_at, foot_from, forward_pose,
                                              inverse_pose, link_jacobians_at, mass_matrix_at,
                                              pose_jacobians, static_at)
from fivebar_drake.robots.quadruped.plant import StateIndices


TOUCHDOWN_BAND_M = 0.004   # a descending swing foot this close to the ground joins the support
MOMENT_LEVER_M = 0.1       # the wrench fit weighs a moment like a force at this lever


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
    what the feet must give the body's mass (the links' weight is taken along the body's -z)."""

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


@jit
def _solve2(m, b0, b1, x):
    """x (2,) with m x = (b0, b1) for a (2, 2) matrix m."""
    det = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    x[0] = (m[1, 1] * b0 - m[0, 1] * b1) / det
    x[1] = (m[0, 0] * b1 - m[1, 0] * b0) / det


@jit
def _feet_body(k, fx, fy):
    """Foot points (legs, 3) in the body frame from leg-plane feet (legs,)."""
    out = k.hips_m.copy()
    for leg in range(out.shape[0]):
        for i in range(3):
            out[leg, i] += k.plane[i, 0] * fx[leg] + k.plane[i, 1] * fy[leg]
    return out


@jit
def catch_offset(k, state, r_wb):
    """Swing foot target offsets (legs, 2) in m: a swing leg under a hip that the body's tilt
    lowers by dz reaches down by catch_gain (dz + catch_rate dz') (and up under a rising hip),
    limited to the step height, so the foot on the side the body falls to lands early and
    catches it."""
    out = np.zeros((k.hips_m.shape[0], 2))
    if k.catch_gain == 0.0:
        return out
    w0 = k.state.nq + k.state.body_v
    for leg in range(out.shape[0]):
        h = k.hips_m[leg]
        hx, hy, hz = (r_wb[0, 0] * h[0] + r_wb[0, 1] * h[1] + r_wb[0, 2] * h[2],
                      r_wb[1, 0] * h[0] + r_wb[1, 1] * h[1] + r_wb[1, 2] * h[2],
                      r_wb[2, 0] * h[0] + r_wb[2, 1] * h[1] + r_wb[2, 2] * h[2])
        dz = hz - h[2]
        dz_dot = state[w0] * hy - state[w0 + 1] * hx        # (omega x r)_z
        out[leg, 1] = min(max(k.catch_gain * (dz + k.catch_rate_s * dz_dot),
                              -k.catch_limit_m), k.catch_limit_m)
    return out


@jit
def early_touchdown(k, fx, fy, velocities, state, r_wb):
    """Support weight (legs,) of swing feet that meet the ground early: a foot on its way down
    (target y' < 0) whose lowest point is within TOUCHDOWN_BAND_M of flat ground at z = 0
    (kinematic contact estimate: body pose and leg angles) joins the support: fully within half
    the band, fading out linearly to none at the band."""
    feet_b = _feet_body(k, fx, fy)
    out = np.zeros(fx.shape[0])
    for leg in range(fx.shape[0]):
        if velocities[leg, 1] < 0.0:
            clearance = (state[k.state.body_q + 6] + feet_b[leg, 0] * r_wb[2, 0]
                         + feet_b[leg, 1] * r_wb[2, 1] + feet_b[leg, 2] * r_wb[2, 2]
                         - k.foot_radius_m)
            out[leg] = min(max(2.0 - clearance / (0.5 * TOUCHDOWN_BAND_M), 0.0), 1.0)
    return out


@jit
def ground_forces(k, targets, velocities, accelerations, weights, fx, fy, state, r_wb):
    """Ground forces on the feet (legs, 2) in N, leg-plane (x, y), from the body wrench in the
    body frame: F_x = m dx (v_x* - v_x), F_z = m (g + z*'') + kz (z* - z) + dz (z*' - z') (and
    m g's components along the slope: support),
    M_roll,pitch = -k_att angle - d_att rate; body targets from the stance feet's targets
    (height stand_offset - y, vertical speed -y', forward speed the feet's x')."""
    n = weights.shape[0]
    total = weights.sum()
    if total <= 0.0:
        return np.zeros((n, 2))
    share = weights / total
    w0 = k.state.nq + k.state.body_v
    z = state[k.state.body_q + 6]
    r_bw = np.ascontiguousarray(r_wb.T)
    omega_b = r_bw @ state[w0:w0 + 3]
    v_w = state[w0 + 3:w0 + 6]
    v_b = r_bw @ v_w
    roll = np.arctan2(r_wb[2, 1], r_wb[2, 2])
    pitch = -np.arcsin(min(max(r_wb[2, 0], -1.0), 1.0))
    z_des = k.stand_offset_m - np.sum(share * targets[:, 1])
    vz_des = -np.sum(share * velocities[:, 1])
    az_des = -np.sum(share * accelerations[:, 1])
    vx_des = np.sum(share * velocities[:, 0])
    force_w = np.array([k.mass_kg * k.support[0], k.mass_kg * k.support[1],
                        k.mass_kg * (k.support[2] + az_des) + k.gains.kz * (z_des - z)
                        + k.gains.dz * (vz_des - v_w[2])])
    force_b = r_bw @ force_w
    force_b[0] += k.gains.dx * (vx_des - v_b[0])
    r = _feet_body(k, fx, fy) - k.com_m
    # unknowns per foot: ground force along body x and z; rows: Fx, Fz, Mx, My, Mz
    a = np.zeros((5, 2 * n))
    for i in range(n):
        a[0, 2 * i], a[1, 2 * i + 1] = 1.0, 1.0
        a[2, 2 * i + 1] = r[i, 1]                              # Mx = y Fz
        a[3, 2 * i], a[3, 2 * i + 1] = r[i, 2], -r[i, 0]       # My = z Fx - x Fz
        a[4, 2 * i] = -r[i, 1]                                 # Mz = -y Fx
    wrench = np.array([force_b[0], force_b[2],
                       -k.gains.k_att[0] * roll - k.gains.d_att[0] * omega_b[0],
                       -k.gains.k_att[1] * pitch - k.gains.d_att[1] * omega_b[1], 0.0])
    scale = np.array([1.0, 1.0, 1.0 / MOMENT_LEVER_M, 1.0 / MOMENT_LEVER_M, 1.0 / MOMENT_LEVER_M])
    sw = np.sqrt(np.repeat(weights, 2))
    sol = np.linalg.lstsq((a * scale[:, None]) * sw, wrench * scale, rcond=1e-6)[0] * sw
    fz = np.maximum(sol[1::2], 0.0)
    fxb = np.minimum(np.maximum(sol[0::2], -k.mu * fz), k.mu * fz)
    out = np.empty((n, 2))
    for j in range(2):      # body (x, 0, z) -> leg plane: F_plane = R_body_plane^T F_body
        out[:, j] = k.plane[0, j] * fxb + k.plane[2, j] * fz
    return out


@jit
def leg_command(k, references, state):
    """(torque command (8) in actuation order, swing IK targets (legs, 2) in m, whether the
    command is finite) from the foot references (footpath.foot_references: targets, velocities,
    accelerations (legs, 2) each, stance weights (legs,)) and the plant state (nx,). NaN where
    a target is out of reach or the legs cannot close."""
    n = references.shape[0] // 7
    targets, velocities = references[:2 * n].reshape(n, 2), references[2 * n:4 * n].reshape(n, 2)
    accelerations, weights = references[4 * n:6 * n].reshape(n, 2), references[6 * n:]
    r_wb = body_rotation(state[k.state.body_q:k.state.body_q + 4])
    goal = targets + catch_offset(k, state, r_wb)
    swing, stance, jf_now = np.empty((n, 2)), np.empty((n, 2)), np.empty((n, 2, 2))
    fx, fy = np.empty(n), np.empty(n)
    pts, jac, acc = np.empty((5, 2)), np.empty((5, 2, 2)), np.empty((5, 2))
    jv, jw, jf = np.empty((4, 2, 2)), np.empty((4, 2)), np.empty((2, 2))
    av, aw, af = np.empty((4, 2)), np.empty(4), np.empty(2)
    m, c, weight, foot = np.empty((2, 2)), np.empty(2), np.empty(2), np.empty(2)
    qd_des, qdd_des = np.empty(2), np.empty(2)
    for i in range(n):
        qa, qb = state[k.state.q_index[i, 0]], state[k.state.q_index[i, 1]]
        qda, qdb = state[k.state.nq + k.state.v_index[i, 0]], state[k.state.nq + k.state.v_index[i, 1]]
        # swing: IK of the target (moved by the catch reflex), its rates and accelerations,
        # inverse-dynamics feed-forward
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
        # stance: virtual model, links' weight at the measured pose
        cx, cy, dx, dy, ex, ey, fx[i], fy[i] = forward_pose(k.geom, qa, qb, 1.0, True)
        pose_jacobians(k.geom, cx, cy, dx, dy, ex, ey, pts, jac)
        link_jacobians_at(k.geom, k.com_fraction, pts, jac, jv, jw)
        foot_from(k.geom, jac[4], jac[3], jf_now[i])
        static_at(k.masses, k.gravity, 0.0, jv, jf_now[i], stance[i], foot)
    if k.touchdown:
        weights = np.maximum(weights, early_touchdown(k, fx, fy, velocities, state, r_wb))
    forces = ground_forces(k, targets, velocities, accelerations, weights, fx, fy, state, r_wb)
    out = np.zeros(2 * n)
    for i in range(n):
        w = weights[i]
        for j in range(2):
            push = jf_now[i, 0, j] * forces[i, 0] + jf_now[i, 1, j] * forces[i, 1]
            out[k.state.actuators[i, j]] = w * stance[i, j] + (1.0 - w) * swing[i, j] - push
    return out, goal, np.all(np.isfinite(out))
