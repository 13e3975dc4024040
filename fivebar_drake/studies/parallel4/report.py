"""The text of the parallel4 jobs: the analysis's report.md and report.json, with the table of
the seed's claims (each claim once per reading the text allows, "reproduced" within 5 % for
numbers), the run's summary.json, and the lines the command line prints about each."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.text import figure
from fivebar_drake.mechanisms.parallel4.params import Params
from fivebar_drake.studies.parallel4.analysis import READINGS, SEED_COND, Analysis
from fivebar_drake.studies.parallel4.plots import ANALYSIS_FIGURES
from fivebar_drake.studies.base import claims_answer

ANALYSIS_FILES = ("report.md", "report.json")          # report.json last
SIMULATION_FILES = ("summary.json",)


def _claim(id_, claim, seed_value, computed_value, unit, reading, reproduced, why="") -> dict:
    return {"id": id_, "claim": claim, "seed_value": seed_value,
            "computed_value": computed_value, "unit": unit, "reading": reading,
            "reproduced": bool(reproduced), "why": why}


def _monotone(values, increasing: bool) -> bool:
    d = np.diff(np.asarray(values, dtype=float))
    return bool(np.all(d > 0) if increasing else np.all(d < 0))


def _studies(results: dict, name: str, theta: float | None = None) -> list[dict]:
    """The computed studies of that name (and angle); none if the file has no such study."""
    return [s for s in results["workspace"]
            if s["name"] == name and (theta is None or s["theta_deg"] == theta)]


def _reading(s: dict, rows: list[dict] | None = None) -> str:
    rows = s["rows"] if rows is None else rows
    base = ", ".join(f"{k} = {v:g}" for k, v in s["base"].items())
    return (f"{s['varied']} = {[r['value'] for r in rows]} on {base} m, theta = "
            f"{s['theta_deg']:g} deg")


def _column(rows, key, index=None) -> list[float]:
    return [r[key] if index is None else r[key][index] for r in rows]


def workspace_claims(results: dict) -> list[dict]:
    """The seed's statements about Fig. 2.9-2.12, each checked on the computed cross-sections
    of the studies of those names in the parameter file."""
    out = []
    for s in _studies(results, "a_minus_b"):
        areas = _column(s["rows"], "area_m2")
        out.append(_claim("ws_a_minus_b", "Fig. 2.9: the yz workspace grows much as (a - b) "
                          "shrinks", "area falls as a - b grows", areas, "m^2", _reading(s),
                          _monotone(areas, increasing=False),
                          f"{areas[0] / areas[-1]:.2f} times the area over this range"))
    for s in _studies(results, "c_equals_d", 0.0):
        areas = _column(s["rows"], "area_m2")
        spread = (max(areas) - min(areas)) / max(areas)
        out.append(_claim("ws_c_equals_d_0deg", "Sec. 2.3: with c = d the yz workspace at 0 deg "
                          "is the same for every c", 0.0, spread, "relative spread of the areas",
                          _reading(s), spread < 1e-9))
    for s in _studies(results, "c_equals_d", 60.0):
        # the seed's values "0.02; 0.04; 1.0" as written, and with 1.0 read as 0.10
        for label, drop in (("as written", 0.1), ("1.0 read as 0.10 m", 1.0)):
            rows = [r for r in s["rows"] if r["value"] != drop]
            areas = _column(rows, "area_m2")
            shift = [abs(v) for v in _column(rows, "centroid_yz_m", 0) if not math.isnan(v)]
            out.append(_claim(
                "ws_c_equals_d_60deg", "Fig. 2.10: larger c = d moves the 60 deg workspace off "
                "y = 0 and shrinks it much", "area falls, |centroid y| grows",
                {"area_m2": areas, "centroid_abs_y_m": shift}, "m^2, m",
                f"{label}: {_reading(s, rows)}",
                _monotone(areas, False) and _monotone(shift, True),
                f"the area falls by {(1 - areas[-1] / areas[0]) * 100:.1f} %"
                + ("" if areas[-1] > 0 else f"; c = d = {rows[-1]['value']:g} m leaves no "
                   "workspace")))
    for s in _studies(results, "c_over_d"):
        areas, low = _column(s["rows"], "area_m2"), _column(s["rows"], "lowest_point_yz_m", 0)
        values = _column(s["rows"], "value")
        if 1.0 not in values:
            continue
        eq = values.index(1.0)
        ok = all(a <= areas[eq] for a in areas) and all(
            abs(y) > abs(low[eq]) for i, y in enumerate(low) if i != eq)
        out.append(_claim(
            "ws_c_over_d", "Fig. 2.11: c != d moves the lowest point off the centre, the "
            "workspace becomes asymmetric and smaller", "largest and centred at c/d = 1",
            {"area_m2": areas, "lowest_point_y_m": low}, "m^2, m", _reading(s), ok,
            f"the areas differ by at most {(1 - min(areas) / areas[eq]) * 100:.1f} %"))
    for s in _studies(results, "leg_length"):
        areas, zc = _column(s["rows"], "area_m2"), _column(s["rows"], "centroid_yz_m", 1)
        out.append(_claim(
            "ws_R", "Fig. 2.12: longer legs give a larger workspace whose centre lies lower",
            "area grows, centre falls", {"area_m2": areas, "centroid_z_m": zc}, "m^2, m",
            _reading(s) + " (R values assumed: the seed gives none)",
            _monotone(areas, True) and _monotone(zc, False)))
    return out


def claims(params: Params, results: dict) -> list[dict]:
    """Every number and statement of the seed, computed (one object per reading)."""
    mob, sing = results["mobility"], results["singularities"]
    out = [
        _claim("mobility_joint_freedoms", "Eq. 2.3: sum f_i = F + 6L = 22", 22,
               mob["joint_freedoms"], "", "the seed's joints: 4 x (P + U + U) + 2 R",
               mob["joint_freedoms"] == 22),
        _claim("mobility_F", "Grübler (eq. 2.1): the mechanism has F = 4 freedoms", 4, mob["F"],
               "", f"n = {mob['links']} links, j = {mob['joints']} joints", mob["F"] == 4),
        _claim("mobility_F", "Grübler (eq. 2.1): the mechanism has F = 4 freedoms", 4,
               results["drake_statics"]["mobility"][0], "",
               "Drake model: velocities minus the rank of the loop constraint Jacobian",
               results["drake_statics"]["mobility"] == [4]),
        _claim("loops_L", "Euler (eq. 2.2): L = 3 loops", 3, mob["L"], "",
               "L = j - n + 1 with the seed's joints", mob["L"] == 3),
        _claim("singular_theta_90", "Eq. 2.25: theta = +-90 deg is singular (det B = 0)", 0.0,
               sing["det_B_theta_90_m5"], "m^5", "det B at (0, 0, -0.3 m, 90 deg)",
               abs(sing["det_B_theta_90_m5"]) < 1e-15),
        _claim("singular_spread_2R", "Sec. 2.3: d_max must stay below 2R to avoid a "
               "singularity", 0.0, sing["det_B_spread_2R_m5"], "m^5",
               "det B with |l1 - l2| = 2R (the pair's point on its actuator line)",
               abs(sing["det_B_spread_2R_m5"]) < 1e-15),
    ]
    for theta, s in sing["type2_slope_dz_dy"].items():
        if float(theta) == 0.0:
            continue
        out.append(_claim(
            "type2_line", "Eq. 2.25, case 3: det B = 0 on z = y (d - c cos theta)/(b - a)",
            s["seed"], s["ours"], "dz/dy",
            f"slope of the det B = 0 line on the design geometry at theta = {theta} deg",
            False, "the seed's bracket y (d - c cos) - z (b - a) has the wrong sign on its y "
            "term; det B vanishes on z = y (d - c cos theta)/(a - b) (the line through the two "
            "pair circles' centres; checked numerically); both agree only where c cos = d"))
    ck = results["checks"]
    out.append(_claim(
        "fk_closed_form", "Eq. 2.14, 2.15, 2.18, 2.20 give the pose from l1..l4 (inverting eq. "
        "2.10-2.13)", 0.0, ck["fk_ik_round_trip_max"], "max |FK(IK(pose)) - pose|",
        f"{ck['poses']} random workspace poses", ck["fk_ik_round_trip_max"] < 1e-9))
    out.append(_claim(
        "eq_2_17", "Eq. 2.17: (d1^2 - d2^2)/4 = 4y(b - a) - 4z(c cos theta - d)", 0.0,
        ck["eq_2_17_as_written_residual"], "max residual / max |left side|",
        f"{ck['poses']} random workspace poses", ck["eq_2_17_as_written_residual"] < 1e-9,
        "" if ck["eq_2_17_as_written_residual"] < 1e-9 else
        f"the y term's sign slipped: 4y(a - b) - 4z(c cos theta - d) holds to "
        f"{ck['eq_2_17_derived_residual']:.1e}. Eq. 2.17 follows from the FK derivation's leg-1 "
        "offset y - b + a (eq. 2.10 has y + b - a); eq. 2.18 then divides by a - b, which undoes "
        "it: the final formula is right"))
    out.append(_claim(
        "B_fourth_column", "Eq. 2.23: row i of B is [A_iB_i, (A_iB_i x PB_i) . j]", 0.0,
        ck["seed_B_jacobian_vs_finite_differences_max"], "max |J - dq/dx|",
        "A^-1 B with the seed's B against central differences of the IK", False,
        f"the seed's cross product has the factors swapped: (r_i x A_iB_i) . j matches the "
        f"differences to {ck['jacobian_vs_finite_differences_max']:.1e}; only the sign of the "
        "theta column differs, so det B up to sign, the loci and the condition numbers are "
        "unaffected"))
    out += workspace_claims(results)
    medians = {r: [m["median"][r] for m in results["maps"] if m["a_minus_b"] > 0.05]
               for r in results["maps"][0]["median"]}
    for reading, values in medians.items():
        out.append(_claim(
            "cond_grows_with_tilt", "Fig. 2.13-2.16: the manipulator nears singularity as the "
            "platform tilts more (0, 30, 60, 80 deg)", "condition number grows", values, "",
            f"median over the workspace, {reading}", _monotone(values, True)))
    for row in results["seed_point"]:
        base, theta, _ = SEED_COND[row["id"]]
        out.append(_claim(
            row["id"], f"Sec. 2.4: condition number about {row['seed_value']:g} at (y, z) = "
            f"(0.04, -0.32) m, {base} base, {theta:g} deg", row["seed_value"],
            row["computed_value"], "", row["reading"], row["reproduced"],
            "" if row["reproduced"] else "out of reach" if math.isnan(row["computed_value"]) else
            f"{row['computed_value']:.3g} is {row['computed_value'] / row['seed_value']:.2f} "
            "times the seed's"))
    return out


def _fmt(v) -> str:
    if isinstance(v, float):
        return figure(v, "{:.4g}")
    if isinstance(v, list):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    if isinstance(v, dict):
        return "; ".join(f"{k} {_fmt(x)}" for k, x in v.items())
    return str(v)


def _condition_tables(rows: list[dict]) -> list[str]:
    """One table per condition-number claim: readings by (a - b, R), * where reproduced."""
    lines = []
    for claim, (base, theta, seed_value) in SEED_COND.items():
        mine = [r for r in rows if r["id"] == claim]
        variants = list(dict.fromkeys(r["reading"].split("; ", 1)[1] for r in mine))
        lines += ["", f"**{claim}**: the seed reads about {seed_value:g} at (y, z) = (0.04, "
                  f"-0.32) m, {base} base, theta = {theta:g} deg (* within 5 %):", "",
                  "| reading | " + " | ".join(variants) + " |",
                  "|---|" + "---|" * len(variants)]
        for reading in READINGS:
            cells = []
            for v in variants:
                r = next(r for r in mine if r["reading"] == f"{reading}; {v}")
                cells.append(f"{r['computed_value']:.4g}" + (" *" if r["reproduced"] else ""))
            lines.append(f"| {reading} | " + " | ".join(cells) + " |")
        hits = [r["reading"] for r in mine if r["reproduced"]]
        finite = [r for r in mine if not math.isnan(r["computed_value"])]
        close = min(finite, key=lambda r: abs(r["computed_value"] - seed_value), default=None)
        lines += ["", f"Reproduced by: {'; '.join(hits)}." if hits else
                  "No reading computes: the point is out of reach." if close is None else
                  f"No reading within 5 %; the closest is {close['computed_value']:.3g} "
                  f"({close['reading']})."]
    return lines


def markdown(params: Params, results: dict, seed_claims: list[dict]) -> str:
    g, ck, ds = params.geometry, results["checks"], results["drake_statics"]
    lines = [
        "# parallel4: the 4-DOF parallel manipulator after Pierrot (seed 004)", "",
        claims_answer(seed_claims, "claims"), "",
        f"- Design geometry: a = {g.a:g} m, b = {g.b:g} m (a - b = {g.e:g} m), c = {g.c:g} m, "
        f"d = {g.d:g} m, R = {g.R:g} m; pair spread |l1 - l2| in [{g.d_min_over_R:g}, "
        f"{g.d_max_over_R:g}] R.",
        "- Workspace: each leg pair reaches within that spread, on the seed's forward branch (z "
        "below the line through the pair circles' centres), |theta| < 90 deg. It is the same at "
        "every x: areas are m^2 of the yz cross-section, i.e. m^3 of workspace per metre of x "
        "travel.", "",
        "## Checks", "",
        f"- FK(IK(pose)) over {ck['poses']} random workspace poses: max error "
        f"{ck['fk_ik_round_trip_max']:.2g} (lower branch), "
        f"{ck['fk_upper_branch_round_trip_max']:.2g} (upper branch).",
        f"- J = A^-1 B against central differences of the IK: max "
        f"{ck['jacobian_vs_finite_differences_max']:.2g}; with the seed's B: "
        f"{ck['seed_B_jacobian_vs_finite_differences_max']:.2g}.",
        f"- Grübler: n = {results['mobility']['links']}, j = {results['mobility']['joints']}, "
        f"sum f = {results['mobility']['joint_freedoms']}: F = {results['mobility']['F']}, "
        f"L = {results['mobility']['L']}. Drake model: mobility {ds['mobility']}.",
        f"- Drake model (SAP ball constraints), projected static actuator forces against the "
        f"closed form J^T tau + W = 0 over {ds['poses']} poses: max relative difference "
        f"{ds['max_relative_difference']:.2g} (loop gaps {ds['max_loop_gap_m']:.1g} m).", "",
        "## Workspace (Fig. 2.9-2.12)", "",
        "| figure | theta (deg) | varied | value | area (m^2) | centroid (y, z) m | lowest point "
        "(y, z) m |", "|---|---|---|---|---|---|---|"]
    for s in results["workspace"]:
        for r in s["rows"]:
            lines.append(f"| {s['figure']} | {s['theta_deg']:g} | {s['varied']} | {r['value']:g} "
                         f"| {figure(r['area_m2'], '{:.4g}')} | {_fmt(r['centroid_yz_m'])} | "
                         f"{_fmt(r['lowest_point_yz_m'])} |")
    lines += ["", "## Condition-number maps (Fig. 2.13-2.18)", "",
              "Medians over the workspace cross-section:", "",
              "| figure | a - b (m) | theta (deg) | " + " | ".join(results["maps"][0]["median"])
              + " |", "|---|---|---|" + "---|" * len(results["maps"][0]["median"])]
    for mp in results["maps"]:
        lines.append(f"| {mp['figure']} | {mp['a_minus_b']:.3g} | {mp['theta_deg']:g} | "
                     + " | ".join(f"{v:.3g}" for v in mp["median"].values()) + " |")
    lines += ["", "## The seed's claims", "",
              "| id | claim | seed | computed | unit | reading | result |",
              "|---|---|---|---|---|---|---|"]
    for c in seed_claims:
        if c["id"] in SEED_COND:
            continue
        result = ("reproduced" if c["reproduced"] else "not reproduced") + (
            f" — {c['why']}" if c["why"] else "")
        cells = (c["id"], c["claim"], _fmt(c["seed_value"]), _fmt(c["computed_value"]),
                 c["unit"], c["reading"], result)
        lines.append("| " + " | ".join(str(v).replace("|", "\\|") for v in cells) + " |")
    lines += _condition_tables(results["seed_point"])
    lines += ["", "## Readings of the condition number", "",
              "The seed defines the condition number as sqrt(lambda_max/lambda_min) of "
              "K = J^T k J (eq. 2.27, 2.28) but mixes m and rad in x and gives no k. Equal k "
              "cancel. Readings computed: " + "; ".join(READINGS) + ".", "",
              "## Assumptions", ""]
    lines += [f"- {a}" for a in ASSUMPTIONS]
    lines += ["", "## Figures", ""] + [f"- `{f}`" for f in ANALYSIS_FIGURES]
    return "\n".join(lines) + "\n"


ASSUMPTIONS = (
    "Values the seed does not state are marked ASSUMPTION in fivebar_drake/data/parallel4.toml "
    "(a - b = 0.12 m of its 0.10-0.14, d_min = 0.55 R, d_max = 1.5 R, Fig. 2.9's d = c and "
    "angle, Fig. 2.12's R values, masses).",
    "The IK mode is the seed's (l1, l3 lead their pair); the FK branch is the seed's lower root "
    "of eq. 2.20 with cos theta >= 0 (eq. 2.15).",
    "The Drake model holds the platform's rotations about x and z with a frictionless guide "
    "(prismatic x, y, z, revolute y) instead of the U-joint metachains: the guide carries only "
    "the moments the seed's F = [f, M_y] leaves out, so the actuator statics are the seed's.",
)


def write_analysis(a: Analysis, out: Path) -> list[Path]:
    """report.md, then report.json (last)."""
    params, results = a
    seed_claims = claims(params, results)
    public = {k: v for k, v in results.items() if k not in ("workspace", "maps")}
    public["workspace"] = [{**s, "rows": [{k: v for k, v in r.items() if k != "mask"}
                                          for r in s["rows"]]} for s in results["workspace"]]
    public["maps"] = [{k: v for k, v in m.items() if k != "maps"} for m in results["maps"]]
    public["geometry"] = vars(params.geometry)
    public["seed_claims"] = seed_claims
    return [write_atomic(out / "report.md", markdown(params, results, seed_claims)),
            write_atomic(out / "report.json",
                         json.dumps(_plain(public), indent=1, allow_nan=False) + "\n")]


def _plain(value):
    """value with numpy numbers as Python ones and NaN as null (strict JSON)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.integer, np.bool_)):
        return value.item()
    if isinstance(value, (float, np.floating)):
        return None if math.isnan(value) else float(value)
    return value


