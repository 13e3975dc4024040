"""The seed's elliptical foot path (seed 000 section 3)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from fivebar_drake.core.compiled import jit
from fivebar_drake.gaits.base import FootPath, Gait, register_path


class EllipseConstants(NamedTuple):
    """The seed ellipse's semi-axes a, b and centre (x_center, y_home) in m, frequency in Hz."""

    a: float
    b: float
    x_center: float
    y_home: float
    frequency: float


@jit
def ellipse_point(c, u):
    """Seed ellipse (EllipseConstants c) at cycle phase u: (x, y, vx, vy, ax, ay) in m, m/s,
    m/s^2 and the stance flag."""
    w = 2.0 * np.pi * c.frequency
    cu, su = np.cos(2.0 * np.pi * u), np.sin(2.0 * np.pi * u)
    return (c.x_center + c.a * cu, c.y_home + c.b * su, -c.a * w * su, c.b * w * cu,
            -c.a * w * w * cu, -c.b * w * w * su, su < 0.0)


@register_path
@dataclass(frozen=True)
class SeedEllipse(FootPath):
    """The seed's ellipse (module docstring): the lower half is the stance."""

    kind: ClassVar[str] = "seed_ellipse"
    point: ClassVar = staticmethod(ellipse_point)
    title: ClassVar[str] = "seed's elliptical gait"

    def text(self, gait: Gait) -> str:
        g = gait
        return (f"the seed's ellipse x = {g.x_center_m * 1e3:g} + {g.a_m * 1e3:g} cos(wt) mm, "
                f"y = {g.y_home_m * 1e3:g} + {g.b_m * 1e3:g} sin(wt) mm")

    def constants(self, gait: Gait) -> EllipseConstants:
        return EllipseConstants(gait.a_m, gait.b_m, gait.x_center_m, gait.y_home_m,
                                gait.frequency_hz)

    def stance_start(self, gait: Gait) -> float:
        return 0.5
