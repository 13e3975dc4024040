"""Safety-factor verdicts against the motor: thresholds (Checks) and the verdict of one safety
factor."""

from __future__ import annotations

from dataclasses import dataclass

from fivebar_drake.core.validation import MAX_SAFETY_FACTOR, check_number, require


def verdict(checks: Checks, safety_factor: float) -> str:
    """'pass' (SF >= sf_pass), 'warn' (sf_warn <= SF < sf_pass) or 'fail'."""
    if safety_factor >= checks.sf_pass:
        return "pass"
    return "warn" if safety_factor >= checks.sf_warn else "fail"


@dataclass(frozen=True)
class Checks:
    """Safety-factor verdict thresholds: SF >= sf_pass passes, SF >= sf_warn warns, else fails."""

    sf_pass: float
    sf_warn: float

    def __post_init__(self):
        for name in ("sf_pass", "sf_warn"):
            check_number(f"checks.{name}", getattr(self, name), 0.0, MAX_SAFETY_FACTOR,
                         low_open=True)
        require(self.sf_warn <= self.sf_pass, "checks.sf_warn", self.sf_warn,
                 f"must be <= checks.sf_pass = {self.sf_pass}")
