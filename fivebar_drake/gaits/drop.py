"""The drop onto the feet."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from fivebar_drake.core.validation import check_number, MAX_LENGTH_M
from fivebar_drake.gaits.base import Events, Gait, register_path
from fivebar_drake.gaits.maneuver import hold, Landing


@register_path
@dataclass(frozen=True)
class Drop(Landing):
    """A drop: the robot starts at rest with its feet height_m above the ground, legs extended
    extension_m below the standing line, falls and lands (Landing) at sqrt(2 g height_m)."""

    kind: ClassVar[str] = "drop"
    title: ClassVar[str] = "drop onto the feet"
    stand_first: ClassVar[bool] = False
    height_m: float = 0.1
    extension_m: float = 0.04
    landing_stroke_m: float = 0.08

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.height_m", self.height_m, 0.0, MAX_LENGTH_M, low_open=True,
                     why="a drop from no height is no landing (and its touchdown speed, 0, "
                         "divides the landing's time)")

    def lift_m(self, gait: Gait) -> float:
        return self.height_m

    def touchdown_speed(self, gait: Gait) -> float:
        """sqrt(2 g height_m) (m/s)."""
        return math.sqrt(2.0 * gait.gravity_m_s2 * self.height_m)

    def segments(self, gait: Gait) -> list[tuple]:
        g = gait.gravity_m_s2
        foot = (gait.x_center_m, gait.y_home_m - self.extension_m)
        return ([hold(math.sqrt(2.0 * self.height_m / g), False, foot)]
                + self.landing(gait, self.touchdown_speed(gait)))

    def events(self, gait: Gait) -> Events:
        return Events(touchdown=math.sqrt(2.0 * self.height_m / gait.gravity_m_s2))
