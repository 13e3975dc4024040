"""report.md's sections on the design metrics (design_metrics.py): force capability and the
assembly modes, torque-speed envelope, thermal check, hinge loads, gear-ratio trade."""

from __future__ import annotations

from fivebar_drake.analysis.design_metrics import GEAR_MODEL, PHYSICAL
from fivebar_drake.analysis.force_capability import CAPABILITY_KEYS
from fivebar_drake.analysis.joint_loads import JOINT_NAMES
from fivebar_drake.mechanisms.fivebar import MODE_NAMES, MOTORS
from fivebar_drake.robots.quadruped.params import Params


def _at(at: dict) -> str:
    x, y = (v * 1e3 for v in at["foot_m"])
    return f"t = {at['time_s']:.3f} s (F = ({x:.1f}, {y:.1f}) mm)"


def _least(entry: dict | None) -> str:
    return "no load" if entry is None else f"{entry['value']:.2f}x at {_at(entry['at'])}"


def design_assumptions(params: Params) -> list[str]:
    m = params.motor
    return [
        "Force capability: the foot forces the motor torques |tau_i| <= peak hold through "
        "J_F^-T (link weights aside); 'while moving' takes off the torques the motion and the "
        "link weights already need (full models).",
        f"Thermal: copper loss 1.5 R i_rms^2, the current i of the torque the motor delivers "
        f"at each sample (the joint's and the output friction; k_t = "
        f"{m.torque_constant_Nm_per_A:.4g} N·m/A, motor side, through the gearbox at "
        f"{m.gear_efficiency:g}), R = {m.winding_resistance_ohm:g} ohm constant, one first-order lag "
        f"(R_th = {m.thermal_resistance_K_W:g} K/W, tau = {m.thermal_time_constant_s:g} s) from "
        f"{m.ambient_C:g} °C; iron losses left out; these motor values are "
        "assumptions (parameter file).",
        "Hinge loads: Newton-Euler of the four rigid links under the full models' loads, with the "
        "analysis' joint rates and accelerations; frictionless hinges.",
        "Gear-ratio trade: the gearbox's efficiency kept at every ratio; the rotor's reflected "
        "inertia N^2 J_r q'' and the output friction are added to each joint's torque (the rest "
        "of the analysis leaves the rotor out).",
    ]


