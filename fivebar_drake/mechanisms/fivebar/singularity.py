"""Singularity measures and the workspace of the 5-bar leg (leg plane, m, rad).

Transmission angles: at C between C->A and C->E, at D between D->B and D->E, at E between E->C
and E->D; 0 or pi means the two links are in line. E folded in line with CD (E angle 0 or pi)
is the parallel singularity (the loop matrix A of seed 003 is singular, J_F blows up); an upper
link in line with its lower link (C or D angle 0 or pi) is the serial singularity (det J_F = 0).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
import numpy as np

from fivebar_drake.core.rotation import angle_between
from fivebar_drake.mechanisms.fivebar.geometry import LegGeometry
from fivebar_drake.mechanisms.fivebar.jacobians import foot_jacobian
from fivebar_drake.mechanisms.fivebar.kinematics import (KNEES_OUT, LegPose, UnreachableError,
                                                         inverse)


@dataclass(frozen=True)
class SingularityMeasures:
    """Transmission angles (rad) at C, D, E; det J_F (m^2/rad^2); condition number of J_F."""

    angle_c: np.ndarray
    angle_d: np.ndarray
    angle_e: np.ndarray
    det_jf: np.ndarray
    cond_jf: np.ndarray


def singularity_measures(leg: LegGeometry, pose: LegPose) -> SingularityMeasures:
    jf = foot_jacobian(leg, pose)
    s = np.linalg.svd(jf, compute_uv=False)
    return SingularityMeasures(
        angle_c=angle_between(leg.a - pose.c, pose.e - pose.c),
        angle_d=angle_between(leg.b - pose.d, pose.e - pose.d),
        angle_e=angle_between(pose.c - pose.e, pose.d - pose.e),
        det_jf=np.linalg.det(jf),
        cond_jf=s[..., 0] / s[..., 1])


@dataclass(frozen=True)
class Workspace:
    """Foot workspace on a grid: x (nx,), y (ny,) in m; reachable (ny, nx); measures of the
    reachable poses (NaN elsewhere)."""

    x: np.ndarray
    y: np.ndarray
    reachable: np.ndarray
    measures: SingularityMeasures


def workspace(leg: LegGeometry, x, y, mode=KNEES_OUT) -> Workspace:
    """Reachable foot positions of one assembly mode on the grid x by y (m), with singularity
    measures."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    pose = inverse(leg, np.stack(np.meshgrid(x, y), axis=-1), mode, strict=False)
    ok = ~np.isnan(pose.q).any(axis=-1)
    if not ok.any():
        raise UnreachableError(f"no point of the grid x {x.min():.3f}..{x.max():.3f} m, "
                               f"y {y.min():.3f}..{y.max():.3f} m is reachable")
    # Unreachable points borrow a reachable pose so the batched SVD stays finite; masked below.
    first = tuple(np.argwhere(ok)[0])
    pose = LegPose(*(np.where(ok[..., None], v, v[first]) for v in astuple_shallow(pose)))
    with np.errstate(divide="ignore", invalid="ignore"):
        m = singularity_measures(leg, pose)
    masked = SingularityMeasures(*(np.where(ok, v, np.nan) for v in astuple_shallow(m)))
    return Workspace(x=x, y=y, reachable=ok, measures=masked)


def astuple_shallow(obj) -> tuple:
    """The fields of a dataclass instance, in order, without copying."""
    return tuple(getattr(obj, f.name) for f in fields(obj))
