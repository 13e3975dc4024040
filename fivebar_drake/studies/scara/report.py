"""The SCARA analysis written out: report.md, report.json and the plots (workspace with the
trajectory, joint motion, joint forces along the trajectory)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
import matplotlib.pyplot as plt
import numpy as np

from fivebar_drake.core.files import save_figure, write_atomic
from fivebar_drake.mechanisms.scara import Dynamics, OutOfReach, Scara, ScaraParams, seed_inertia
from fivebar_drake.mechanisms.scara import sizing as sz
from fivebar_drake.studies.scara.analysis import (REPRODUCED_WITHIN, Motion, drake_check,
                                                  seed_claims, seed_motion, seed_notes)

FIGURES = ("workspace", "joint_motion", "joint_forces")
ANALYSIS_FILES = ("report.json", *(f"{name}.png" for name in FIGURES), "report.md")
UNITS = ("N*m", "N*m", "N")


def assumptions(params: ScaraParams) -> list[str]:
    k, links = params.kinematics, params.links
    return [
        f"The prismatic joint moves the tool {'down' if k.q3_direction < 0 else 'up'} "
        f"(q3_direction = {k.q3_direction}): z_E = d1 + d2 {'-' if k.q3_direction < 0 else '+'} "
        "q3. Eq. 2.20 as written (+) puts the tool at z in [0.45, 0.85] m, where the seed's own "
        "trajectory (z = 0.3 .. 0.4 m) cannot go; the seed's Matlab workspace code has ze = -i.",
        f"Elbow {k.elbow:+d} along the trajectory (the seed's IK takes q2 = +arccos); both elbows "
        "are reported at A.",
        "Link 3 (screw + gripper, and the payload) is a mass on the axis of joint 3 turning with "
        "link 2 (the seed's J_T3, J_R2), so only joint 3 feels gravity.",
        "Inertias as the seed writes them: Izz1 = m_khau1 l1^2/12, Izz2 = m_khau2 l2^2/12 with "
        "l = a/2 and the bare link masses (8.2, 11.8 kg), Izz3 = m_vit r^2/2; the Drake model "
        "takes Ixx = Iyy = Izz (they never enter the motion: every joint axis is vertical).",
        f"Payload {links.payload_kg:g} kg at the tool in the loaded readings; the seed sizes "
        "joints 1 and 2 without it (section 2.3.2 b).",
        "No friction, ideal model (the seed's section 2.3.1 c); the reducer and screw "
        "efficiencies enter the powers only.",
        f"A computed value reproduces the seed's when within {REPRODUCED_WITHIN:.0%} of it.",
    ]


def _demand_rows(params, motion: Motion, payload: float) -> dict:
    dyn = Dynamics(params.kinematics, seed_inertia(params.links, payload))
    tau = dyn.torques(motion.q, motion.qd, motion.qdd)
    d = sz.demand(motion.t, tau["total"], motion.qd, params.sizing.reducer_efficiency)
    return {"payload_kg": payload, "peak": d["peak"].tolist(), "rms": d["rms"].tolist(),
            "peak_time_s": d["peak_time_s"].tolist(), "peak_speed": d["peak_speed"].tolist(),
            "peak_power_W": d["peak_power_W"].tolist(),
            "input_power_W": d["input_power_W"].tolist(),
            "parts_peak": {k: np.abs(v).max(axis=0).tolist() for k, v in tau.items()}}


def _elbows(params: ScaraParams) -> list[dict]:
    """The trajectory with each elbow: peak joint speeds and forces with the payload."""
    out = []
    dyn = Dynamics(params.kinematics, seed_inertia(params.links, params.links.payload_kg))
    for elbow in (1, -1):
        try:
            m = seed_motion(params, elbow=elbow)
        except OutOfReach as err:
            out.append({"elbow": elbow, "reachable": False, "why": str(err)})
            continue
        tau = dyn.torques(m.q, m.qd, m.qdd)["total"]
        out.append({"elbow": elbow, "reachable": True,
                    "peak_joint_speed": np.abs(m.qd).max(axis=0).tolist(),
                    "peak_force": np.abs(tau).max(axis=0).tolist()})
    return out


def analysis_data(params: ScaraParams) -> tuple[dict, Motion]:
    """Everything report.json holds, and the sampled trajectory."""
    k, sp, links = params.kinematics, params.sizing, params.links
    scara = Scara(k)
    motion = seed_motion(params)
    dyn0 = Dynamics(k, seed_inertia(links))
    qdd3 = k.q3_direction * sp.qdd3_m_s2           # the tool accelerating upwards
    tau3 = abs(float(dyn0.torques(np.zeros(3), np.zeros(3), np.array([0.0, 0.0, qdd3]))
                     ["total"][2]))
    a = np.asarray(params.trajectory.a_m)
    elbows = {f"{e:+d}": scara.inverse(a, e, strict=False).q.tolist() for e in (1, -1)}
    inner, outer = scara.radial_extent()
    z = sorted(scara.z0 + k.q3_direction * np.array(k.q3_limits_m))
    boundary = scara.workspace_boundary()
    data = {
        "mechanism": "scara",
        "source": params.source,
        "parameters": {f.name: (dataclasses.asdict(getattr(params, f.name))
                                if dataclasses.is_dataclass(getattr(params, f.name))
                                else getattr(params, f.name))
                       for f in dataclasses.fields(params)},
        "kinematics": {"ik_at_A": elbows, "cardan_at_A_rad": scara.cardan_angles(
            np.asarray(elbows[f"{k.elbow:+d}"])).tolist()},
        "workspace": {"inner_radius_m": inner, "outer_radius_m": outer, "z_range_m": z,
                      "boundary_pieces": len(boundary),
                      "trajectory_inside": bool(scara.reachable_xy(motion.p[:, :2]).all())},
        "trajectory": {"duration_s": params.trajectory.duration_s,
                       "samples": len(motion.t),
                       "peak_joint_speed": np.abs(motion.qd).max(axis=0).tolist(),
                       "peak_joint_acceleration": np.abs(motion.qdd).max(axis=0).tolist(),
                       "peak_tool_speed_m_s": float(np.linalg.norm(motion.v, axis=1).max()),
                       "joint_units": ["rad", "rad", "m"]},
        "demand": [_demand_rows(params, motion, w) for w in (0.0, links.payload_kg)],
        "elbows": _elbows(params),
        "drake_check": [drake_check(params, motion, w) for w in (0.0, links.payload_kg)],
        "seed_claims": seed_claims(params, motion, tau3),
        "seed_notes": seed_notes(params),
        "assumptions": assumptions(params),
    }
    return data, motion


def _f(v, digits=4) -> str:
    return f"{v:.{digits}g}"


def markdown(data: dict) -> str:
    ws, tr = data["workspace"], data["trajectory"]
    lines = ["# SCARA arm (seed 002): kinematics, workspace, trajectory, dynamics, drive sizing",
             "", f"Parameters: `{data['source']}`.", "", "## Kinematics and workspace", "",
             "IK of A with both elbows (q1, q2 rad, q3 m): " + "; ".join(
                 f"elbow {e}: ({', '.join(_f(v, 6) for v in q)})"
                 for e, q in data["kinematics"]["ik_at_A"].items()) + ".",
             f"Tool Cardan angles at A (alpha, beta, eta) rad: "
             f"{', '.join(_f(v, 6) for v in data['kinematics']['cardan_at_A_rad'])}.", "",
             f"Horizontal reach {_f(ws['inner_radius_m'])} .. {_f(ws['outer_radius_m'])} m, tool "
             f"height {_f(ws['z_range_m'][0])} .. {_f(ws['z_range_m'][1])} m; the exact boundary "
             f"under the joint limits has {ws['boundary_pieces']} arcs (workspace.png); the "
             f"trajectory is {'inside' if ws['trajectory_inside'] else 'NOT inside'} it.", "",
             "## Trajectory (section 2.2.2)", "",
             f"{_f(tr['duration_s'])} s, {tr['samples']} samples; peak joint speeds "
             f"{', '.join(_f(v) for v in tr['peak_joint_speed'])} (rad/s, rad/s, m/s), peak "
             f"accelerations {', '.join(_f(v) for v in tr['peak_joint_acceleration'])}; peak "
             f"tool speed {_f(tr['peak_tool_speed_m_s'])} m/s.", "",
             "## Joint forces along the trajectory (Lagrange) and the drive demand", "",
             "| payload (kg) | joint | peak | at t (s) | RMS | peak speed | peak power (W) "
             "| input power at mu (W) |", "|---|---|---|---|---|---|---|---|"]
    for d in data["demand"]:
        for j in range(3):
            lines.append(f"| {d['payload_kg']:g} | {j + 1} | {_f(d['peak'][j])} {UNITS[j]} | "
                         f"{d['peak_time_s'][j]:.3f} | {_f(d['rms'][j])} | "
                         f"{_f(d['peak_speed'][j])} | {_f(d['peak_power_W'][j])} | "
                         f"{_f(d['input_power_W'][j])} |")
    elbow = data["parameters"]["kinematics"]["elbow"]
    lines += ["", f"With the payload, by elbow (the trajectory's is {elbow:+d}): "
              + "; ".join(f"elbow {e['elbow']:+d}: peak speeds "
                          f"{', '.join(_f(v) for v in e['peak_joint_speed'])}, peak forces "
                          f"{', '.join(_f(v) for v in e['peak_force'])}" if e["reachable"]
                          else f"elbow {e['elbow']:+d}: {e['why']}" for e in data["elbows"]) + "."]
    lines += ["", "Lagrange model against Drake's MultibodyPlant of the same arm (generated SDF):"]
    for c in data["drake_check"]:
        lines.append(f"- payload {c['payload_kg']:g} kg, {c['samples']} samples: inverse "
                     f"dynamics within {max(c['max_relative_difference']):.2e} of the peaks, "
                     f"M within {c['mass_matrix_max_abs']:.1e}, C qd within "
                     f"{c['bias_max_abs']:.1e}, G within {c['gravity_max_abs']:.1e} "
                     f"({'agrees' if c['agrees'] else 'DISAGREES'} within 0.1 %)")
    lines += ["", "## Drive sizing: the seed's numbers beside the computed ones", "",
              "| id | seed | computed | unit | reading | verdict |", "|---|---|---|---|---|---|"]
    for c in data["seed_claims"]:
        verdict = ("reproduced" if c["reproduced"] else
                   f"not reproduced — because this reading gives {_f(c['computed_value'])} "
                   f"({c['deviation']:+.1%})")
        lines.append(f"| {c['id']} | {_f(c['seed_value'])} | {_f(c['computed_value'])} | "
                     f"{c['unit']} | {c['reading'].replace('|', '/')} | {verdict} |")
    lines += ["", "## Where the seed's text is inconsistent", ""]
    lines += [f"- {n}" for n in data["seed_notes"]]
    lines += ["", "## Assumptions", ""] + [f"- {a}" for a in data["assumptions"]]
    lines += ["", "## Plots", ""] + [f"![{n}]({n}.png)" for n in FIGURES]
    return "\n".join(lines) + "\n"


def plot_workspace(params: ScaraParams, motion: Motion) -> plt.Figure:
    scara = Scara(params.kinematics)
    fig, (top, side) = plt.subplots(1, 2, figsize=(12, 5.5), width_ratios=[1.4, 1])
    grid = scara.seed_grid()
    top.plot(grid[:, 0], grid[:, 1], ".", color="0.7", ms=2, label="the seed's grid (Fig. 2.4)")
    for k, piece in enumerate(scara.workspace_boundary()):
        top.plot(piece[:, 0], piece[:, 1], "k-", lw=1.2, label="boundary" if k == 0 else None)
    top.plot(motion.p[:, 0], motion.p[:, 1], "r-", lw=2, label="trajectory")
    top.plot(0, 0, "ko")
    top.set(aspect="equal", xlabel="x (m)", ylabel="y (m)",
            title="workspace under the joint limits (top view)")
    top.legend(loc="lower left")
    radius = np.linalg.norm(motion.p[:, :2], axis=1)
    inner, outer = scara.radial_extent()
    z = sorted(scara.z0 + params.kinematics.q3_direction * np.array(params.kinematics.q3_limits_m))
    side.fill_between([inner, outer], z[0], z[1], color="0.85", label="reach x height")
    side.plot(radius, motion.p[:, 2], "r-", lw=2, label="trajectory")
    side.set(xlabel="horizontal distance from axis 1 (m)", ylabel="z (m)", title="side view")
    side.legend()
    fig.tight_layout()
    return fig


def plot_joint_motion(motion: Motion) -> plt.Figure:
    fig, axes = plt.subplots(3, 3, figsize=(12, 8), sharex=True)
    units = (("rad", "rad/s", "rad/s^2"), ("rad", "rad/s", "rad/s^2"), ("m", "m/s", "m/s^2"))
    for j in range(3):
        for r, (values, name) in enumerate(((motion.q, "q"), (motion.qd, "qd"),
                                           (motion.qdd, "qdd"))):
            axes[r, j].plot(motion.t, values[:, j])
            axes[r, j].set_ylabel(f"{name}{j + 1} ({units[j][r]})")
            axes[r, j].grid(alpha=0.3)
        axes[2, j].set_xlabel("t (s)")
    fig.suptitle("joint positions, speeds and accelerations along the seed's trajectory")
    fig.tight_layout()
    return fig


def plot_joint_forces(params: ScaraParams, motion: Motion) -> plt.Figure:
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    for payload, style in ((0.0, "-"), (params.links.payload_kg, "--")):
        dyn = Dynamics(params.kinematics, seed_inertia(params.links, payload))
        tau = dyn.torques(motion.q, motion.qd, motion.qdd)["total"]
        for j, ax in enumerate(axes):
            k = int(np.argmax(np.abs(tau[:, j])))
            line, = ax.plot(motion.t, tau[:, j], style, label=f"payload {payload:g} kg")
            ax.plot(motion.t[k], tau[k, j], "o", color=line.get_color())
            ax.annotate(f"peak {tau[k, j]:.3g}", (motion.t[k], tau[k, j]),
                        textcoords="offset points", xytext=(5, 5))
            ax.set_ylabel(f"tau{j + 1} ({UNITS[j]})")
            ax.grid(alpha=0.3)
    axes[0].legend()
    axes[-1].set_xlabel("t (s)")
    fig.suptitle("joint forces along the trajectory (Lagrange: M qdd + C qd + G)")
    fig.tight_layout()
    return fig


def write_analysis(params: ScaraParams, out: Path) -> tuple[list[str], list[Path]]:
    """The analysis into out (report.json and the plots first, report.md last); returns the
    lines the command line prints and the paths written."""
    data, motion = analysis_data(params)
    figures = (plot_workspace(params, motion), plot_joint_motion(motion),
               plot_joint_forces(params, motion))
    written = [write_atomic(out / "report.json",
                            json.dumps(data, indent=2, allow_nan=False) + "\n")]
    written += [save_figure(fig, out / f"{name}.png") for fig, name in zip(figures, FIGURES)]
    written.append(write_atomic(out / "report.md", markdown(data)))
    claims = data["seed_claims"]
    loaded = data["demand"][1]
    lines = [f"trajectory peaks with {loaded['payload_kg']:g} kg: tau1 "
             f"{loaded['peak'][0]:.3g} N*m, tau2 {loaded['peak'][1]:.3g} N*m, F3 "
             f"{loaded['peak'][2]:.4g} N; Lagrange vs Drake within "
             f"{max(max(c['max_relative_difference']) for c in data['drake_check']):.1e}",
             f"seed claims: {sum(c['reproduced'] for c in claims)} of {len(claims)} readings "
             f"reproduce the seed's number (report.md, drive sizing)"]
    return lines, written

