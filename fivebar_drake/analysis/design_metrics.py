"""The leg-design metrics of one design along its gait (issue 10 part 1): force capability at the
home pose per assembly mode and along the gait, the winding temperature at the gait's RMS
torques, the hinge loads of the closed chain and the gear-ratio trade; arrays for the plots and
the JSON-ready results for the report."""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from fivebar_drake.analysis.force_capability import home_capability, max_force, support_available
from fivebar_drake.analysis.gear_ratio import GearTrade, RATIO_RANGE, gear_trade
from fivebar_drake.analysis.joint_loads import JOINT_LINKS, JOINT_NAMES, JointLoads, joint_loads
from fivebar_drake.actuators.thermal import Thermal, rms_current, thermal_margin
from fivebar_drake.mechanisms.fivebar import (ALL_MODES, DynamicsModel, GaitSamples,
                                              MODE_ALIASES, MODE_NAMES, MOTORS, TorqueBreakdown, UnreachableError,
                                              foot_jacobian, inverse)
from fivebar_drake.robots.quadruped.params import Params


PHYSICAL = ("full", "full_trot")   # the models whose loads are physical (the seed's is not)
GEAR_MODEL = "full_trot"          # the model the gear ratio is traded on: the answer's


def sample_at(samples: GaitSamples, k: int) -> dict:
    """Where sample k is in the cycle: index, time (s) and foot target (m)."""
    return {"sample": int(k), "time_s": float(samples.t[k]),
            "foot_m": [float(v) for v in samples.foot[k]]}


@dataclass(frozen=True)
class Support:
    """Vertical foot force along the gait (N,) N: needed (the model's foot load), available at
    rest (the torque box alone) and while moving (what the torques left after the motion and
    the link weights allow: force_capability.support_available)."""

    needed: np.ndarray
    at_rest: np.ndarray
    moving: np.ndarray


@dataclass(frozen=True)
class DesignMetrics:
    """Per physical model: support along the gait, winding temperature of motors A and B,
    hinge loads; the gear-ratio trade; results: report.json's entries (force_capability,
    thermal, joint_loads, gear_ratio)."""

    support: dict[str, Support]
    thermal: dict[str, Thermal]
    loads: dict[str, JointLoads]
    gear: GearTrade
    results: dict


def _least(ratio: np.ndarray, samples: GaitSamples) -> dict:
    """The smallest finite ratio over the cycle and where (None if there is none)."""
    finite = np.where(np.isfinite(ratio), ratio, np.inf)
    k = int(np.argmin(finite))
    return {"value": float(finite[k]), "at": sample_at(samples, k)} if np.isfinite(
        finite[k]) else None


def _home(params: Params) -> dict:
    g = params.gait
    foot = (g.x_center_m, g.y_home_m)
    home = home_capability(params.leg, params.motor.peak_torque_Nm, foot)
    vertical = {m: v["max_vertical_N"] for m, v in home.items() if v is not None}
    ranked = sorted(vertical, key=vertical.get, reverse=True)
    why = {}
    for mode, name in zip(ALL_MODES, MODE_NAMES):
        if home[name] is None:
            try:
                inverse(params.leg, np.asarray(foot, dtype=float), mode)
            except UnreachableError as err:
                why[name] = str(err)
    return {"home_foot_m": list(foot), "peak_torque_Nm": params.motor.peak_torque_Nm,
            "home_pose": home, "home_pose_null_why": why, "support_ranking": ranked,
            "former_mode_names": MODE_ALIASES,
            "most_support_over_next": (vertical[ranked[0]] / vertical[ranked[1]]
                                       if len(ranked) > 1 else None)}


def _thermal_results(params: Params, th: Thermal, rms: np.ndarray, current: np.ndarray) -> dict:
    m = params.motor
    return {motor: {
        "rms_torque_Nm": float(rms[j]), "continuous_torque_Nm": m.continuous_torque_Nm,
        "rms_current_A": float(current[j]), "continuous_current_A": m.rated_continuous_current_A,
        "rms_over_continuous": float(current[j] / m.rated_continuous_current_A),
        "copper_loss_W": float(th.loss_W[j]), "steady_state_C": float(th.steady_C[j]),
        "margin_K": float(th.margin_K[j]),
        "time_to_limit_s": (float(th.time_to_limit_s[j]) if np.isfinite(th.time_to_limit_s[j])
                            else None)} for j, motor in enumerate(MOTORS)}


