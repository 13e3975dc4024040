"""Seed 004's 4-DOF parallel manipulator after Pierrot through the pipeline (catalog contract):
`analyze --mechanism parallel4` writes the report and plots, `simulate --mechanism parallel4`
moves the Drake model's platform along the configured path and records it to Rerun."""

from __future__ import annotations

import json
from pathlib import Path

from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.parameter_files import load_parameter_file
from fivebar_drake.mechanisms.parallel4.params import Params, params_from_dict
from fivebar_drake.studies.parallel4 import analysis, plots, report
from fivebar_drake.studies.parallel4.simulation import (run_summary, simulate,
                                                        write_recording)

PACKAGED = "parallel4.toml"
ANALYSIS_FILES = plots.FIGURES + report.REPORT_FILES
SIMULATION_FILES = ("run.rrd", "summary.json")


def load_params(config: str | Path | None) -> Params:
    """The validated parameters of `config` (None: the packaged file); ParameterError naming the
    file and field."""
    return load_parameter_file(config, PACKAGED, params_from_dict)


def results_of(params: Params) -> dict:
    """Every computed result of the analysis (see analysis.py)."""
    return {"checks": analysis.checks(params.geometry),
            "mobility": analysis.mobility(),
            "singularities": analysis.singularities(params.geometry),
            "drake_statics": analysis.drake_statics(params),
            "workspace": analysis.workspace_studies(params),
            "maps": analysis.condition_maps(params),
            "seed_point": analysis.seed_point_conditions(params)}


def write_analysis(params: Params, out: Path) -> tuple[list[str], list[Path]]:
    results = results_of(params)
    figures = plots.write(out, params, results)
    written = report.write(out, params, results, [f.name for f in figures])
    claims = json.loads((out / "report.json").read_text())["seed_claims"]
    ds = results["drake_statics"]
    lines = [f"FK(IK) round trip {results['checks']['fk_ik_round_trip_max']:.1e} m; Jacobian "
             f"vs finite differences {results['checks']['jacobian_vs_finite_differences_max']:.1e}"
             f"; Grübler F = {results['mobility']['F']}",
             f"Drake projected static forces vs closed form: {ds['max_relative_difference']:.1e} "
             f"(relative, {ds['poses']} poses)",
             f"seed claims: {sum(c['reproduced'] for c in claims)} of {len(claims)} readings "
             "reproduced"]
    ids = dict.fromkeys(c["id"] for c in claims if c["id"] not in analysis.SEED_COND)
    for id_ in ids:
        mine = [c["reproduced"] for c in claims if c["id"] == id_]
        lines.append(f"  {id_}: {sum(mine)} of {len(mine)} readings reproduced")
    best = {}
    for c in claims:
        if c["id"] in analysis.SEED_COND and c["computed_value"] is not None:
            err = abs(c["computed_value"] - c["seed_value"])
            if c["id"] not in best or err < best[c["id"]][0]:
                best[c["id"]] = (err, c)
    for id_, (_, c) in best.items():
        lines.append(f"  {id_}: seed {c['seed_value']:g}, closest {c['computed_value']:.3g} "
                     f"({c['reading']})")
    return lines, figures + written


def write_simulation(params: Params, out: Path, duration_s: float | None,
                     progress: bool) -> tuple[list[str], list[Path]]:
    """Simulate the path, write run.rrd and summary.json. progress: unused (runs take ~1 s)."""
    run = simulate(params, duration_s)
    summary = run_summary(run)
    recording = write_recording(out / SIMULATION_FILES[0], params, run)
    written = [recording, write_atomic(out / SIMULATION_FILES[1],
                                       json.dumps(summary, indent=1) + "\n")]
    lines = [f"simulated {summary['duration_s']:g} s: tracking error max "
             f"{summary['tracking_error_max_m'] * 1e3:.3g} mm, "
             f"{summary['tracking_error_max_deg']:.3g} deg; loop gap max "
             f"{summary['loop_gap_max_m']:.2g} m",
             f"Drake projected static forces vs closed form along the run: "
             f"{summary['static_drake_vs_closed_form_max_relative']:.1e} (relative)",
             f"open it with: .venv/bin/rerun '{recording}'"]
    return lines, written
