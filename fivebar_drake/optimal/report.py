"""What the legs allow for any controller, for one design (`fivebar-drake optimal`): the
vertical jump's ceiling and floor and the drop's landing (vertical_jump.py), the stand-up's
floor (stand_up.py), the gaits' floors (gait_floor.py: trot, walk, bound, pronk) and top speeds
(top_speed.py), as optimal.json, optimal.md and optimal_jump.png: the answer first, then the
figures beside the bounds."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from fivebar_drake.core.files import json_ready, save_figure, write_atomic
from fivebar_drake.verdicts.rules import beyond_limit
from fivebar_drake.gaits import (EXTENSION_STOP_S, PUSH_SHARES, Drop, Jump as JumpPath,
                                         StandUp)
from fivebar_drake.core.validation import ParameterError, check_number
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.optimal.recording import RECORDING_FILE, write_recording
from fivebar_drake.optimal.gait_floor import (KINDS, fastest_gait, fastest_joint, gait_floor,
                                              max_pitch_rad)
from fivebar_drake.optimal.stand_up import stand_up_floor
from fivebar_drake.optimal.top_speed import GAITS as SPEED_GAITS, top_speed
from fivebar_drake.optimal.vertical_jump import (Jump, body_apexes, jump_need, landing_need,
                                                 point_mass_bound, push, reach, stroke)
from fivebar_drake.robots.quadruped.config import with_path_defaults
from fivebar_drake.robots.quadruped.params import Params

OPTIMAL_FILES = ("optimal_jump.png", RECORDING_FILE, "optimal.md",
                 "optimal.json")                                   # the JSON last: complete
MARGIN_LANDING_M = 0.005   # the max jump's landing stops this short of its crouch
FASTEST = ("trot", "bound")   # the gaits whose fastest the report gives
REPRODUCED = 0.15   # a published jump figure is reproduced within this relative difference: the
#                     presets' own numbers (masses, currents) are estimates to about this


def published_jump(params: Params, ceiling: dict | None) -> list[dict]:
    """The parameter file's published jump figures ([published]: vertical_jump_height_m,
    vertical_jumping_agility_m_s) beside the ceiling's: the height read both ways (the centre
    of mass's rise from the crouch, Haldane's and Kau's definition, and from standing; the
    source's own definition is quoted), reproduced when the crouch reading (the agility) is
    within REPRODUCED of the value."""
    rows = []
    for name, key in (("vertical_jump_height_m", "com_rise_from_crouch_m"),
                      ("vertical_jumping_agility_m_s", "agility_m_s")):
        entry = params.published.get(name)
        if entry is None or ceiling is None:
            continue
        ours = ceiling[key]
        row = {"name": name, "value": entry.value, "source": entry.source,
               "definition": entry.definition, "computed": ours,
               "ratio": ours / entry.value, "reproduced": abs(ours / entry.value - 1) <= REPRODUCED}
        if name == "vertical_jump_height_m":
            row["computed_from_standing"] = ceiling["body_apex_above_standing_m"]
        rows.append(row)
    return rows


def published_speed(params: Params, speeds: dict) -> list[dict]:
    """The parameter file's published forward speed beside the fastest top speed found (a
    model's optimum against a robot's run: never "reproduced"; below it, the reason: what
    limits the top speed)."""
    entry = params.published.get("forward_speed_m_s")
    found = {k: t for k, t in speeds.items() if t["speed_m_s"] == t["speed_m_s"]}
    if entry is None or not found:
        return []
    kind, top = max(found.items(), key=lambda item: item[1]["speed_m_s"])
    ours = top["speed_m_s"]
    return [{"name": "forward_speed_m_s", "value": entry.value, "source": entry.source,
             "definition": entry.definition, "computed": ours, "ratio": ours / entry.value,
             "reproduced": None, "gait": kind,
             "why_below": f"the {kind}'s top speed is limited by {top['limited_by']}"
             if ours < entry.value else ""}]


def _jump_figures(j: Jump, motor) -> dict:
    """A jump's figures (SI) and each motor's peak delivered torque, speed and share of the
    envelope's torque at its speed (the most used point)."""
    upper, lower = motor.limits(j.speed_rad_s)
    bound = np.where(j.delivered_Nm >= 0.0, upper, -lower)
    share = np.abs(j.delivered_Nm) / np.maximum(bound, 1e-12)
    return {
        "takeoff_speed_m_s": j.v_com,
        "com_rise_from_standing_m": j.com_rise_from_standing_m,
        "com_rise_from_crouch_m": j.com_rise_from_crouch_m,
        "body_apex_above_standing_m": j.body_apex_above_standing_m,
        "crouch_hip_height_m": float(j.stroke.u[0]),
        "takeoff_hip_height_m": float(j.stroke.u[j.takeoff]),
        "stance_s": j.stance_s, "to_apex_s": j.to_apex_s, "agility_m_s": j.agility_m_s,
        "motors": {m: {"peak_torque_Nm": float(np.abs(j.delivered_Nm[:, i]).max()),
                       "peak_speed_rad_s": float(np.abs(j.speed_rad_s[:, i]).max()),
                       "largest_share_of_envelope": float(share[:, i].max())}
                   for i, m in enumerate(MOTORS)}}


