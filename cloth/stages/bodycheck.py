"""`cloth body check`: a mesh body as the simulation sees it, in lines a person reads.

Loads the mesh as a case would (units, up axis, checks, repair), prints its size, watertightness,
bounds and girth profile, and, for the smooth contact surface (the default), fits it (or reads
it from the cache) and reports how far the mesh's vertices lie from it, in mm: what smoothing
the surface costs. ``curvature`` writes a figure of the surface's mean curvature at the mesh's
vertices (front, side, back), where a scan's noise or a coarse mesh's facets would show.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cloth.bodies.surface import FitOptions
from cloth.figures.plots import plot_body_field
from cloth.files.avatar import load_mesh
from cloth.files.surface import smooth_body


def describe(
    path: Path,
    units: str = "m",
    up: str = "z",
    repair: bool = False,
    levels: int = 10,
    surface: str = "smooth",
    options: FitOptions | None = None,
    curvature: Path | None = None,
    surface_file: Path | None = None,
) -> list[str]:
    """The check report's lines (and the curvature figure when ``curvature`` is a path); the
    smooth surface is read from ``surface_file`` when that holds it (else from the cache)."""
    smooth = surface == "smooth"
    body, _ = load_mesh(path, units=units, up=up, repair=repair, allow_holes=smooth)
    report = body.report
    low, high = body.z_range
    lo, hi = body.vertices.min(axis=0), body.vertices.max(axis=0)
    lines = [
        f"mesh: {path} ({units}, {up} up; shown in m, z up)",
        f"vertices: {report.n_vertices}  faces: {report.n_faces}",
        f"watertight: {report.watertight}  consistently wound: {report.winding_consistent}  "
        f"degenerate faces: {report.degenerate_faces}  volume: {report.volume:.6g} m3",
        f"bounds: x {lo[0]:.4f}..{hi[0]:.4f}  y {lo[1]:.4f}..{hi[1]:.4f}  "
        f"z {lo[2]:.4f}..{hi[2]:.4f} m",
        f"height: {high - low:.4f} m",
    ]
    if report.repairs:
        lines.append("repairs: " + "; ".join(report.repairs))
    if smooth:
        fitted = smooth_body(body, options or FitOptions(), surface_file)
        fit = fitted.fit
        lines += [
            f"smooth surface: sigma {fit.smoothing * 1e3:.3g} mm, grid {fit.spacing * 1e3:.3g} mm "
            f"(creases {fit.crease_spacing * 1e3:.3g} mm apart, the mesh refined "
            f"{fit.refine_levels} times"
            + (f", denoised first: {fit.denoise_move * 1e3:.3g} mm RMS" if fit.denoise_move else "")
            + f"); {fitted.record()['file']}",
            f"vertices from the smooth surface: max {fit.deviation_max * 1e3:.3g} mm, "
            f"RMS {fit.deviation_rms * 1e3:.3g} mm, mean {fit.deviation_mean * 1e3:+.3g} mm "
            "(positive: the surface lies inside the mesh)",
        ]
        if curvature is not None:
            centres = body.vertices[body.faces].mean(axis=1)
            points = np.concatenate([body.vertices, centres])
            # where the surface was fitted: all of the mesh, or a region's part (not the arms)
            points = points[fit.field.within(points)]
            feet = fitted.closest(points)
            feet = feet[fit.field.within(feet) & np.isfinite(feet).all(axis=1)]
            k1, k2 = fitted.curvature(feet)
            plot_body_field(
                feet,
                0.5 * (k1 + k2),
                "mean curvature [1/m] (positive: convex)",
                curvature,
                title=f"{path.name}: mean curvature of the smooth contact surface "
                f"(sigma {fit.smoothing * 1e3:.3g} mm)",
            )
            lines.append(f"curvature figure: {curvature}")
    else:
        lines.append("contact surface: the mesh's facets (surface: mesh)")
    lines.append("girth profile:  height [m]   section [m]   convex hull [m]")
    for z in np.linspace(low, high, levels + 2)[1:-1]:
        section, hull = body.girth(float(z))
        lines.append(f"                {z:10.4f}   {section:11.4f}   {hull:15.4f}")
    return lines
