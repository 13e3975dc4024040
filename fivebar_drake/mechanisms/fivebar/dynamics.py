"""Motor torques of the 5-bar leg: the seed's model as written and the physically consistent one.

Both have the form tau = M(q) q_ddot [+ c(q, q_dot)] + G(q), tau = [tau_A, tau_B] in N*m, with
M = sum_i m_i Jv_i^T Jv_i + Izz_i Jw_i^T Jw_i over the links AC, BD, CE, DE (seed 000 eq. 7) and
the weight share m_leg at the foot: the ground pushes the foot up with m_leg g, which the motors
resist with m_leg g J_F^T [0, -1]^T. The models differ (SPEC.md section 3) in
- the link weights: the seed writes m_i g Jv_i^T [0, -1]^T; holding a link up against gravity
  needs +m_i g Jv_i^T [0, 1]^T (G = dV/dq with V = sum m_i g y_i);
- Coriolis/centrifugal terms c = sum m_i Jv_i^T (Jv_i' q_dot) + Izz_i Jw_i^T (Jw_i' q_dot),
  dropped by the seed;
- Izz of AC: the seed's "~0" is used as 0 in the seed model and as a thin rod in the full one.
"""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.mechanisms.fivebar.geometry import LINK_NAMES, LegGeometry, LinkInertia
from fivebar_drake.mechanisms.fivebar.jacobians import (LinkJacobians, bias_accelerations,
                                                        link_jacobians)
from fivebar_drake.mechanisms.fivebar.kinematics import LegPose


@dataclass(frozen=True)
class DynamicsModel:
    """One reading of the seed's torque model.

    izz: Izz per link (kg*m^2); link_weight_sign: +1 for G_links = +m g Jv^T [0, 1]^T (physical),
    -1 for the seed's m g Jv^T [0, -1]^T; coriolis: include c(q, q_dot); foot_load_N: upward
    ground force on the foot (N), a number or one per sample; gravity_m_s2: g;
    rotor_inertia_kg_m2: each motor's rotor reflected to the output (N^2 J_rotor), its torque
    N^2 J q_ddot added to the motor's (0: the seed's model has none)."""

    name: str
    description: str
    izz: tuple[float, ...]
    link_weight_sign: float
    coriolis: bool
    foot_load_N: float | np.ndarray
    gravity_m_s2: float
    rotor_inertia_kg_m2: float = 0.0


@dataclass(frozen=True)
class TorqueBreakdown:
    """Motor torque components (..., 2) in N*m, [tau_A, tau_B]."""

    inertial: np.ndarray       # M(q) q_ddot
    coriolis: np.ndarray       # c(q, q_dot), zero where the model drops it
    link_weight: np.ndarray    # gravity on the four links
    foot_load: np.ndarray      # the weight share carried at the foot
    rotor: np.ndarray          # N^2 J_rotor q_ddot: the rotors, reflected (zero without)

    @property
    def static(self) -> np.ndarray:
        """Torque that holds the pose without motion under the same loads (q_dot = q_ddot = 0)."""
        return self.link_weight + self.foot_load

    @property
    def joint(self) -> np.ndarray:
        """Torque the gearboxes deliver to the links (the motors' less the rotors' own)."""
        return self.inertial + self.coriolis + self.static

    @property
    def total(self) -> np.ndarray:
        """The motors' torque at the output: the links' and the rotors'."""
        return self.joint + self.rotor


@jit
def mass_matrix_at(masses, izz, jv, jw, m):
    """One pose: M (2, 2) into m, sum_k m_k Jv_k^T Jv_k + Izz_k Jw_k^T Jw_k from its link
    Jacobians jv (4, 2, 2), jw (4, 2); masses, izz (4,)."""
    for j in range(2):
        for i in range(2):
            total = 0.0
            for k in range(4):
                total += (masses[k] * (jv[k, 0, j] * jv[k, 0, i] + jv[k, 1, j] * jv[k, 1, i])
                          + izz[k] * jw[k, j] * jw[k, i])
            m[j, i] = total


@jit
def mass_matrix_arrays(masses, izz, jv, jw):
    """M (n, 2, 2) from link Jacobians jv (n, 4, 2, 2), jw (n, 4, 2) (mass_matrix_at)."""
    m = np.empty((jv.shape[0], 2, 2))
    for n in range(jv.shape[0]):
        mass_matrix_at(masses, izz, jv[n], jw[n], m[n])
    return m


@jit
def coriolis_at(masses, izz, jv, jw, av, aw, c):
    """One pose: c (2,) into c, sum_k m_k Jv_k^T a_k + Izz_k Jw_k^T alpha_k with the links'
    velocity-product accelerations av (4, 2), aw (4,)."""
    for j in range(2):
        total = 0.0
        for k in range(4):
            total += (masses[k] * (jv[k, 0, j] * av[k, 0] + jv[k, 1, j] * av[k, 1])
                      + izz[k] * jw[k, j] * aw[k])
        c[j] = total