def analysis_lines(a: Analysis) -> list[str]:
    """The closed forms' checks, Drake's statics, how many claims hold (per claim), and the
    reading closest to each of the seed's condition numbers."""
    results = a.results
    seed_claims = _plain(claims(*a))
    ds = results["drake_statics"]
    lines = [f"FK(IK) round trip {results['checks']['fk_ik_round_trip_max']:.1e} m; Jacobian "
             f"vs finite differences {results['checks']['jacobian_vs_finite_differences_max']:.1e}"
             f"; Grübler F = {results['mobility']['F']}",
             f"Drake projected static forces vs closed form: {ds['max_relative_difference']:.1e} "
             f"(relative, {ds['poses']} poses)",
             f"seed claims: {sum(c['reproduced'] for c in seed_claims)} of {len(seed_claims)} "
             "readings reproduced"]
    for id_ in dict.fromkeys(c["id"] for c in seed_claims if c["id"] not in SEED_COND):
        mine = [c["reproduced"] for c in seed_claims if c["id"] == id_]
        lines.append(f"  {id_}: {sum(mine)} of {len(mine)} readings reproduced")
    best = {}
    for c in seed_claims:
        if c["id"] in SEED_COND and c["computed_value"] is not None:
            err = abs(c["computed_value"] - c["seed_value"])
            if c["id"] not in best or err < best[c["id"]][0]:
                best[c["id"]] = (err, c)
    for id_, (_, c) in best.items():
        lines.append(f"  {id_}: seed {c['seed_value']:g}, closest {c['computed_value']:.3g} "
                     f"({c['reading']})")
    return lines


def write_simulation(summary: dict, out: Path) -> list[Path]:
    return [write_atomic(out / SIMULATION_FILES[0], json.dumps(summary, indent=1) + "\n")]


def simulation_lines(summary: dict, recording: Path) -> list[str]:
    """The tracking error and loop gap, Drake's statics along the run, how to open the
    recording."""
    return [f"simulated {summary['duration_s']:g} s: tracking error max "
            f"{summary['tracking_error_max_m'] * 1e3:.3g} mm, "
            f"{summary['tracking_error_max_deg']:.3g} deg; loop gap max "
            f"{summary['loop_gap_max_m']:.2g} m",
            f"Drake projected static forces vs closed form along the run: "
            f"{summary['static_drake_vs_closed_form_max_relative']:.1e} (relative)",
            f"open it with: .venv/bin/rerun '{recording}'"]
