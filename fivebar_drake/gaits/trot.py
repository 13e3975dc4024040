"""The trot: a flat stance at constant ground speed and a touchdown-matched quintic swing; the
base of the walk, bound and pronk."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar, NamedTuple, Optional

import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.validation import MAX_LENGTH_M, check_number
from fivebar_drake.gaits.base import FootPath, Gait, register_path


@jit
def _quintic_h(r):
    """H (unit start slope, zero end slope, zero second derivative at both ends) and its first
    and second derivatives at r."""
    return (r - 6 * r**3 + 8 * r**4 - 3 * r**5, 1 - 18 * r**2 + 32 * r**3 - 15 * r**4,
            -36 * r + 96 * r**2 - 60 * r**3)


class TrotConstants(NamedTuple):
    """The trot path's stride half-length a, lift b and centre (x_center, y_home) in m, period
    in s, duty factor beta, stance dip (m; the pronk's, 0 for a flat stance) and the swing's
    shape terms (m; Trot's swing_*_m)."""

    a: float
    b: float
    x_center: float
    y_home: float
    period: float
    beta: float
    dip: float = 0.0
    reach: float = 0.0
    skew: float = 0.0
    lift_skew: float = 0.0


@jit
def trot_point(c, u):
    """Trot path (module docstring; TrotConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in
    m, m/s, m/s^2 and the stance flag. The swing's x is the min-jerk P (0 -> 1) with H and G
    (G(s) = -H(1 - s)) adding the matched end slopes."""
    a, b, x_center, y_home, period, beta = c.a, c.b, c.x_center, c.y_home, c.period, c.beta
    v = 2.0 * a / (beta * period)
    w = np.pi / (beta * period)             # the dip's rate: A sin(w t) over the stance
    if u >= 1.0 - beta:                     # stance: flat (or dipping), at constant speed
        sigma = min(max((u - (1.0 - beta)) / beta, 0.0), 1.0)
        sn, cs = np.sin(np.pi * sigma), np.cos(np.pi * sigma)
        return ((-a + 2 * a * sigma) + x_center, y_home + c.dip * sn, v, c.dip * w * cs, 0.0,
                -c.dip * w * w * sn, True)
    t_sw = (1.0 - beta) * period
    s = min(max(u / (1.0 - beta), 0.0), 1.0)
    p, dp, ddp = 10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4, \
        60 * s - 180 * s**2 + 120 * s**3
    h0, dh0, ddh0 = _quintic_h(s)
    h1, dh1, ddh1 = _quintic_h(1.0 - s)
    hg, dhg, ddhg = h0 - h1, dh0 + dh1, ddh0 - ddh1
    bump = 64 * s**3 * (1 - s) ** 3
    dbump = 192 * s**2 * (1 - s) ** 2 * (1 - 2 * s) / t_sw
    ddbump = 384 * s * (1 - s) * ((1 - 2 * s) ** 2 - s * (1 - s)) / t_sw**2
    # the shape terms: the bump and the bump times (2s - 1), which leave the ends' position,
    # speed and acceleration as they are
    skew, dskew = bump * (2 * s - 1), dbump * (2 * s - 1) + 2 * bump / t_sw
    ddskew = ddbump * (2 * s - 1) + 4 * dbump / t_sw
    # the dip's vertical speed -A w at lift-off and +A w at touchdown, matched by H and G
    vd = -c.dip * w * t_sw
    return (a - 2 * a * p + v * t_sw * hg + x_center + c.reach * bump + c.skew * skew,
            y_home + b * bump + vd * (h0 + h1) + c.lift_skew * skew,
            (-2 * a * dp + v * t_sw * dhg) / t_sw + c.reach * dbump + c.skew * dskew,
            b * dbump + vd * (dh0 - dh1) / t_sw + c.lift_skew * dskew,
            (-2 * a * ddp + v * t_sw * ddhg) / t_sw**2 + c.reach * ddbump + c.skew * ddskew,
            b * ddbump + vd * (ddh0 + ddh1) / t_sw**2 + c.lift_skew * ddskew,
            False)


@register_path
@dataclass(frozen=True)
class Trot(FootPath):
    """The trot path (module docstring); duty_factor: its fraction of the cycle in stance
    (None: the parameter file's gait.duty_factor); the swing's shape terms (m, 0: the plain
    quintic): swing_reach_m adds 64 s^3 (1 - s)^3 to x (the foot further back at mid-swing),
    swing_skew_m and swing_lift_skew_m that times (2s - 1) to x and y (the foot earlier or later
    along its way, its lift earlier or later); none changes the ends (the optimal top speed's
    swing, optimal/top_speed.py)."""

    kind: ClassVar[str] = "trot"
    point: ClassVar = staticmethod(trot_point)
    title: ClassVar[str] = "trot foot path"
    duty_factor: Optional[float] = None
    swing_reach_m: float = 0.0
    swing_skew_m: float = 0.0
    swing_lift_skew_m: float = 0.0

    def text(self, gait: Gait) -> str:
        g = gait
        return (f"the trot path (gaits/): stance flat at y = {g.y_home_m * 1e3:g} mm "
                f"over the stride 2a = {2 * g.a_m * 1e3:g} mm at {self.stance_speed(g):.3f} m/s, "
                f"duty factor {self.beta(g):g} (stance fraction of the cycle), swing lifting the "
                f"foot by b = {g.b_m * 1e3:g} mm with matched touchdown speed")

    def at_duty(self, beta: float, gait: Gait) -> "Trot":
        """This path at duty factor beta under gait (its frequency): the top speed's search
        varies both (optimal/top_speed.py)."""
        return dataclasses.replace(self, duty_factor=beta)

    def beta(self, gait: Gait) -> float:
        """The duty factor: this path's, or the parameter file's."""
        return gait.duty_factor if self.duty_factor is None else self.duty_factor

    def gait_fields(self) -> tuple[str, ...]:
        """The periodic path's, and gait.duty_factor unless the path has its own."""
        return super().gait_fields() + (("duty_factor",) if self.duty_factor is None else ())

    def check(self, field: str) -> None:
        if self.duty_factor is not None:
            check_number(f"{field}.duty_factor", self.duty_factor, 0.0, 1.0, low_open=True,
                         high_open=True)
        for name in ("swing_reach_m", "swing_skew_m", "swing_lift_skew_m"):
            check_number(f"{field}.{name}", getattr(self, name), -MAX_LENGTH_M, MAX_LENGTH_M)

    def constants(self, gait: Gait) -> TrotConstants:
        return TrotConstants(gait.a_m, gait.b_m, gait.x_center_m, gait.y_home_m, gait.period_s,
                             self.beta(gait), 0.0, self.swing_reach_m, self.swing_skew_m,
                             self.swing_lift_skew_m)

    def stance_start(self, gait: Gait) -> float:
        return 1.0 - self.beta(gait)

    def stance_speed(self, gait: Gait) -> float:
        return 2.0 * gait.a_m / (self.beta(gait) * gait.period_s)