def jump_limits(params: Params, height_m: float | None = None, payload_kg: float = 0.0,
                speed_gaits=SPEED_GAITS) -> tuple[dict, dict[str, Jump]]:
    """The design's vertical jump, for any controller: the ceiling (the highest jump over the
    leg's whole reach within [limits]) beside a bound by another method, and the floor (the
    least peak motor torque) of the packaged jump maneuver's stroke (crouch and extension of
    gaits.Jump) to height_m above standing (default the maneuver's), or why it is
    beyond the motors; the drop, the stand-up, the gaits' floors and the top speeds of
    speed_gaits. Returns (the figures, JSON-ready; the jumps by name)."""
    plan = JumpPath()
    height = plan.height_m if height_m is None else check_number("--height", height_m, 0.0,
                                                                  low_open=True)
    standing = -params.gait.y_home_m
    u0, u1 = reach(params)
    ceiling = push(stroke(params, u0, u1, payload_kg), standing)
    why_none = ("the motors cannot lift the crouched robot" if ceiling is None else
                f"the motors cannot lift the body above its standing height (the highest "
                f"push's apex lies {-ceiling.body_apex_above_standing_m * 1e3:.0f} mm below it; "
                f"no-load speed {params.motor.no_load_speed_rad_s:.2g} rad/s)"
                if ceiling.body_apex_above_standing_m <= 0.0 else "")
    if why_none:
        ceiling = None
    bound_speed, bound_rise = point_mass_bound(params, u0, u1, standing, payload_kg)
    result = {
        "model": "one leg of a symmetric vertical jump: a quarter of the robot on the leg's "
                 "exact 5-bar dynamics (links and reflected rotor inertia), foot fixed, motors "
                 "within their envelope at their speeds, friction cone (optimal/vertical_jump.py)",
        "quarter_mass_kg": float((params.robot.total_mass_kg + payload_kg) / params.robot.legs),
        "payload_kg": payload_kg,
        "ceiling": None if ceiling is None else _jump_figures(ceiling, params.motor),
        "ceiling_why_none": why_none,
        "bound": {"takeoff_speed_m_s": bound_speed, "hip_apex_above_standing_m": bound_rise,
                  "method": "point mass at the hip on a massless leg, the envelope through "
                            "J_F^T, energy over the same stroke"},
        "floor": None, "floor_why_none": ""}
    jumps = {"ceiling": ceiling}
    need = jump_need(params, dataclasses.replace(plan, height_m=height), payload_kg)
    result["floor_status"] = need.status
    if need.status == "floor":
        jumps["floor"] = need.found
        u = need.found.stroke.u
        landing = landing_need(params, dataclasses.replace(plan, height_m=height), payload_kg)
        result["floor"] = {"height_m": height, "crouch_m": standing - float(u[0]),
                           "extension_m": float(u[-1]) - standing,
                           "least_peak_torque_Nm": need.floor_Nm, "on": need.why or
                           "the jump maneuver's own stroke",
                           "landing_peak_torque_Nm": landing.floor_Nm,
                           **_jump_figures(jumps["floor"], params.motor)}
    else:
        result["floor_why_none"] = need.why
    result["drop"] = drop_limits(params, payload_kg)
    result["stand_up"] = stand_up_limits(params, payload_kg)
    result["gaits"] = {kind: gait_limits(params, kind, payload_kg) for kind in KINDS}
    result["fastest"] = {kind: fastest_gait(params, kind, payload_kg) for kind in FASTEST}
    result["top_speed"] = {kind: top_speed(params, kind, payload_kg).row()
                           for kind in speed_gaits}
    result["published"] = (published_jump(params, result["ceiling"])
                           + published_speed(params, result["top_speed"]))
    result["answer"] = answer(result, params)
    result["answer_details"] = answer_details(result, params)
    return result, jumps


