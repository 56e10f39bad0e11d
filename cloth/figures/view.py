"""The interactive view of a result: one self-contained HTML file (``cloth view``).

The body (light grey, opaque: WebGL's unsorted transparency streaks) and the garment (its
grid's quads split into triangles, coloured per node) as plotly ``Mesh3d`` traces, rotatable;
the field is chosen from a menu (`FIELDS`: those the result holds); hovering a node shows its
row, column and every field with its unit. plotly.js is written into the page
(``include_plotlyjs=True``), so the file works offline and references no network address.
plotly is the optional extra ``view`` (``pip install 'cloth[view]'``).
"""

from __future__ import annotations

import html
import json
import logging
from pathlib import Path

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.figures.seams import body_edges, body_seams
from cloth.io import atomic_output

log = logging.getLogger(__name__)

#: Menu entry -> (result variable, scale to the shown unit, unit). Entries whose variable the
#: result lacks (indentation, on a rigid body) are left out.
FIELDS = {
    "pressure": ("pressure_mmHg", 1.0, "mmHg"),
    "weft stress": ("stress_weft", 1e-3, "kPa"),
    "warp stress": ("stress_warp", 1e-3, "kPa"),
    "weft strain": ("strain_weft", 100.0, "%"),
    "warp strain": ("strain_warp", 100.0, "%"),
    "indentation": ("indentation", 1e3, "mm"),
}
#: Positions are written to the page rounded to this (m): 0.01 mm.
DECIMALS = 5


def grid_triangles(m: int, n: int, closed: bool) -> NDArray[np.int64]:
    """Triangles ((2 (m - 1) n', 3)) of an m x n node grid numbered row by row, two per quad;
    n' = n for a closed tube (the last column joins the first), else n - 1."""
    cols = np.arange(n if closed else n - 1)
    rows = np.arange(m - 1)
    a = (rows[:, None] * n + cols[None, :]).ravel()
    b = (rows[:, None] * n + (cols[None, :] + 1) % n).ravel()
    c, d = a + n, b + n
    return np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)]).astype(np.int64)


def _plotly():
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise InputError(
            "the interactive view needs plotly; install the extra: pip install 'cloth[view]'",
            field="view",
        ) from None
    return go


#: The first camera's distance from the scene's centre, in units of its longest side (plotly's
#: default eye, (1.25, 1.25, 1.25), frames a unit cube from 2.17), and its rise.
EYE_DISTANCE, EYE_RISE = 1.7, 0.15


def scene_frame(points: NDArray[np.float64]) -> dict:
    """The scene's aspect and first camera that frame ``points`` ((P, 3), m) whole, whatever
    their aspect: one scale on every axis (the box's sides in proportion to the data's ranges,
    the longest 1), seen from the front (+y) at `EYE_DISTANCE` of the longest side. Plotly's
    ``aspectmode: data`` scales the box so that a tall leg's is several units high, which its
    default camera, 2 units away, crops at both ends."""
    ranges = np.ptp(points, axis=0)
    ratio = ranges / max(float(ranges.max()), 1e-12)
    return {
        "aspectmode": "manual",
        "aspectratio": {"x": float(ratio[0]), "y": float(ratio[1]), "z": float(ratio[2])},
        "camera": {
            "eye": {"x": 0.0, "y": EYE_DISTANCE, "z": EYE_RISE},
            "center": {"x": 0.0, "y": 0.0, "z": 0.0},
        },
    }


