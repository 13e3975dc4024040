"""Study of seed 001: the serial two-link leg with a ball-screw knee against the geared knee
(`fivebar-drake analyze|simulate --mechanism ballscrew_leg`), the contract of catalog.py."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fivebar_drake.mechanisms.ballscrew_leg import Params, load_params
from fivebar_drake.studies.ballscrew_leg.analysis import analyze
from fivebar_drake.studies.ballscrew_leg.plots import PLOT_FILES, write_plots
from fivebar_drake.studies.ballscrew_leg.report import REPORT_FILES, write_report
from fivebar_drake.studies.ballscrew_leg.simulation import SIMULATION_FILES, write_simulation

ANALYSIS_FILES = PLOT_FILES + REPORT_FILES      # report.json last

__all__ = ["ANALYSIS_FILES", "SIMULATION_FILES", "load_params", "write_analysis",
           "write_simulation"]


def write_analysis(params: Params, out: Path) -> tuple[list[str], list[Path]]:
    """The analysis's plots and report in out; the headline lines for the console."""
    a = analyze(params)
    written = write_plots(a, out) + write_report(a, out)
    lines = []
    for s, st in a.statics.items():
        r = st.ratio["joint", "forward"]
        i = int(np.argmax(r))
        lines.append(f"s1 = {s * 1e3:g} mm: equivalent ratio max {r[i]:.2f} at q1 = "
                     f"{np.degrees(st.q1[i]):.2f} deg, min {np.min(r):.3f} (forward efficiency); "
                     f"Drake check {a.drake[s]['max_rel_screw']:.1e}")
    held = sum(c["reproduced"] for c in a.claims)
    lines.append(f"seed claims: {held} of {len(a.claims)} readings reproduced (report.md)")
    return lines, written
