"""The one test of leg poses against the leg's mechanical limits (geometry.LegLimits), and the
ranges those limits give the joints of the Drake model.

Each limit set in LegLimits becomes a LimitTest over the poses: the limited quantity in SI (rad,
m), its bound and side, and which poses lie past it. The quantities: each motor angle
theta_A, theta_B (from +x, counter-clockwise, in (-pi, pi]); the leg extension |F - H| (H the hip
axis, midway between the motors); the knee angles at C (between C->A and C->E) and at D (between
D->B and D->E); the angle between the upper links A->C and B->D. The inverse kinematics, the gait
checks, the workspace plots and the simulation's limit report all use limit_tests.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

from fivebar_drake.core.rotation import angle_between
from fivebar_drake.mechanisms.fivebar.geometry import LegGeometry


@dataclass(frozen=True)
class LimitTest:
    """One limit over poses (...): its name ("knee C angle"), the [limits] field it comes from,
    the limited value (...) in SI (rad or m), the bound in SI, its side (-1: a least value, the
    value must be >= bound; +1: a most value, <= bound), and the field's unit ("deg" or "m") with
    the factor from SI to it."""

    name: str
    field: str
    value: np.ndarray
    bound: float
    side: int
    unit: str
    scale: float

    @property
    def excess(self) -> np.ndarray:
        """How far each pose lies past the bound (...) in SI; <= 0 within it, NaN for NaN."""
        return self.side * (self.value - self.bound)

    @property
    def past(self) -> np.ndarray:
        """Poses past the bound (...), False where the value is NaN (no pose)."""
        with np.errstate(invalid="ignore"):
            return self.excess > 0

    def text(self, value: float) -> str:
        """A value of this quantity (SI) against the bound, e.g. "knee C angle 7.9 deg < least
        10 deg ([limits].knee_min_deg)"."""
        sign, word = ("<", "least") if self.side < 0 else (">", "most")
        return (f"{self.name} {value * self.scale:.4g} {self.unit} {sign} {word} "
                f"{self.bound * self.scale:.4g} {self.unit} ([limits].{self.field})")


# the limits of LegLimits: field -> (name, side, unit)
LIMITS = {"theta_a_min_deg": ("motor A angle", -1, "deg"),
          "theta_a_max_deg": ("motor A angle", 1, "deg"),
          "theta_b_min_deg": ("motor B angle", -1, "deg"),
          "theta_b_max_deg": ("motor B angle", 1, "deg"),
          "extension_min_m": ("leg extension", -1, "m"),
          "extension_max_m": ("leg extension", 1, "m"),
          "knee_min_deg": ("knee {} angle", -1, "deg"),
          "upper_links_min_deg": ("upper links' angle", -1, "deg")}


def _quantities(leg: LegGeometry, pose) -> dict[str, np.ndarray]:
    """The limited quantities (SI) of poses, by the name in LIMITS."""
    q = np.arctan2(np.sin(pose.q), np.cos(pose.q))                   # in (-pi, pi]
    return {"motor A angle": q[..., 0], "motor B angle": q[..., 1],
            "leg extension": np.linalg.norm(pose.f - leg.hip, axis=-1),
            "knee C angle": angle_between(leg.a - pose.c, pose.e - pose.c),
            "knee D angle": angle_between(leg.b - pose.d, pose.e - pose.d),
            "upper links' angle": angle_between(pose.c - leg.a, pose.d - leg.b)}


def limit_tests(leg: LegGeometry, pose) -> list[LimitTest]:
    """The tests of poses (a kinematics.LegPose, shape ...) against each limit set in
    leg.limits (none set: [])."""
    given = leg.limits.given
    if not given:
        return []
    values, tests = _quantities(leg, pose), []
    for field, (name, side, unit) in LIMITS.items():
        if field not in given:
            continue
        scale = math.degrees(1.0) if unit == "deg" else 1.0
        for each in ("C", "D") if "{}" in name else ("",):
            named = name.format(each)
            tests.append(LimitTest(named, field, values[named], given[field] / scale, side, unit,
                                   scale))
    return tests


def past_any(tests: list[LimitTest], shape=()) -> np.ndarray:
    """Poses (shape) past any of the tests."""
    past = np.zeros(shape, dtype=bool)
    for test in tests:
        past = past | test.past
    return past


def first_past(tests: list[LimitTest], index: int) -> LimitTest:
    """The first of the tests (in LIMITS order) that the pose at flat index lies past."""
    return next(t for t in tests if np.ravel(t.past)[index])


def joint_ranges(leg: LegGeometry) -> dict[str, tuple[float, float]]:
    """Ranges (lower, upper) in rad of the joints of the Drake model (sdf.py) that the limits
    give, by joint (A, B, C, D); a joint without one is left out. The motor joints' angles are
    theta_A, theta_B (a side without a bound is +-inf); the knee joints' angle phi is the lower
    link's angle from the upper link's direction, so the knee angle is pi - |phi| and the least
    knee angle k is |phi| <= pi - k. The extension and the upper links' angle span several
    joints: no joint range."""
    lim, ranges = leg.limits, {}
    for joint, lo, hi in (("A", lim.theta_a_min_deg, lim.theta_a_max_deg),
                          ("B", lim.theta_b_min_deg, lim.theta_b_max_deg)):
        if lo is not None or hi is not None:
            ranges[joint] = (-math.inf if lo is None else math.radians(lo),
                             math.inf if hi is None else math.radians(hi))
    if lim.knee_min_deg is not None:
        reach = math.pi - math.radians(lim.knee_min_deg)
        ranges["C"] = ranges["D"] = (-reach, reach)
    return ranges
