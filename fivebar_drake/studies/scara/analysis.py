"""The SCARA study's analysis (everything report.json holds): the seed's trajectory through
the kinematics and the Lagrange model (checked against Drake), the drive demand along it, and
the seed's drive-sizing numbers recomputed under every reading its text allows
(seed_claims)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
import math
from typing import NamedTuple

import numpy as np

from fivebar_drake.mechanisms.scara import (Dynamics, OutOfReach, Scara, ScaraParams,
                                            seed_inertia, seed_path)
from fivebar_drake.mechanisms.scara import sizing as sz
from fivebar_drake.studies.scara.model import drake_terms

REPRODUCED_WITHIN = 0.05          # a computed value within 5 % of the seed's reproduces it
DRAKE_TOLERANCE = 1e-3            # closed-form torques against Drake's, relative to the peak


@dataclass(frozen=True)
class Motion:
    """The seed's trajectory sampled: times (n,) s, tool point, velocity, acceleration (n, 3)
    and the joint motion q, qd, qdd (n, 3) with the configured elbow."""

    t: np.ndarray
    p: np.ndarray
    v: np.ndarray
    a: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray


def seed_motion(params: ScaraParams, duration_s: float | None = None,
                elbow: int | None = None) -> Motion:
    """The seed's trajectory at trajectory.samples_per_s over duration_s (default: the
    trajectory's; beyond its end the tool rests at A), with an elbow (default: the configured
    one)."""
    tr = params.trajectory
    duration = tr.duration_s if duration_s is None else duration_s
    t = np.linspace(0.0, duration, int(round(duration * tr.samples_per_s)) + 1)
    p, v, a = seed_path(tr, t)
    q, qd, qdd = Scara(params.kinematics).joint_motion(
        p, v, a, params.kinematics.elbow if elbow is None else elbow)
    return Motion(t, p, v, a, q, qd, qdd)


def claim(id_, text, seed, computed, unit, reading) -> dict:
    """One seed_claims entry; reproduced when within REPRODUCED_WITHIN of the seed's value."""
    ok = abs(computed - seed) <= REPRODUCED_WITHIN * abs(seed)
    return {"id": id_, "claim": text, "seed_value": seed, "computed_value": float(computed),
            "unit": unit, "reading": reading, "reproduced": bool(ok),
            "deviation": float(computed / seed - 1.0)}


def _sizing_parts(dyn: Dynamics, joint: int, q2, qd, qdd) -> dict[str, float]:
    """A joint's force and its parts at (q1 = 0, q2, q3 = 0) with joint 1, 2 speeds qd and
    accelerations qdd (joint 3 at rest)."""
    parts = dyn.torques(np.array([0.0, q2, 0.0]), np.array([*qd, 0.0]), np.array([*qdd, 0.0]))
    return {k: float(v[joint]) for k, v in parts.items()}


def _sizing_torque(dyn: Dynamics, joint: int, q2, qd, qdd) -> float:
    return _sizing_parts(dyn, joint, q2, qd, qdd)["total"]


def _worst(dyn: Dynamics, joint: int, limits, qd, qdd) -> tuple[float, float]:
    """Largest |torque| of a joint over q2 in its limits (0.5 deg grid) and every sign of the
    speeds and accelerations; returns (torque, q2)."""
    signs = np.array(np.meshgrid(*[[1.0, -1.0]] * 4)).reshape(4, -1).T          # (16, 4)
    q2 = np.linspace(limits[0], limits[1], int(round(np.degrees(limits[1] - limits[0]) * 2)) + 1)
    n = len(q2) * len(signs)
    q = np.zeros((n, 3))
    q[:, 1] = np.repeat(q2, len(signs))
    s = np.tile(signs, (len(q2), 1))
    v, a = np.zeros((n, 3)), np.zeros((n, 3))
    v[:, :2], a[:, :2] = s[:, :2] * qd, s[:, 2:] * qdd
    tau = np.abs(dyn.torques(q, v, a)["total"][:, joint])
    k = int(np.argmax(tau))
    return float(tau[k]), float(q[k, 1])


