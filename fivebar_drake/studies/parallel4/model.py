"""The Drake model of the 4-DOF parallel manipulator: generated SDF, a discrete SAP plant whose
four leg loops are closed by ball constraints, its tree coordinates for a platform pose, and the
static actuator forces obtained by projecting the tree's gravity forces through the loop
constraints (Lagrange multipliers).

The tree: world -> slider_i (prismatic along x, actuated; position l_i) -> leg_i (universal
joint at A_i: about x, then about the leg's y; the leg points along its -z, R long). The
platform hangs on a frictionless, unactuated guide world -> guide_x -> guide_y -> guide_z
(prismatic x, y, z) -> platform (revolute about y): it leaves x, y, z, theta free and holds the
two rotations (about x and z) that the real machine's U-joint metachains hold (seed 2.1: the
platform turns about y only). Leg ends join the platform at B12 = (0, b, c) and B34 =
(0, -b, -c) in the platform frame by <drake:ball_constraint>s: 4 x 3 = 12 constraint rows on
4 + 4 + 8 = 16 velocities leave the 4 freedoms of the seed's machine.
"""

from __future__ import annotations

import numpy as np
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import JacobianWrtVariable, PdControllerGains
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.core.sdf import (PASSIVE, axis, ball_constraint, box, cylinder, document,
                                    element, inertial, joint, pose, visual)
from fivebar_drake.mechanisms.parallel4.geometry import Geometry
from fivebar_drake.mechanisms.parallel4.kinematics import PAIR, inverse, platform_offsets
from fivebar_drake.mechanisms.parallel4.params import Model
from fivebar_drake.mechanisms.parallel4.statics import holding_forces

LEGS = (1, 2, 3, 4)
GUIDE = (("guide_x", "prismatic", "1 0 0"), ("guide_y", "prismatic", "0 1 0"),
         ("guide_z", "prismatic", "0 0 1"), ("platform", "revolute", "0 1 0"))


def _box_inertia(m: float, sx: float, sy: float, sz: float) -> tuple[float, float, float]:
    return m * (sy * sy + sz * sz) / 12, m * (sx * sx + sz * sz) / 12, m * (sx * sx + sy * sy) / 12


def base_points(g: Geometry) -> np.ndarray:
    """O_i (4, 3), m: where each actuator's position l_i is measured from."""
    return np.array([[0.0, g.a, g.d], [0.0, g.a, g.d], [0.0, -g.a, -g.d], [0.0, -g.a, -g.d]])


def sdf_text(g: Geometry, m: Model) -> str:
    """The model's SDFormat 1.9 text."""
    parts = []
    slider = 0.04
    for i, origin in zip(LEGS, base_points(g)):
        rod = m.leg_mass_kg * g.R ** 2 / 12               # thin rod about its centre
        spin = m.leg_mass_kg * m.leg_radius_m ** 2 / 2
        colour = "0.85 0.45 0.2 1" if i < 3 else "0.2 0.45 0.85 1"
        parts += [
            element("link", pose(*origin),
                    inertial(m.slider_mass_kg, _box_inertia(m.slider_mass_kg, *(slider,) * 3),
                             (0, 0, 0)),
                    visual("v", box(slider, slider, slider), "0.3 0.3 0.3 1", pose()),
                    name=f"slider_{i}"),
            joint(f"l{i}", "prismatic", "world", f"slider_{i}", axis("1 0 0")),
            element("link", pose(*origin),
                    inertial(m.leg_mass_kg, (rod, rod, spin), (0, 0, -g.R / 2)),
                    visual("v", cylinder(m.leg_radius_m, g.R), colour, pose(0, 0, -g.R / 2)),
                    name=f"leg_{i}"),
            joint(f"u{i}", "universal", f"slider_{i}", f"leg_{i}", axis("1 0 0", PASSIVE),
                  axis("0 1 0", PASSIVE, tag="axis2"))]
    parent = "world"
    for name, kind, direction in GUIDE:
        if name == "platform":
            size = (0.05, 2 * g.b + 0.03, 2 * g.c + 0.03)
            body = (inertial(m.platform_mass_kg, _box_inertia(m.platform_mass_kg, *size), (0, 0, 0))
                    + visual("v", box(*size), "0.2 0.7 0.3 1", pose()))
        else:
            body = inertial(m.guide_mass_kg, (m.guide_mass_kg * 1e-4,) * 3, (0, 0, 0))
        parts += [element("link", body, name=name),
                  joint(f"{name}_joint", kind, parent, name, axis(direction, PASSIVE))]
        parent = name
    offsets = platform_offsets(g, 0.0)
    parts += [ball_constraint(f"leg_{i}", (0, 0, -g.R), "platform", offsets[pair])
              for i, pair in zip(LEGS, PAIR)]
    return document("parallel4", *parts)


