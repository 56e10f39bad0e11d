"""Cross-sections of a triangle mesh at a height: loops, closure, the loop a garment wraps.

A plane z = const cuts a mesh in unordered segments ((K, 2, 2), xy, m); `loops` groups them into
connected chains by shared endpoints, `closed` says whether a chain closes (or nearly does: a
small hole), `loop_area` ranks loops (the garment wraps the largest), and `loop_around` picks
the loops enclosing a point (``garment.loop_point``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from cloth.bodies.base import Segments, loop_length
from cloth.errors import InputError


def loops(segments: Segments) -> list[Segments]:
    """Split unordered section segments into connected loops (by shared endpoints)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    scale = max(float(np.abs(segments).max()), 1e-9)
    keys = np.round(segments.reshape(-1, 2) / (1e-9 * scale)).astype(np.int64)
    _, ids = np.unique(keys, axis=0, return_inverse=True)
    ids = ids.reshape(-1, 2)
    n = int(ids.max()) + 1
    graph = coo_matrix((np.ones(len(ids)), (ids[:, 0], ids[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    seg_label = label[ids[:, 0]]
    return [segments[seg_label == value] for value in np.unique(seg_label)]


#: An open section chain whose two ends are closer than this share of its length is closed
#: across the gap (a small hole in the mesh at that height).
GAP_SHARE = 0.1


def closed(loop: Segments) -> bool:
    """Whether a connected chain of section segments is a closed loop, or one whose two loose
    ends lie within `GAP_SHARE` of its length of each other (a small hole)."""
    scale = max(float(np.abs(loop).max()), 1e-9)
    keys = np.round(loop.reshape(-1, 2) / (1e-9 * scale)).astype(np.int64)
    _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    ends = loop.reshape(-1, 2)[first[counts == 1]]
    if len(ends) == 0:
        return True
    return len(ends) == 2 and np.linalg.norm(ends[1] - ends[0]) <= GAP_SHARE * loop_length(loop)


def loop_area(loop: Segments) -> float:
    """Area (m2) of the convex hull of a section loop: which loop is the largest."""
    from scipy.spatial import ConvexHull

    return float(ConvexHull(loop.reshape(-1, 2)).volume)


def loop_around(loops: list[Segments], point: ArrayLike) -> list[Segments]:
    """The loops that enclose ``point`` ((2,), m) by ray casting; an error when none does."""
    px, py = np.asarray(point, dtype=np.float64)
    chosen = []
    for loop in loops:
        (x1, y1), (x2, y2) = loop[:, 0].T, loop[:, 1].T
        crosses = (y1 > py) != (y2 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = x1 + (py - y1) * (x2 - x1) / (y2 - y1)
        if np.count_nonzero(crosses & (xi > px)) % 2 == 1:
            chosen.append(loop)
    if not chosen:
        raise InputError(
            f"no cross-section loop encloses the point ({px:g}, {py:g}) m; pick a point inside "
            "the part the garment goes around",
            field="garment.loop_point",
        )
    return chosen
