"""The seed's torque analysis (seed 000 sections 6-7): torques along one gait cycle for each
reading of the model, peaks, static vs dynamic, safety factor and the speed check."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
import numpy as np

from fivebar_drake.analysis.design_metrics import DesignMetrics, design_metrics, sample_at
from fivebar_drake.verdicts.checks import motor_checks, verdict
from fivebar_drake.mechanisms.fivebar import (DynamicsModel, GaitSamples, MODE_NAMES, MOTORS,
                                              SingularityMeasures, TorqueBreakdown, sample_gait,
                                              singularity_measures)
from fivebar_drake.robots.quadruped.leg_loads import full_model, seed_model, trot_model
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.published import compare_published


@dataclass(frozen=True)
class Analysis:
    """Everything the report shows: the sampled gait, the torques of each model (by name), the
    design metrics and the JSON-ready results."""

    params: Params
    samples: GaitSamples
    models: dict[str, DynamicsModel]
    torques: dict[str, TorqueBreakdown]
    measures: SingularityMeasures
    metrics: DesignMetrics
    results: dict


def motor_results(params: Params, samples: GaitSamples, tb: TorqueBreakdown, j: int) -> dict:
    """Peaks of motor j (0 = A, 1 = B) over the sampled cycle; magnitudes are absolute values.
    The seed's safety factor (Table 5) is the driving peak over the peak |joint torque|; the
    checks and the torque-speed margin take the motor's operating points (Motor.delivered_torque:
    the joint torque plus the output friction, at the joint speed), each sample against its own
    quadrant."""
    motor = params.motor
    total, static, speed = np.abs(tb.total[:, j]), np.abs(tb.static[:, j]), np.abs(samples.qd[:, j])
    k_peak, k_static, k_speed = (int(np.argmax(v)) for v in (total, static, speed))
    peak = float(total[k_peak])
    sf = motor.peak_torque_Nm / peak
    demand = motor.delivered_torque(tb.total[:, j], samples.qd[:, j])
    # The envelope's torque at each sample's speed in the direction of its demand (< 1 outside).
    margin = motor.torque_margins(demand, samples.qd[:, j])
    k_line = int(np.argmin(margin))
    return {
        "peak_torque_Nm": peak,
        "peak_time_s": float(samples.t[k_peak]),
        "peak_at": sample_at(samples, k_peak),
        "static_torque_Nm": float(static[k_static]),
        "static_peak_at": sample_at(samples, k_static),
        "dynamic_to_static_ratio": peak / float(static[k_static]),
        "rms_torque_Nm": float(np.sqrt(np.mean(tb.total[:, j] ** 2))),
        "peak_inertial_Nm": float(np.max(np.abs(tb.total[:, j] - tb.static[:, j]))),
        "safety_factor": sf,
        "verdict": verdict(params.checks, sf),
        "peak_speed_rad_s": float(speed[k_speed]),
        "peak_speed_at": sample_at(samples, k_speed),
        "speed_limit_rad_s": motor.no_load_speed_rad_s,
        "speed_ok": bool(speed[k_speed] <= motor.no_load_speed_rad_s),
        "peak_acceleration_rad_s2": float(np.max(np.abs(samples.qdd[:, j]))),
        "torque_speed_margin": float(margin[k_line]),
        "torque_speed_margin_at": sample_at(samples, k_line),
        "peak_motor_torque_Nm": float(np.max(np.abs(demand))),
        "checks": motor_checks(motor, params.checks, demand, samples.qd[:, j]),
    }


def seed_results(params: Params) -> dict:
    """analyze(params)'s results of the seed model on the seed's ellipse (results.seed, per
    motor) alone: the reference every simulation summary compares with."""
    samples = sample_gait(params.leg, params.gait, "seed_ellipse")
    tb = params.fivebar_leg.torques(seed_model(params), samples.pose, samples.qd, samples.qdd)
    return {motor: motor_results(params, samples, tb, j) for j, motor in enumerate(MOTORS)}


def analyze(params: Params, path: str = "seed_ellipse") -> Analysis:
    """Run the seed's analysis over one cycle of the foot path (gaits.PATHS) for the seed
    model, the full model and the full model under trot loading."""
    samples = sample_gait(params.leg, params.gait, path)
    models = {m.name: m for m in (seed_model(params), full_model(params),
                                  trot_model(params, path, samples.t))}
    tbs = {name: params.fivebar_leg.torques(m, samples.pose, samples.qd, samples.qdd)
           for name, m in models.items()}
    measures = singularity_measures(params.leg, samples.pose)
    metrics = design_metrics(params, samples, models, tbs)
    results = {
        "results": {name: {motor: motor_results(params, samples, tb, j)
                           for j, motor in enumerate(MOTORS)} for name, tb in tbs.items()},
        "models": {name: m.description for name, m in models.items()},
        "path": {
            "gait": path,
            "samples": params.gait.samples,
            "dt_s": params.gait.period_s / params.gait.samples,
            "assembly_modes_used": [MODE_NAMES[i] for i in sorted({int(i) for i in samples.mode_index})],
            "min_transmission_angle_deg": {
                j: float(np.degrees(np.min(np.minimum(a, np.pi - a))))
                for j, a in (("C", measures.angle_c), ("D", measures.angle_d),
                             ("E", measures.angle_e))},
            "max_cond_jf": float(np.max(measures.cond_jf)),
            "min_abs_det_jf_m2": float(np.min(np.abs(measures.det_jf))),
        },
        "motor": {"model": params.motor.model,
                  "peak_torque_Nm": params.motor.peak_torque_Nm,
                  "braking_peak_torque_Nm": params.motor.braking_peak_torque_Nm,
                  "no_load_speed_rad_s": params.motor.no_load_speed_rad_s,
                  "continuous_torque_Nm": params.motor.continuous_torque_Nm,
                  "continuous_current_A": params.motor.rated_continuous_current_A,
                  "reflected_inertia_kg_m2": params.motor.reflected_inertia_kg_m2,
                  "envelope": params.motor.envelope()},
        **metrics.results,
        "published": compare_published(params),
        "parameters": dataclasses.asdict(params),
    }
    return Analysis(params=params, samples=samples, models=models, torques=tbs,
                    measures=measures, metrics=metrics, results=results)
