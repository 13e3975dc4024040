"""The bound: the trot's path with the front pair and the rear pair together."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Optional

from fivebar_drake.gaits.base import register_path
from fivebar_drake.gaits.trot import Trot


@register_path
@dataclass(frozen=True)
class Bound(Trot):
    """A bound: the trot path with the front pair and the rear pair half a cycle apart."""

    kind: ClassVar[str] = "bound"
    title: ClassVar[str] = "bound (front pair, rear pair)"
    gait_defaults: ClassVar[dict] = {"frequency_hz": 2.0, "a_m": 0.03}
    duty_factor: Optional[float] = 0.75

    def leg_phase(self, leg: str) -> float:
        return 0.0 if leg[0] == "F" else math.pi
