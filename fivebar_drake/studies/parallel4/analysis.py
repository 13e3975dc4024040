"""The parallel4 analysis: checks of the closed forms, singularities, the seed's four workspace
studies, the condition-number maps and the seed's stiffness figures under every reading, the
Drake model's static check, and the table of the seed's claims."""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np

from fivebar_drake.mechanisms.parallel4.geometry import (SEED_JOINT_FREEDOMS, SEED_LINKS,
                                                         Geometry, grubler)
from fivebar_drake.mechanisms.parallel4.kinematics import (
    forward, inverse, jacobians, reach, seed_B, type2_line_z, velocity_jacobian)
from fivebar_drake.mechanisms.parallel4.params import Params
from fivebar_drake.mechanisms.parallel4.statics import (
    condition_number, in_workspace, poses_yz, stiffness, translational_block,
    translational_free_rotation, yz_grid)
from fivebar_drake.studies.parallel4.model import Parallel4Plant, closed_form_static_forces

REPRODUCED_WITHIN = 0.05     # a number is reproduced within 5 % of the seed's (issue 13)
SEED_COND = {"cond_wide_0deg": ("wide", 0.0, 2.5), "cond_narrow_0deg": ("narrow", 0.0, 8.5),
             "cond_narrow_60deg": ("narrow", 60.0, 25.0)}
CHECK_SAMPLES = 4000         # random poses for the round-trip and Jacobian checks


READINGS = {
    # name: (unit scale of (x, y, z, theta), what is taken of K, square root?)
    "K (4x4, m and rad), sqrt(lmax/lmin)": ((1, 1, 1, 1), None, True),
    "K (4x4, mm and rad)": ((1e3, 1e3, 1e3, 1), None, True),
    "K (4x4, m and deg)": ((1, 1, 1, 180 / math.pi), None, True),
    "K (4x4, m and rad), lmax/lmin without the root": ((1, 1, 1, 1), None, False),
    "K translational block (theta held)": ((1, 1, 1, 1), translational_block, True),
    "translational stiffness, theta free (Schur complement)":
        ((1, 1, 1, 1), translational_free_rotation, True),
}
MAP_READINGS = ("K (4x4, m and rad), sqrt(lmax/lmin)", "K translational block (theta held)")


def reading_condition(g: Geometry, poses, k, reading: str) -> np.ndarray:
    """Condition number of poses (..., 4) under one of READINGS."""
    scale, part, root = READINGS[reading]
    K = stiffness(g, poses, k, scale=scale)
    cond = condition_number(K if part is None else part(K))
    return cond if root else cond ** 2


def _grid(params: Params):
    gr = params.grid
    return yz_grid(gr.half_width, gr.z_low, gr.z_high, gr.step)


def checks(g: Geometry, seed: int = 7) -> dict:
    """Round trip FK(IK) on both FK branches, and J = A^-1 B against central differences of
    the IK, over random workspace poses; the seed's B column against the same."""
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(-0.3, 0.3, CHECK_SAMPLES),
                             rng.uniform(-g.R / 2, g.R / 2, CHECK_SAMPLES),
                             rng.uniform(-g.R - g.c - g.d, -g.R / 2, CHECK_SAMPLES),
                             rng.uniform(-1.4, 1.4, CHECK_SAMPLES)])
    poses = poses[in_workspace(g, poses)]
    q = inverse(g, poses)
    upper = forward(g, q, lower=False)
    h = 1e-7
    fd = np.stack([(inverse(g, poses + h * e) - inverse(g, poses - h * e)) / (2 * h)
                   for e in np.eye(4)], axis=-1)
    A, B = jacobians(g, poses, q)
    J = velocity_jacobian(g, poses, q)
    Js = seed_B(B) / np.diagonal(A, axis1=-2, axis2=-1)[..., None]
    # eq. 2.17: (d1^2 - d2^2)/4 against its right side as written (y (b - a)) and as derived
    d1, d2 = q[:, 0] - q[:, 1], q[:, 2] - q[:, 3]
    lhs = (d1 ** 2 - d2 ** 2) / 4
    y, z = poses[:, 1], poses[:, 2]
    gz = 4 * z * (g.c * np.cos(poses[:, 3]) - g.d)
    scale = np.abs(lhs).max()
    return {"eq_2_17_as_written_residual": float(np.abs(lhs - (4 * y * (g.b - g.a) - gz)).max()
                                                 / scale),
            "eq_2_17_derived_residual": float(np.abs(lhs - (4 * y * (g.a - g.b) - gz)).max()
                                              / scale),"poses": int(len(poses)),
            "fk_ik_round_trip_max": float(np.abs(forward(g, q) - poses).max()),
            "fk_upper_branch_round_trip_max": float(np.abs(
                forward(g, inverse(g, upper), lower=False) - upper).max()),
            "jacobian_vs_finite_differences_max": float(np.abs(J - fd).max()),
            "seed_B_jacobian_vs_finite_differences_max": float(np.abs(Js - fd).max())}


