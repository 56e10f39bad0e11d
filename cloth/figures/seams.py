"""Where a garment of several pieces is sewn, for the figures (issue 69): its seams and its
bands' edges, on the flat pattern and on the body (`cloth.files.pieces`).

A seam is where two panels meet: on the flat maps the line through each row's point at the
seam's share of the row's rest circumference; on the body its equilibrium position
(``seam_x``, ``seam_y``, ``seam_z`` in result.nc). A band's edge is where a row of one fabric
meets a row of another (``node_fabric``): on the maps halfway between the two rows' rest v, on
the body halfway between their positions.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr
from numpy.typing import NDArray

#: How seams and band edges are drawn (matplotlib line style).
SEAM_STYLE = {"color": "white", "lw": 1.0, "ls": "--"}
EDGE_STYLE = {"color": "white", "lw": 1.0, "ls": ":"}


def _shares(ds: xr.Dataset) -> NDArray[np.float64]:
    return np.asarray(json.loads(str(ds.attrs.get("seam_share", "[]"))), dtype=float)


def edge_rows(ds: xr.Dataset) -> list[int]:
    """The rows j whose fabric differs from row j + 1's (a band's edge between them)."""
    if "node_fabric" not in ds:
        return []
    fabric = ds["node_fabric"].values
    # a band's rows are one fabric all round; a body row may change around (panels)
    whole = np.where(np.all(fabric == fabric[:, :1], axis=1), fabric[:, 0], -1)
    return [j for j in range(len(whole) - 1) if whole[j] != whole[j + 1]]


def flat_seams(ds: xr.Dataset) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """Each seam on the flat pattern: (u (m,), v (m,)) in m, one point per row."""
    if "rest_circumference" not in ds:
        return []
    width = ds["rest_circumference"].values
    v = ds["v"].values[:, 0]
    return [(share * width, v) for share in _shares(ds)]


def flat_edges(ds: xr.Dataset) -> list[float]:
    """Each band edge on the flat pattern: its rest v, m."""
    v = ds["v"].values[:, 0]
    return [0.5 * (v[j] + v[j + 1]) for j in edge_rows(ds)]


def body_seams(ds: xr.Dataset) -> list[NDArray[np.float64]]:
    """Each seam on the body at equilibrium: (m, 3) points, m."""
    if "seam_x" not in ds:
        return []
    return [
        np.stack([ds[f"seam_{c}"].values[k] for c in "xyz"], axis=1)
        for k in range(ds.sizes["seam"])
    ]


def body_edges(ds: xr.Dataset) -> list[NDArray[np.float64]]:
    """Each band edge on the body: (n, 3) points halfway between its two rows, m."""
    points = np.stack([ds[c].values for c in "xyz"], axis=-1)  # (m, n, 3)
    return [0.5 * (points[j] + points[j + 1]) for j in edge_rows(ds)]


__all__ = [
    "EDGE_STYLE",
    "SEAM_STYLE",
    "body_edges",
    "body_seams",
    "edge_rows",
    "flat_edges",
    "flat_seams",
]