def gait_limits(params: Params, kind: str, payload_kg: float = 0.0) -> dict:
    """A gait's floors for any controller (gait_floor.py) at its own gait fields (the path's
    defaults over the parameter file's, as simulate runs it): at the gait's own mean height,
    held level (None where no forces hold the body level: a single pair down) and with the
    height free; the motion the floor takes; the thermal floor (the least worst-motor RMS
    torque) against the continuous current; the best speed margin any controller has (the
    least of the floor's stance operating points' against the envelope, Motor.speed_margins,
    and of the no-load speed over the path's fastest joint, swing included: the path fixes the
    joints' speeds); whether the floor is beyond the motors."""
    params = with_path_defaults(params, kind)
    at_gait, free = (gait_floor(params, kind, payload_kg, free_height=f) for f in (False, True))
    thermal = gait_floor(params, kind, payload_kg, thermal=True)
    continuous = params.motor.rated_continuous_current_A
    motor = params.motor
    stance = at_gait.speed_rad_s != 0.0
    margins = motor.speed_margins(
        at_gait.torque_Nm + motor.friction(at_gait.speed_rad_s), at_gait.speed_rad_s)[0]
    return {"floor_Nm": at_gait.floor_Nm,
            "speed_margin": float(min(np.nanmin(np.where(stance, margins, np.inf)),
                                      motor.no_load_speed_rad_s / fastest_joint(params, kind))),
            "beyond_motors": beyond_motor(params, at_gait.floor_Nm),
            "level_floor_Nm": at_gait.level_Nm,
            "height_swing_m": float(np.ptp(at_gait.z_m)),
            "surge_swing_m": float(np.ptp(at_gait.x_m)),
            "pitch_swing_deg": float(np.degrees(np.ptp(at_gait.pitch_rad))),
            "free_height_floor_Nm": free.floor_Nm,
            "free_height_change_m": float(np.mean(free.z_m)),
            "thermal_floor_rms_torque_Nm": thermal.floor_Nm,
            "thermal_floor_rms_current_A": thermal.rms_current_A,
            "continuous_current_A": continuous,
            "thermal_margin": continuous / thermal.rms_current_A if continuous else None,
            "frequency_hz": params.gait.frequency_hz,
            "scope": f"stance legs at the {kind}'s speed, period and duty factor, the body "
                     f"free to surge, heave and pitch (within {math.degrees(max_pitch_rad(params)):g} deg); the "
                     "swing legs' torques are not in the floor"}


def drop_limits(params: Params, payload_kg: float = 0.0) -> dict:
    """The packaged drop maneuver's landing for any controller (vertical_jump.landing_need): the
    least peak motor torque that stops the body from its height (braking) within its landing
    stroke, or over the leg's whole reach where that stroke gives way, and the highest drop the
    stroke absorbs (m); the floor None with why where the legs give way even over the whole
    reach (undecided)."""
    plan = Drop()
    need = landing_need(params, plan, payload_kg)
    return {"height_m": plan.height_m, "landing_stroke_m": plan.landing_stroke_m,
            "highest_drop_m": need.stroke_optimum_m, "least_peak_torque_Nm": need.floor_Nm,
            "limit_Nm": params.motor.braking_peak_torque_Nm, "status": need.status,
            "why_none": "" if need.status == "floor" else need.why, "on": need.why}