def workspace_studies(params: Params) -> list[dict]:
    """For each study, angle and value: the yz cross-section's area (m^2), centroid and lowest
    point (m), and its mask for the plots."""
    Y, Z, cell = _grid(params)
    out = []
    for study in params.studies:
        for theta_deg in study.theta_deg:
            rows = []
            for value, g in zip(study.values, study.geometries()):
                mask = in_workspace(g, poses_yz(Y, Z, math.radians(theta_deg)))
                area = float(mask.sum() * cell)
                if mask.any():
                    low = np.argmin(np.where(mask, Z, np.inf))
                    centroid = [float(Y[mask].mean()), float(Z[mask].mean())]
                    lowest = [float(Y.flat[low]), float(Z.flat[low])]
                else:
                    centroid = lowest = [math.nan, math.nan]
                rows.append({"value": value, "area_m2": area, "centroid_yz_m": centroid,
                             "lowest_point_yz_m": lowest, "mask": mask})
            out.append({"name": study.name, "figure": study.figure, "varied": study.varied,
                        "theta_deg": theta_deg, "rows": rows,
                        "base": {k: getattr(study.base, k) for k in "abcdR"}})
    return out


def map_geometries(params: Params) -> list[tuple[str, Geometry, float]]:
    """(figure, geometry, theta_deg) of the seed's six condition-number maps: the design
    geometry (Fig. 2.13-2.16) and the narrow base (Fig. 2.17, 2.18)."""
    g, st = params.geometry, params.stiffness
    narrow = dataclasses.replace(g, a=g.b + st.narrow_a_minus_b)
    wide = [(f"2.{13 + i}", g, th) for i, th in enumerate(st.wide_theta_deg)]
    return wide + [(f"2.{17 + i}", narrow, th) for i, th in enumerate(st.narrow_theta_deg)]


def condition_maps(params: Params) -> list[dict]:
    """The condition number over the workspace's yz cross-section (NaN outside) for each map of
    map_geometries under MAP_READINGS, with its median."""
    Y, Z, _ = _grid(params)
    out = []
    for figure, g, theta_deg in map_geometries(params):
        poses = poses_yz(Y, Z, math.radians(theta_deg))
        mask = in_workspace(g, poses)
        maps = {}
        for reading in MAP_READINGS:
            cond = np.full(Y.shape, np.nan)
            cond[mask] = reading_condition(g, poses[mask], params.stiffness.actuator_N_m, reading)
            maps[reading] = cond
        out.append({"figure": figure, "a_minus_b": g.e, "theta_deg": theta_deg, "maps": maps,
                    "median": {r: float(np.nanmedian(m)) if mask.any() else math.nan
                               for r, m in maps.items()}})
    return out


def seed_point_conditions(params: Params) -> list[dict]:
    """The condition number at the seed's point (y, z) for each claim of SEED_COND, every
    reading and every parameter reading (a - b, R)."""
    st, g = params.stiffness, params.geometry
    rows = []
    for claim, (base, theta_deg, seed_value) in SEED_COND.items():
        spans = st.wide_a_minus_b if base == "wide" else (st.narrow_a_minus_b,)
        for e in spans:
            for R in st.R_readings:
                ge = dataclasses.replace(g, a=g.b + e, R=R)
                pose = np.array([0.0, st.point_y, st.point_z, math.radians(theta_deg)])
                reachable = bool(np.all(reach(ge, pose) >= 0))
                note = ("" if in_workspace(ge, pose) else "; the point is outside the workspace"
                        if reachable else "; the point is out of the legs' reach")
                for reading in READINGS:
                    value = (float(reading_condition(ge, pose, st.actuator_N_m, reading))
                             if reachable else math.nan)
                    rows.append({"id": claim, "seed_value": seed_value, "computed_value": value,
                                 "reading": f"{reading}; a - b = {e:g} m, R = {R:g} m{note}",
                                 "reproduced": abs(value - seed_value)
                                 <= REPRODUCED_WITHIN * seed_value})
    return rows


