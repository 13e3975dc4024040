"""Bushing parameters for the loop closure at E, derived from the leg's effective mass at the
knee, the force the loop carries and the loop gap one accepts.

A discrete plant applies the bushing force explicitly: a spring k and damper d on the effective
mass m_eff = 1 / lambda_max(J_c M^-1 J_c^T) felt at the cut (J_c: Jacobian of the gap), stepped
with dt by symplectic Euler. With a = k dt^2 / m_eff and b = d dt / m_eff = 2 zeta sqrt(a)
(zeta = damping ratio), the step is stable iff a + 2 b < 4 (Jury criterion on the 2x2 step
matrix, trace 2 - a - b, determinant 1 - b). The gap under the loop force F is F / k. So:
k = F / gap, then the largest dt with a + 4 zeta sqrt(a) = 4 margin, and d = 2 zeta sqrt(k m_eff).

SAP treats the compliant "bushing" (two distance constraints) implicitly, stable at any k, but
it keeps the law gap = F / k only while a constraint's regularisation 1 / (dt (dt + tau) k)
(tau = d / k) stays above its near-rigid floor beta^2 w / (4 pi^2) (beta = NEAR_RIGID_BETA; w =
J diag(A)^-1 J^T, Drake's Delassus estimate with only the diagonal of the tree's mass matrix A).
Stiffer, SAP clamps the constraint to an effective stiffness 2 pi^2 / (beta^2 w dt^2) whatever k
is: the loop is softer than designed (min_loop_gap).

The closures are variants (Closure, registered by kind in CLOSURES): the compliant "bushing", the
explicit "bushing_rpy" and the "ball", each with its design, its SDF element and its constraints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
from pydrake.multibody.plant import MultibodyPlant

from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.sdf import ball_constraint, element, fmt
from fivebar_drake.core.validation import ParameterError, check_number
from fivebar_drake.core.variants import Variant, by_kind, registrar
from fivebar_drake.mechanisms.fivebar import sample_gait, tree_positions
from fivebar_drake.robots.quadruped.inverse_dynamics import loop_jacobian, plane_point_jacobian
from fivebar_drake.robots.quadruped.leg_loads import trot_model
from fivebar_drake.robots.quadruped.mjcf import MJCF_FILE, quadruped_mjcf
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import ClosureDesign, add_model, leg_indices
from fivebar_drake.robots.quadruped.sdf import quadruped_sdf, single_leg_sdf
from fivebar_drake.mechanisms.base import Bushing, LoopCut


STABILITY_MARGIN = 0.8   # fraction of the explicit stability bound a + 2 b < 4
DAMPING_RATIO = 0.3
NEAR_RIGID_BETA = 0.1    # SAP's near-rigid parameter of a distance constraint (drake 1.51,
#                          SapDistanceConstraint)
OFFSET_M = 0.02   # the compliant bushing's second distance constraint's point: this far off DE at E


def fixed_leg(params: Params):
    """One leg on a welded hip, as a finalized continuous plant without closure (a tree):
    (plant, default context, model instance, LegIndices)."""
    plant = MultibodyPlant(0.0)
    instance, _ = add_model(plant, params, "leg", None)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    return plant, context, instance, leg_indices(plant, instance, "leg")


def near_rigid_mass(params: Params) -> float:
    """The least mass (kg) over the gait that SAP sees along the bushing's distance constraints at
    E (along DE and across it, the directions of plant.add_model's two constraints): 1 / w with
    w = u^T J_c diag(M)^-1 J_c^T u, Drake's Delassus estimate (the diagonal of the mass matrix
    only; joint damping, which adds dt D to it, left out: a lighter mass, a safe bound), from
    the Drake model of one fixed-hip leg with its motors free, as in the robot."""
    plant, context, instance, idx = fixed_leg(params)
    plane = plant.GetFrameByName("leg_plane", instance)
    de = plant.GetBodyByName("leg_DE", instance).body_frame()
    q = plant.GetPositions(context)
    w = 0.0
    for x in tree_positions(sample_gait(params.leg, params.gait).pose):
        q[idx.q] = x
        plant.SetPositions(context, q)
        jc, _ = loop_jacobian(plant, context, instance, params, "leg")
        delassus = (jc / plant.CalcMassMatrix(context).diagonal()) @ jc.T
        d, e = plant.CalcPointsPositions(context, de, [[0.0, params.leg.de_m], [0.0, 0.0],
                                                       [0.0, 0.0]], plane)[:2].T
        along = (e - d) / np.linalg.norm(e - d)
        for u in (along, np.array([-along[1], along[0]])):
            w = max(w, float(u @ delassus @ u))
    return 1.0 / w


def loop_load(params: Params):
    """Effective mass at the knee (kg, least over the gait) and the largest loop force (N) over
    the gait under trot loading (half the robot's weight on a stance foot), both from the Drake
    model of one fixed-hip leg: lambda = J_phi^-T tau_tree[phi]."""
    plant, context, instance, idx = fixed_leg(params)
    samples = sample_gait(params.leg, params.gait)
    load = trot_model(params, samples.path, samples.t).foot_load_N
    x = tree_positions(samples.pose)
    m_eff, force = np.inf, 0.0
    q = plant.GetPositions(context)
    for k in range(len(x)):
        q[idx.q] = x[k]
        plant.SetPositions(context, q)
        jc, _ = loop_jacobian(plant, context, instance, params, "leg")
        m_inv = np.linalg.inv(plant.CalcMassMatrix(context))
        m_eff = min(m_eff, 1.0 / np.max(np.linalg.eigvalsh(jc @ m_inv @ jc.T)))
        # static loop force: passive joints carry no torque, the foot load goes through E
        j_foot, _ = plane_point_jacobian(plant, context, instance, "leg", "DE",
                                         params.leg.de_m + params.leg.ef_m)
        tau_tree = -j_foot.T @ np.array([0.0, load[k]])
        lam = np.linalg.solve(jc[:, idx.v[2:]].T, tau_tree[idx.v[2:]])
        force = max(force, float(np.linalg.norm(lam)))
    return m_eff, force


def bushing_parameters(m_eff_kg: float, loop_force_N: float, target_gap_m: float,
                       damping_ratio: float = DAMPING_RATIO,
                       margin: float = STABILITY_MARGIN) -> tuple[Bushing, float]:
    """Bushing stiffness/damping and the largest stable time step (s) for a loop gap of
    target_gap_m (m) under loop_force_N (N) with effective mass m_eff_kg (kg)."""
    for name, value in (("m_eff_kg", m_eff_kg), ("loop_force_N", loop_force_N),
                        ("target_gap_m", target_gap_m)):
        if not value > 0:
            raise ValueError(f"{name} = {value!r}: must be > 0")
    k = loop_force_N / target_gap_m
    root_a = -2.0 * damping_ratio + np.sqrt(4.0 * damping_ratio**2 + 4.0 * margin)
    dt = float(root_a * np.sqrt(m_eff_kg / k))
    d = 2.0 * damping_ratio * np.sqrt(k * m_eff_kg)
    return Bushing(stiffness_N_m=float(k), damping_N_s_m=float(d)), dt


def min_loop_gap(m_eff_kg: float, sap_mass_kg: float, loop_force_N: float, time_step_s: float,
                 damping_ratio: float = DAMPING_RATIO, beta: float = NEAR_RIGID_BETA) -> float:
    """The least target gap (m) at which SAP keeps the compliant bushing's law gap = F / k at
    plant step time_step_s (s): with the bushing's damping (bushing_parameters, tau = d / k =
    2 zeta sqrt(m_eff / k)) the constraint stays compliant while 1 / (dt (dt + tau) k) >=
    beta^2 / (4 pi^2 sap_mass), i.e. k dt^2 + 2 zeta dt sqrt(m_eff k) <= 4 pi^2 sap_mass / beta^2;
    the gap is loop_force_N / k at the largest such k. Scales with dt^2; sap_mass_kg:
    near_rigid_mass."""
    root_k = (math.sqrt(damping_ratio**2 * m_eff_kg + 4.0 * math.pi**2 * sap_mass_kg / beta**2)
              - damping_ratio * math.sqrt(m_eff_kg)) / time_step_s
    return loop_force_N / root_k**2


IMPLICIT_TIME_STEP_S = 1e-3   # plant step of the closures SAP treats implicitly


CLOSURES: dict[str, type[Closure]] = {}    # the loop closures by kind, in registration order
register_closure = registrar(CLOSURES, "closure")


@dataclass(frozen=True)
class Closure(Variant):
    """A loop closure at E (register with register_closure): whether it is a SAP constraint
    (`sap`: the plant needs a SAP solver), its design, the SDF element it declares at each loop
    cut and the constraints it adds after parsing."""

    sap: ClassVar[bool] = False

    def sdf(self, cut: LoopCut, bushing: Bushing | None) -> str:
        """The SDF element closing the loop at the cut (the designed bushing); "" for none."""
        return ""

    def design(self, params: Params, m_eff_kg: float, loop_force_N: float, target_gap_m: float,
               time_step_s: float, log_period_s: float) -> ClosureDesign:
        """The design from the knee's effective mass (kg) and loop force (N) for the accepted gap
        (m) at the asked step (s, 0: derived); ParameterError naming the scenario field if it
        cannot hold."""
        raise NotImplementedError

    def add_to(self, plant: MultibodyPlant, instance, legs, params: Params,
               bushing: Bushing | None) -> None:
        """Add what the SDF cannot declare to the parsed, unfinalized plant (nothing here)."""


@register_closure
@dataclass(frozen=True)
class CompliantBushing(Closure):
    """The bushing's force law (a translational spring-damper at E, free about the hinge) as two
    compliant SAP distance constraints, treated implicitly: SAP steps it at IMPLICIT_TIME_STEP_S
    while its gap is at least min_loop_gap (SAP would regularise a stiffer one: not F / k)."""

    kind: ClassVar[str] = "bushing"
    sap: ClassVar[bool] = True

    def design(self, params, m_eff_kg, loop_force_N, target_gap_m, time_step_s, log_period_s):
        step = time_step_s or IMPLICIT_TIME_STEP_S
        least = min_loop_gap(m_eff_kg, near_rigid_mass(params), loop_force_N, step)
        check_number("scenario.target_loop_gap_m", target_gap_m, least, why=(
            f"at the plant step {step:g} s SAP regularises a stiffer bushing (k = loop force "
            f"{loop_force_N:.3g} N / gap > {loop_force_N / least:.3g} N/m) as near-rigid, and "
            "the gap is no longer F / k; the bound scales with the step squared: use a larger gap "
            "or a smaller scenario.time_step_s"))
        bushing, _ = bushing_parameters(m_eff_kg, loop_force_N, target_gap_m)
        return ClosureDesign(self, step, bushing, m_eff_kg, loop_force_N)

    def add_to(self, plant, instance, legs, params, bushing):
        """E on CE joined to D on DE at the length DE and to the point Q OFFSET_M off DE at E
        (perpendicular, in the leg plane) at OFFSET_M: both springs have the bushing's stiffness
        and damping, their directions at E are orthogonal, so E feels an isotropic in-plane
        spring, and both lines of action pass through E: no torque about the hinge."""
        g, k, d = params.leg, bushing.stiffness_N_m, bushing.damping_N_s_m
        for leg in legs:
            ce = plant.GetBodyByName(f"{leg}_CE", instance)
            de = plant.GetBodyByName(f"{leg}_DE", instance)
            plant.AddDistanceConstraint(ce, [g.ce_m, 0.0, 0.0], de, [0.0, 0.0, 0.0], g.de_m, k, d)
            plant.AddDistanceConstraint(ce, [g.ce_m, 0.0, 0.0], de, [g.de_m, OFFSET_M, 0.0],
                                        OFFSET_M, k, d)


@register_closure
@dataclass(frozen=True)
class ExplicitBushing(Closure):
    """Drake's explicit LinearBushingRollPitchYaw with the bushing's stiffness (the reference the
    seed names): the plant steps at the largest stable step that divides the log interval, so
    every interval has whole steps."""

    kind: ClassVar[str] = "bushing_rpy"

    def sdf(self, cut, bushing):
        """A <drake:linear_bushing_rpy> between the cut's frames: the bushing's force stiffness
        and damping, free in rotation."""
        k, d = bushing.stiffness_N_m, bushing.damping_N_s_m
        return element("drake:linear_bushing_rpy",
                       element("drake:bushing_frameA", cut.frame_a),
                       element("drake:bushing_frameC", cut.frame_b),
                       element("drake:bushing_torque_stiffness", "0 0 0"),
                       element("drake:bushing_torque_damping", "0 0 0"),
                       element("drake:bushing_force_stiffness", fmt(k, k, k)),
                       element("drake:bushing_force_damping", fmt(d, d, d)))

    def design(self, params, m_eff_kg, loop_force_N, target_gap_m, time_step_s, log_period_s):
        bushing, dt = bushing_parameters(m_eff_kg, loop_force_N, target_gap_m)
        if time_step_s > dt:
            raise ParameterError(
                f"scenario.time_step_s = {time_step_s!r}: the explicit bushing (k = "
                f"{bushing.stiffness_N_m:.3g} N/m, m_eff = {m_eff_kg * 1e3:.2f} g) is stable up "
                f"to {dt:.3g} s; use 0 (derived) or a smaller step, a larger target_loop_gap_m, "
                "or the implicit closure 'bushing'", "scenario.time_step_s")
        derived = log_period_s / math.ceil(log_period_s / dt - 1e-9)
        return ClosureDesign(self, time_step_s or derived, bushing, m_eff_kg, loop_force_N)


@register_closure
@dataclass(frozen=True)
class Ball(Closure):
    """A SAP ball constraint: SAP regularises it to a spring whose stiffness the step sets
    (nothing to design); IMPLICIT_TIME_STEP_S by default."""

    kind: ClassVar[str] = "ball"
    sap: ClassVar[bool] = True

    def sdf(self, cut, bushing):
        return ball_constraint(cut.body_a, cut.p_a, cut.body_b, cut.p_b)

    def design(self, params, m_eff_kg, loop_force_N, target_gap_m, time_step_s, log_period_s):
        return ClosureDesign(self, time_step_s or IMPLICIT_TIME_STEP_S, None, m_eff_kg,
                             loop_force_N)


def design_closure(params: Params, closure: "Closure | str", target_gap_m: float,
                   time_step_s: float = 0.0, log_period_s: float = 2e-3) -> ClosureDesign:
    """The closure (a Closure or its kind) designed for the parameters (Closure.design) from the
    knee's effective mass and the loop force (loop_load). time_step_s > 0 asks for a plant step
    (s; 0: derived), log_period_s (s) is the recorder's interval."""
    m_eff, force = loop_load(params)
    return by_kind(CLOSURES, closure, "closure").design(params, m_eff, force, target_gap_m,
                                                        time_step_s, log_period_s)


# The committed models (sdf/), each closed by its closure.
MODEL_FILES = {"leg.sdf": (single_leg_sdf, ExplicitBushing()),
               "quadruped.sdf": (quadruped_sdf, ExplicitBushing()),
               "quadruped_ball.sdf": (quadruped_sdf, Ball())}


def write_models(params: Params, bushing: Bushing, out_dir: Path) -> list[Path]:
    """Write the MODEL_FILES into out_dir, each atomically: the fixed-hip leg and the quadruped
    closed by the explicit bushing, and the quadruped closed by ball constraints; then the
    quadruped for MuJoCo (mjcf.MJCF_FILE)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    return [write_atomic(out_dir / name, make(params, closure, bushing))
            for name, (make, closure) in MODEL_FILES.items()] + [
        write_atomic(out_dir / MJCF_FILE, quadruped_mjcf(params))]
