"""Validation of input values: ParameterError naming the source, field, value and what is allowed,
and the bounds every parameter file is held to."""

from __future__ import annotations

import math



# Bounds of the values of a parameter file (SI). Each lies far outside any design this tool is
# for (a ~7 kg quadruped with ~0.3 m legs) and is there to catch a slip, such as millimetres
# written as metres or grams as kilograms, before it turns into a result that looks valid.
MAX_LENGTH_M = 2.0              # any length or coordinate: "105" for 0.105 m is refused
MAX_MASS_KG = 500.0             # any mass: "6700" (grams) for the 6.7 kg robot is refused
MAX_GRAVITY_M_S2 = 30.0         # the largest surface gravity in the solar system is 24.8 (Jupiter)
MAX_GAIT_FREQUENCY_HZ = 10.0    # small quadrupeds trot at 1-5 Hz; no hip motor of the kind follows 10
MAX_SAMPLES = 10_000            # per cycle: central differences are exact to ~1e-7 of the peaks long
#                                 before; the IK mode tracking costs ~10 us per sample in Python
MAX_TORQUE_NM = 1000.0          # hip motors of legged robots this size give well under 100 N m
MAX_GEAR_RATIO = 1000.0         # the largest harmonic drives are ~160:1
MAX_SPEED_RAD_S = 10_000.0      # ~95 000 RPM at the output: beyond any motor
MAX_ROTOR_INERTIA_KG_M2 = 1.0   # a small outrunner's rotor is ~1e-6 kg m^2
MAX_FRICTION_COEFFICIENT = 5.0  # rubber on rough ground is 1-2
MAX_CONTACT_STIFFNESS_N_M = 1e9  # a steel ball on steel is ~1e8-1e9 N/m
MAX_RELAXATION_TIME_S = 1.0     # a foot pad still dissipating a second after touchdown is no foot
MIN_PLANT_STEP_S = 1e-6        # no mechanism here needs a finer plant step
MAX_PLANT_STEPS = 20_000_000   # a run of more steps takes hours (~0.1-0.3 ms each)
MAX_SAFETY_FACTOR = 100.0       # a verdict threshold beyond this can never pass
MAX_SPEED_M_S = 100.0           # any linear speed: a legged robot this size runs a few m/s
MAX_FORCE_N = 1e5               # any force: ten tonnes on a 7 kg robot's foot
# a field's unit from its name's suffix (the longest that matches): (low, high, low_open), the
# bounds unit_bounds gives a variant's field of that unit
UNIT_SUFFIXES = {"_m_s": (-MAX_SPEED_M_S, MAX_SPEED_M_S, False),
                 "_rad_s": (-MAX_SPEED_RAD_S, MAX_SPEED_RAD_S, False),
                 "_Nm": (-MAX_TORQUE_NM, MAX_TORQUE_NM, False),
                 "_N": (-MAX_FORCE_N, MAX_FORCE_N, False),
                 "_hz": (0.0, MAX_GAIT_FREQUENCY_HZ, True),
                 "_kg": (0.0, MAX_MASS_KG, False),
                 "_s": (0.0, 1e5, True),
                 "_m": (0.0, MAX_LENGTH_M, False)}


class ParameterError(ValueError):
    """Bad input: a parameter or scenario file, a command-line value or an output path that is
    malformed or describes something that cannot exist. Its text names the source (a file, the
    command line), the field (dotted path), the value and what is allowed."""

    def __init__(self, message: str, field: str = "", source: str = ""):
        super().__init__(message)
        self.message, self.field, self.source = message, field, source

    def __str__(self) -> str:
        return f"{self.source}: {self.message}" if self.source else self.message

    def located(self, source) -> "ParameterError":
        """The same error with its source (a file, "command line"), unless it has one."""
        return self if self.source else ParameterError(self.message, self.field, str(source))


