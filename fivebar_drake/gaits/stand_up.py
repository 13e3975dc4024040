"""Standing up from lying on the belly."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from fivebar_drake.core.validation import check_number, MAX_LENGTH_M
from fivebar_drake.gaits.base import Gait, MAX_MANEUVER_S, register_path
from fivebar_drake.gaits.maneuver import hold, Maneuver, move


@register_path
@dataclass(frozen=True)
class StandUp(Maneuver):
    """Standing up from lying on the belly: the feet start folded at (fold_x_m, fold_y_m) (the
    default: 150 mm behind the hips, 28 mm below them, on the ground when the default body lies
    on its belly) and move in a straight line to the standing point over rise_s, all in stance,
    then hold it settle_s."""

    kind: ClassVar[str] = "stand_up"
    title: ClassVar[str] = "stand up from lying"
    fold_x_m: float = 0.15
    fold_y_m: float = -0.028
    rise_s: float = 1.5
    settle_s: float = 0.5

    def check(self, field: str) -> None:
        check_number(f"{field}.fold_x_m", self.fold_x_m, -MAX_LENGTH_M, MAX_LENGTH_M)
        check_number(f"{field}.fold_y_m", self.fold_y_m, -MAX_LENGTH_M, MAX_LENGTH_M)
        for name in ("rise_s", "settle_s"):
            check_number(f"{field}.{name}", getattr(self, name), 0.0, MAX_MANEUVER_S,
                         low_open=True)

    def segments(self, gait: Gait) -> list[tuple]:
        home = (gait.x_center_m, gait.y_home_m)
        return [move(self.rise_s, True, (self.fold_x_m, self.fold_y_m), home),
                hold(self.settle_s, True, home)]
