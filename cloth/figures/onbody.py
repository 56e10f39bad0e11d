"""Figures of a result on the body (matplotlib, Agg): the garment as a coloured surface over the
body, seen from the front, the side and the back, with its girth lines labelled.

The garment is drawn as the quads of its grid (every `stride` th row and column where the grid
is finer than `MAX_AROUND` x `MAX_UP` quads, each quad coloured by the mean of its corners), the
body as its triangles above and below the garment, translucent, drawn first (the garment
covers it). Faces turned away from the viewer are left out. Front is +y, the torso's front
(docs/bodies.md), side is +x.

Colour ranges are given by the caller (the same for every case of a sweep, so that figures
compare); values outside them take the colour bar's end colours.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from pathlib import Path

import matplotlib

from cloth.results.landmarks import nearest_row
from cloth.results.pressure import MMHG

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib import cm, colors
from mpl_toolkits.mplot3d import proj3d
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from numpy.typing import NDArray

from cloth.figures.drawing import body_band, garment_positions
from cloth.figures.plots import save_figure
from cloth.figures.ranges import field_range
from cloth.figures.seams import body_edges, body_seams

log = logging.getLogger(__name__)

#: Figure name -> (result variable, scale to the shown unit, colour-bar label with unit).
FIELDS = {
    "body_pressure": ("pressure_mmHg", 1.0, "pressure [mmHg]"),
    "body_stress_weft": ("stress_weft", 1e-3, "weft stress [kPa]"),
    "body_stress_warp": ("stress_warp", 1e-3, "warp stress [kPa]"),
}
#: View name -> the camera's azimuth, degrees (matplotlib: 0 looks from +x, 90 from +y).
VIEWS = {"front": 90.0, "side": 0.0, "back": -90.0}
ELEVATION = 8.0
#: At most this many quads around and up are drawn (finer grids: every stride-th line).
MAX_AROUND, MAX_UP = 96, 48
CMAP = "viridis"
#: The body's colour (RGBA): light grey, translucent.
BODY_COLOUR = (0.78, 0.78, 0.8, 0.35)
#: Space around the body in a view, m; gap between the body and a girth label, m.
FRAME_PAD, LABEL_GAP = 0.01, 0.01
#: The girth labels' size, points, and the room they take beside the body, inches (the longest,
#: "underbust 99.9 mmHg", is about 1.1 in at 7 points).
LABEL_POINTS, LABEL_ROOM_INCHES = 7, 1.15
#: The 3D box's zoom in its panel (matplotlib's default 1 leaves a wide margin).
ZOOM = 1.25
#: Height of a figure's row of views, inches; a panel's width follows the body's aspect, up to
#: `MAX_PANEL_WIDTH`.
PANEL_HEIGHT = 5.0
MAX_PANEL_WIDTH = 8.0
#: Share of a tall panel's height its zoomed box may take (`_tallness`).
TALL_FILL = 0.82
#: Share of its panel's width a view's box (the body and its girth labels' room) may take once
#: drawn (`fill_panels`); its height may take `TALL_FILL`.
WIDE_FILL = 0.95


def _quads(points: NDArray, values: NDArray, closed: bool):
    """Quads ((Q, 4, 3), m) of the grid ``points`` ((m, n, 3)) at every stride-th line, with
    their values (the mean of their corners) and outward unit normals ((Q, 3))."""
    m, n = values.shape
    rows = np.unique(np.linspace(0, m - 1, min(m, MAX_UP + 1)).round().astype(int))
    cols = np.unique(np.linspace(0, n, min(n, MAX_AROUND) + 1).round().astype(int))
    if not closed:
        cols = cols[cols < n]
        cols = np.unique(np.append(cols, n - 1))
    wrap = cols % n
    p = points[rows][:, wrap]
    v = values[rows][:, wrap]
    corners = np.stack([p[:-1, :-1], p[:-1, 1:], p[1:, 1:], p[1:, :-1]], axis=2)
    quads = corners.reshape(-1, 4, 3)
    mean = np.stack([v[:-1, :-1], v[:-1, 1:], v[1:, 1:], v[1:, :-1]], axis=2).mean(axis=2)
    normal = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    centre = quads.mean(axis=1)
    axis_point = points.reshape(-1, 3).mean(axis=0)
    outward = centre - axis_point
    outward[:, 2] = 0.0
    normal *= np.sign(np.sum(normal * outward, axis=1))[:, None]  # the grid may wind either way
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    return quads, mean.ravel(), normal


def _eye(azimuth: float) -> NDArray[np.float64]:
    """Unit vector (3,) from the body towards a camera at ``azimuth`` (degrees), level."""
    a = np.radians(azimuth)
    return np.array([np.cos(a), np.sin(a), 0.0])


def visible_quads(ds: xr.Dataset, variable: str, scale: float, azimuth: float):
    """The garment's quads ((Q, 4, 3), m) that a camera at ``azimuth`` (degrees) sees, and
    their values ((Q,): ``variable`` x ``scale``, the mean of their corners)."""
    closed = bool(int(ds.attrs.get("closed", 1)))
    quads, values, normals = _quads(garment_positions(ds), ds[variable].values * scale, closed)
    shown = normals @ _eye(azimuth) > -0.15
    return quads[shown], values[shown]


def _girth_rows(ds: xr.Dataset) -> list[tuple[str, int, int]]:
    """(landmark, its row, its index in the landmark dim) of every landmark on the garment: the
    row nearest the line, where it is drawn (its values are the summary's, taken at the line's
    height: `cloth.results.landmarks.girth_line`)."""
    heights = ds["z"].values.mean(axis=1)
    rows = []
    for index, name in enumerate(ds["landmark"].values.tolist()):
        row = nearest_row(heights, float(ds["landmark_height"][index]))
        if row is not None:
            rows.append((str(name), row, index))
    return rows


def _girth_value(ds: xr.Dataset, variable: str, scale: float, row: int, index: int) -> float:
    if variable == "pressure_mmHg" and "pressure_mean" in ds:
        return float(ds["pressure_mean"][index]) / MMHG  # the summary's girth-line mean
    return float(np.nanmean(ds[variable].values[row])) * scale


def draw_view(
    ax,
    ds: xr.Dataset,
    body: tuple[NDArray, NDArray] | None,
    variable: str,
    scale: float,
    norm: colors.Normalize,
    azimuth: float,
    unit: str = "",
    girths: bool = True,
) -> None:
    """One view of the garment (coloured by ``variable`` x ``scale`` on ``norm``) over
    ``body`` (vertices, faces; or None) on the 3D axes ``ax``, from ``azimuth`` (degrees)."""
    points = garment_positions(ds)
    eye = _eye(azimuth)
    quads, values = visible_quads(ds, variable, scale, azimuth)
    garment_colours = plt.get_cmap(CMAP)(norm(values))
    garment = Poly3DCollection(
        quads, facecolors=garment_colours, edgecolors=garment_colours, linewidths=0.2
    )
    garment.set_gid("garment")
    low, high = float(points[..., 2].min()), float(points[..., 2].max())
    ax.computed_zorder = False  # the body inside is drawn first, the garment over it
    if body is not None:
        vertices, faces = body
        tri = vertices[faces]
        z = tri[:, :, 2].mean(axis=1)
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        keep = ((z < low) | (z > high)) & (n @ eye > 0)  # the garment hides the band
        skin = Poly3DCollection(tri[keep], facecolors=BODY_COLOUR, linewidths=0, zorder=1)
        skin.set_gid("body")
        skin.set_clip_on(False)  # a zoomed tall box reaches past the axes' square (_tallness)
        skin.set_in_layout(False)  # and the layout keeps the panel, not the box, in the figure
        ax.add_collection3d(skin)
    garment.set_zorder(2)
    garment.set_clip_on(False)
    garment.set_in_layout(False)
    ax.add_collection3d(garment)
    right = _right(azimuth)
    for line in [*body_seams(ds), *body_edges(ds)]:
        facing = (line - points.reshape(-1, 3).mean(axis=0)) @ eye > 0
        seen = [np.where(facing, line[:, c], np.nan) for c in range(3)]
        ax.plot(*seen, color="white", lw=0.8, ls="--", zorder=3, clip_on=False)
    if girths:
        for name, row, index in _girth_rows(ds):
            line = points[row]
            facing = (line - line.mean(axis=0)) @ eye > 0
            seen = np.where(facing, line[:, 0], np.nan), np.where(facing, line[:, 1], np.nan)
            ax.plot(seen[0], seen[1], line[:, 2], color="black", lw=1.0, zorder=3, clip_on=False)
            tip = line[np.argmax(line @ right)]  # beside the body, on the screen's right
            value = _girth_value(ds, variable, scale, row, index)
            ax.text(
                *(tip + LABEL_GAP * right),
                f"{name} {value:.3g} {unit}",
                fontsize=LABEL_POINTS,
                zorder=4,
                ha="left",
                va="center",
                bbox={"fc": "white", "alpha": 0.75, "lw": 0, "pad": 1},
            ).set_in_layout(False)
    low_corner, high_corner = frame(framed_points(ds, body), azimuth, girths)
    for setter, lo, hi in zip(
        (ax.set_xlim, ax.set_ylim, ax.set_zlim), low_corner, high_corner, strict=True
    ):
        setter(lo, hi)
    ax.set_box_aspect(tuple(high_corner - low_corner), zoom=ZOOM * _tallness(ax))
    ax.set_proj_type("ortho")
    ax.view_init(elev=ELEVATION, azim=azimuth)
    ax.set_axis_off()
    ax.patch.set_visible(False)  # a neighbour's labels reach into this panel


def fill_panels(fig: plt.Figure, drawn: Sequence[NDArray[np.float64]]) -> None:
    """Zoom every 3D view of the laid-out ``fig`` that is not tall (`_tallness`) so that what
    it draws, ``drawn`` ((P, 3) m per 3D view, in order: the garment and the body,
    `framed_points`), fills `TALL_FILL` of its panel's height, or its box (the body and its
    girth labels' room) `WIDE_FILL` of the panel's width, whichever binds. matplotlib fits a
    box by its diagonal, so a box wider than tall (a short band of a torso, its labels' room
    beside it) was drawn in the middle half of its panel (an avatar's band read 0.48 of the
    height); and the box's own height, seen from above, is more than the body's (its depth
    tilted into view), so the body is measured, not the box (a band filled 0.68). The box is
    not drawn. The projection is orthographic, so the drawn size scales with the zoom."""
    fig.draw_without_rendering()  # the constrained layout places the panels, and settles
    fig.draw_without_rendering()  # on its second pass (as savefig does)
    views = [ax for ax in fig.axes if ax.name == "3d"]
    for ax, points in zip(views, drawn, strict=True):
        if _tallness(ax) > 1.0:  # a tall panel's box is zoomed to its height
            continue
        corners = _box_corners(ax)
        spans = tuple(corners.max(axis=0) - corners.min(axis=0))  # draw_view's box aspect
        ax.set_box_aspect(spans, zoom=1.0)
        height = drawn_share(ax, points)[0]
        width = drawn_share(ax, corners)[1]
        if height > 0 and width > 0:
            ax.set_box_aspect(spans, zoom=min(TALL_FILL / height, WIDE_FILL / width))


def _box_corners(ax) -> NDArray[np.float64]:
    """(8, 3) m: the corners of ``ax``'s 3D limits."""
    x, y, z = ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()
    return np.array([[a, b, c] for a in x for b in y for c in z])