class Parallel4Plant:
    """The plant (discrete, SAP) in a DiagramBuilder, with the joint bookkeeping."""

    def __init__(self, g: Geometry, m: Model, time_step_s: float, builder=None,
                 pd_gains: tuple[float, float] | None = None):
        """pd_gains: (kp N/m, kd N*s/m) of the plant's implicit PD on each actuator, or none."""
        self.g, self.m = g, m
        self.builder = builder or DiagramBuilder()
        config = MultibodyPlantConfig(time_step=time_step_s, discrete_contact_approximation="sap")
        self.plant, _ = AddMultibodyPlant(config, self.builder)
        self.plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -m.gravity_m_s2])
        (self.instance,) = Parser(self.plant).AddModelsFromString(sdf_text(g, m), "sdf")
        if pd_gains is not None:
            for index in self.plant.GetJointActuatorIndices():
                self.plant.get_mutable_joint_actuator(index).set_controller_gains(
                    PdControllerGains(p=pd_gains[0], d=pd_gains[1]))
        self.plant.Finalize()
        p = self.plant
        self.sliders = [p.GetJointByName(f"l{i}") for i in LEGS]
        self.universals = [p.GetJointByName(f"u{i}") for i in LEGS]
        self.guide = [p.GetJointByName(f"{name}_joint") for name, _, _ in GUIDE]
        self.legs = [p.GetBodyByName(f"leg_{i}") for i in LEGS]
        self.platform = p.GetBodyByName("platform")

    def positions(self, pose) -> np.ndarray:
        """Plant positions (nq,) of a platform pose (4,) (m, rad), on the seed's IK mode."""
        g = self.g
        pose = np.asarray(pose, dtype=float)
        q = inverse(g, pose)
        x = np.zeros(self.plant.num_positions())
        tip = pose[:3] + platform_offsets(g, pose[3])[list(PAIR)]
        anchors = base_points(g) + np.outer(q, [1.0, 0, 0])
        u = (tip - anchors) / g.R
        for k in range(4):
            x[self.sliders[k].position_start()] = q[k]
            start = self.universals[k].position_start()
            x[start] = np.arctan2(u[k, 1], -u[k, 2])
            x[start + 1] = np.arctan2(-u[k, 0], np.hypot(u[k, 1], u[k, 2]))
        for guide, value in zip(self.guide, pose):
            x[guide.position_start()] = value
        return x

    def _constraint_rows(self, context) -> tuple[np.ndarray, np.ndarray]:
        """Loop gaps (4, 3), m, and the constraint Jacobian (12, nv): leg end minus platform
        point, in the world frame."""
        p, W = self.plant, self.plant.world_frame()
        offsets = platform_offsets(self.g, 0.0)
        gaps, rows = [], []
        for leg, pair in zip(self.legs, PAIR):
            end = np.array([0.0, 0.0, -self.g.R])
            pin = offsets[pair]
            a = p.CalcPointsPositions(context, leg.body_frame(), end, W)[:, 0]
            b = p.CalcPointsPositions(context, self.platform.body_frame(), pin, W)[:, 0]
            Ja = p.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV,
                                                     leg.body_frame(), end, W, W)
            Jb = p.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV,
                                                     self.platform.body_frame(), pin, W, W)
            gaps.append(a - b)
            rows.append(Ja - Jb)
        return np.array(gaps), np.vstack(rows)

    def loop_gaps(self, context) -> np.ndarray:
        """Distance (4,), m, across each ball constraint."""
        return np.linalg.norm(self._constraint_rows(context)[0], axis=1)

    def mobility(self, context) -> int:
        """nv minus the rank of the loop constraint Jacobian: the freedoms the model keeps."""
        rank = np.linalg.matrix_rank(self._constraint_rows(context)[1])
        return self.plant.num_velocities() - rank

    def projected_static_forces(self, context) -> np.ndarray:
        """Actuator forces (4,), N, holding the plant's current pose at rest under gravity:
        B u + G^T lambda = -tau_g solved for u and the constraint forces lambda (tree
        inverse dynamics at rest is -tau_g; Drake's inverse dynamics ignores the loops)."""
        p = self.plant
        tau_g = p.CalcGravityGeneralizedForces(context)
        _, G = self._constraint_rows(context)
        actuation = p.MakeActuationMatrix()
        system = np.hstack([actuation, G.T])
        sol, *_ = np.linalg.lstsq(system, -tau_g, rcond=None)
        residual = np.linalg.norm(system @ sol + tau_g)
        if residual > 1e-9 * max(1.0, np.linalg.norm(tau_g)):
            raise RuntimeError(f"no static equilibrium of the tree model (residual {residual:g})")
        return sol[:actuation.shape[1]]

    def actuator_order(self) -> list[int]:
        """For each actuator index of the plant, the leg (0..3) it drives."""
        joints = [self.plant.get_joint_actuator(a).joint().index()
                  for a in self.plant.GetJointActuatorIndices()]
        return [[s.index() for s in self.sliders].index(j) for j in joints]


def gravity_load(g: Geometry, m: Model, pose) -> np.ndarray:
    """The platform wrench (..., 4) of gravity, N and N*m about y through P, for the closed
    form: the platform and the guide's z body at P, and half of each leg's weight at its
    platform point (a leg's centre moves by half its platform end's z, its slider end never
    moves in z). Sliders and the x, y guide bodies never move in z."""
    pose = np.asarray(pose, dtype=float)
    w = m.gravity_m_s2
    r = platform_offsets(g, pose[..., 3])                      # (..., 2, 3)
    at_points = -w * m.leg_mass_kg         # f_z at each platform point: two half legs
    # moment about y of a force f_z at offset r: (r x f)_y = r_z f_x - r_x f_z = -r_x f_z
    my = -(r[..., 0, 0] + r[..., 1, 0]) * at_points
    fz = np.full_like(my, -w * (m.platform_mass_kg + m.guide_mass_kg) + 2 * at_points)
    zero = np.zeros_like(my)
    return np.stack([zero, zero, fz, my], axis=-1)


def closed_form_static_forces(g: Geometry, m: Model, pose) -> np.ndarray:
    """Actuator forces (..., 4), N, holding poses at rest under gravity: the seed's Jacobian
    relation (statics.holding_forces) with gravity_load."""
    return holding_forces(g, pose, gravity_load(g, m, pose))
