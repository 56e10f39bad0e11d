"""Cross-sections of a triangle mesh at a height: loops, closure, the loop a garment wraps.

A plane z = const cuts a mesh in unordered segments ((K, 2, 2), xy, m); `loops` groups them into
connected chains by shared endpoints, `closed` says whether a chain closes (or nearly does: a
small hole), `loop_area` ranks loops, `loop_around` picks the loops enclosing a point
(``garment.loop_point``), and `follow` picks, row by row, the loops of one part of the body (the
torso without the arms, one leg): those that overlap the part's hull on the row before.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.bodies.base import Segments, hull_polygon, loop_length, polygon_perimeter
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


def hull_girth(body, z: float, point: ArrayLike, side: float = 0.0) -> float:
    """What a tape measures around the part of ``body`` (anything with ``sections(z)``) that
    encloses ``point`` ((2,), m) at height ``z`` (m): the perimeter of the convex hull of that
    part's section loops (m). An arm beside the torso or the other leg is not in it. ``side``
    (+1 or -1; 0: the whole part): only the part at x * side >= 0, where the section meets the
    plane x = 0 cut off along it: one thigh where the thighs touch, as a tape passed between
    them measures it. Where no loop encloses ``point`` (the trunk where the thighs part: a
    section shaped like a horseshoe, or two loops either side of it), the tape goes around the
    loops whose convex hull holds it, else around every loop whose hull with the others'
    holds it: it passes over the gap as it passes over a concavity."""
    sections = body.sections(float(z))
    try:
        loops = loop_around(sections, point)
    except InputError:
        at = np.asarray(point, dtype=np.float64)[None]
        loops = [loop for loop in sections if inside_convex(at, hull_polygon([loop]))[0]]
        if not loops and sections and inside_convex(at, hull_polygon(sections))[0]:
            loops = list(sections)
        if not loops:
            raise
    if side == 0.0:
        return polygon_perimeter(hull_polygon(loops))
    segments = np.concatenate(loops)
    a, b = segments[:, 0], segments[:, 1]
    keep = [a[a[:, 0] * side >= 0.0], b[b[:, 0] * side >= 0.0]]
    crossing = (a[:, 0] * side >= 0.0) != (b[:, 0] * side >= 0.0)
    t = a[crossing, 0] / (a[crossing, 0] - b[crossing, 0])
    keep.append(a[crossing] + t[:, None] * (b[crossing] - a[crossing]))
    points = np.concatenate(keep)
    return polygon_perimeter(hull_polygon([np.stack([points, points], axis=1)]))


def inside_convex(points: NDArray[np.float64], hull: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether each of ``points`` ((P, 2), m) lies in the counter-clockwise convex polygon
    ``hull`` ((H, 2), m; `cloth.bodies.base.hull_polygon`), its boundary included."""
    edge = np.roll(hull, -1, axis=0) - hull
    rel = points[:, None, :] - hull[None, :, :]
    cross = edge[None, :, 0] * rel[..., 1] - edge[None, :, 1] * rel[..., 0]
    return np.all(cross >= -1e-12 * max(float(np.abs(hull).max()), 1.0), axis=1)


def overlaps(loop: Segments, hull: NDArray[np.float64]) -> bool:
    """Whether a section loop and a convex polygon ((H, 2), m) overlap: a point of either lies
    in the other's convex hull."""
    own = hull_polygon([loop])
    return bool(inside_convex(loop.reshape(-1, 2), hull).any() or inside_convex(hull, own).any())


def follow(
    sections: list[list[Segments]], start: int, first: list[Segments]
) -> list[list[Segments]]:
    """The loops of one part of the body at every row: ``first`` at row ``start``, and on each
    row above and below it the loops that overlap the hull of the part's loops on the row next
    to it, nearer the start. Rows are ``sections`` (a list of loops each), ordered by height.
    A torso's section splits into two thighs below the crotch (both overlap the hip above
    them, both are kept); an arm or a hand beside the torso never overlaps it (left out). A
    row where nothing overlaps keeps its largest loop."""
    chosen: list[list[Segments]] = [[] for _ in sections]
    chosen[start] = first
    for step in (1, -1):
        k = start + step
        while 0 <= k < len(sections):
            hull = hull_polygon(chosen[k - step])
            kept = [loop for loop in sections[k] if overlaps(loop, hull)]
            if not kept:
                kept = [max(sections[k], key=loop_area)]
            chosen[k] = kept
            k += step
    return chosen