def drawn_share(ax, points: NDArray[np.float64]) -> tuple[float, float]:
    """The shares of ``ax``'s panel (the figure's cell it was given, before a 3D axes makes
    its own box square) in height and width that ``points`` ((P, 3), m) fill as drawn."""
    x, y, _ = proj3d.proj_transform(*points.T, ax.get_proj())
    shown = ax.transData.transform(np.column_stack([x, y]))
    box = ax.get_position(original=True).transformed(ax.figure.transFigure)
    height = (shown[:, 1].max() - shown[:, 1].min()) / box.height
    width = (shown[:, 0].max() - shown[:, 0].min()) / box.width
    return float(height), float(width)


def _cell_ratio(ax) -> float:
    """Height over width of ``ax``'s panel (the figure's cell it was given)."""
    cell = ax.get_position(original=True)
    width, height = ax.figure.get_size_inches()
    return (cell.height * height) / (cell.width * width)


def _tallness(ax) -> float:
    """How much a tall panel's box is zoomed (1 for a wide panel). A 3D axes draws in a square
    of its panel's width, centred; a tall box (a leg) is zoomed to fill `TALL_FILL` of the
    panel's height instead (3D artists are not clipped to the square), the rest left for the
    view's name above it."""
    return max(1.0, TALL_FILL * _cell_ratio(ax))


