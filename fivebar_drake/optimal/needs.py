"""What any controller needs for a path, by its kind: the one way every output reaches a
maneuver's floors. A kind's need function (registered with register_need, built-ins below and
plugins alike) gives per phase its Need (vertical_jump.Need: status, floor, why, optima, bound)
and the motors' limit in the quadrant the phase acts (driving or braking, N*m). A kind with no
registered function has no floor: needs_of says so (None), and the verdict split calls it
unknown, never borrowing another maneuver's floor (a forward leap is not a vertical jump)."""

from __future__ import annotations

from typing import Callable

from fivebar_drake.core.validation import ParameterError
from fivebar_drake.optimal import gait_floor, stand_up, vertical_jump
from fivebar_drake.optimal.vertical_jump import Need
from fivebar_drake.robots.quadruped.params import Params

NeedFunction = Callable[[Params, object, float], dict[str, tuple[Need, float]]]
NEEDS: dict[str, NeedFunction] = {}     # kind -> its need function


def register_need(*kinds: str):
    """The decorator that registers a need function (params, path, payload_kg) -> {phase: (Need,
    limit N*m)} for the path kinds given; a kind registered twice is refused (its floors would be
    another's)."""
    def register(function: NeedFunction) -> NeedFunction:
        for kind in kinds:
            if kind in NEEDS and NEEDS[kind] is not function:
                raise ParameterError(f"the need of {kind!r} is registered twice: by "
                                     f"{NEEDS[kind].__module__} and {function.__module__}",
                                     f"need {kind}", "plugin registry")
            NEEDS[kind] = function
        return function
    return register


def needs_of(params: Params, path, payload_kg: float = 0.0) -> dict[str, tuple[Need, float]] | None:
    """Per phase of the path (its kind's registered need function) its need and limit; None
    where the kind has no floor."""
    function = NEEDS.get(path.kind)
    return None if function is None else function(params, path, payload_kg)


@register_need("jump", "drop")
def strokes(params: Params, path, payload_kg: float) -> dict[str, tuple[Need, float]]:
    """A jump's push-off (driving) and landing (braking), a drop's landing: on the maneuver's
    own strokes, or the leg's whole reach beyond them (vertical_jump.jump_need, landing_need)."""
    motor, out = params.motor, {}
    if path.pushes:
        out["push-off"] = (vertical_jump.jump_need(params, path, payload_kg),
                           motor.peak_torque_Nm)
    out["landing"] = (vertical_jump.landing_need(params, path, payload_kg),
                      motor.braking_peak_torque_Nm)
    return out


@register_need("stand_up")
def standing_up(params: Params, path, payload_kg: float) -> dict[str, tuple[Need, float]]:
    """The stand-up's balanced quasi-static floor (driving; stand_up.stand_up_floor): undecided
    where no balanced loaded path reaches standing."""
    why = ("quasi-static, a level lift balanced about the pitch axis (front and rear feet "
           "placed apart; the nose resting on the ground is not modelled)")
    try:
        found = stand_up.stand_up_floor(params, path, payload_kg)
    except ParameterError as err:
        return {"stand-up": (Need("undecided", None, f"{why}; {err.message}", None),
                             params.motor.peak_torque_Nm)}
    return {"stand-up": (Need("floor", found.floor_Nm,
                              f"{why}; the dynamics add at most {found.dynamic_share:.0%} of the "
                              f"weight in {path.rise_s:g} s", None, found=found),
                         params.motor.peak_torque_Nm)}


@register_need(*gait_floor.KINDS)
def stance(params: Params, path, payload_kg: float) -> dict[str, tuple[Need, float]]:
    """A gait's stance floor at its own mean height (driving; gait_floor.gait_floor): stance legs
    only, a local search's least; none (unknown) where the search finds no motion. A path that
    asks a joint beyond the no-load speed is this path's failing, said in why."""
    why = ["stance legs only (the swing legs' torques are not in the floor)",
           "the least a local search found (a lower one may exist)"]
    limit = params.motor.peak_torque_Nm
    try:
        floor = gait_floor.gait_floor(params, path, payload_kg)
    except ParameterError as err:
        return {"stance": (Need("unknown", None, f"{why[0]}; {err.message}", None), limit)}
    if floor is None:
        return {"stance": (Need("unknown", None, "no floor for this path", None), limit)}
    joint = gait_floor.fastest_joint(params, path)
    if joint > params.motor.no_load_speed_rad_s:
        why.append(f"this path asks a joint for {joint:.2f} rad/s, beyond the motors' no-load "
                   f"speed {params.motor.no_load_speed_rad_s:.2f} rad/s (another path of the "
                   "gait may ask less)")
    return {"stance": (Need("floor", floor.floor_Nm, "; ".join(why), None, found=floor), limit)}
