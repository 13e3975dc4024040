"""The walk (a crawl): the trot's path one leg at a time."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Optional

import numpy as np

from fivebar_drake.core.validation import check_number
from fivebar_drake.gaits.base import MIN_CRAWL_DUTY, register_path
from fivebar_drake.gaits.trot import Trot


@register_path
@dataclass(frozen=True)
class Walk(Trot):
    """A statically stable crawl: the trot path, one leg at a time (rear left, front left, rear
    right, front right, a quarter cycle apart), duty factor >= 0.75 so three or four feet are
    always down."""

    kind: ClassVar[str] = "walk"
    title: ClassVar[str] = "crawl (one leg at a time)"
    gait_defaults: ClassVar[dict] = {"frequency_hz": 0.5}
    order: ClassVar[tuple] = ("RL", "FL", "RR", "FR")   # each lifts off at f t = 1 - phase / 2 pi
    duty_factor: Optional[float] = 0.8

    def leg_phase(self, leg: str) -> float:
        return float(np.mod(-2.0 * math.pi * self.order.index(leg) / 4.0, 2.0 * math.pi))

    def check(self, field: str) -> None:
        check_number(f"{field}.duty_factor", self.duty_factor, MIN_CRAWL_DUTY, 1.0,
                     high_open=True, why="a crawl keeps three feet down: one leg swings at a time")