def view_figure(ds: xr.Dataset, body: tuple[NDArray, NDArray] | None = None):
    """The plotly figure of a result ``ds``: ``body`` (vertices (V, 3) m, faces (F, 3)), the
    garment coloured by the first of `FIELDS`, a menu of the others, node hover."""
    go = _plotly()
    m, n = int(ds.attrs["m"]), int(ds.attrs["n"])
    closed = bool(int(ds.attrs.get("closed", 1)))
    xyz = np.round(np.stack([ds[c].values.ravel() for c in "xyz"], axis=1), DECIMALS)
    fields = {k: v for k, v in FIELDS.items() if v[0] in ds}
    values = {k: ds[v].values.ravel() * s for k, (v, s, _) in fields.items()}
    row, col = np.divmod(np.arange(m * n), n)
    hover = "row %{customdata[0]}, column %{customdata[1]}<br>" + "<br>".join(
        f"{name}: %{{customdata[{k + 2}]:.4g}} {unit}"
        for k, (name, (_, _, unit)) in enumerate(fields.items())
    )
    custom = np.column_stack([row, col, *values.values()])
    tri = grid_triangles(m, n, closed)
    first = next(iter(fields))
    traces = []
    if body is not None:
        v, f = body
        v = np.round(v, DECIMALS)
        # the garment covers the body between its edges and lies a fraction of a millimetre off
        # it there, closer than a depth buffer separates: leave those faces out
        z = v[f][:, :, 2]
        f = f[(z.min(axis=1) < xyz[:, 2].min()) | (z.max(axis=1) > xyz[:, 2].max())]
        traces.append(
            go.Mesh3d(
                x=v[:, 0],
                y=v[:, 1],
                z=v[:, 2],
                i=f[:, 0],
                j=f[:, 1],
                k=f[:, 2],
                color="rgb(215,215,220)",
                name="body",
                hoverinfo="skip",
            )
        )
    garment = len(traces)

    def colour(name: str) -> dict:
        finite = values[name][np.isfinite(values[name])]
        low, high = np.percentile(finite, [1, 99]) if finite.size else (0.0, 1.0)
        return {
            "cmin": min(0.0, float(low)),
            "cmax": float(max(high, low + 1e-9)),
            "title": f"{name} [{fields[name][2]}]",
        }

    start = colour(first)
    traces.append(
        go.Mesh3d(
            x=xyz[:, 0],
            y=xyz[:, 1],
            z=xyz[:, 2],
            i=tri[:, 0],
            j=tri[:, 1],
            k=tri[:, 2],
            intensity=values[first],
            intensitymode="vertex",
            colorscale="Viridis",
            cmin=start["cmin"],
            cmax=start["cmax"],
            colorbar={"title": {"text": start["title"]}},
            customdata=custom,
            hovertemplate=hover + "<extra>garment</extra>",
            name="garment",
        )
    )
    buttons = []
    for name in fields:
        c = colour(name)
        buttons.append(
            {
                "label": f"{name} [{fields[name][2]}]",
                "method": "restyle",
                "args": [
                    {
                        "intensity": [values[name].tolist()],
                        "cmin": c["cmin"],
                        "cmax": c["cmax"],
                        "colorbar.title.text": c["title"],
                    },
                    [garment],
                ],
            }
        )
    seams = body_seams(ds)
    for k, line in enumerate([*seams, *body_edges(ds)]):
        traces.append(
            go.Scatter3d(
                x=line[:, 0],
                y=line[:, 1],
                z=line[:, 2],
                mode="lines",
                line={"color": "white", "width": 3, "dash": "dash"},
                name="seam" if k < len(seams) else "band edge",
                hoverinfo="name",
                showlegend=False,
            )
        )
    fig = go.Figure(traces)
    status = "" if int(ds.attrs.get("converged", 1)) else " (NOT CONVERGED)"
    fig.update_layout(
        title={
            "text": f"{ds.attrs.get('fabric_name', 'garment')}: {n} x {m} = {m * n:,} nodes{status}"
        },
        scene={
            "xaxis_title": "x [m]",
            "yaxis_title": "y [m]",
            "zaxis_title": "z [m]",
            **scene_frame(np.vstack([xyz, *([body[0]] if body is not None else [])])),
        },
        updatemenus=[
            {
                "buttons": buttons,
                "direction": "down",
                "x": 0.0,
                "y": 1.0,
                "xanchor": "left",
                "yanchor": "top",
            }
        ],
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
    )
    return fig


def write_view(ds: xr.Dataset, path: str | Path, body: tuple[NDArray, NDArray] | None = None):
    """Write the view of ``ds`` over ``body`` to ``path`` (HTML, atomically). Its head carries
    the node count and the fields as ``<meta name="cloth:nodes">`` and ``"cloth:fields"``."""
    fig = view_figure(ds, body)
    page = fig.to_html(include_plotlyjs=True, full_html=True, config={"displaylogo": False})
    fields = [k for k, v in FIELDS.items() if v[0] in ds]
    meta = (
        f'<meta name="cloth:nodes" content="{int(ds.attrs["m"]) * int(ds.attrs["n"])}">'
        f'<meta name="cloth:fields" content="{html.escape(json.dumps(fields))}">'
        f"<title>{html.escape(str(ds.attrs.get('title', 'cloth result')))}</title>"
    )
    page = page.replace("<head>", "<head>" + meta, 1)
    path = Path(path)
    with atomic_output(path) as tmp:
        tmp.write_text(page, encoding="utf-8")
    log.info("wrote %s (%.1f MB)", path, path.stat().st_size / 1e6)
    return path
