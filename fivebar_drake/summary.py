"""Dynamic vs static motor torques of a simulated trot: summary.json, summary.md and plots.

Per leg and motor, over the trot window (t >= stand_s + ramp_s, the gait at full size):
- applied torque (motor model output): peak and RMS;
- static torque for the same poses: -J_F(q)^T F with F the measured ground force on the foot in
  the leg plane, averaged over 20 ms because point contact chatters at touchdown ("contact"),
  and the seed's model G_seed(q) with m_leg g at the foot ("seed");
- their ratio, the safety factor against the motor and its verdict, the fraction of time the
  motor model clipped the command, the peak joint speed against the no-load speed.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .analysis import verdict
from .dynamics import seed_model, static_torques
from .jacobians import foot_jacobian
from .kinematics import forward
from .params import Params
from .plant_model import loop_gaps
from .scenario import Scenario
from .sdf_model import plane_rotation
from .simulation import Setup, SimResult
from .systems import body_rotation

MOTORS = ("A", "B")
CONTACT_AVERAGE_S = 0.02   # contact forces chatter at touchdown: average them over 20 ms


def _period(t) -> float:
    return float(np.median(np.diff(t))) if len(t) > 1 else 1.0


def moving_average(x, n: int):
    """Centred moving average over n samples along axis 0 (edges use the available samples)."""
    n = min(n, len(x))
    if n <= 1:
        return x
    kernel = np.ones(n)
    flat = x.reshape(len(x), -1)
    num = np.apply_along_axis(lambda c: np.convolve(c, kernel, mode="same"), 0, flat)
    den = np.convolve(np.ones(len(x)), kernel, mode="same")[:, None]
    return (num / den).reshape(x.shape)


@dataclass(frozen=True)
class Signals:
    """Time series derived from a run. Per step: t_state (s), loop gap (legs, steps) m, body
    position (steps, 3) m, quaternion (steps, 4), velocity (steps, 3) m/s, joint angles and
    speeds (steps, legs, 2). Per log sample: t_log (s), command/applied/saturated/static_contact/
    static_seed (samples, legs, 2) N*m, foot force in the leg plane (samples, legs, 2) N."""

    t_state: np.ndarray
    gap: np.ndarray
    body_p: np.ndarray
    body_quat: np.ndarray
    body_v: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    t_log: np.ndarray
    command: np.ndarray
    applied: np.ndarray
    saturated: np.ndarray
    static_contact: np.ndarray
    static_seed: np.ndarray
    foot_force_plane: np.ndarray


def signals(result: SimResult, setup: Setup, params: Params) -> Signals:
    plant = setup.plant
    nq = plant.num_positions()
    body = plant.GetBodyByName("body", setup.instance)
    qs, vs = body.floating_positions_start(), nq + body.floating_velocities_start_in_v()
    st = result.state
    legs = setup.legs
    gap = np.array([loop_gaps(params, st[:, setup.indices[leg].q]) for leg in legs])
    q = np.stack([st[:, setup.indices[leg].q[:2]] for leg in legs], 1)
    qd = np.stack([st[:, nq + setup.indices[leg].v[:2]] for leg in legs], 1)
    act = np.array([setup.indices[leg].actuators for leg in legs])     # (legs, 2)
    per_leg = lambda x: x[:, act]  # noqa: E731  (samples, 8) -> (samples, legs, 2)
    # poses at the log samples (the state logged at or just before each sample)
    k = np.clip(np.searchsorted(result.t_state, result.t_log, side="right") - 1, 0, len(st) - 1)
    q_log = q[k]
    pose = forward(params.leg, q_log)
    r_plane = np.array([body_rotation(v) @ plane_rotation() for v in st[k, qs:qs + 4]])
    f_plane = np.einsum("sji,slj->sli", r_plane, result.foot_forces)[..., :2]
    f_plane = moving_average(f_plane, max(1, round(CONTACT_AVERAGE_S / _period(result.t_log))))
    static_contact = -np.einsum("slji,slj->sli", foot_jacobian(params.leg, pose), f_plane)
    static_seed = static_torques(params, seed_model(params), pose)
    return Signals(
        t_state=result.t_state, gap=gap, body_p=st[:, qs + 4:qs + 7], body_quat=st[:, qs:qs + 4],
        body_v=st[:, vs + 3:vs + 6], q=q, qd=qd, t_log=result.t_log,
        command=per_leg(result.command), applied=per_leg(result.applied),
        saturated=per_leg(result.saturated), static_contact=static_contact,
        static_seed=static_seed, foot_force_plane=f_plane)


def _ratio(a: float, b: float) -> float:
    return a / b if b else float("nan")


def _peak(x):
    return float(np.max(np.abs(x))) if np.size(x) else float("nan")


def summarize(sig: Signals, scenario: Scenario, params: Params, setup: Setup,
              result: SimResult, seed_analysis: dict) -> dict:
    """The summary.json dictionary (SI units). seed_analysis: analysis results of the seed model
    (report.json's results.seed), for the 'was the seed optimistic' verdict."""
    # the trot at full size; a shorter (or failed) run falls back to what it has
    start = next(s for s in (scenario.stand_s + scenario.ramp_s, scenario.stand_s, 0.0)
                 if sig.t_log[-1] > s or s == 0.0)
    win = sig.t_log >= start
    win_state = sig.t_state >= start
    motor = params.motor
    legs = {}
    for i, leg in enumerate(setup.legs):
        legs[leg] = {}
        for j, name in enumerate(MOTORS):
            applied = sig.applied[win, i, j]
            peak = _peak(applied)
            static = _peak(sig.static_contact[win, i, j])
            sf = _ratio(motor.peak_torque_Nm, peak)
            legs[leg][name] = {
                "peak_torque_Nm": peak,
                "rms_torque_Nm": float(np.sqrt(np.mean(applied**2))),
                "static_torque_Nm": static,
                "seed_static_torque_Nm": _peak(sig.static_seed[win, i, j]),
                "dynamic_to_static_ratio": _ratio(peak, static),
                "dynamic_to_seed_static_ratio": _ratio(peak, _peak(sig.static_seed[win, i, j])),
                "safety_factor": sf,
                "verdict": verdict(params, sf),
                "saturated_fraction": float(np.mean(sig.saturated[win, i, j])),
                "peak_speed_rad_s": _peak(sig.qd[win_state, i, j]),
                "speed_ok": bool(_peak(sig.qd[win_state, i, j]) <= motor.no_load_speed_rad_s),
            }
    worst = max((m["peak_torque_Nm"] for leg in legs.values() for m in leg.values()))
    seed_peak = max(seed_analysis[m]["peak_torque_Nm"] for m in MOTORS)
    duration = float(sig.t_state[-1])
    p = sig.body_p
    quat = sig.body_quat / np.linalg.norm(sig.body_quat, axis=1, keepdims=True)
    tilt = np.degrees(np.arccos(np.clip(1 - 2 * (quat[:, 1] ** 2 + quat[:, 2] ** 2), -1, 1)))
    trot_t = sig.t_state[win_state]
    return {
        "closure": scenario.closure,
        "duration_s": duration,
        "requested_duration_s": scenario.duration_s,
        "completed": not result.error,
        "error": result.error,
        "time_step_s": setup.time_step_s,
        "real_time_factor": duration / result.wall_s,
        "wall_time_s": result.wall_s,
        "max_loop_gap_m": float(np.max(sig.gap)),
        "max_loop_gap_per_leg_m": {leg: float(np.max(g)) for leg, g in zip(setup.legs, sig.gap)},
        "bushing": None if setup.bushing is None else {
            "stiffness_N_m": setup.bushing.stiffness_N_m,
            "damping_N_s_m": setup.bushing.damping_N_s_m},
        "knee_effective_mass_kg": setup.m_eff_kg,
        "design_loop_force_N": setup.loop_force_N,
        "trot_window_s": [float(start), duration],
        "body_height_m": {"min": float(p[:, 2].min()), "max": float(p[:, 2].max())},
        "max_tilt_deg": float(tilt.max()),
        "forward_distance_m": float(p[-1, 0] - p[0, 0]),
        "mean_forward_speed_m_s": float((p[win_state][-1, 0] - p[win_state][0, 0])
                                        / (trot_t[-1] - trot_t[0])) if len(trot_t) > 1
                                  else float("nan"),
        "balance_feedback": {"gain": scenario.balance_gain, "rate_s": scenario.balance_rate_s},
        "seed_peak_torque_Nm": seed_peak,
        "simulated_peak_torque_Nm": worst,
        "seed_static_estimate_optimistic": bool(worst > seed_peak),
        "legs": legs,
    }


def markdown(summary: dict, params: Params) -> str:
    s = summary
    lines = [
        f"# Simulated trot: dynamic vs static motor torque ({s['closure']} closure)", "",
        f"Simulated {s['duration_s']:.2f} s (requested {s['requested_duration_s']:g} s) at "
        f"time step {s['time_step_s'] * 1e3:.3f} ms, {s['real_time_factor']:.2f}x real time. "
        f"Statistics over the trot window t = {s['trot_window_s'][0]:.2f} .. "
        f"{s['trot_window_s'][1]:.2f} s.",
    ]
    if s["error"]:
        lines += ["", f"**The run stopped early:** {s['error']}"]
    lines += [
        "", f"- worst loop gap: {s['max_loop_gap_m'] * 1e3:.4f} mm; body height "
        f"{s['body_height_m']['min'] * 1e3:.1f} .. {s['body_height_m']['max'] * 1e3:.1f} mm; "
        f"largest tilt {s['max_tilt_deg']:.1f} deg; forward {s['forward_distance_m']:.3f} m "
        f"(mean trot speed {s['mean_forward_speed_m_s']:.3f} m/s)",
        f"- balance feedback: gain {s['balance_feedback']['gain']:g}, rate "
        f"{s['balance_feedback']['rate_s']:g} s (0 = plain trot)",
        "", "| leg | motor | peak (N m) | RMS (N m) | static J^T F (N m) | dyn/static | seed static "
        "(N m) | dyn/seed static | SF | verdict | saturated | peak speed (rad/s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for leg, motors in s["legs"].items():
        for name, m in motors.items():
            lines.append(
                f"| {leg} | {name} | {m['peak_torque_Nm']:.3f} | {m['rms_torque_Nm']:.3f} | "
                f"{m['static_torque_Nm']:.3f} | {m['dynamic_to_static_ratio']:.2f}x | "
                f"{m['seed_static_torque_Nm']:.3f} | {m['dynamic_to_seed_static_ratio']:.2f}x | "
                f"{m['safety_factor']:.2f} | {m['verdict'].upper()} | "
                f"{m['saturated_fraction'] * 100:.1f} % | {m['peak_speed_rad_s']:.2f} |")
    verdict_text = ("**optimistic**: the simulated trot needs more torque than the seed's static "
                    "analysis predicts" if s["seed_static_estimate_optimistic"]
                    else "not optimistic: the simulated trot stays within it")
    lines += [
        "", f"Seed analysis peak (seed model, 1.675 kg at the foot all cycle): "
        f"{s['seed_peak_torque_Nm']:.3f} N m; simulated peak applied torque: "
        f"{s['simulated_peak_torque_Nm']:.3f} N m. The seed's static estimate was {verdict_text}.",
        "", f"Motor limit {params.motor.peak_torque_Nm:g} N m at the output, torque-speed line to "
        f"{params.motor.no_load_speed_rad_s:.2f} rad/s; 'static J^T F' uses the measured ground "
        "force on each foot; 'seed static' the seed's G(q) at the same poses."]
    return "\n".join(lines) + "\n"


def _finite(value):
    """The summary with non-finite numbers (a diverged run) as null, so the JSON stays valid."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def write_summary(summary: dict, params: Params, out_dir: Path) -> list[Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    md, js = out_dir / "summary.md", out_dir / "summary.json"
    md.write_text(markdown(summary, params))
    js.write_text(json.dumps(_finite(summary), indent=2, allow_nan=False) + "\n")
    return [md, js]