def torque_readings(params: ScaraParams) -> list[tuple[str, float, float]]:
    """tau1_max and tau2_max (N·m) under each reading: (joint, reading, value)."""
    k, sp = params.kinematics, params.sizing
    scara = Scara(k)
    dyn = Dynamics(k, seed_inertia(params.links))
    rod = Dynamics(k, seed_inertia(params.links, rod_length=True, kin=k))
    qdd = np.array([sp.qdd1_rad_s2, sp.qdd2_rad_s2])
    q2_written, q2_half = sp.qdd2_rad_s2 * sp.t_q2_s**2, 0.5 * sp.qdd2_rad_s2 * sp.t_q2_s**2
    speeds = sp.qd1_rad_s
    out = []
    for joint, written_qd1 in ((0, speeds[0]), (1, speeds[-1])):
        qd = np.array([written_qd1, sp.qd2_rad_s])
        name = f"tau{joint + 1}"
        parts = _sizing_parts(dyn, joint, q2_written, qd, qdd)
        out.append((name, f"as written: eq. 2.{79 + 4 * joint} with qd1 = {written_qd1} rad/s, "
                    f"qd2 = {sp.qd2_rad_s} rad/s, qdd = {qdd.tolist()} rad/s^2, q2 = eps2 t^2 = "
                    f"{q2_written:.3f} rad, all of the same sign (inertial "
                    f"{parts['inertial']:.1f}, Coriolis/centrifugal {parts['coriolis']:.1f}, "
                    f"total {parts['total']:.1f} N·m)", parts["total"]))
        for other in speeds:
            if other != written_qd1:
                out.append((name, f"as written but qd1 = {other} rad/s (the seed's other value)",
                            _sizing_torque(dyn, joint, q2_written, np.array(
                                [other, sp.qd2_rad_s]), qdd)))
        out.append((name, f"q2 = eps2 t^2 / 2 = {q2_half:.3f} rad (the angle reached from rest "
                    "at t = 0.189 s)", _sizing_torque(dyn, joint, q2_half, qd, qdd)))
        out.append((name, "as written with the links' Izz as thin rods of the full link length "
                    "(m a^2/12)", _sizing_torque(rod, joint, q2_written, qd, qdd)))
        tau, at = _worst(dyn, joint, (scara.lower[1], scara.upper[1]), qd, qdd)
        out.append((name, f"worst case: the seed's speeds and accelerations with any signs, q2 "
                    f"anywhere in its limits (worst at q2 = {math.degrees(at):.1f} deg)", tau))
        alone = np.zeros(2)
        alone[joint] = qdd[joint]
        out.append((name, "starting from rest (qd = 0) with only this joint at its maximum "
                    "acceleration, arm stretched (q2 = 0)",
                    _sizing_torque(dyn, joint, 0.0, np.zeros(2), alone)))
        tau, at = _worst(dyn, joint, (scara.lower[1], scara.upper[1]), np.zeros(2), qdd)
        out.append((name, f"starting from rest with both joints at their maximum accelerations "
                    f"(any signs), worst q2 = {math.degrees(at):.1f} deg", tau))
    return out


def _trajectory_peaks(params: ScaraParams, motion: Motion, payload_kg: float) -> np.ndarray:
    dyn = Dynamics(params.kinematics, seed_inertia(params.links, payload_kg))
    return np.abs(dyn.torques(motion.q, motion.qd, motion.qdd)["total"]).max(axis=0)


def screw(params: ScaraParams) -> dict:
    """The ball-screw chain of section 2.3.2 computed from its inputs (SI and the seed's units
    where named)."""
    sp, links = params.sizing, params.links
    beta = math.radians(sp.contact_angle_deg)
    unloaded = links.m3_kg
    loaded = links.m3_kg + links.payload_kg
    c = sz.groove_offset(sp.groove_radius_m, sp.ball_diameter_m, beta)
    dtb = sz.ball_circle_diameter(sp.core_diameter_m, sp.groove_radius_m, c)
    gamma = sz.lead_angle(sp.screw_lead_m, dtb)
    phi = sz.friction_angle(sp.rolling_friction_m, sp.core_diameter_m, beta)
    eta = sz.screw_efficiency(gamma, phi)
    out = {"Fa_unloaded_N": sz.axial_force(unloaded, sp.qdd3_m_s2, links.gravity_m_s2),
           "Fa_loaded_N": sz.axial_force(loaded, sp.qdd3_m_s2, links.gravity_m_s2),
           "groove_offset_m": c, "Dtb_m": dtb, "gamma_rad": gamma, "phi_rad": phi,
           "eta": eta, "eta_p": sp.screw_efficiency_factor * eta,
           "n3_rpm": sz.nut_speed_rpm(sp.v3_m_s, sp.screw_starts, sp.screw_lead_m),
           "Zb": sz.ball_count(dtb, sp.working_turns, sp.ball_diameter_m)}
    out["d1_min_m"] = sz.core_diameter_min(out["Fa_loaded_N"], sp.allowable_stress_Pa)
    return out


