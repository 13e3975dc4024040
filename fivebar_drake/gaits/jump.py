"""The vertical jump: crouch, push-off, flight, landing."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from fivebar_drake.verdicts.checks import Checks
from fivebar_drake.core.validation import check_number, MAX_LENGTH_M
from fivebar_drake.gaits.base import (Events, EXTENSION_STOP_S, Gait, Outcome, PUSH_SHARES,
                                      REACH_SPEED_M_S, register_path)
from fivebar_drake.gaits.maneuver import hold, Landing, move, REST


@register_path
@dataclass(frozen=True)
class Jump(Landing):
    """A vertical jump of all four legs: crouch crouch_m above the standing line over crouch_s,
    hold hold_s, push off (the foot's quintic from rest to the takeoff speed at extension_m below
    the standing line over push_share of 2 stroke / v: at 1, peak acceleration 0.75 v^2 /
    stroke; an optimal push, which the tracking controller follows, is shorter), fly (the legs'
    extension stopped
    within EXTENSION_STOP_S, the feet tucked retract_m and reaching down at 0.1 m/s to land),
    land (Landing). The takeoff speed puts the body's apex
    height_m above its standing height: v = sqrt(2 g (height_m - extension_m))."""

    pushes: ClassVar[bool] = True
    kind: ClassVar[str] = "jump"
    title: ClassVar[str] = "vertical jump"
    height_m: float = 0.06
    crouch_m: float = 0.06
    crouch_s: float = 0.4
    hold_s: float = 0.2
    retract_m: float = 0.02
    push_share: float = 1.0

    def shortfalls(self, gait: Gait, outcome: Outcome, checks: Checks) -> list[str]:
        """A jump leaves the ground with every foot, its body's apex rises at least
        checks.achieved_height_fraction of height_m above standing, and it ends standing
        (Maneuver)."""
        m = outcome.maneuver
        jump = None if m is None else m["jump"]
        if jump is None:
            missed = ["no foot left the ground" + (f" ({m['why_grounded']})" if m else "")]
        elif not jump["height_m"] >= checks.achieved_height_fraction * self.height_m:
            missed = [f"it rose {jump['height_m'] * 1e3:.1f} mm, less than "
                      f"{checks.achieved_height_fraction:.0%} of the planned "
                      f"{self.height_m * 1e3:.1f} mm"]
        else:
            missed = []
        return missed + super().shortfalls(gait, outcome, checks)

    def takeoff_speed(self, gait: Gait) -> float:
        """Planned takeoff speed (m/s) of the body."""
        return math.sqrt(2.0 * gait.gravity_m_s2 * max(self.height_m - self.extension_m, 0.0))

    def touchdown_speed(self, gait: Gait) -> float:
        """The body lands at its takeoff height, at its takeoff speed (m/s)."""
        return self.takeoff_speed(gait)

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.crouch_m", self.crouch_m, 0.0 - self.extension_m, MAX_LENGTH_M,
                     low_open=True, why="the push-off's stroke is crouch_m + extension_m: none "
                                        "would push in no distance")
        check_number(f"{field}.height_m", self.height_m, self.extension_m, MAX_LENGTH_M,
                     low_open=True, why=f"the apex lies above the takeoff height "
                                        f"(extension_m = {self.extension_m:g} m)")
        check_number(f"{field}.push_share", self.push_share, *PUSH_SHARES, low_open=True,
                     why="the push's time over 2 stroke / takeoff speed: at 0.5 the whole "
                         "stroke at the takeoff speed; beyond 1.25 the foot's quintic "
                         "reverses")

    def timing(self, gait: Gait) -> tuple[float, float, float]:
        """(push-off s, flight s, takeoff speed m/s) of the plan: the body lands at its takeoff
        height."""
        v = self.takeoff_speed(gait)
        return (2.0 * self.push_share * (self.crouch_m + self.extension_m) / v,
                2.0 * v / gait.gravity_m_s2, v)

    def segments(self, gait: Gait) -> list[tuple]:
        x, y0 = gait.x_center_m, gait.y_home_m
        push, flight, v = self.timing(gait)
        crouch, takeoff = (x, y0 + self.crouch_m), (x, y0 - self.extension_m)
        tucked = (x, takeoff[1] + self.retract_m)
        stopped = (x, takeoff[1] - v * EXTENSION_STOP_S / 2)     # the extension, stopped
        return [move(self.crouch_s, True, (x, y0), crouch), hold(self.hold_s, True, crouch),
                (push, True, (x, *REST, x, *REST),
                 (crouch[1], 0.0, 0.0, takeoff[1], -v, 0.0)),
                move(EXTENSION_STOP_S, False, takeoff, stopped, (-v, 0.0)),
                move(flight / 2 - EXTENSION_STOP_S, False, stopped, tucked),
                move(flight / 2, False, tucked, takeoff, (0.0, -REACH_SPEED_M_S)),
                ] + self.landing(gait, v)

    def events(self, gait: Gait) -> Events:
        push, flight, _ = self.timing(gait)
        onset = self.crouch_s + self.hold_s
        return Events(onset=onset, takeoff=onset + push, touchdown=onset + push + flight)
