"""The pronk: all four legs together, the stance dipping the body into a flight."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar, Optional

from fivebar_drake.core.validation import check_number, MAX_LENGTH_M
from fivebar_drake.gaits.base import Gait, register_path
from fivebar_drake.gaits.trot import Trot, TrotConstants


@register_path
@dataclass(frozen=True)
class Pronk(Trot):
    """A pronk: all four legs together; in stance the foot rises
    by dip_m sin(pi sigma) towards the hip (the body dips and is pushed back up), leaving at the
    vertical speed pi dip_m / T_stance, so the body flies 2 pi dip_m / (g T_stance) s: the
    default dip, 36 mm, gives the 0.1 s flight of the default 3 Hz, duty 0.7 (g = 9.81 m/s^2);
    choose dip_m = g (1 - beta) beta T^2 / (2 pi) for another."""

    kind: ClassVar[str] = "pronk"
    title: ClassVar[str] = "pronk (all four legs together)"
    # all four land together: a pair down before its schedule is the body's pitch, not an
    # early step, and freezing it made the gait flip between two patterns with the plant step
    # (issue 39: the heavy-rotor designs' pronk not achieved at 1 ms, achieved at 0.5 ms)
    early_touchdown: ClassVar[bool] = False
    gait_defaults: ClassVar[dict] = {"frequency_hz": 3.0, "a_m": 0.03, "b_m": 0.015}
    duty_factor: Optional[float] = 0.7
    dip_m: float = 0.0364

    def leg_phase(self, leg: str) -> float:
        return 0.0

    def at_duty(self, beta: float, gait: Gait) -> "Pronk":
        """At duty factor beta with the dip that flies the body for the rest of the period:
        dip_m = g (1 - beta) beta T^2 / (2 pi)."""
        dip = gait.gravity_m_s2 * (1.0 - beta) * beta * gait.period_s**2 / (2.0 * math.pi)
        return dataclasses.replace(self, duty_factor=beta, dip_m=dip)

    def check(self, field: str) -> None:
        super().check(field)
        check_number(f"{field}.dip_m", self.dip_m, 0.0, MAX_LENGTH_M)

    def constants(self, gait: Gait) -> TrotConstants:
        return super().constants(gait)._replace(dip=self.dip_m)