def seed_claims(params: ScaraParams, motion: Motion, lagrange_tau3: float) -> list[dict]:
    """Every number of the seed's drive sizing beside the computed one, one entry per reading."""
    sc, sp = params.seed_claims, params.sizing
    mu, const = sp.reducer_efficiency, sp.power_constant
    out = []
    rows = torque_readings(params)
    for joint, n_rpm in ((1, sp.n1_rpm), (2, sp.n2_rpm)):
        key = f"tau{joint}_max"
        text = (f"peak torque of joint {joint} at the seed's maximum speeds and accelerations "
                "(no load)")
        mine = [(r, v) for name, r, v in rows if name == f"tau{joint}"]
        for reading, value in mine:
            out.append(claim(key, text, sc[f"{key}_Nm"], abs(value), "N·m", reading))
        for payload in (0.0, params.links.payload_kg):
            peak = _trajectory_peaks(params, motion, payload)[joint - 1]
            out.append(claim(key, text, sc[f"{key}_Nm"], peak, "N·m",
                             f"the peak along the seed's own trajectory (section 2.2.2), "
                             f"payload {payload:g} kg (Lagrange model)"))
        wkey, wtext = f"W{joint}", (f"motor power of joint {joint}: W = tau n / (9550 mu), "
                                    f"n = {n_rpm:g} rpm, mu = {mu}")
        out.append(claim(wkey, wtext, sc[f"W{joint}_kW"],
                         sz.motor_power_kW(sc[f"{key}_Nm"], n_rpm, mu, const), "kW",
                         f"the seed's tau{joint}max = {sc[f'{key}_Nm']:g} N·m (checks the "
                         "formula)"))
        for reading, value in mine:
            out.append(claim(wkey, wtext, sc[f"W{joint}_kW"],
                             sz.motor_power_kW(abs(value), n_rpm, mu, const), "kW",
                             f"tau from: {reading}"))
    s = screw(params)
    m3, m_loaded, g = params.links.m3_kg, params.links.m3_kg + params.links.payload_kg, \
        params.links.gravity_m_s2
    fa_text = "axial force of the screw, no load: (m_vit + m_tkep)(qdd3 - g) (eq. 2.85)"
    fa_loaded_text = "axial force with the 20 kg load: m3 (qdd3 + g), m3 = 24 kg (eq. 2.90)"
    out += [claim("Fa_unloaded", fa_text, sc["Fa_unloaded_N"], s["Fa_unloaded_N"], "N",
                  f"m3 = {m3:g} kg lifted at {sp.qdd3_m_s2} m/s^2 against gravity (the seed's "
                  "numbers: qdd3 + g)"),
            claim("Fa_unloaded", fa_text, sc["Fa_unloaded_N"],
                  sz.axial_force(m3, sp.qdd3_m_s2, -g), "N",
                  f"the formula's sign as written, qdd3 - g with qdd3 = {sp.qdd3_m_s2} m/s^2 "
                  "(lowering, or lifting with gravity helping)"),
            claim("Fa_unloaded", fa_text, sc["Fa_unloaded_N"], lagrange_tau3, "N",
                  "abs(tau3) of the Lagrange model (eq. 2.78) with the tool accelerating upwards"),
            claim("Fa_loaded", fa_loaded_text, sc["Fa_loaded_N"], s["Fa_loaded_N"], "N",
                  "as written: 24 kg lifted at qdd3 + g"),
            claim("Fa_loaded", fa_loaded_text, sc["Fa_loaded_N"],
                  sz.axial_force(m_loaded, sp.qdd3_m_s2, -g), "N",
                  "with eq. 2.85's sign, qdd3 - g")]
    t3_text = "nut torque T3 = Fa Dtb tan(gamma + phi) / 2 (eq. 2.86)"
    seed_angles = math.radians(sc["gamma_deg"]), math.radians(sc["phi_deg"])
    t3_written = sz.screw_torque(sc["Fa_unloaded_N"], sc["Dtb_mm"] * 1e-3, *seed_angles)
    t3_computed = sz.screw_torque(s["Fa_unloaded_N"], s["Dtb_m"], s["gamma_rad"], s["phi_rad"])
    t3_loaded = sz.screw_torque(s["Fa_loaded_N"], s["Dtb_m"], s["gamma_rad"], s["phi_rad"])
    out += [claim("T3", t3_text, sc["T3_Nm"], t3_written, "N·m",
                  "the seed's Fa = 215.76 N, Dtb = 26.02 mm, gamma = 17 deg, phi = 0.035 deg"),
            claim("T3", t3_text, sc["T3_Nm"], t3_computed, "N·m",
                  "Fa, Dtb, gamma, phi all computed here (no load)"),
            claim("T3", t3_text, sc["T3_Nm"], t3_loaded, "N·m",
                  "with the loaded axial force (20 kg payload)")]
    out.append(claim("n3", "nut speed n3 = 60 v3max / (Z p) (eq. 2.87)", sc["n3_rpm"],
                     s["n3_rpm"], "rpm", f"v3max = {sp.v3_m_s} m/s, Z = {sp.screw_starts}, "
                     f"p = {sp.screw_lead_m * 1e3:g} mm"))
    w3_text = "motor power of joint 3: W = T3 n3 / (9550 eta_p) (eq. 2.89)"
    for torque, eta, reading in (
            (sc["T3_Nm"], sc["eta_p"], "the seed's T3 = 0.86 N·m and eta_p = 0.898"),
            (t3_computed, s["eta_p"], "T3 and eta_p computed here (no load)"),
            (t3_loaded, s["eta_p"], "with the loaded T3 (20 kg payload)")):
        out.append(claim("W3", w3_text, sc["W3_kW"],
                         sz.motor_power_kW(torque, s["n3_rpm"], eta, const), "kW", reading))
    out += [claim("d1_min", "smallest screw core diameter in tension (eq. 2.91)",
                  sc["d1_min_mm"], s["d1_min_m"] * 1e3, "mm",
                  f"Fa = loaded force, [sigma] = {sp.allowable_stress_Pa / 1e6:g} MPa"),
            claim("Dtb", "diameter through the ball centres Dtb = d1 + 2 (r1 - c) (eq. 2.93)",
                  sc["Dtb_mm"], s["Dtb_m"] * 1e3, "mm",
                  f"c = (r1 - db/2) cos(beta) = {s['groove_offset_m'] * 1e3:.4f} mm unrounded "
                  "(the seed rounds it to 0.02 mm)"),
            claim("gamma", "lead angle gamma = atan(p / (pi Dtb)) (eq. 2.94)", sc["gamma_deg"],
                  math.degrees(s["gamma_rad"]), "deg", "p = 25 mm, Dtb computed"),
            claim("Zb", "balls in the working turns pi Dtb K / db - 1 (eq. 2.95)", sc["Zb"],
                  s["Zb"], "balls", f"K = {sp.working_turns} (the seed's K), Dtb computed; "
                  "the seed then takes 62"),
            claim("phi", "equivalent friction angle atan(2 f / (d1 sin beta)) (eq. 2.97)",
                  sc["phi_deg"], math.degrees(s["phi_rad"]), "deg",
                  "f = 0.005 mm (the seed's 0.005 with d1 in mm)"),
            claim("eta_p", "screw efficiency 0.9 tan(gamma) / tan(gamma + phi)", sc["eta_p"],
                  s["eta_p"], "-", "gamma, phi computed")]
    return out


