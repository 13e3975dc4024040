"""Figures published for a real robot, kept in its parameter file's optional [published] table
beside the numbers they came from, and the same figures as the toolkit computes them from the
file's data, so a report shows which published figures the model reproduces.

[published.NAME] has `value` (a number, or [low, high] for a range), `source` (where it is
published) and optionally `note` (why the figures may differ: a different reading, a different
model). NAME is one of
- FIGURES: a figure the toolkit computes independently of the value given (compare_published);
  optionally `tolerance` (relative, default DEFAULT_TOLERANCE);
- REPORTED: a robot's dynamic figure (a jump, a speed), reported as its source gives it and not
  yet computed here; it needs `definition`, what the source measured (from where to where, over
  what), since sources define these figures differently.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
import math
import numpy as np

from fivebar_drake.core.validation import require
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, LegLimits, reachable

DEFAULT_TOLERANCE = 0.02
EXTENSION_SAMPLES = 20001     # foot distances tried below the hip axis: ~25 um apart on a 0.5 m leg


def extension_range_m(params) -> list[float]:
    """Least and most leg extension (m): the foot's distance from the hip axis (the leg plane's
    origin) along the line straight below it, over the foot points the knees-out assembly reaches
    by geometry alone (to EXTENSION_SAMPLES points; the [limits] aside: they may be the very
    stops a published range reports)."""
    leg = dataclasses.replace(params.leg, limits=LegLimits())
    reach = leg.ac_m + leg.ce_m + leg.ef_m + abs(leg.motor_b_m[0] - leg.motor_a_m[0])
    r = np.linspace(0.0, reach, EXTENSION_SAMPLES)
    ok = reachable(leg, np.stack([np.zeros_like(r), -r], axis=-1), KNEES_OUT)
    return [float(r[ok].min()), float(r[ok].max())] if ok.any() else [math.nan, math.nan]


FIGURES = {   # name -> (what, unit, the toolkit's figure from Params)
    "extension_range_m": ("leg extension range (foot below the hip axis)", "m",
                          extension_range_m),
    "peak_output_torque_Nm": ("peak output torque at the peak current (with the torque-current "
                              "table where given)", "N·m", lambda p: p.motor.peak_torque_Nm),
    "no_load_speed_rad_s": ("no-load output speed of the voltage limit", "rad/s",
                            lambda p: p.motor.no_load_speed_rad_s),
}
# dynamic figures (the unit ends the name), reported with their source's definition, not computed
REPORTED = ("vertical_jump_height_m", "vertical_jumping_agility_m_s", "forward_speed_m_s")


@dataclass(frozen=True)
class Published:
    """One published figure: value (float, or (low, high)), its source, the relative tolerance
    within which the toolkit's figure reproduces it (FIGURES; None for REPORTED, which nothing
    compares), what the source measured (definition: REPORTED) and a note."""

    value: float | tuple[float, float]
    source: str
    tolerance: float | None = DEFAULT_TOLERANCE
    note: str = ""
    definition: str = ""


def published_from(table, section: str = "published") -> dict[str, Published]:
    """The [published] table of a parameter file as {NAME: Published}, validated (the names,
    numbers, ranges, sources and definitions) with errors naming the key."""
    require(isinstance(table, dict), f"[{section}]", table, "must be a table of [published.NAME]")
    out = {}
    for name, entry in table.items():
        field = f"{section}.{name}"
        require(name in FIGURES or name in REPORTED, field, name,
                f"must be one of {[*FIGURES, *REPORTED]}")
        if name in FIGURES:
            required, keys = {"value", "source"}, {"value", "source", "tolerance", "note"}
            shape = "value, source and optionally tolerance and note"
        else:
            required, keys = {"value", "source", "definition"}, {"value", "source", "definition",
                                                                  "note"}
            shape = ("value, source, definition (what the source measured: this figure is "
                     "reported, not computed) and optionally note")
        require(isinstance(entry, dict) and required <= set(entry) and set(entry) <= keys, field,
                entry, f"must be a table with {shape}")
        value = entry["value"]
        numbers = value if isinstance(value, list) else [value]
        require(len(numbers) in (1, 2) and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            and v > 0 for v in numbers), f"{field}.value", value,
            "must be a positive finite number or a [low, high] pair of them")
        require(len(numbers) == 1 or numbers[0] < numbers[1], f"{field}.value", value,
                "a range must be [low, high] with low < high")
        require((len(numbers) == 2) == (name == "extension_range_m"), f"{field}.value", value,
                "must be a [low, high] pair" if name == "extension_range_m"
                else "must be one number")
        require(isinstance(entry["source"], str) and entry["source"].strip(), f"{field}.source",
                entry["source"], "must name where the figure is published")
        for text in ("note", "definition"):
            require(isinstance(entry.get(text, ""), str), f"{field}.{text}", entry.get(text),
                    "must be text")
        require(name in FIGURES or entry["definition"].strip(), f"{field}.definition",
                entry.get("definition"), "must say what the source measured")
        tolerance = entry.get("tolerance", DEFAULT_TOLERANCE)
        require(isinstance(tolerance, (int, float)) and not isinstance(tolerance, bool)
                and 0 < tolerance < 1, f"{field}.tolerance", tolerance, "must be in (0, 1)")
        out[name] = Published(tuple(float(v) for v in numbers) if len(numbers) == 2
                              else float(numbers[0]), entry["source"],
                              float(tolerance) if name in FIGURES else None,
                              entry.get("note", ""), entry.get("definition", ""))
    return out


def compare_published(params) -> list[dict]:
    """Each published figure of params.published that the toolkit computes (FIGURES) beside the
    toolkit's: {figure, what, unit, published, computed, relative_difference (the largest over a
    range's ends), reproduced (within the tolerance), tolerance, source, note}. REPORTED figures
    are left out: nothing here computes them yet."""
    rows = []
    for name, pub in params.published.items():
        if name not in FIGURES:
            continue
        what, unit, compute = FIGURES[name]
        computed = compute(params)
        want = np.atleast_1d(np.asarray(pub.value, dtype=float))
        got = np.atleast_1d(np.asarray(computed, dtype=float))
        diff = float(np.max(np.abs(got - want) / want))
        rows.append({"figure": name, "what": what, "unit": unit,
                     "published": list(pub.value) if isinstance(pub.value, tuple) else pub.value,
                     "computed": computed, "relative_difference": diff,
                     "reproduced": bool(diff <= pub.tolerance), "tolerance": pub.tolerance,
                     "source": pub.source, "note": pub.note})
    return rows