def stand_up_limits(params: Params, payload_kg: float = 0.0) -> dict:
    """The packaged stand-up's floor for any controller (optimal/stand_up.py): the least peak
    motor torque, where the feet take the load, the maneuver's straight path's own peak, the
    dynamics' bound; the floor None with why where no loaded path reaches standing."""
    plan = StandUp()
    out = {"rise_s": plan.rise_s, "least_peak_torque_Nm": None, "lift_front_x_m": None,
           "lift_rear_x_m": None, "straight_path_peak_Nm": None, "straight_path_why": "",
           "dynamic_share": None, "beyond_motors": False, "why_none": ""}
    try:
        found = stand_up_floor(params, plan, payload_kg)
    except ParameterError as err:
        out["why_none"] = err.message
        return out
    out.update(least_peak_torque_Nm=found.floor_Nm, lift_front_x_m=found.lift_front_x_m,
               lift_rear_x_m=found.lift_rear_x_m, straight_path_peak_Nm=found.straight_Nm,
               straight_path_why=found.straight_why, dynamic_share=found.dynamic_share,
               beyond_motors=beyond_motor(params, found.floor_Nm))
    return out


def answer(r: dict, params: Params) -> str:
    """The result in one line: how high the legs can jump for any controller, under the bound
    no controller exceeds (or why there is no jump); the rest is answer_details'."""
    c = r["ceiling"]
    if c is None:
        return f"No jump: {r['ceiling_why_none']}."
    return (f"In the one-leg model the legs and motors allow a vertical jump of "
            f"{c['body_apex_above_standing_m'] * 1e3:.0f} mm above standing; no controller "
            f"exceeds the bound of {r['bound']['hip_apex_above_standing_m'] * 1e3:.0f} mm.")


def answer_details(r: dict, params: Params) -> list[str]:
    """The answer's figures, one item each: the jump's, the jump maneuver's need, the drop's
    and the stand-up's, each gait's floor, the package's own paths' fastest and the top
    speeds."""
    c = r["ceiling"]
    out = [] if c is None else [
        f"The jump: the body's apex; the centre of mass rises "
        f"{c['com_rise_from_crouch_m'] * 1e3:.0f} mm from the crouch, takeoff at "
        f"{c['takeoff_speed_m_s']:.2f} m/s, agility {c['agility_m_s']:.2f} m/s. The bound is a "
        "point mass on massless legs with the same motors; between the two a controller's run "
        "decides."]
    f = r["floor"]
    whole = "" if f is None or "whole reach" not in f["on"] else " on the leg's whole reach"
    out.append(f"The jump maneuver: {r['floor_why_none']}." if f is None else
               f"The jump maneuver to {f['height_m'] * 1e3:.0f} mm needs at least "
               f"{f['least_peak_torque_Nm']:.2f} N·m at its push-off's peak{whole} (motor A "
               f"{f['motors']['A']['peak_torque_Nm']:.2f}, B "
               f"{f['motors']['B']['peak_torque_Nm']:.2f} N·m; the motors give "
               f"{params.motor.peak_torque_Nm:.2f} N·m) and "
               + ("an undecided landing" if f["landing_peak_torque_Nm"] is None else
                  f"{f['landing_peak_torque_Nm']:.2f} N·m braking at its landing (of "
                  f"{params.motor.braking_peak_torque_Nm:.2f})")
               + " whatever the controller.")
    d = r["drop"]
    out.append(f"The drop maneuver from {d['height_m'] * 1e3:.0f} mm: {d['why_none']}."
               if d["least_peak_torque_Nm"] is None else
               f"Landing the {d['height_m'] * 1e3:.0f} mm drop within "
               f"{d['landing_stroke_m'] * 1e3:.0f} mm needs at least "
               f"{d['least_peak_torque_Nm']:.2f} N·m (braking); that stroke absorbs a drop of "
               f"up to {d['highest_drop_m'] * 1e3:.0f} mm.")
    u = r["stand_up"]
    out.append(f"Standing up from lying: {u['why_none']}." if u["least_peak_torque_Nm"] is None
               else f"Standing up from lying needs at least {u['least_peak_torque_Nm']:.2f} N·m "
                    f"(quasi-static, a level lift balanced about the pitch axis; the front feet "
                    f"taking the load {u['lift_front_x_m'] * 1e3:.0f} mm and the rear "
                    f"{u['lift_rear_x_m'] * 1e3:.0f} mm behind their hips; the maneuver's "
                    f"straight path "
                    + (u["straight_path_why"].removeprefix("the straight path ")
                       if u["straight_path_peak_Nm"] is None else
                       f"asks {u['straight_path_peak_Nm']:.2f} N·m")
                    + f"; its dynamics add at most {u['dynamic_share']:.0%} in "
                      f"{u['rise_s']:g} s)"
                    + (f", beyond the motors' {params.motor.peak_torque_Nm:.2f} N·m for any "
                       "controller" if u["beyond_motors"] else "") + ".")
    out += [
        f"The {kind} needs at least {t['floor_Nm']:.2f} N·m in stance"
        + (f" (beyond the motors' {params.motor.peak_torque_Nm:.2f} N·m)"
           if t["beyond_motors"] else "") + " at its own height (the "
        f"body heaving {t['height_swing_m'] * 1e3:.0f} mm and pitching through "
        f"{t['pitch_swing_deg']:.0f} deg; "
        + ("no level body balances" if t["level_floor_Nm"] is None else
           f"{t['level_floor_Nm']:.2f} N·m held level")
        + f"; with the body {abs(t['free_height_change_m']) * 1e3:.0f} mm "
        f"{'higher' if t['free_height_change_m'] >= 0 else 'lower'} a motion asks "
        f"{t['free_height_floor_Nm']:.2f} N·m, the least found, not a bound)"
        + (f", beyond the motors' {params.motor.peak_torque_Nm:.2f} N·m (the least found)"
           if t["beyond_motors"] else "")
        + ("" if t["thermal_margin"] is None else
           f"; its thermal floor {t['thermal_floor_rms_current_A']:.2f} A RMS, "
           f"{t['thermal_margin']:.2f} of the continuous {t['continuous_current_A']:.2f} A")
        + f"; its best speed margin {t['speed_margin']:.2f}."
        for kind, t in r["gaits"].items()]
    out += [
        f"The package's own {kind} path at its stride and duty factor runs at most "
        + (f"none (its own {f['gait_frequency_hz']:g} Hz does not pass)"
           if f["limited_by"] == "its own frequency" else
           f"{f['speed_m_s']:.3f} m/s ({f['frequency_hz']:.2f} Hz, against its "
           f"{f['gait_speed_m_s']:.3f} m/s), limited by the joints' "
           + ("no-load speed" if f["limited_by"] == "speed" else "torque in stance"))
        + "." for kind, f in r["fastest"].items()]
    return out + top_speed_text(r["top_speed"])


