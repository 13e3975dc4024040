"""The parallel4 analysis plots (PNG): workspace cross-sections and areas of the seed's four
studies, singularity loci, and the condition-number maps of Fig. 2.13-2.18."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

from fivebar_drake.core.files import save_figure
from fivebar_drake.mechanisms.parallel4.kinematics import type2_line_z
from fivebar_drake.mechanisms.parallel4.params import Params
from fivebar_drake.mechanisms.parallel4.statics import in_workspace, poses_yz, yz_grid
from fivebar_drake.studies.parallel4.analysis import MAP_READINGS, Analysis

ANALYSIS_FIGURES = ("workspace_sections.png", "workspace_area.png", "singularities.png",
           "condition_maps.png", "condition_maps_translational.png")


def _grid(params: Params):
    gr = params.grid
    return yz_grid(gr.half_width, gr.z_low, gr.z_high, gr.step)


def workspace_sections(params: Params, results: dict, path: Path) -> Path:
    Y, Z, _ = _grid(params)
    panels = results["workspace"]
    cols = 3
    rows = math.ceil(len(panels) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 4 * rows), squeeze=False)
    for ax, s in zip(axes.flat, panels):
        for k, r in enumerate(s["rows"]):
            if r["mask"].any():
                ax.contour(Y, Z, r["mask"].astype(float), levels=[0.5], colors=[f"C{k}"])
            ax.plot([], [], color=f"C{k}", label=f"{s['varied']} = {r['value']:g}")
        ax.set(title=f"Fig. {s['figure']}: theta = {s['theta_deg']:g} deg", xlabel="y (m)",
               ylabel="z (m)", aspect="equal")
        ax.legend(fontsize=7)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def workspace_area(results: dict, path: Path) -> Path:
    names = list(dict.fromkeys(s["name"] for s in results["workspace"]))
    fig, axes = plt.subplots(1, len(names), figsize=(4 * len(names), 3.5), squeeze=False)
    for ax, name in zip(axes.flat, names):
        for s in results["workspace"]:
            if s["name"] == name:
                ax.plot([r["value"] for r in s["rows"]], [r["area_m2"] for r in s["rows"]],
                        "o-", label=f"theta = {s['theta_deg']:g} deg")
                ax.set(title=f"Fig. {s['figure']}", xlabel=s["varied"],
                       ylabel="yz area (m^2) = m^3 per m of x")
        ax.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def singularities(params: Params, path: Path) -> Path:
    g = params.geometry
    Y, Z, _ = _grid(params)
    angles = params.stiffness.wide_theta_deg
    fig, axes = plt.subplots(1, len(angles), figsize=(4.5 * len(angles), 4.2), squeeze=False)
    y = np.linspace(-params.grid.half_width, params.grid.half_width, 2)
    for ax, deg in zip(axes.flat, angles):
        th = math.radians(deg)
        ax.contourf(Y, Z, in_workspace(g, poses_yz(Y, Z, th)).astype(float), levels=[0.5, 1.5],
                    colors=["0.85"])
        gg = g.c * math.cos(th) - g.d
        for k, (cy, cz) in enumerate(((g.e, -gg), (-g.e, gg))):
            ax.add_patch(plt.Circle((cy, cz), g.R, fill=False, color="C3",
                                    label="det A = 0 (pair at full reach)" if k == 0 else None))
        ax.plot(y, type2_line_z(g, y, th), "C0", label="det B = 0 (ours)")
        ax.plot(y, type2_line_z(g, y, th, seed=True), "C0--", label="eq. 2.25 as written")
        ax.set(title=f"theta = {deg:g} deg", xlabel="y (m)", ylabel="z (m)", aspect="equal",
               xlim=(Y.min(), Y.max()), ylim=(Z.min(), Z.max()))
        ax.legend(fontsize=7, loc="upper right")
    fig.suptitle("Singularity loci on the design geometry (grey: workspace)")
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def condition_maps(params: Params, results: dict, reading: str, path: Path) -> Path:
    Y, Z, _ = _grid(params)
    maps = results["maps"]
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5), squeeze=False)
    st = params.stiffness
    for ax, m in zip(axes.flat, maps):
        cond = m["maps"][reading]
        if np.isfinite(cond).any():
            lo, hi = np.nanmin(cond), np.nanpercentile(cond, 99)
            mesh = ax.pcolormesh(Y, Z, cond, norm=LogNorm(lo, max(hi, lo * 1.01)),
                                 shading="auto")
            fig.colorbar(mesh, ax=ax)
        ax.plot(st.point_y, st.point_z, "r+", ms=12)
        ax.set(title=f"Fig. {m['figure']}: a - b = {m['a_minus_b']:.3g} m, theta = "
               f"{m['theta_deg']:g} deg", xlabel="y (m)", ylabel="z (m)", aspect="equal")
    fig.suptitle(f"Condition number: {reading} (+: the seed's point)")
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def write_analysis(a: Analysis, out: Path) -> list[Path]:
    params, results = a
    return [workspace_sections(params, results, out / ANALYSIS_FIGURES[0]),
            workspace_area(results, out / ANALYSIS_FIGURES[1]),
            singularities(params, out / ANALYSIS_FIGURES[2]),
            condition_maps(params, results, MAP_READINGS[0], out / ANALYSIS_FIGURES[3]),
            condition_maps(params, results, MAP_READINGS[1], out / ANALYSIS_FIGURES[4])]