def seed_notes(params: ScaraParams) -> list[str]:
    """Where the seed's text contradicts itself or its own numbers, with the numbers."""
    tr, k, sp = params.trajectory, params.kinematics, params.sizing
    za, zb = tr.a_m[2] * 1e3, tr.b_m[2] * 1e3
    T = tr.line_s
    a2, a3 = 3 * (za - zb) / T**2, -2 * (za - zb) / T**3            # the seed's eq. 2.48
    end_down = za + a2 * T**2 + a3 * T**3
    end_up = zb - a2 * T**2 - a3 * T**3                               # eq. 2.53
    z_written = sorted(k.d1_m + k.d2_m + np.array(k.q3_limits_m))
    return [
        f"Eq. 2.48-2.49 take a2 = 3 (z0 - zc) / t^2 = {a2:g}, a3 = {a3:g}: z(t) = {za:g} + "
        f"{a2:g} t^2 {a3:+g} t^3 ends at {end_down:g} mm, not at B's {zb:g} mm (the sign of "
        f"z_c - z_0 is swapped); eq. 2.53 likewise ends at {end_up:g} mm, not {za:g}. The code "
        "uses the cubic law from A to B and back (eq. 2.46).",
        f"Eq. 2.20/2.21 (z_E = q3 + 0.45, q3 in [0, 0.4] m) put the tool at z in "
        f"[{z_written[0]:g}, {z_written[1]:g}] m, out of reach of the trajectory's z = "
        f"{zb / 1e3:g} .. {za / 1e3:g} m; the code reads q3 as moving the tool down "
        f"(q3_direction = {k.q3_direction}).",
        "Eq. 2.74 gives G = (0, 0, -m3 g) but eq. 2.77 adds +m3 g: the sign follows the "
        "direction of q3; here G3 = q3_direction m3 g (tool weight along -z).",
        f"The sizing of joint 1 uses qd1 = {sp.qd1_rad_s[0]} rad/s, that of joint 2 qd1 = "
        f"{sp.qd1_rad_s[-1]} rad/s (450 deg/s = 7.854 rad/s); both are computed.",
        f"'q2 = eps2max t^2 = {sp.qdd2_rad_s2 * sp.t_q2_s**2:.2f} rad' at t = {sp.t_q2_s} s: "
        f"from rest at constant acceleration q2 = eps t^2 / 2 = "
        f"{0.5 * sp.qdd2_rad_s2 * sp.t_q2_s**2:.2f} rad; both are computed.",
        "The seed gives no pose, speed signs or time for its tau1max = 206 N·m and tau2max = "
        "115 N·m: every reading its text allows is computed (seed_claims tau1_max, tau2_max).",
    ]