def _right(azimuth: float) -> NDArray[np.float64]:
    """(3,) the screen's right, horizontal, for a camera at ``azimuth`` (degrees)."""
    a = np.radians(azimuth)
    return np.array([-np.sin(a), np.cos(a), 0.0])


def frame(
    cloud: NDArray[np.float64], azimuth: float, labels: bool = True
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The axes' limits ((3,) low and high corners, m) that frame the points ``cloud`` ((P,
    3), m) seen from ``azimuth``: both horizontal axes span the wider horizontal extent (every
    view of a figure at one scale), the vertical its own, with `FRAME_PAD` around; with
    ``labels``, `LABEL_ROOM_INCHES` more on the screen's right for the girth labels (at the
    scale a `PANEL_HEIGHT` tall panel draws the body's height at).
    The box's aspect is these spans, so a leg fills a tall panel and a torso a square one."""
    low, high = cloud.min(axis=0), cloud.max(axis=0)
    centre = 0.5 * (low + high)
    half = 0.5 * float(np.max(high[:2] - low[:2])) + FRAME_PAD
    low_corner = np.array([centre[0] - half, centre[1] - half, low[2] - FRAME_PAD])
    high_corner = np.array([centre[0] + half, centre[1] + half, high[2] + FRAME_PAD])
    if labels:
        room = LABEL_ROOM_INCHES / PANEL_HEIGHT * float(high[2] - low[2] + 2 * FRAME_PAD)
        right = _right(azimuth)
        for axis in (0, 1):
            if right[axis] > 0.5:
                high_corner[axis] += room
            elif right[axis] < -0.5:
                low_corner[axis] -= room
    return low_corner, high_corner