def fastest_achieved_text(kind: str, found: dict) -> str:
    """The sentence on the fastest top speed the tracking controller achieved where the
    optimum's was not (cli._fastest_achieved's record)."""
    if found["folder"] is None:
        plans = "; ".join(f"{_plan_name(t)}: {_missed(t)}" for t in found["tried"])
        return (f"Nor is a slower {kind} ({plans or 'none left'}): this controller achieves "
                "none of them.")
    return (f"The fastest this controller achieves: the {kind}'s {_plan_name(found)} "
            f"({found['planned_m_s']:.3f} m/s planned), tracked at {found['speed_m_s']:.3f} m/s, "
            f"{found['share_of_optimum']:.0%} of the top speed; verdict "
            f"{found['verdict'].upper()} (achieved, also at half the step), "
            f"`{found['folder']}/`.")


def _missed(plan: dict) -> str:
    """What a plan of the fastest-achieved search missed, short: the run's deciding check, or
    why it was not simulated."""
    if not plan.get("simulated", True):
        return f"not simulated, {plan['missed'].rstrip('.')}"
    return plan["missed"].removeprefix("NOT ACHIEVED, decided by the achieved check: ").rstrip(".")


def _plan_name(plan: dict) -> str:
    """A plan of the fastest-achieved search: the top speed at its duty factor, or a share of
    it."""
    at = f"top speed at duty factor {plan['duty_factor']:g}"
    return at if plan["share"] == 1.0 else f"{at} at {plan['share']:.0%} of its speed"