def drake_check(params: ScaraParams, motion: Motion, payload_kg: float, every: int = 10) -> dict:
    """The Lagrange model against Drake's MultibodyPlant of the same arm at every `every`-th
    sample: largest differences of the inverse dynamics (relative to each joint's peak), mass
    matrix, bias and gravity terms."""
    inertia = seed_inertia(params.links, payload_kg)
    dyn = Dynamics(params.kinematics, inertia)
    q, qd, qdd = motion.q[::every], motion.qd[::every], motion.qdd[::every]
    drake = drake_terms(params, inertia, q, qd, qdd)
    mine = dyn.torques(q, qd, qdd)
    peak = np.maximum(np.abs(mine["total"]).max(axis=0), 1e-12)
    rel = np.abs(drake["inverse_dynamics"] - mine["total"]).max(axis=0) / peak
    return {"payload_kg": payload_kg, "samples": len(q),
            "max_relative_difference": rel.tolist(),
            "mass_matrix_max_abs": float(np.abs(drake["mass_matrix"]
                                                - dyn.mass_matrix(q)).max()),
            "bias_max_abs": float(np.abs(drake["bias"] - mine["coriolis"]).max()),
            "gravity_max_abs": float(np.abs(drake["gravity"] - mine["gravity"]).max()),
            "agrees": bool(rel.max() <= DRAKE_TOLERANCE)}


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


class Analysis(NamedTuple):
    """The analysis as plain data: the parameters, report.json's dictionary, the sampled
    trajectory."""

    params: ScaraParams
    data: dict
    motion: Motion


def analyze(params: ScaraParams) -> Analysis:
    return Analysis(params, *analysis_data(params))