def framed_points(ds: xr.Dataset, body: tuple[NDArray, NDArray] | None) -> NDArray[np.float64]:
    """(P, 3) m: what every view of ``ds`` frames, the garment's nodes and the vertices of
    ``body`` (vertices, faces; or None) that its faces use."""
    points = garment_positions(ds).reshape(-1, 3)
    if body is None:
        return points
    vertices, faces = body
    return np.vstack([points, vertices[np.unique(faces)]])


def panel_aspect(ds: xr.Dataset, body: tuple[NDArray, NDArray] | None, labels: bool) -> float:
    """Width over height of the panel one view of ``ds`` over ``body`` fills both ways
    (`fill_panels`): its box (`frame`, the girth labels' room included) `WIDE_FILL` of the
    width when the body, as the front camera at `ELEVATION` sees it (its height, and its depth
    tilted into view), is `TALL_FILL` of the height: what a figure's panels are sized to."""
    points = framed_points(ds, body)
    low, high = frame(points, VIEWS["front"], labels)
    a, tilt = np.radians(VIEWS["front"]), np.radians(ELEVATION)
    up = np.array([-np.cos(a) * np.sin(tilt), -np.sin(a) * np.sin(tilt), np.cos(tilt)])
    width = float(np.max(high[:2] - low[:2]))
    height = float(np.ptp(points @ up))
    return (width / WIDE_FILL) / (height / TALL_FILL)


def _colour_bar(fig, axes, norm: colors.Normalize, label: str, values: NDArray) -> None:
    """One colour bar for ``axes``, with an arrow at each end that ``values`` pass."""
    values = values[np.isfinite(values)]
    below = bool(values.size and values.min() < norm.vmin)
    above = bool(values.size and values.max() > norm.vmax)
    extend = {(False, False): "neither", (True, False): "min", (False, True): "max"}.get(
        (below, above), "both"
    )
    fig.colorbar(
        cm.ScalarMappable(norm=norm, cmap=CMAP), ax=axes, shrink=0.75, extend=extend, label=label
    )