def drake_statics(params: Params, samples: int = 25, seed: int = 11) -> dict:
    """Drake's projected static actuator forces against the closed form over random workspace
    poses, and the model's mobility (nv - rank of the loop constraints)."""
    g = params.geometry
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(-0.3, 0.3, 40 * samples),
                             rng.uniform(-0.15, 0.15, 40 * samples),
                             rng.uniform(-0.4, -0.15, 40 * samples),
                             rng.uniform(-1.0, 1.0, 40 * samples)])
    poses = poses[in_workspace(g, poses)][:samples]
    model = Parallel4Plant(g, params.model, params.simulation.time_step_s)
    context = model.plant.CreateDefaultContext()
    order = model.actuator_order()
    drake, gaps, mobility = [], [], set()
    for pose in poses:
        model.plant.SetPositions(context, model.positions(pose))
        forces = np.empty(4)
        forces[order] = model.projected_static_forces(context)
        drake.append(forces)
        gaps.append(model.loop_gaps(context).max())
        mobility.add(model.mobility(context))
    drake = np.array(drake)
    closed = closed_form_static_forces(g, params.model, poses)
    relative = np.abs(drake - closed).max(axis=1) / np.abs(closed).max(axis=1)
    return {"poses": int(len(poses)), "max_relative_difference": float(relative.max()),
            "max_loop_gap_m": float(max(gaps)), "mobility": sorted(int(v) for v in mobility),
            "example_pose": [float(v) for v in poses[0]],
            "example_drake_N": [float(v) for v in drake[0]],
            "example_closed_form_N": [float(v) for v in closed[0]]}


def singularities(g: Geometry) -> dict:
    """Numbers behind the seed's singularity statements on the design geometry: det B at theta =
    90 deg and at a pair spread of 2R (legs along x), and the type-2 line's slope dz/dy at each
    map angle, ours and the seed's (eq. 2.25)."""
    pose90 = np.array([0.0, 0.0, -0.3, math.pi / 2])
    det90 = float(np.linalg.det(jacobians(g, pose90, inverse(g, pose90))[1]))
    # pair 1's platform point on its actuator line: (y1, z1) = 0, so |l1 - l2| = 2R
    spread = np.array([0.0, g.e, g.d - g.c, 0.0])
    det2R = float(np.linalg.det(jacobians(g, spread, inverse(g, spread))[1]))
    slopes = {f"{th:g}": {"ours": float(type2_line_z(g, 1.0, math.radians(th))),
                          "seed": float(type2_line_z(g, 1.0, math.radians(th), seed=True))}
              for th in (0.0, 30.0, 60.0, 80.0)}
    return {"det_B_theta_90_m5": det90, "det_B_spread_2R_m5": det2R,
            "type2_slope_dz_dy": slopes}


def mobility() -> dict:
    """Grübler's count on the seed's joint list (eq. 2.1-2.3)."""
    F, L = grubler(SEED_LINKS, SEED_JOINT_FREEDOMS)
    return {"links": SEED_LINKS, "joints": len(SEED_JOINT_FREEDOMS),
            "joint_freedoms": sum(SEED_JOINT_FREEDOMS), "F": F, "L": L}


class Analysis(NamedTuple):
    """The analysis as plain data: the parameters and every computed result (by name)."""

    params: Params
    results: dict


def analyze(params: Params) -> Analysis:
    """Every computed result: the closed forms' checks, mobility, singularities, Drake's
    statics, the workspace studies, the condition maps and the seed's point."""
    return Analysis(params, {"checks": checks(params.geometry),
                             "mobility": mobility(),
                             "singularities": singularities(params.geometry),
                             "drake_statics": drake_statics(params),
                             "workspace": workspace_studies(params),
                             "maps": condition_maps(params),
                             "seed_point": seed_point_conditions(params)})
