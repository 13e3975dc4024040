"""The ball-screw leg's analysis: the squat comparison for every lever, the seed's claims against
the numbers computed here (every reading of the seed's text), the stroke's knee range and the
Drake model's check of the static torques."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fivebar_drake.mechanisms.ballscrew_leg import (EFFICIENCY_READINGS, RATIO_READINGS, Params,
                                                     SquatStatics, StrokeRange, peak_ratio_q1,
                                                     squat_statics, stroke_range)
from fivebar_drake.studies.ballscrew_leg.model import build_model

REPRODUCED_WITHIN = 0.05        # relative: a computed value this close to the seed's reproduces it
DRAKE_CHECK_STEP_DEG = 2.0      # the Drake check's poses over the squat, this far apart
SEED_LEVERS = (0.02, 0.05, 0.07)   # the claims name these levers


@dataclass(frozen=True)
class Analysis:
    """Everything the report and the plots show."""

    params: Params
    statics: dict            # lever (m) -> SquatStatics
    strokes: dict            # lever (m) -> StrokeRange
    drake: dict              # lever (m) -> {"max_rel_screw", "max_abs_hip_Nm", "poses"}
    claims: list


def _range_text(params: Params) -> str:
    s = params.squat
    return f"q1 over {s.q1_min_deg:g} .. {s.q1_max_deg:g} deg (the parameter file's squat)"


def _reading(ratio: str, efficiency: str, params: Params) -> str:
    return (f"{ratio} / {efficiency}: {RATIO_READINGS[ratio]}; {EFFICIENCY_READINGS[efficiency]}; "
            f"{_range_text(params)}")


def seed_claims(params: Params, statics: dict) -> list[dict]:
    """report.json's seed_claims: one object per claim and reading (see the issue)."""
    missing = [s for s in SEED_LEVERS if s not in statics]
    if missing:
        return [{"id": "levers", "claim": "the seed's levers s1 = 0.02, 0.05, 0.07 m",
                 "seed_value": list(SEED_LEVERS), "computed_value": sorted(statics),
                 "unit": "m", "reading": f"the parameter file lacks {missing}",
                 "reproduced": False}]
    out = []

    def add(cid, claim, seed, computed, unit, reading, reproduced=None):
        if reproduced is None:
            reproduced = abs(computed - seed) <= REPRODUCED_WITHIN * abs(seed)
        out.append({"id": cid, "claim": claim, "seed_value": seed,
                    "computed_value": round(float(computed), 6), "unit": unit,
                    "reading": reading, "reproduced": bool(reproduced)})

    for r in RATIO_READINGS:
        for e in EFFICIENCY_READINGS:
            reading = _reading(r, e, params)
            top = {s: float(np.max(statics[s].ratio[r, e])) for s in SEED_LEVERS}
            add("ratio_max_s1_0.02", "with the lever s1 = 0.02 m the equivalent reduction ratio "
                "reaches 20:1 at most", 20.0, top[0.02], "ratio", reading)
            add("ratio_min_s1_0.02", "with the lever s1 = 0.02 m the equivalent reduction ratio "
                "is 1:1 at least", 1.0, np.min(statics[0.02].ratio[r, e]), "ratio", reading)
            add("ratio_max_s1_0.05", "with the lever s1 = 0.05 m the equivalent reduction ratio "
                "reaches 56:1", 56.0, top[0.05], "ratio", reading)
            add("ratio_s1_0.07_vs_0.05", "with s1 = 0.07 m the screw motor needs a little more "
                "torque than with 0.05 m: the ratio is a little below the 56:1 of 0.05 m",
                56.0, top[0.07], "ratio", reading + f"; reproduced when the maximum at 0.07 m is "
                f"below the maximum at 0.05 m in the same reading ({top[0.05]:.3f})",
                reproduced=top[0.07] < top[0.05])
    for e in EFFICIENCY_READINGS:
        st = statics[0.05]
        below = float(np.mean(np.abs(st.screw_motor_Nm[e]) < np.abs(st.geared_motor_Nm)))
        add("screw_motor_below_geared_s1_0.05", "with s1 = 0.05 m the screw motor needs less "
            "torque than the geared knee's motor under the same load", 1.0, below,
            "share of the squat", f"{e}: the share of the sampled squat where the screw motor's "
            f"torque is below the geared knee motor's own torque; {EFFICIENCY_READINGS[e]}; "
            + _range_text(params))
    for s in SEED_LEVERS:
        st = statics[s]
        peak = int(np.argmax(st.ratio["joint", "forward"]))
        add(f"ratio_peak_angle_odp_s1_{s:g}", "the ratio rises with q1 to a peak where the angle "
            "ODP is 90 deg and falls after", 90.0, np.degrees(st.odp_rad[peak]), "deg",
            f"angle ODP at the sampled peak (q1 = {np.degrees(st.q1[peak]):.2f} deg; every "
            "ratio and efficiency reading peaks at the same q1: they differ by constant factors); "
            + _range_text(params))
    return out


