"""Design parameters of the 4-DOF parallel manipulator after Pierrot (seed 004, chapter 2) and
Grübler's mobility count.

Frame {O}: x along the four prismatic actuators, z up. Actuators 1 and 2 run on the line
(y, z) = (a, d), actuators 3 and 4 on (-a, -d); legs 1, 2 meet at the platform point B12 =
P + Rot_y(theta) (0, b, c), legs 3, 4 at B34 = P + Rot_y(theta) (0, -b, -c). Only a - b enters
the kinematics (the platform turns about y, which leaves the y offsets alone).
"""

from __future__ import annotations

from dataclasses import dataclass

from fivebar_drake.core.validation import MAX_LENGTH_M, check_number, require


@dataclass(frozen=True)
class Geometry:
    """Base offsets a, d (m), platform offsets b, c (m), leg length R (m), and the stroke of the
    leg pairs: d_min_over_R <= |l1 - l2|/R, |l3 - l4|/R <= d_max_over_R (seed Fig. 2.8)."""

    a: float
    b: float
    c: float
    d: float
    R: float
    d_min_over_R: float
    d_max_over_R: float

    @property
    def e(self) -> float:
        """a - b (m): how much wider the base is than the platform."""
        return self.a - self.b

    def check(self, section: str = "geometry") -> "Geometry":
        """self if every value is usable by the closed forms, else ParameterError naming the
        field: lengths in (0, MAX_LENGTH_M], a > b (the forward kinematics divides by a - b),
        0 < d_min_over_R < d_max_over_R <= 2 (a leg pair spreads at most 2R)."""
        for name in ("a", "b", "c", "d", "R"):
            check_number(f"{section}.{name}", getattr(self, name), 0.0, MAX_LENGTH_M,
                         low_open=name in ("c", "R"))
        require(self.a > self.b, f"{section}.a", self.a,
                f"must exceed b = {self.b:g} (the forward kinematics divides by a - b)")
        check_number(f"{section}.d_max_over_R", self.d_max_over_R, 0.0, 2.0, low_open=True,
                     why="a leg pair of two legs R long spreads at most 2R")
        check_number(f"{section}.d_min_over_R", self.d_min_over_R, 0.0, self.d_max_over_R,
                     high_open=True, why="below d_max_over_R")
        return self


# The seed's joint list (section 2.1): per leg a prismatic actuator (1 freedom) and two universal
# joints (2 each); two revolute joints join the two metachains to the platform.
SEED_JOINT_FREEDOMS = (1, 2, 2) * 4 + (1, 1)
SEED_LINKS = 12        # base, 4 sliders, 4 legs, 2 metachain heads, the platform
SPATIAL = 6            # lambda: freedoms of a body in space


def grubler(links: int, joint_freedoms, lam: int = SPATIAL) -> tuple[int, int]:
    """(mobility F, loops L) by Grübler's criterion F = lambda (n - j - 1) + sum f_i (eq. 2.1)
    and Euler's L = j - n + 1 (eq. 2.2), n links counting the base."""
    joints = len(joint_freedoms)
    return lam * (links - joints - 1) + sum(joint_freedoms), joints - links + 1
