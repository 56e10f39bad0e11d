"""Figures (matplotlib, Agg backend: no display needed, safe in workers)."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import matplotlib

from cloth.bodies import MeshBody
from cloth.figures.seams import EDGE_STYLE, SEAM_STYLE, flat_edges, flat_seams
from cloth.results.landmarks import along, girth_line

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from cloth.case.judge import Judge
from cloth.io import atomic_output
from cloth.materials.curves import DIRECTIONS

log = logging.getLogger(__name__)

COLOURS = {"weft": "tab:blue", "warp": "tab:orange", "bias": "tab:green"}
#: Every figure `cloth plot` writes for a case, as ``{name}.png`` in its folder (the rule
#: ``figures`` imports this list): the flat maps, the garment in 3D before and after, the girth
#: profiles, convergence, the fabric, and the garment on the body (`cloth.figures.onbody.FIELDS`).
FIGURES = (
    "stress_weft",
    "stress_warp",
    "pressure",
    "garment_stress",
    "garment_stress_initial",
    "landmarks",
    "convergence",
    "material",
    "body_pressure",
    "body_stress_weft",
    "body_stress_warp",
)
#: Rings of a closed-form body (or the smooth torso) drawn between the garment's edges.
BODY_RINGS = 24
#: The garment in 3D shows at most this many rows and columns of nodes (every stride-th of a
#: finer grid): 18,432 dots of a 192 x 96 grid overlap at 150 dpi and took half its time.
MAX_ROWS, MAX_COLUMNS = 48, 96


#: zlib level of the PNGs written: 1 (fastest) writes files about 20 % larger than the default
#: 6 in a tenth of the time (issue 54: the figures were a third of `make run`'s job time).
PNG_COMPRESSION = 1


def save_figure(fig: plt.Figure, path: str | Path) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix, 150 dpi) atomically and close it."""
    path = Path(path)
    form = path.suffix.lstrip(".") or "png"
    options = {"pil_kwargs": {"compress_level": PNG_COMPRESSION}} if form == "png" else {}
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=form, dpi=150, **options)
    plt.close(fig)
    log.info("wrote %s", path)
    return path


