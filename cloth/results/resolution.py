"""Where a mesh body limits a girth line's accuracy: its own vertical sampling against the
garment's rows.

A mesh samples the body at its vertices: a torso written as rings of vertices resolves nothing
between two rings, a scan nothing finer than its triangles. The error estimate
(`cloth.results.richardson`) measures the garment's grid on a fixed body surface, so it cannot
see this. `mesh_spacing` is the mesh's vertical sampling at a height: the median height span
|dz| of the mesh edges that cross or touch it (edges of no height, along a ring, left out; a
ring mesh gives its ring spacing, a scan about 0.6 x its edge length). Where it is wider than
the garment's row spacing there (`row_spacing`), the line's value holds detail the mesh does
not resolve: the body between its vertices is the fitted surface's guess (docs/validation.md,
"scan_profile"), and the aggregate stage says so.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def mesh_spacing(
    vertices: NDArray[np.float64], faces: NDArray[np.intp], heights: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The mesh's vertical sampling (m) at each of ``heights`` ((L,), m) of a mesh of
    ``vertices`` ((V, 3), m, z up) and ``faces`` ((F, 3)): (L,), NaN where no edge crosses it."""
    edges = np.unique(np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
    z = vertices[edges, 2]
    low, high = z.min(axis=1), z.max(axis=1)
    span = high - low
    tall = span > 1e-9 * max(float(np.ptp(vertices[:, 2])), 1e-12)
    out = np.full(len(heights), np.nan)
    for k, height in enumerate(np.asarray(heights, dtype=float)):
        crossing = tall & (low <= height) & (height <= high)
        if np.any(crossing):
            out[k] = float(np.median(span[crossing]))
    return out


def row_spacing(rows_z: NDArray[np.float64], heights: NDArray[np.float64]) -> NDArray[np.float64]:
    """The garment's row spacing (m) at each of ``heights`` ((L,), m): the gap between the two
    rows (mean heights ``rows_z``, (m,), bottom to top) around it, the nearest gap at an edge."""
    gaps = np.diff(rows_z)
    k = np.clip(np.searchsorted(rows_z, heights, side="right") - 1, 0, len(gaps) - 1)
    return np.abs(gaps[k])