def design_lines(results: dict, params: Params) -> list[str]:
    """The markdown lines of the design-metric sections of report.md, from report.json's
    results."""
    fc, m = results["force_capability"], params.motor
    x, y = (v * 1e3 for v in fc["home_foot_m"])
    lines = ["", "## Force capability", "",
             f"Foot forces the motors (±{fc['peak_torque_Nm']:.2f} N·m) hold statically at the "
             f"home foot position ({x:g}, {y:g}) mm, per assembly mode (knees_out: knee C forward, knee D back, the diamond; knees_in: both toward the leg's centre line; knees_forward / knees_back: both knees on one side):", "",
             "| mode | largest vertical (N) | largest horizontal (N) | every direction (N) |",
             "|---|---|---|---|"]
    for mode in MODE_NAMES:
        v = fc["home_pose"][mode]
        lines.append(f"| {mode} | " + (" | ".join(f"{v[k]:.1f}" for k in CAPABILITY_KEYS)
                                       if v else "unreachable | | ") + " |")
    ranked, used = fc["support_ranking"], results["path"]["assembly_modes_used"]
    support = {mode: fc["home_pose"][mode]["max_vertical_N"] for mode in ranked}
    lines += ["", (f"Most vertical support: **{ranked[0]}** ({support[ranked[0]]:.1f} N)"
                   if ranked else "No assembly mode reaches the home position")
              + (f", {fc['most_support_over_next']:.2f}x the next, {ranked[1]} "
                 f"({support[ranked[1]]:.1f} N)" if len(ranked) > 1 else "")
              + f". The gait runs in {', '.join(used)}.",
              "", "Along the gait (vertical support force available / foot load, least over the "
              "cycle):", "", "| model | at rest | while moving |", "|---|---|---|"]
    for name in PHYSICAL:
        g = fc["gait"][name]
        lines.append(f"| {name} | {_least(g['least_margin_at_rest'])} | "
                     f"{_least(g['least_margin_moving'])} |")
    r = results["results"]
    lines += ["", "## Torque-speed envelope", "",
              f"Operating points (the torque the motor delivers, joint torque + output friction, "
              f"at the joint speed) against the actuator's envelope in their own quadrant "
              f"(driving: {m.peak_torque_Nm:g} N·m up to the corner speed, zero at the no-load "
              f"speed {m.no_load_speed_rad_s:.2f} rad/s, beyond which the back-EMF forces "
              f"braking; braking: {m.braking_peak_torque_Nm:.3g} N·m) and the continuous rating "
              f"{m.continuous_torque_Nm:.3g} N·m. Margin: the envelope's torque at the sample's "
              "speed in the direction of its torque over that torque (below 1 exactly outside the "
              "envelope):", "",
              "| motor | model | least margin to the envelope | where |", "|---|---|---|---|"]
    for motor in MOTORS:
        for name in PHYSICAL:
            v = r[name][motor]
            lines.append(f"| {motor} | {name} | {v['torque_speed_margin']:.2f}x | "
                         f"{_at(v['torque_speed_margin_at'])} |")
    th = results["thermal"]
    lines += ["", "## Thermal check", "",
              f"Continuous rating {th['continuous_torque_Nm']:.3f} N·m (the thermal model's "
              f"continuous current {th['thermal_continuous_current_A']:.3f} A);"
              f" winding limit {th['winding_limit_C']:g} °C from {th['ambient_C']:g} °C.", "",
              "| motor | model | RMS torque (N·m) | RMS / continuous current | copper loss (W) | "
              "steady winding (°C) | margin (K) | time to limit |",
              "|---|---|---|---|---|---|---|---|"]
    for motor in MOTORS:
        for name in PHYSICAL:
            v = th["models"][name][motor]
            when = "never" if v["time_to_limit_s"] is None else f"{v['time_to_limit_s']:.0f} s"
            lines.append(f"| {motor} | {name} | {v['rms_torque_Nm']:.3f} | "
                         f"{v['rms_over_continuous']:.2f} | {v['copper_loss_W']:.2f} | "
                         f"{v['steady_state_C']:.1f} | {v['margin_K']:.1f} | {when} |")
    lines += ["", "## Hinge loads", "",
              "Peak force in each hinge over the cycle (Newton-Euler of the closed chain), on the "
              "downstream link, direction from +x counter-clockwise:", "",
              "| hinge | model | peak (N) | direction (deg) | on link (from) | where |",
              "|---|---|---|---|---|---|"]
    for joint in JOINT_NAMES:
        for name in PHYSICAL:
            v = results["joint_loads"][name][joint]
            lines.append(f"| {joint} | {name} | {v['peak_N']:.2f} | {v['direction_deg']:.1f} | "
                         f"{v['on_link']} ({v['from']}) | {_at(v['peak_at'])} |")
    gr = results["gear_ratio"]
    side = gr["motor_side"]
    lines += ["", "## Gear-ratio trade", "",
              f"The same motor (motor side {side['peak_torque_Nm']:.4g} N·m, "
              f"{side['no_load_speed_rad_s']:.2f} rad/s, rotor {side['rotor_inertia_kg_m2']:.3g} "
              f"kg m^2) behind ratios {gr['search_range'][0]:g}..{gr['search_range'][1]:g}, on "
              f"the `{GEAR_MODEL}` model, safety factor = least ratio of the envelope's torque in "
              "the direction of the torque the motor delivers (each sample's quadrant) to that "
              "torque: the joint's, the reflected rotor inertia's and the output friction:", "",
              f"- current {gr['current']:g}:1: safety factor {gr['safety_factor_at_current']:.2f}",
              f"- the largest at {gr['best']:.2f}:1: safety factor "
              f"{gr['safety_factor_at_best']:.2f}", "",
              "A one-parameter trade of the torque check on this path, not a recommendation: "
              "the no-load speed falls as 1/N, and the other checks and maneuvers are not "
              "weighed here. Which motor, gearbox and leg pass every maneuver in simulation is "
              "`fivebar-drake codesign`'s answer (README \"Co-design\")."]
    return lines