def plot_material(ds: xr.Dataset, path: str | Path) -> Path:
    """Measured points and fitted piecewise-linear curves of every direction (stress in kPa)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    for direction in DIRECTIONS:
        if f"{direction}_knot_strain" not in ds:
            continue
        colour = COLOURS[direction]
        if f"{direction}_point_strain" in ds:
            ax.plot(
                100 * ds[f"{direction}_point_strain"].values,
                ds[f"{direction}_point_stress"].values / 1e3,
                ".",
                ms=2,
                alpha=0.35,
                color=colour,
                label=f"{direction} measured",
            )
        knots_x = ds[f"{direction}_knot_strain"].values
        knots_y = ds[f"{direction}_knot_stress"].values
        label = f"{direction} curve ({knots_x.size} knots)"
        if f"{direction}_fit_max_error_percent" in ds:
            label += f", max error {float(ds[f'{direction}_fit_max_error_percent']):.2g} %"
        ax.plot(100 * knots_x, knots_y / 1e3, "-o", ms=4, color=colour, label=label)
    ax.set_xlabel("strain [%]")
    ax.set_ylabel("stress [kPa]")
    ax.set_title(f"{ds.attrs.get('fabric_name', 'fabric')}: lab data and fitted curves")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=min(0.0, float(np.nanmin(ax.get_ylim()))))
    return save_figure(fig, path)


def _body_triangles(body, z_low: float, z_high: float):
    """Vertices and faces of a body for drawing (meshes as they are, closed forms sampled)."""
    if not isinstance(body, MeshBody):
        body = getattr(body, "mesh", body)  # a smooth surface fitted to a mesh: draw the mesh
    if isinstance(body, MeshBody):
        keep = np.all(
            (body.vertices[body.faces][:, :, 2] >= z_low)
            & (body.vertices[body.faces][:, :, 2] <= z_high),
            axis=1,
        )
        return body.vertices, body.faces[keep]
    heights = np.linspace(z_low, z_high, BODY_RINGS)
    rings = []
    for z in heights:
        loop = body.sections(float(z))[0][:, 0][:: max(1, len(body.sections(float(z))[0]) // 64)]
        rings.append(np.column_stack([loop, np.full(len(loop), z)]))
    k = len(rings[0])
    vertices = np.concatenate(rings)
    i = np.arange(k)
    faces = [
        np.stack([r * k + i, r * k + (i + 1) % k, (r + 1) * k + i], axis=1)
        for r in range(BODY_RINGS - 1)
    ] + [
        np.stack([r * k + (i + 1) % k, (r + 1) * k + (i + 1) % k, (r + 1) * k + i], axis=1)
        for r in range(BODY_RINGS - 1)
    ]
    return vertices, np.concatenate(faces)


def plot_garment_3d(
    x: np.ndarray,
    n: int,
    m: int,
    values: np.ndarray,
    label: str,
    path: str | Path,
    body=None,
    title: str = "",
    vmin: float | None = None,
    vmax: float | None = None,
) -> Path:
    """The garment grid in 3D, its nodes coloured by ``values`` ((m*n,) array, label with unit),
    over a translucent body."""
    from matplotlib import cm, colors

    fig = plt.figure(figsize=(6.4, 7.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    pts = x.reshape(m, n, 3)
    low, high = float(pts[..., 2].min()), float(pts[..., 2].max())
    if body is not None:
        margin = 0.08 * (high - low)
        lo, hi = body.z_range
        verts, faces = _body_triangles(body, max(lo, low - margin), min(hi, high + margin))
        if len(faces):
            ax.plot_trisurf(
                verts[:, 0],
                verts[:, 1],
                faces,
                verts[:, 2],
                color="0.85",
                alpha=0.25,
                linewidth=0,
            )
    norm = colors.Normalize(
        vmin=float(np.nanmin(values)) if vmin is None else vmin,
        vmax=float(np.nanmax(values)) if vmax is None else vmax,
    )
    # at most MAX_ROWS x MAX_COLUMNS nodes and lines are drawn: finer grids every stride-th
    rows = slice(None, None, max(1, -(-m // MAX_ROWS)))
    columns = slice(None, None, max(1, -(-n // MAX_COLUMNS)))
    shown = pts[rows][:, columns]
    closed = np.concatenate([shown, shown[:, :1]], axis=1)
    for ring in closed:
        ax.plot(*ring.T, color="0.3", lw=0.3)
    for i in range(0, n, max(1, n // 48)):
        ax.plot(*pts[:, i].T, color="0.3", lw=0.3)
    coloured = np.asarray(values).reshape(m, n)[rows][:, columns]
    ax.scatter(
        *shown.reshape(-1, 3).T,
        c=coloured.ravel(),
        cmap="viridis",
        norm=norm,
        s=4,
        depthshade=False,
    )
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, shrink=0.6, label=label)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    span = np.ptp(x, axis=0).max() / 2
    centre = (x.max(axis=0) + x.min(axis=0)) / 2
    ax.set_xlim(centre[0] - span, centre[0] + span)
    ax.set_ylim(centre[1] - span, centre[1] + span)
    ax.set_zlim(centre[2] - span, centre[2] + span)
    ax.view_init(elev=15, azim=-60)
    ax.set_title(title, fontsize=10)
    return save_figure(fig, path)


def _status(ds: xr.Dataset) -> str:
    return "" if int(ds.attrs.get("converged", 1)) else " (NOT CONVERGED)"


def judge_of(ds: xr.Dataset) -> Judge:
    """The judge of the case of result ``ds`` (its ``judge`` block); the default one for a
    file without a case (a sweep)."""
    return Judge.from_block(
        json.loads(ds.attrs["case"]).get("judge") if "case" in ds.attrs else None
    )


def class_bands(ds: xr.Dataset) -> list[tuple[str, float, float]]:
    """The compression classes (name, low, high; mmHg, the finite ones) the case of result or
    sweep ``ds`` judges its class point by (`judge_of`), where ``ds``'s girth lines include
    that point (a stocking's B); none elsewhere (a torso: the summary judges no class there, so
    the figures draw no class bands)."""
    judge = judge_of(ds)
    if judge.class_point not in [str(v) for v in ds["landmark"].values]:
        return []
    return [(name, lo, hi) for name, (lo, hi) in judge.classes.items() if np.isfinite(hi)]


def _flat_map(ds, name, path, scale=1.0, label=None, vmin=None, vmax=None, levels=None):
    from matplotlib import colors  # noqa: F401

    fig, ax = plt.subplots(figsize=(7.0, 4.4), layout="constrained")
    u, v = ds["u"].values, ds["v"].values
    values = ds[name].values * scale
    # each node's own cell ("nearest"): half the drawing time of Gouraud shading (issue 54), and
    # at 150 dpi a 192 x 96 grid's cells are 3-4 pixels wide
    mesh = ax.pcolormesh(u, v, values, shading="nearest", cmap="viridis", vmin=vmin, vmax=vmax)
    if levels is not None:
        finite = values[np.isfinite(values)]
        usable = [lv for lv in levels if finite.size and finite.min() < lv < finite.max()]
        if usable:
            lines = ax.contour(u, v, values, levels=usable, colors="white", linewidths=0.8)
            ax.clabel(lines, fmt="%g", fontsize=7)
    for seam_u, seam_v in flat_seams(ds):
        ax.plot(seam_u, seam_v, **SEAM_STYLE)
    for edge in flat_edges(ds):
        ax.axhline(edge, **EDGE_STYLE)
    var = ds[name]
    fig.colorbar(mesh, ax=ax, label=label or f"{var.attrs['long_name']} [{var.attrs['units']}]")
    ax.set_xlabel("u, around (weft) [m]")
    ax.set_ylabel("v, up (warp) [m]")
    ax.set_aspect("equal")
    ax.set_title(
        f"{ds.attrs.get('fabric_name', '')}: {var.attrs['long_name']}{_status(ds)}", fontsize=10
    )
    return save_figure(fig, path)


def plot_result(
    ds: xr.Dataset,
    folder: str | Path,
    stress_range: tuple[float, float] | None = None,
    pressure_range: tuple[float, float] | None = None,
) -> list[Path]:
    """Every figure of a result: stress maps (the paper's Figure 4), the garment in 3D (its
    Figure 3), pressure in mmHg (with the class bounds where the case judges a class), landmark
    profiles, convergence,
    material curves. Fixed colour ranges (Pa, mmHg) make runs comparable."""
    folder = Path(folder)
    s_lo, s_hi = stress_range or (None, None)
    p_lo, p_hi = pressure_range or (None, None)
    paths = [
        _flat_map(ds, "stress_weft", folder / "stress_weft.png", vmin=s_lo, vmax=s_hi),
        _flat_map(ds, "stress_warp", folder / "stress_warp.png", vmin=s_lo, vmax=s_hi),
    ]
    bounds = sorted({b for _, lo, hi in class_bands(ds) for b in (lo, hi)}) or None
    paths.append(
        _flat_map(ds, "pressure_mmHg", folder / "pressure.png", vmin=p_lo, vmax=p_hi, levels=bounds)
    )
    n, m = int(ds.attrs["n"]), int(ds.attrs["m"])
    x = np.stack([ds[c].values.ravel() for c in ("x", "y", "z")], axis=1)
    paths.append(
        plot_garment_3d(
            x,
            n,
            m,
            ds["stress_weft"].values.ravel() / 1e3,
            "weft stress [kPa]",
            folder / "garment_stress.png",
            title=f"garment on the body after relaxation{_status(ds)}",
            vmin=None if s_lo is None else s_lo / 1e3,
            vmax=None if s_hi is None else s_hi / 1e3,
        )
    )
    if "x_initial" in ds:
        start = np.stack([ds[f"{c}_initial"].values.ravel() for c in "xyz"], axis=1)
        paths.append(
            plot_garment_3d(
                start,
                n,
                m,
                ds["stress_weft_initial"].values.ravel() / 1e3,
                "weft stress [kPa]",
                folder / "garment_stress_initial.png",
                title="garment on the body before relaxation",
                vmin=None if s_lo is None else s_lo / 1e3,
                vmax=None if s_hi is None else s_hi / 1e3,
            )
        )
    fig, ax = plt.subplots(figsize=(6.4, 4.0), layout="constrained")
    angle = np.linspace(0, 360, n, endpoint=False)
    on = ds["contact"].values.astype(bool)
    for index, name in enumerate(ds["landmark"].values.tolist()):
        line = girth_line(ds["z"].values.mean(axis=1), float(ds["landmark_height"][index]))
        if line is None:  # every landmark a result holds is on its garment; kept for safety
            continue
        ax.plot(
            angle,
            along(np.where(on, ds["pressure_mmHg"].values, 0.0), line),  # what the summary took
            label=f"{name} ({float(ds['landmark_height'][index]):.3f} m)",
        )
    for name, lo, hi in class_bands(ds):
        ax.axhspan(lo, hi, alpha=0.08, color="tab:red", gid="class-band")
        ax.text(358, (lo + hi) / 2, f"class {name}", ha="right", va="center", fontsize=7)
    ax.set_xlabel("position around, from the centre back [degrees]")
    ax.set_ylabel("pressure [mmHg]")
    ax.set_title(f"pressure along the girth lines{_status(ds)}", fontsize=10)
    ax.grid(alpha=0.3)
    if len(ds["landmark"]):
        ax.legend(fontsize=8)
    paths.append(save_figure(fig, folder / "landmarks.png"))
    fig, ax = plt.subplots(figsize=(6.0, 4.0), layout="constrained")
    if "residual" in ds:
        ax.semilogy(np.arange(ds.sizes["iteration"]), ds["residual"].values, "o-", ms=3)
        tol = ds.attrs.get("solver_tolerance")
        if tol:
            ax.axhline(float(tol), color="k", lw=0.8, ls="--", label="tolerance")
            ax.legend()
    ax.set_xlabel("iteration")
    ax.set_ylabel("relative residual [1]")
    ax.set_title(f"convergence ({ds.attrs.get('solver_method', '')}){_status(ds)}", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    paths.append(save_figure(fig, folder / "convergence.png"))
    paths.append(plot_material(ds, folder / "material.png"))
    return paths + plot_skin(ds, folder)


#: The skin models' maps, drawn where the result has them (not in `FIGURES`: optional).
SKIN_FIGURES = {
    "indentation": ("indentation.png", 1e3, "indentation of the soft tissue [mm]"),
    "friction_force": ("friction.png", 1e3, "skin friction force on the node [mN]"),
}


def plot_skin(ds: xr.Dataset, folder: str | Path) -> list[Path]:
    """The maps of the skin models a result has: the tissue's indentation (mm), the friction
    force (mN); none for a rigid, frictionless body."""
    return [
        _flat_map(ds, name, Path(folder) / file, scale=scale, label=label)
        for name, (file, scale, label) in SKIN_FIGURES.items()
        if name in ds
    ]


def plot_body_field(
    points: np.ndarray, values: np.ndarray, label: str, path: str | Path, title: str = ""
) -> Path:
    """Points on a body ((P, 3), m, z up, front towards +y) coloured by ``values`` ((P,), label
    with unit), seen from the front, the side (+x) and the back, on one colour scale."""
    from matplotlib import colors

    finite = values[np.isfinite(values)]
    low, high = np.percentile(finite, [1, 99]) if finite.size else (0.0, 1.0)
    norm = (
        colors.TwoSlopeNorm(0.0, min(low, -1e-9), max(high, 1e-9))
        if low < 0 < high
        else (colors.Normalize(low, high))
    )
    fig, axes = plt.subplots(1, 3, figsize=(11, 5.2), layout="constrained", sharey=True)
    views = (("front", 0, 1, 1.0), ("side", 1, 0, 1.0), ("back", 0, 1, -1.0))
    for ax, (name, across, depth, facing) in zip(axes, views, strict=True):
        order = np.argsort(facing * points[:, depth])  # far points first, near ones on top
        shown = ax.scatter(
            facing * points[order, across] * (1 if name != "side" else -1),
            points[order, 2],
            c=values[order],
            cmap="coolwarm",
            norm=norm,
            s=3,
            linewidths=0,
        )
        ax.set_title(name)
        ax.set_aspect("equal")
        ax.set_xlabel("m")
    axes[0].set_ylabel("height z [m]")
    fig.colorbar(shown, ax=axes, shrink=0.8, label=label)
    if title:
        fig.suptitle(title)
    return save_figure(fig, path)
