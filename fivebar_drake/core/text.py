"""Figures as the reports write them (docs/output_style.md): a value that does not exist is a
dash, a zero is never written with a minus sign."""

from __future__ import annotations

import math
import re

DASH = "—"
ANSWER_CHARS = 200   # a report's answer, its first line, in at most this many characters
_NEGATIVE_ZERO = re.compile(r"^[-−](0(?:\.0*)?)(\D*)$")


def figure(x, pattern: str = "{:.2f}") -> str:
    """x formatted with pattern; "—" for None, NaN or an infinity; "-0.00" written "0.00"."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return DASH
    text = pattern.format(x)
    return _NEGATIVE_ZERO.sub(r"\1\2", text)


def verdict_word(verdict: str) -> str:
    """A verdict as the reports write it: PASS, WARN, FAIL, INSUFFICIENT, NOT ACHIEVED."""
    return str(verdict).upper().replace("_", " ")