@jit
def coriolis_arrays(masses, izz, jv, jw, av, aw):
    """c (n, 2) with av (n, 4, 2), aw (n, 4) (coriolis_at)."""
    c = np.empty((jv.shape[0], 2))
    for n in range(jv.shape[0]):
        coriolis_at(masses, izz, jv[n], jw[n], av[n], aw[n], c[n])
    return c


@jit
def static_at(masses, weight_sign_g, foot_load, jv, jf, weight, foot):
    """One pose: torques (2,) holding the links' weights into weight (weight_sign_g =
    link_weight_sign g, m/s^2: weight_sign_g sum_k m_k Jv_k^T [0, 1]) and the upward ground
    force foot_load N at the foot into foot (-foot_load J_F^T [0, 1])."""
    for j in range(2):
        total = 0.0
        for k in range(4):
            total += weight_sign_g * masses[k] * jv[k, 1, j]
        weight[j] = total
        foot[j] = -foot_load * jf[1, j]


@jit
def static_arrays(masses, weight_sign_g, foot_load, jv, jf):
    """(link weight, foot load) torques (n, 2) for foot loads (n,) N (static_at)."""
    weight, foot = np.empty((jv.shape[0], 2)), np.empty((jv.shape[0], 2))
    for n in range(jv.shape[0]):
        static_at(masses, weight_sign_g, foot_load[n], jv[n], jf[n], weight[n], foot[n])
    return weight, foot


def _masses(links: dict[str, LinkInertia]) -> np.ndarray:
    return np.array([links[n].mass_kg for n in LINK_NAMES])


def _flat_jacobians(lj: LinkJacobians):
    shape = lj.jf.shape[:-2]
    return shape, lj.jv.reshape(-1, 4, 2, 2), lj.jw.reshape(-1, 4, 2), lj.jf.reshape(-1, 2, 2)


def mass_matrix(leg: LegGeometry, links: dict[str, LinkInertia], izz, pose: LegPose) -> np.ndarray:
    """M(q) (..., 2, 2) in kg*m^2 = sum_i m_i Jv_i^T Jv_i + Izz_i Jw_i^T Jw_i."""
    return _mass_matrix(links, izz, link_jacobians(leg, links, pose))


def _mass_matrix(links, izz, lj):
    shape, jv, jw, _ = _flat_jacobians(lj)
    m = mass_matrix_arrays(_masses(links), np.asarray(izz, dtype=float), jv, jw)
    return m.reshape(shape + (2, 2))


def coriolis(leg: LegGeometry, links: dict[str, LinkInertia], izz, pose: LegPose, qd, lj=None,
             bias=None) -> np.ndarray:
    """c(q, q_dot) (..., 2) in N*m: sum_i m_i Jv_i^T a_i + Izz_i Jw_i^T alpha_i with a_i, alpha_i
    the velocity-product accelerations of link i (lj, bias: the poses' LinkJacobians and
    bias_accelerations at qd, if already computed)."""
    lj = lj or link_jacobians(leg, links, pose)
    av, aw, _ = bias or bias_accelerations(leg, links, pose, qd)
    shape, jv, jw, _ = _flat_jacobians(lj)
    c = coriolis_arrays(_masses(links), np.asarray(izz, dtype=float), jv, jw,
                        np.ascontiguousarray(av).reshape(-1, 4, 2),
                        np.ascontiguousarray(aw).reshape(-1, 4))
    return c.reshape(shape + (2,))


def _static(links, model: DynamicsModel, lj):
    shape, jv, _, jf = _flat_jacobians(lj)
    load = np.ascontiguousarray(np.broadcast_to(np.asarray(model.foot_load_N, dtype=float),
                                                shape)).ravel()
    weight, foot = static_arrays(_masses(links), model.link_weight_sign * model.gravity_m_s2,
                                 load, jv, jf)
    return weight.reshape(shape + (2,)), foot.reshape(shape + (2,))


def static_torques(leg: LegGeometry, links: dict[str, LinkInertia], model: DynamicsModel,
                   pose: LegPose, lj=None) -> np.ndarray:
    """Torque (..., 2) in N*m that holds the poses at rest under the model's loads (lj: the
    poses' LinkJacobians if already computed)."""
    return sum(_static(links, model, lj or link_jacobians(leg, links, pose)))


def torques(leg: LegGeometry, links: dict[str, LinkInertia], model: DynamicsModel, pose: LegPose,
            qd, qdd, lj=None, bias=None) -> TorqueBreakdown:
    """Motor torques (N*m) for poses with motor rates qd (rad/s) and accelerations qdd (rad/s^2)
    (lj, bias: the poses' LinkJacobians and bias_accelerations at qd, if already computed)."""
    lj = lj or link_jacobians(leg, links, pose)
    link_weight, foot_load = _static(links, model, lj)
    qdd = np.asarray(qdd, dtype=float)
    inertial = np.einsum("...ij,...j->...i", _mass_matrix(links, model.izz, lj), qdd)
    cor = (coriolis(leg, links, model.izz, pose, qd, lj, bias) if model.coriolis
           else np.zeros_like(inertial))
    return TorqueBreakdown(inertial=inertial, coriolis=cor, link_weight=link_weight,
                           foot_load=foot_load, rotor=model.rotor_inertia_kg_m2 * qdd)