def require(ok: bool, field: str, value, rule: str) -> None:
    """ParameterError "field = value: rule" unless ok; a value longer than MAX_ECHO characters
    (a rule longer than MAX_RULE: one quoting values) is cut there (a list of a million steps
    is not echoed whole)."""
    if not ok:
        raise ParameterError(f"{field} = {_echo(repr(value), MAX_ECHO)}: "
                             f"{_echo(rule, MAX_RULE)}", field)


MAX_ECHO, MAX_RULE = 200, 700   # characters of a value, and of a rule, an error quotes


def _echo(text: str, most: int) -> str:
    """text, or its first `most` characters and how many there were."""
    return text if len(text) <= most else f"{text[:most]}... ({len(text)} characters)"


def _bound(value: float, integer: bool) -> str:
    """A bound as an error message gives it: an integer field's whole (2147483647, not
    2.14748e+09), else 6 significant digits."""
    return str(int(value)) if integer and float(value).is_integer() else f"{value:g}"


def check_number(field: str, value, low=-math.inf, high=math.inf, *, low_open=False,
                 high_open=False, integer=False, why: str = ""):
    """value as a float (an int if integer) if it is a finite number within low .. high (the
    ends included unless *_open); else ParameterError naming the field, the value and the
    allowed range (and why, if given). Booleans are not numbers."""
    numeric = isinstance(value, int) if integer else isinstance(value, (int, float))
    require(numeric and not isinstance(value, bool), field, value,
            "must be an integer" if integer else "must be a number")
    try:
        finite = math.isfinite(value)
    except OverflowError:          # an integer beyond any float
        finite = False
    inside = (finite and (value > low if low_open else value >= low)
              and (value < high if high_open else value <= high))
    if not inside:
        kind = "an integer " if integer else "" if finite else "a finite number "
        if low == high:
            kind, allowed = "", _bound(low, integer)
        elif math.isfinite(low) and math.isfinite(high):
            allowed = (f"in {'(' if low_open else '['}{_bound(low, integer)}, "
                       f"{_bound(high, integer)}{')' if high_open else ']'}")
        elif math.isfinite(low):
            allowed = f"{'>' if low_open else '>='} {_bound(low, integer)}"
        elif math.isfinite(high):
            allowed = f"{'<' if high_open else '<='} {_bound(high, integer)}"
        else:
            kind, allowed = "a finite number", ""
        require(False, field, value, f"must be {kind}{allowed}".rstrip()
                + (f" ({why})" if why else "") + _millimetres(field, value, low, high))
    return int(value) if integer else float(value)


def _millimetres(field: str, value, low: float, high: float) -> str:
    """A hint where a length (a field ending in _m) is out of range and the same number in
    millimetres would be inside it: "; lengths are in metres: did you mean 0.105?"."""
    if not field.endswith("_m") and "_m[" not in field:
        return ""
    try:
        metres = value / 1000.0
    except TypeError:
        return ""
    if math.isfinite(metres) and low <= metres <= high and abs(value) > high:
        return f"; lengths are in metres: did you mean {metres:g}?"
    return ""



def check_lengths(section: str, obj, names, low_open=True) -> None:
    for name in names:
        check_number(f"{section}.{name}", getattr(obj, name), 0.0, MAX_LENGTH_M, low_open=low_open)


def check_point(field: str, point) -> None:
    require(isinstance(point, (tuple, list)) and len(point) == 2, field, point, "must be [x, y] in m")
    for i, v in enumerate(point):
        check_number(f"{field}[{i}]", v, -MAX_LENGTH_M, MAX_LENGTH_M)


def unit_of(name: str) -> str | None:
    """The unit suffix of a field's name (UNIT_SUFFIXES, the longest that matches: "_m_s"
    before "_s"), None for a field without one (a share, a count)."""
    return next((suffix for suffix in sorted(UNIT_SUFFIXES, key=len, reverse=True)
                 if name.endswith(suffix)), None)