def body_figure(
    ds: xr.Dataset,
    name: str,
    value_range: tuple[float, float] | None = None,
    body: tuple[NDArray, NDArray] | None = None,
) -> plt.Figure:
    """Figure ``name`` (a key of `FIELDS`) of the result ``ds``: front, side and back views of
    the garment (polygons, gid "garment") on ``body`` (vertices, faces; gid "body"), in
    ``value_range`` (the field's shown unit) or its own range."""
    variable, scale, label = FIELDS[name]
    unit = label[label.index("[") + 1 : label.index("]")]
    low, high = value_range or field_range([ds], variable, scale)
    norm = colors.Normalize(low, high)
    width = float(np.clip(PANEL_HEIGHT * panel_aspect(ds, body, True), 1.6, MAX_PANEL_WIDTH))
    fig = plt.figure(figsize=(3 * width + 1.4, PANEL_HEIGHT + 0.6), layout="constrained")
    axes = [fig.add_subplot(1, 3, k + 1, projection="3d") for k in range(3)]
    for ax, (view, azimuth) in zip(axes, VIEWS.items(), strict=True):
        draw_view(ax, ds, body, variable, scale, norm, azimuth, unit)
        if _tallness(ax) > 1.0:  # at the top of a tall panel, above its zoomed box (which
            # the layout does not see: it keeps the panel in place)
            ax.set_title(view, y=0.5 + 0.5 * _cell_ratio(ax), va="top").set_in_layout(False)
        else:
            ax.set_title(view)
    _colour_bar(fig, axes, norm, label, ds[variable].values * scale)
    status = "" if int(ds.attrs.get("converged", 1)) else " (NOT CONVERGED)"
    fig.suptitle(f"{ds.attrs.get('fabric_name', '')}: {label.split(' [')[0]} on the body{status}")
    fill_panels(fig, [framed_points(ds, body)] * len(axes))
    return fig


def plot_on_body(
    ds: xr.Dataset,
    name: str,
    path: str | Path,
    value_range: tuple[float, float] | None = None,
    body: tuple[NDArray, NDArray] | None = None,
) -> Path:
    """`body_figure` written to ``path``."""
    return save_figure(body_figure(ds, name, value_range, body), path)


def plot_sweep_on_body(
    cases: Sequence[tuple[str, float, xr.Dataset]], path: str | Path, view: str = "front"
) -> Path:
    """Small multiples of a sweep: the pressure on the body (one colour range) for each body
    (rows; or material and body) and reduction (columns), from ``view``; ``cases`` is (row
    label, reduction, result)."""
    variable, scale, label = FIELDS["body_pressure"]
    bodies = sorted({body for body, _, _ in cases})
    reductions = sorted({r for _, r, _ in cases})
    low, high = field_range([ds for _, _, ds in cases], variable, scale)
    norm = colors.Normalize(low, high)
    fig = plt.figure(
        figsize=(2.6 * len(reductions) + 1.2, 3.0 * len(bodies) + 0.6), layout="constrained"
    )
    axes, drawn = [], []
    for body, reduction, ds in cases:
        k = bodies.index(body) * len(reductions) + reductions.index(reduction)
        ax = fig.add_subplot(len(bodies), len(reductions), k + 1, projection="3d")
        band = body_band(ds)
        draw_view(ax, ds, band, variable, scale, norm, VIEWS[view], girths=False)
        drawn.append(framed_points(ds, band))
        ax.set_title(f"{body}, reduction {reduction:g}", fontsize=8)
        axes.append(ax)
    every = np.concatenate([np.ravel(ds[variable].values) * scale for _, _, ds in cases])
    _colour_bar(fig, axes, norm, label, every)
    fig.suptitle(f"pressure on the body, {view} view")
    fill_panels(fig, drawn)
    return save_figure(fig, path)
