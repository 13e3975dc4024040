"""SCARA dynamics by Lagrange (seed 002 section 2.3.1): M(q) (eq. 2.69), C(q, qd) from the
Christoffel symbols of M (eq. 2.71), G(q) (eq. 2.74), and the joint forces
tau = M qdd + C qd + G (N*m for joints 1, 2; N for the prismatic joint 3).

Links 1 and 2 turn about vertical axes with their centres of mass at c1, c2 from their joint
axes; link 3 (and the payload) is a mass on the axis of joint 3 turning with link 2."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.mechanisms.scara.params import Kinematics, Links


@dataclass(frozen=True)
class Inertia:
    """Masses m1, m2, m3 (kg; m3 with any payload), COM distances c1, c2 (m), moments of
    inertia about vertical axes through the COMs izz1, izz2, izz3 (kg*m^2), gravity g (m/s^2)."""

    m1: float
    m2: float
    m3: float
    c1: float
    c2: float
    izz1: float
    izz2: float
    izz3: float
    g: float


def seed_inertia(links: Links, payload_kg: float = 0.0, rod_length: bool = False,
                 kin: Kinematics | None = None) -> Inertia:
    """The seed's inertia data: Izz1 = m_khau1 l1^2/12, Izz2 = m_khau2 l2^2/12 with l = the COM
    distance (= a/2, as written), or with l = a (rod_length: a thin rod's m a^2/12; needs kin);
    Izz3 = m_vit r^2/2. payload_kg is added to m3."""
    l1, l2 = (kin.a1_m, kin.a2_m) if rod_length else (links.com1_m, links.com2_m)
    return Inertia(links.m1_kg, links.m2_kg, links.m3_kg + payload_kg, links.com1_m,
                   links.com2_m, links.link1_body_kg * l1**2 / 12, links.link2_body_kg * l2**2 / 12,
                   links.screw_kg * links.screw_radius_m**2 / 2, links.gravity_m_s2)


class Dynamics:
    """M, C, G of the arm with link lengths a1, a2 (m) and prismatic direction s (+1 up)."""

    def __init__(self, kin: Kinematics, inertia: Inertia):
        self.a1, self.a2, self.s, self.i = kin.a1_m, kin.a2_m, float(kin.q3_direction), inertia

    def _coupling(self) -> float:
        """h0 = a1 (m2 c2 + m3 a2): m11 = const + 2 h0 cos q2, m12 = const + h0 cos q2."""
        return self.a1 * (self.i.m2 * self.i.c2 + self.i.m3 * self.a2)

    def mass_matrix(self, q) -> np.ndarray:
        """M(q) (..., 3, 3) (eq. 2.69 with the COMs at c1, c2)."""
        i, a1, a2 = self.i, self.a1, self.a2
        c2 = np.cos(np.asarray(q, dtype=float)[..., 1])
        m = np.zeros(c2.shape + (3, 3))
        m22 = i.izz2 + i.izz3 + i.m2 * i.c2**2 + i.m3 * a2**2
        m[..., 0, 0] = i.izz1 + i.m1 * i.c1**2 + i.m2 * a1**2 + i.m3 * a1**2 + m22 \
            + 2 * self._coupling() * c2
        m[..., 0, 1] = m[..., 1, 0] = m22 + self._coupling() * c2
        m[..., 1, 1] = m22
        m[..., 2, 2] = i.m3
        return m

    def mass_matrix_derivative(self, q) -> np.ndarray:
        """dM/dq_k (..., 3, 3, 3), index k last: only q2 enters M."""
        s2 = np.sin(np.asarray(q, dtype=float)[..., 1])
        d = np.zeros(s2.shape + (3, 3, 3))
        d[..., 0, 0, 1] = -2 * self._coupling() * s2
        d[..., 0, 1, 1] = d[..., 1, 0, 1] = -self._coupling() * s2
        return d

    def coriolis_matrix(self, q, qd) -> np.ndarray:
        """C(q, qd) (..., 3, 3) by the Christoffel symbols of M (eq. 2.71):
        c_ij = 1/2 sum_k (dm_ij/dq_k + dm_ik/dq_j - dm_jk/dq_i) qd_k."""
        d = self.mass_matrix_derivative(q)                    # d[i, j, k] = dm_ij / dq_k
        gamma = 0.5 * (d + np.swapaxes(d, -1, -2) - np.moveaxis(d, -1, -3))
        return np.einsum("...ijk,...k->...ij", gamma, np.asarray(qd, dtype=float))

    def gravity(self, q) -> np.ndarray:
        """G(q) (..., 3) = -sum m_i J_Ti^T g (eq. 2.74): only the vertical joint 3 feels it."""
        q = np.asarray(q, dtype=float)
        g = np.zeros(q.shape)
        g[..., 2] = self.s * self.i.m3 * self.i.g
        return g

    def torques(self, q, qd, qdd) -> dict[str, np.ndarray]:
        """Joint forces (..., 3) and their parts: inertial M qdd, coriolis C qd, gravity G,
        total (N*m, N*m, N)."""
        parts = {"inertial": np.einsum("...ij,...j->...i", self.mass_matrix(q), qdd),
                 "coriolis": np.einsum("...ij,...j->...i", self.coriolis_matrix(q, qd), qd),
                 "gravity": self.gravity(q)}
        parts["total"] = parts["inertial"] + parts["coriolis"] + parts["gravity"]
        return parts
