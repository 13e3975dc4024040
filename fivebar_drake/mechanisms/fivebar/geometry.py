"""Parameters of the 5-bar leg: geometry (LegGeometry), link mass properties (LinkInertia) and the
facts derived from them alone."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.core.validation import check_lengths, check_point


MOTORS = ("A", "B")


def physical_izz(leg: LegGeometry, links: dict[str, LinkInertia]) -> tuple[float, ...]:
    """Izz about each link's COM (kg*m^2); a zero ("~0" in the seed) becomes the thin-rod
    estimate m L^2 / 12 with L the link's length."""
    return tuple(link.izz_kg_m2 if link.izz_kg_m2 > 0
                 else link.mass_kg * leg.link_length(name) ** 2 / 12.0
                 for name, link in ((n, links[n]) for n in LINK_NAMES))

LINK_NAMES = ("AC", "BD", "CE", "DE")


@dataclass(frozen=True)
class LegGeometry:
    """5-bar leg in its plane (x right, y up, origin between the motors); lengths in m."""

    motor_a_m: tuple[float, float]
    motor_b_m: tuple[float, float]
    ac_m: float
    bd_m: float
    ce_m: float
    de_m: float
    ef_m: float

    def __post_init__(self):
        check_lengths("leg", self, ("ac_m", "bd_m", "ce_m", "de_m"))
        check_lengths("leg", self, ("ef_m",), low_open=False)
        for name in ("motor_a_m", "motor_b_m"):
            check_point(f"leg.{name}", getattr(self, name))

    @property
    def a(self) -> np.ndarray:
        return np.asarray(self.motor_a_m, dtype=float)

    @property
    def b(self) -> np.ndarray:
        return np.asarray(self.motor_b_m, dtype=float)

    @property
    def core(self) -> tuple[float, ...]:
        """(x_A, y_A, x_B, y_B, AC, BD, CE, DE, EF) in m: the geometry as the compiled kernels
        take it."""
        return tuple(float(v) for v in (*self.motor_a_m, *self.motor_b_m, self.ac_m, self.bd_m,
                                         self.ce_m, self.de_m, self.ef_m))

    def link_length(self, link: str) -> float:
        """Length of a link's rigid body in m; DE carries the foot, so it reaches F."""
        return {"AC": self.ac_m, "BD": self.bd_m, "CE": self.ce_m, "DE": self.de_m + self.ef_m}[link]


@dataclass(frozen=True)
class LinkInertia:
    """Mass (kg), COM distance from the link's first joint along the link (m), Izz about the COM
    with the axis along the hinges (kg*m^2)."""

    mass_kg: float
    com_m: float
    izz_kg_m2: float
