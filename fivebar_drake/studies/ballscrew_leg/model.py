"""The Drake model of the ball-screw leg: a generated SDF (thigh, shank with its lever, the screw
housing (motor and shaft) pivoting at the hip, the nut on Drake's ScrewJoint, the loop closed at
D by a SAP ball constraint) on one of two rigs, and its static motor torques projected through
the loops.

Rigs (the plane of the leg is the world's x-y plane, y up, hinges along z):
- "bench": the hip fixed to the world at O, hip and screw motors actuated, the foot free; the
  seed's analysis (the foot load applied as an external force, no gravity).
- "squat": the hip on a carriage sliding on a vertical rail (mass foot_force / g: the 700 N
  load), the foot pinned by a ball constraint to a ground link welded at the world origin (a
  ball constraint on the world body itself crashes drake 1.51.1's SAP step), the hip free: one
  degree of freedom, driven by the screw motor alone.

The ScrewJoint's coordinate is the screw motor's angle (rad): the nut advances lead / (2 pi)
per radian, so the joint's generalized force is the motor torque of a lossless screw. The model
spins the nut with the shaft (the real nut only slides); the shaft's spin inertia is the
joint's rotor inertia, the nut's axial inertia is tiny.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import (AddMultibodyPlant, MultibodyPlant, MultibodyPlantConfig)
from pydrake.multibody.tree import JacobianWrtVariable, MultibodyForces
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.core.sdf import (PASSIVE, axis, ball_constraint, document, element, fmt,
                                    inertial, joint, pose)
from fivebar_drake.mechanisms.ballscrew_leg import TREE_JOINTS, BallScrewLeg, Params

RIGS = ("bench", "squat")
MODEL = "ballscrew_leg"
LINK_RADIUS_M = 0.01            # inertia of the slender links about their own axis
QUARTER_TURN = repr(-np.pi / 2)  # rad, every digit: link frames (x along the link) hang down at 0


def _rod(mass_kg: float, start_m: float, end_m: float) -> str:
    """<inertial> of a thin rod along x from start_m to end_m (m)."""
    length = end_m - start_m
    across = mass_kg * length**2 / 12.0
    return inertial(mass_kg, (0.5 * mass_kg * LINK_RADIUS_M**2, across, across),
                    (0.5 * (start_m + end_m), 0, 0))


def _revolute(name: str, parent: str, child: str, actuated: bool) -> str:
    return joint(name, "revolute", parent, child, axis("0 0 1", *(() if actuated else (PASSIVE,))))


def _link(name: str, at: str, body: str) -> str:
    return element("link", at, body, name=name)


def model_sdf(params: Params, leg: BallScrewLeg, rig: str) -> str:
    """The SDF of the leg on a rig (see the module docstring), links at the zero pose (straight
    leg, screw along the thigh, nut at the hip)."""
    s, m = params.simulation, params.motor
    l1, l2, s1 = leg.thigh_m, leg.shank_m, leg.lever_m
    down = pose(0, 0, 0, 0, 0, QUARTER_TURN)
    base = "world"
    links = []
    if rig == "squat":
        base = "carriage"
        mass = params.load.foot_force_N / s.gravity_m_s2
        links += [element("link", inertial(mass, (0.1, 0.1, 0.1), (0, 0, 0)), name="carriage"),
                  joint("rail", "prismatic", "world", "carriage", axis("0 1 0", PASSIVE)),
                  element("link", inertial(1.0, (1.0, 1.0, 1.0), (0, 0, 0)), name="ground"),
                  joint("ground_weld", "fixed", "world", "ground"),
                  ball_constraint("shank", (leg.shank_m, 0, 0), "ground")]
    nut_izz = 0.5 * s.nut_mass_kg * LINK_RADIUS_M**2
    links += [
        _link("thigh", down, _rod(s.thigh_mass_kg, 0.0, l1)),
        _link("shank", pose(0, -l1, 0, 0, 0, QUARTER_TURN), _rod(s.shank_mass_kg, -s1, l2)),
        _link("housing", down, _rod(s.screw_mass_kg, 0.0, l1 - s1)),
        _link("nut", down, inertial(s.nut_mass_kg, (2 * nut_izz, nut_izz, nut_izz), (0, 0, 0))),
        _revolute("hip", base, "thigh", actuated=rig == "bench"),
        _revolute("knee", "thigh", "shank", actuated=False),
        _revolute("screw_pivot", "thigh", "housing", actuated=False),
        joint("screw", "screw", "housing", "nut",
              axis("1 0 0", element("limit", element("effort", fmt(m.peak_torque_Nm)))),
              element("screw_thread_pitch", fmt(leg.lead_m)),
              element("drake:rotor_inertia", fmt(m.rotor_inertia_kg_m2)),
              element("drake:gear_ratio", fmt(m.gear_ratio))),
        ball_constraint("shank", (-s1, 0, 0), "nut"),
    ]
    return document(MODEL, *links)


@dataclass
class LegModel:
    """A finalized plant of the leg on a rig and what the projections need: the tree joints'
    position and velocity indices (TREE_JOINTS order), the rail's, the actuated velocity
    indices, and the loop rows (the lever point D on shank and nut; on the squat rig also the
    foot pinned to the world)."""

    leg: BallScrewLeg
    rig: str
    plant: MultibodyPlant
    q_index: np.ndarray
    v_index: np.ndarray
    rail: tuple | None
    actuated_v: np.ndarray

    def positions(self, pose, carriage_y_m=None) -> np.ndarray:
        """Plant positions of leg poses (..., nq), loop closed; the rail at carriage_y_m."""
        x = self.leg.tree_positions(pose)
        q = np.zeros(x.shape[:-1] + (self.plant.num_positions(),))
        q[..., self.q_index] = x
        if self.rail is not None:
            q[..., self.rail[0]] = carriage_y_m
        return q

    def loop_jacobian(self, context) -> np.ndarray:
        """J_c (rows, nv): in-plane velocity of D on the shank relative to the nut, and on the
        squat rig the foot's in-plane velocity (pinned)."""
        p, world = self.plant, self.plant.world_frame()

        def point(body, x_m):
            frame = p.GetBodyByName(body).body_frame()
            return p.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV, frame,
                                                       [x_m, 0.0, 0.0], world, world)[:2]

        rows = [point("shank", -self.leg.lever_m) - point("nut", 0.0)]
        if self.rig == "squat":
            rows.append(point("shank", self.leg.shank_m))
        return np.vstack(rows)

    def admissible(self, context) -> np.ndarray:
        """Orthonormal basis (nv, dof) of the velocities the loops allow (null space of J_c)."""
        jc = self.loop_jacobian(context)
        _, sv, vt = np.linalg.svd(jc)
        rank = int(np.sum(sv > 1e-9 * sv[0]))
        return vt[rank:].T

    def static_torques(self, positions, foot_force_N=(0.0, 0.0)) -> np.ndarray:
        """Actuator efforts (rows, actuators) holding plant positions (rows, nq) at rest under
        gravity and the external force foot_force_N (N, world x-y) on the foot: Drake's tree
        inverse dynamics tau_tree with zero velocity and acceleration, projected on the
        admissible velocities N: (N^T B) u = N^T tau_tree (virtual work; the loop forces do no
        work along N)."""
        p = self.plant
        context = p.CreateDefaultContext()
        shank = p.GetBodyByName("shank")
        force = np.r_[np.asarray(foot_force_N, dtype=float), 0.0]
        out = np.zeros((len(positions), len(self.actuated_v)))
        for k, q in enumerate(np.atleast_2d(positions)):
            p.SetPositions(context, q)
            forces = MultibodyForces(p)
            p.CalcForceElementsContribution(context, forces)
            r_wb = shank.EvalPoseInWorld(context).rotation().matrix()
            shank.AddInForce(context, r_wb @ [self.leg.shank_m, 0.0, 0.0],
                             SpatialForce(np.zeros(3), force), p.world_frame(), forces)
            tau = p.CalcInverseDynamics(context, np.zeros(p.num_velocities()), forces)
            n = self.admissible(context)
            out[k] = np.linalg.lstsq(n[self.actuated_v].T, n.T @ tau, rcond=None)[0]
        return out

    def motor_inertia(self, positions) -> float:
        """The inertia (kg m^2) the screw motor feels at plant positions (nq,): N^T M N with the
        admissible velocity scaled to a unit motor speed (squat rig, one degree of freedom)."""
        p = self.plant
        context = p.CreateDefaultContext()
        p.SetPositions(context, positions)
        n = self.admissible(context)[:, 0]
        n = n / n[self.v_index[TREE_JOINTS.index("screw")]]
        return float(n @ p.CalcMassMatrix(context) @ n)