def _load_results(samples: GaitSamples, jl: JointLoads) -> dict:
    out = {}
    size = np.linalg.norm(jl.forces, axis=-1)
    for j, joint in enumerate(JOINT_NAMES):
        k = int(np.argmax(size[:, j]))
        fx, fy = jl.forces[k, j]
        on, by = JOINT_LINKS[joint]
        out[joint] = {"peak_N": float(size[k, j]), "force_N": [float(fx), float(fy)],
                      "direction_deg": float(np.degrees(np.arctan2(fy, fx))),
                      "on_link": on, "from": by or "ground", "peak_at": sample_at(samples, k)}
    return out


def design_metrics(params: Params, samples: GaitSamples, models: dict[str, DynamicsModel],
                   tbs: dict[str, TorqueBreakdown]) -> DesignMetrics:
    """The metrics of the design along the sampled gait, for the physical models (PHYSICAL) of
    models and their torques tbs."""
    peak = params.motor.peak_torque_Nm
    jf = foot_jacobian(params.leg, samples.pose)
    at_rest = max_force(jf, peak, (0.0, 1.0))
    support, thermal, loads = {}, {}, {}
    m = params.motor
    results = {"force_capability": dict(_home(params), gait={}), "joint_loads": {},
               "thermal": {"continuous_torque_Nm": m.continuous_torque_Nm,
                           "thermal_continuous_current_A": m.thermal_continuous_current_A,
                           "winding_limit_C": m.winding_limit_C, "ambient_C": m.ambient_C,
                           "models": {}}}
    for name in PHYSICAL:
        model, tb = models[name], tbs[name]
        needed = np.broadcast_to(np.asarray(model.foot_load_N, dtype=float), samples.t.shape)
        s = Support(needed=needed, at_rest=at_rest,
                    moving=support_available(jf, peak, tb.total - tb.foot_load))
        support[name] = s
        with np.errstate(divide="ignore", invalid="ignore"):   # masked by where
            results["force_capability"]["gait"][name] = {
                "least_margin_at_rest": _least(np.where(needed > 0, s.at_rest / needed, np.inf),
                                               samples),
                "least_margin_moving": _least(np.where(needed > 0, s.moving / needed, np.inf),
                                              samples)}
        rms = np.sqrt(np.mean(tb.total**2, axis=0))
        # the current of the torque the motor delivers: the joint's and the output friction
        current = rms_current(params.motor, params.motor.delivered_torque(tb.total, samples.qd),
                              samples.qd)
        thermal[name] = thermal_margin(params.motor, current)
        results["thermal"]["models"][name] = _thermal_results(params, thermal[name], rms, current)
        loads[name] = joint_loads(params.leg, params.links, model, samples.pose, samples.qd,
                                  samples.qdd)
        results["joint_loads"][name] = _load_results(samples, loads[name])
    tb = tbs[GEAR_MODEL]
    gear = gear_trade(params.motor, tb.joint, samples.qd, samples.qdd)
    results["gear_ratio"] = {
        "model": GEAR_MODEL, "search_range": list(RATIO_RANGE), "current": m.gear_ratio,
        "safety_factor_at_current": gear.current_safety, "best": gear.best_ratio,
        "safety_factor_at_best": gear.best_safety,
        "motor_side": {"peak_torque_Nm": m.peak_torque_Nm / (m.gear_ratio * m.gear_efficiency),
                       "no_load_speed_rad_s": m.no_load_speed_rad_s * m.gear_ratio,
                       "rotor_inertia_kg_m2": m.rotor_inertia_kg_m2}}
    return DesignMetrics(support=support, thermal=thermal, loads=loads, gear=gear,
                         results=results)
