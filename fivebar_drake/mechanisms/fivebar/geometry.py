"""Parameters of the 5-bar leg: geometry (LegGeometry) with its mechanical limits (LegLimits), link
mass properties (LinkInertia) and the facts derived from them alone."""

from __future__ import annotations

from dataclasses import dataclass, field, fields
import numpy as np

from fivebar_drake.core.validation import (MAX_LENGTH_M, check_lengths, check_number, check_point,
                                           require)


MOTORS = ("A", "B")


def physical_izz(leg: LegGeometry, links: dict[str, LinkInertia]) -> tuple[float, ...]:
    """Izz about each link's COM (kg*m^2); a zero ("~0" in the seed) becomes the thin-rod
    estimate m L^2 / 12 with L the link's length."""
    return tuple(link.izz_kg_m2 if link.izz_kg_m2 > 0
                 else link.mass_kg * leg.link_length(name) ** 2 / 12.0
                 for name, link in ((n, links[n]) for n in LINK_NAMES))

LINK_NAMES = ("AC", "BD", "CE", "DE")


@dataclass(frozen=True)
class LegLimits:
    """The leg's mechanical limits, the [limits] table of a parameter file, each optional (None:
    no limit), in the file's units (deg, m; limits.py tests poses against them in SI):
    each motor's range theta_{a,b}_{min,max}_deg (the motor angle as the kinematics gives it,
    from +x counter-clockwise, in (-180, 180]); the least and most leg extension
    extension_{min,max}_m (foot F to the hip axis, the origin midway between the motors); the
    least angle between the links at each knee knee_min_deg (at C between C->A and C->E, at D
    between D->B and D->E; 0: folded onto each other); the least angle between the two upper
    links upper_links_min_deg (between A->C and B->D: their interference)."""

    theta_a_min_deg: float | None = None
    theta_a_max_deg: float | None = None
    theta_b_min_deg: float | None = None
    theta_b_max_deg: float | None = None
    extension_min_m: float | None = None
    extension_max_m: float | None = None
    knee_min_deg: float | None = None
    upper_links_min_deg: float | None = None

    def __post_init__(self):
        bounds = {"theta_a": (-180.0, 180.0), "theta_b": (-180.0, 180.0),
                  "extension": (0.0, MAX_LENGTH_M)}
        for name, (low, high) in bounds.items():
            unit = "m" if name == "extension" else "deg"
            lo, hi = (getattr(self, f"{name}_{end}_{unit}") for end in ("min", "max"))
            for end, value in (("min", lo), ("max", hi)):
                if value is not None:
                    check_number(f"limits.{name}_{end}_{unit}", value, low, high)
            if lo is not None and hi is not None:
                require(lo < hi, f"limits.{name}_min_{unit}", lo,
                        f"must be < limits.{name}_max_{unit} = {hi:g}")
        for name in ("knee_min_deg", "upper_links_min_deg"):
            if getattr(self, name) is not None:
                check_number(f"limits.{name}", getattr(self, name), 0.0, 180.0, high_open=True,
                             why="the angle between two links is 0 .. 180 deg")

    @property
    def given(self) -> dict[str, float]:
        """The limits set, by field name, in the file's units."""
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) is not None}


@dataclass(frozen=True)
class LegGeometry:
    """5-bar leg in its plane (x right, y up, origin between the motors); lengths in m; its
    mechanical limits (none by default), which the inverse kinematics respects."""

    motor_a_m: tuple[float, float]
    motor_b_m: tuple[float, float]
    ac_m: float
    bd_m: float
    ce_m: float
    de_m: float
    ef_m: float
    limits: LegLimits = field(default_factory=LegLimits)

    def __post_init__(self):
        check_lengths("leg", self, ("ac_m", "bd_m", "ce_m", "de_m"))
        check_lengths("leg", self, ("ef_m",), low_open=False)
        for name in ("motor_a_m", "motor_b_m"):
            check_point(f"leg.{name}", getattr(self, name))
        require(isinstance(self.limits, LegLimits), "leg.limits", self.limits,
                "the leg's limits are the [limits] table of the file, not a key of [leg]")

    @property
    def a(self) -> np.ndarray:
        return np.asarray(self.motor_a_m, dtype=float)

    @property
    def b(self) -> np.ndarray:
        return np.asarray(self.motor_b_m, dtype=float)

    @property
    def hip(self) -> np.ndarray:
        """The hip axis (2,) in m: the origin midway between the motors."""
        return (self.a + self.b) / 2.0

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