def build_model(params: Params, lever_m: float, rig: str, builder: DiagramBuilder | None = None,
                gravity: bool | None = None) -> LegModel:
    """The leg's plant on a rig (RIGS), discrete with SAP (the ball constraints need it), added
    to builder if given (else to a builder of its own, never built: the plant alone, for the
    statics). gravity: None for the
    rig's default (off on the bench, as in the seed's analysis; on for the squat)."""
    if rig not in RIGS:
        raise ValueError(f"rig {rig!r}: one of {RIGS}")
    leg = BallScrewLeg(params.leg.thigh_m, params.leg.shank_m, lever_m, params.screw.lead_m)
    config = MultibodyPlantConfig(time_step=params.simulation.time_step_s,
                                  discrete_contact_approximation="sap")
    plant, _ = AddMultibodyPlant(config, DiagramBuilder() if builder is None else builder)
    Parser(plant).AddModelsFromString(model_sdf(params, leg, rig), "sdf")
    if gravity is None:
        gravity = rig == "squat"
    plant.mutable_gravity_field().set_gravity_vector(
        [0.0, -params.simulation.gravity_m_s2 if gravity else 0.0, 0.0])
    plant.Finalize()
    joints = [plant.GetJointByName(name) for name in TREE_JOINTS]
    rail = None
    if rig == "squat":
        j = plant.GetJointByName("rail")
        rail = (j.position_start(), j.velocity_start())
    actuated = np.array([plant.get_joint_actuator(i).joint().velocity_start()
                         for i in plant.GetJointActuatorIndices()])
    return LegModel(leg=leg, rig=rig, plant=plant,
                    q_index=np.array([j.position_start() for j in joints]),
                    v_index=np.array([j.velocity_start() for j in joints]),
                    rail=rail, actuated_v=actuated)
