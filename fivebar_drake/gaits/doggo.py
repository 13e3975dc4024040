"""The Doggo-style path (Stanford Doggo's trot)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple, Optional

import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.core.validation import check_number, MAX_LENGTH_M
from fivebar_drake.gaits.base import FootPath, Gait, register_path


class DoggoConstants(NamedTuple):
    """The Doggo-style path's stride half-length a, flight height h, stance depth d and centre
    (x_center, y_home) in m, frequency in Hz and flight share (fraction of the cycle)."""

    a: float
    h: float
    d: float
    x_center: float
    y_home: float
    frequency: float
    flight: float


@jit
def doggo_point(c, u):
    """Doggo-style path (DoggoConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in m, m/s,
    m/s^2 and the stance flag. Flight (u < flight): x from x_c + a to x_c - a at constant speed,
    y = y_home + h sin(pi s); stance: back from x_c - a to x_c + a, y = y_home - d sin(pi s)
    (s: the fraction of the flight or the stance), as Stanford Doggo's sinusoidal gait; the
    foot's speed jumps at lift-off and touchdown."""
    if u < c.flight:
        rate = c.frequency / c.flight                   # ds/dt
        s = u / c.flight
        sn, cs = np.sin(np.pi * s), np.cos(np.pi * s)
        return (c.x_center + c.a - 2.0 * c.a * s, c.y_home + c.h * sn, -2.0 * c.a * rate,
                c.h * np.pi * cs * rate, 0.0, -c.h * np.pi**2 * sn * rate**2, False)
    rate = c.frequency / (1.0 - c.flight)
    s = (u - c.flight) / (1.0 - c.flight)
    sn, cs = np.sin(np.pi * s), np.cos(np.pi * s)
    return (c.x_center - c.a + 2.0 * c.a * s, c.y_home - c.d * sn, 2.0 * c.a * rate,
            -c.d * np.pi * cs * rate, 0.0, c.d * np.pi**2 * sn * rate**2, True)


@register_path
@dataclass(frozen=True)
class Doggo(FootPath):
    """Stanford Doggo's sinusoidal foot path (its firmware's trajectory, in this package's
    frame): a half sine up in flight, a half sine down in stance, straight at constant speed
    along x in each. flight_height_m (None: gait.b_m), stance_depth_m (m, the foot pressed below
    the ground line mid-stance; 0: flat), flight_share (None: 1 - gait.duty_factor)."""

    kind: ClassVar[str] = "doggo"
    point: ClassVar = staticmethod(doggo_point)
    title: ClassVar[str] = "Doggo-style sinusoidal foot path"
    flight_height_m: Optional[float] = None
    stance_depth_m: float = 0.0
    flight_share: Optional[float] = None

    def text(self, gait: Gait) -> str:
        return (f"a Doggo-style path: flight {self.share(gait):.0%} of the cycle lifting the foot "
                f"{self.height(gait) * 1e3:g} mm (half sine), stance pressing it "
                f"{self.stance_depth_m * 1e3:g} mm below y = {gait.y_home_m * 1e3:g} mm (half "
                f"sine), stride 2a = {2 * gait.a_m * 1e3:g} mm at {self.stance_speed(gait):.3f} "
                "m/s in stance")

    def height(self, gait: Gait) -> float:
        return gait.b_m if self.flight_height_m is None else self.flight_height_m

    def share(self, gait: Gait) -> float:
        return 1.0 - gait.duty_factor if self.flight_share is None else self.flight_share

    def check(self, field: str) -> None:
        for name in ("flight_height_m", "stance_depth_m"):
            if getattr(self, name) is not None:
                check_number(f"{field}.{name}", getattr(self, name), 0.0, MAX_LENGTH_M)
        if self.flight_share is not None:
            check_number(f"{field}.flight_share", self.flight_share, 0.0, 1.0, low_open=True,
                         high_open=True)

    def gait_fields(self) -> tuple[str, ...]:
        return super().gait_fields() + (("duty_factor",) if self.flight_share is None else ())

    def constants(self, gait: Gait) -> DoggoConstants:
        return DoggoConstants(gait.a_m, self.height(gait), self.stance_depth_m, gait.x_center_m,
                              gait.y_home_m, gait.frequency_hz, self.share(gait))

    def stance_start(self, gait: Gait) -> float:
        return self.share(gait)