def drake_check(params: Params, lever_m: float) -> dict:
    """The bench rig's projected static torques against the closed form over the squat, every
    DRAKE_CHECK_STEP_DEG: the largest relative difference of the (lossless) screw motor torque
    and the largest hip torque difference (N*m; the closed form's hip torque is 0 here)."""
    model = build_model(params, lever_m, "bench")
    s = params.squat
    q1 = np.radians(np.arange(s.q1_min_deg, s.q1_max_deg + 1e-9, DRAKE_CHECK_STEP_DEG))
    pose = model.leg.points(q1, -2.0 * q1)
    force = (0.0, params.load.foot_force_N)
    drake = model.static_torques(model.positions(pose), force)
    closed = model.leg.static_torques(force, pose)
    screw = model.leg.screw_motor_torque(closed[:, 1], 1.0)
    return {"poses": len(q1),
            "max_rel_screw": float(np.max(np.abs(drake[:, 1] / screw - 1.0))),
            "max_abs_hip_Nm": float(np.max(np.abs(drake[:, 0] - closed[:, 0])))}


def analyze(params: Params) -> Analysis:
    """The whole analysis of the parameter file."""
    levers = params.screw.lever_lengths_m
    statics = {s: squat_statics(params, s) for s in levers}
    return Analysis(params=params, statics=statics,
                    strokes={s: stroke_range(params, s) for s in levers},
                    drake={s: drake_check(params, s) for s in levers},
                    claims=seed_claims(params, statics))


def ratio_crossings(st: SquatStatics, key, level: float = 1.0) -> list[float]:
    """Hip angles (deg) where a ratio reading crosses `level`, linearly interpolated."""
    r = st.ratio[key] - level
    i = np.flatnonzero(np.sign(r[:-1]) != np.sign(r[1:]))
    q = st.q1[i] - r[i] * (st.q1[i + 1] - st.q1[i]) / (r[i + 1] - r[i])
    return [float(v) for v in np.degrees(q)]


def lever_summary(params: Params, st: SquatStatics, stroke: StrokeRange) -> dict:
    """report.json's figures of one lever."""
    out = {"peak_q1_geometry_deg": float(np.degrees(peak_ratio_q1(params, st.lever_m)))}
    for (r, e), ratio in st.ratio.items():
        i, j = int(np.argmax(ratio)), int(np.argmin(ratio))
        out[f"ratio_{r}_{e}"] = {
            "max": float(ratio[i]), "max_at_q1_deg": float(np.degrees(st.q1[i])),
            "min": float(ratio[j]), "min_at_q1_deg": float(np.degrees(st.q1[j])),
            "crosses_1_at_q1_deg": ratio_crossings(st, (r, e))}
    out["peak_geared_motor_Nm"] = float(np.max(np.abs(st.geared_motor_Nm)))
    out["peak_screw_motor_Nm"] = {e: float(np.max(np.abs(v))) for e, v in
                                  st.screw_motor_Nm.items()}
    out["peak_screw_force_N"] = float(np.max(np.abs(st.screw_force_N)))
    out["stroke"] = {"screw_length_m": list(stroke.screw_m),
                     "knee_bend_deg": [float(np.degrees(b)) for b in stroke.bend_rad],
                     "q1_deg": [float(np.degrees(q)) for q in stroke.q1_rad],
                     "needed_for_squat_m": stroke.needed_stroke_m}
    return out