def top_speed_text(speeds: dict) -> list[str]:
    """The top speeds, one item each (none for none searched)."""
    if not speeds:
        return []
    bound = next(iter(speeds.values()))["bound_m_s"]
    return [f"The {kind}'s top speed for any controller: "
            + (f"{t['speed_m_s']:.2f} m/s ({t['frequency_hz']:.2f} Hz, duty factor "
               f"{t['duty_factor']:.2f}, stride {t['stride_m'] * 1e3:.0f} mm; limited by "
               f"{t['limited_by']})." if t["speed_m_s"] == t["speed_m_s"] else
               f"none ({t['limited_by']}).")
            for kind, t in speeds.items()] + [
        f"A top speed is the fastest a search of stride, frequency, duty factor and swing "
        f"found; no gait is faster than the no-load bound of {bound:.2f} m/s."]


def markdown(r: dict) -> str:
    """optimal.md: the answer, then a table per jump."""
    lines = ["# What the legs allow: the vertical jump", "", r["answer"], "",
             *[f"- {item}" for item in r["answer_details"]], "",
             f"Model: {r['model']}. Quarter mass {r['quarter_mass_kg']:.3f} kg.", ""]
    rows = [("ceiling (highest jump)", r["ceiling"]), ("floor (jump maneuver)", r["floor"])]
    lines += ["| | body apex above standing (mm) | COM above standing (mm) | COM from crouch "
              "(mm) | takeoff (m/s) | stance (s) | agility (m/s) | A peak (N·m) | B peak (N·m) |",
              "|---|---|---|---|---|---|---|---|---|"]
    for name, j in rows:
        if j is None:
            continue
        lines.append(f"| {name} | {j['body_apex_above_standing_m'] * 1e3:.1f} | "
                     f"{j['com_rise_from_standing_m'] * 1e3:.1f} | "
                     f"{j['com_rise_from_crouch_m'] * 1e3:.1f} | {j['takeoff_speed_m_s']:.3f} | "
                     f"{j['stance_s']:.3f} | {j['agility_m_s']:.2f} | "
                     f"{j['motors']['A']['peak_torque_Nm']:.2f} | "
                     f"{j['motors']['B']['peak_torque_Nm']:.2f} |")
    b = r["bound"]
    lines += ["", f"Bound ({b['method']}): takeoff {b['takeoff_speed_m_s']:.3f} m/s, hip apex "
              f"{b['hip_apex_above_standing_m'] * 1e3:.1f} mm above standing."]
    if r["floor_why_none"]:
        lines += ["", f"Floor: none — {r['floor_why_none']}."]
    lines += ["", "## Gaits", "", "| gait | Hz | floor (N·m) | heave (mm) | pitch (deg, "
              "peak to peak) | held level (N·m) | height free (N·m) | thermal floor (A RMS) | "
              "speed margin | fastest (m/s) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for kind, t in r["gaits"].items():
        fast = r["fastest"].get(kind)
        level = t["level_floor_Nm"]
        lines.append(f"| {kind} | {t['frequency_hz']:g} | {t['floor_Nm']:.2f} | "
                     f"{t['height_swing_m'] * 1e3:.0f} | {t['pitch_swing_deg']:.1f} | "
                     f"{'none' if level is None else f'{level:.2f}'} | "
                     f"{t['free_height_floor_Nm']:.2f} | "
                     f"{t['thermal_floor_rms_current_A']:.2f} | {t['speed_margin']:.2f} | "
                     + ("—" if fast is None else "none" if fast["limited_by"] ==
                        "its own frequency" else f"{fast['speed_m_s']:.3f} "
                        f"({fast['limited_by']})") + " |")
    if r["top_speed"]:
        lines += ["", "## Top speed (any controller)", "",
                  "The fastest a search of duty factor, stride and frequency found (per gait, "
                  "the swing's shape optimized against the leg's dynamics, the stance's floor "
                  "with the body's sagittal dynamics; optimal/top_speed.py), under the no-load "
                  f"bound of {next(iter(r['top_speed'].values()))['bound_m_s']:.2f} m/s.", "",
                  "| gait | speed (m/s) | Hz | duty factor | stride (mm) | Froude | cost of "
                  "transport | A peak / RMS (N·m) | B peak / RMS (N·m) | limited by |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for kind, t in r["top_speed"].items():
            if t["speed_m_s"] != t["speed_m_s"]:
                lines.append(f"| {kind} | none | | | | | | | | {t['limited_by']} |")
                continue
            lines.append(
                f"| {kind} | {t['speed_m_s']:.3f} | {t['frequency_hz']:.2f} | "
                f"{t['duty_factor']:.2f} | {t['stride_m'] * 1e3:.0f} | {t['froude']:.2f} | "
                f"{t['cost_of_transport']:.2f} | {t['peak_Nm'][0]:.2f} / {t['rms_Nm'][0]:.2f} | "
                f"{t['peak_Nm'][1]:.2f} / {t['rms_Nm'][1]:.2f} | {t['limited_by']} |")
    for kind, m in (r.get("top_speed_simulated") or {}).items():
        lines += ["", f"Simulated {kind} (the top speed's gait, the tracking controller "
                      f"following its floor, `{m['folder']}/`): "
                  + (m["why_none"] if m["why_none"] else
                     f"{m['speed_m_s']:.3f} m/s, {m['share_of_optimum']:.0%} of its top speed; "
                     f"verdict {m['verdict'].replace('_', ' ').upper()}"
                     f"{' (achieved)' if m['achieved'] else ''}; largest tilt {m['max_tilt_deg']:.1f} deg; the controller asked up to "
                     f"{m['demand_peak_Nm']:.2f} N·m against the optimum's "
                     f"{m['optimum_peak_Nm']:.2f} N·m") + "."]
        if m.get("fastest_achieved"):
            lines[-1] += " " + fastest_achieved_text(kind, m["fastest_achieved"])
    if r.get("max_jump_simulated"):
        m = r["max_jump_simulated"]
        asked = "; ".join(f"{name}: asked {p['asked_Nm']:.2f} N·m against its floor "
                          f"{p['floor_Nm']:.2f} N·m" for name, p in m["phases"].items()
                          if p["asked_Nm"] is not None and p["floor_Nm"] is not None)
        lines += ["", f"Simulated (the jump maneuver planned at the ceiling, the tracking "
                      f"controller pushing with the ceiling's torques, `{m['folder']}/`): apex "
                      f"{m['height_m'] * 1e3:.1f} mm, {m['share_of_ceiling']:.0%} of the "
                      f"ceiling; verdict {m['verdict'].upper()}"
                      f"{' (achieved)' if m['achieved'] else ''}"
                      + (f"; {asked}" if asked else "") + "."]
    if r.get("simulation_interrupted"):
        lines += ["", f"Simulations interrupted by {r['simulation_interrupted']}: only those "
                      "above finished; run `optimal --simulate` again for the rest."]
    if r["published"]:
        lines += ["", "## Published figures", "",
                  "| figure | published | computed (the ceiling) | ratio | reproduced | "
                  "the source's definition |", "|---|---|---|---|---|---|"]
        for p in r["published"]:
            extra = (f" from the crouch ({p['computed_from_standing']:.3f} body apex above "
                     "standing)" if "computed_from_standing" in p else
                     f" (the {p['gait']}'s top speed)" if "gait" in p else "")
            said = ("a run against a limit" + (f"; {p['why_below']}" if p["why_below"] else "")
                    if p["reproduced"] is None else "yes" if p["reproduced"] else "no")
            lines.append(f"| {p['name']} | {p['value']:g} | {p['computed']:.3f}{extra} | "
                         f"{p['ratio']:.2f} | {said} | {p['definition']} |")
    return "\n".join(lines) + "\n"


def plot(jumps: dict, params: Params, path: Path) -> Path:
    """Each motor's delivered torque against its speed along the ceiling's and the floor's
    jumps, over the envelope (both quadrants)."""
    import matplotlib.pyplot as plt

    motor = params.motor
    speed = np.linspace(-1.2, 1.2, 241) * motor.no_load_speed_rad_s
    upper, lower = motor.limits(speed)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True, constrained_layout=True)
    for i, (ax, name) in enumerate(zip(axes, MOTORS)):
        ax.fill_between(speed, lower, upper, color="0.92", label="envelope")
        for label, j in jumps.items():
            if j is not None:
                ax.plot(j.speed_rad_s[:, i], j.delivered_Nm[:, i], label=label)
        ax.set_title(f"motor {name}")
        ax.set_xlabel("joint speed (rad/s)")
        ax.axhline(0.0, color="0.6", lw=0.5)
    axes[0].set_ylabel("delivered torque (N·m)")
    axes[0].legend(loc="lower left", fontsize=8)
    fig.suptitle("Optimal vertical jumps against the actuator's envelope")
    return save_figure(fig, path)


def max_jump_plan(params: Params, ceiling: Jump, payload_kg: float = 0.0) -> JumpPath:
    """The jump maneuver that asks for the ceiling: its crouch at the ceiling's start, its
    takeoff at the ceiling's node of highest apex from which the leg, stopping its extension
    within EXTENSION_STOP_S (sinking the foot w EXTENSION_STOP_S / 2 further), stays within its
    reach (the ceiling's own takeoff where it does), its height and push time the highest push's
    on that stroke (its grid's: what the tracking controller and the run's floor compute; the
    height rounded down to 0.1 mm; push_share: the run's takeoff and touchdown are the
    optimum's), landing over the whole stroke back to the crouch (MARGIN_LANDING_M short of
    it)."""
    s, standing = ceiling.stroke, -params.gait.y_home_m
    n = ceiling.takeoff + 1
    apex = body_apexes(s, ceiling.w, standing)
    stops = s.u[:n] + ceiling.w * EXTENSION_STOP_S / 2.0 <= s.u[-1]
    k = int(np.argmax(np.where(stops, apex, -np.inf)))
    crouch, extension = round(standing - float(s.u[0]), 4), round(float(s.u[k]) - standing, 4)
    own = push(stroke(params, standing - crouch, standing + extension, payload_kg), standing)
    plan = JumpPath(height_m=math.floor(own.body_apex_above_standing_m * 1e4) / 1e4,
                    crouch_m=crouch, extension_m=extension,
                    landing_stroke_m=round(crouch + extension - MARGIN_LANDING_M, 4))
    share = own.stance_s / plan.timing(params.gait)[0]
    return dataclasses.replace(plan, push_share=round(min(max(share, PUSH_SHARES[0] + 1e-3),
                                                          PUSH_SHARES[1]), 4))


def beyond_motor(params: Params, floor_Nm: float) -> bool:
    """Whether a driving floor is beyond the motors for any controller: its floor less the
    model margin (checks.floor_margin) beyond their peak (verdicts.rules.fails_for's rule)."""
    return beyond_limit(floor_Nm, params.motor.peak_torque_Nm, params.checks.floor_margin)


def beyond(result: dict) -> str:
    """What the design cannot do for any controller, in a line ("" where it can do all): no
    jump where the bound by another method allows none either, a jump beyond that bound, a gait's or the
    stand-up's floor beyond the motors by more than the model margin. An undecided jump (beyond
    the model's optimum, within the bound) or a landing without a floor is not among them."""
    bound = result["bound"]["hip_apex_above_standing_m"]
    why = [result["ceiling_why_none"] if result["ceiling"] is None and bound <= 0.0 else ""]
    if result["floor_status"] == "beyond bound":
        why.append(result["floor_why_none"])
    why += [f"the {kind} needs at least {t['floor_Nm']:.2f} N·m in stance"
            for kind, t in result["gaits"].items() if t["beyond_motors"]]
    u = result["stand_up"]
    if u["beyond_motors"]:
        why.append(f"standing up needs at least {u['least_peak_torque_Nm']:.2f} N·m")
    why += [f"no {kind} at any speed: {t['limited_by']}"
            for kind, t in result["top_speed"].items() if t["speed_m_s"] != t["speed_m_s"]]
    return "; ".join(w for w in why if w)


def write(result: dict, jumps: dict[str, Jump], params: Params,
          out: Path) -> list[Path]:
    """Write OPTIMAL_FILES of jump_limits' result and jumps into out; the paths."""
    gaits = {kind: gait_floor(with_path_defaults(params, kind), kind, result["payload_kg"])
             for kind in result["gaits"]}                 # computed by jump_limits: cached
    files = [plot(jumps, params, out / "optimal_jump.png"),
             write_recording(out / RECORDING_FILE, jumps, params, gaits, "\n".join(
                 [result["answer"], ""] + [f"- {item}" for item in result["answer_details"]])),
             write_atomic(out / "optimal.md", markdown(result)),
             write_atomic(out / "optimal.json", json.dumps(json_ready(result), indent=2))]
    return files
