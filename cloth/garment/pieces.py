"""The garment of several fabrics on its grid: which fabric each spring stands for (issue 69).

A garment of bands, panels, layers and seams (`cloth.case.pieces`) stays one n x m grid; each
weft and warp spring carries a curve made of the fabrics it stands for
(`cloth.materials.composite`), evaluated for all springs at once (`cloth.materials.curveset`).

Rows and where pieces lie around are `cloth.garment.layout`'s. Between a body row and a band
row the warp spring is the two fabrics in series, split at the band's edge.

**Around.** A weft spring spans [i, i + 1] / n of the
row: the panels' and seam strips' pieces of that span in series (each piece the panel's fabric,
or the seam: the two fabrics in parallel over the allowance, or the seam strip's curve), with
any layer over a piece in parallel, weighted by the share of the row's tributary strip it
covers. A warp spring stands for the tributary width around its column: its pieces in parallel,
and along it, in series, the parts in a band, in a layer's heights or outside them.

A spring's area is its tributary width times the thickness of the fabric at its middle (its
own), and its curve the composite's tension over that thickness, so a spring of one fabric
reports that fabric's stress exactly.
"""

from __future__ import annotations

import itertools
import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from cloth.case.pieces import Pieces
from cloth.errors import InputError
from cloth.garment.grid import WARP, WEFT, Grid
from cloth.garment.layout import Layout, share_of, tributary_boundaries
from cloth.garment.state import grid_fabric
from cloth.materials.composite import parallel, scaled, series
from cloth.materials.curves import Fabric, StressStrainCurve
from cloth.materials.curveset import CurveSet

log = logging.getLogger(__name__)

#: The name of the case's own fabric among a garment's fabrics.
BODY = "body"
#: Shares (1) are rounded to this before composites are compared, so that springs of one
#: recipe share one curve.
ROUND = 12


@dataclass(frozen=True, eq=False)
class SpringMaterials:
    """The fabrics of a garment's weft and warp springs (module docstring).

    Attributes
    ----------
    curves : tuple of StressStrainCurve
        The composite curves (Pa over each spring's own thickness).
    index : (W,) int
        The curve of each weft and warp spring (W of them, in the grid's order).
    fabric : (W,) int
        The fabric at each spring's middle, an index into ``names``.
    node_fabric : (N,) int
        The fabric at each node, an index into ``names`` (a band's, else the panel's).
    names : tuple of str
        The fabrics: the case's material first, then the pieces' in order of mention.
    seams : (J,) float, 1
        Where the seams are, as shares of the rest circumference from the centre back.
    fabric_thickness : tuple of float, m
        Each fabric's thickness, like ``names``.
    split : (m - 1,) float, 1
        The share of the cell between rows j and j + 1 that row j stands for (0.5 but beside
        a band's edge): the node areas follow it (`cloth.garment.grid.node_area`).
    """

    curves: tuple[StressStrainCurve, ...]
    index: NDArray[np.intp]
    fabric: NDArray[np.int16]
    node_fabric: NDArray[np.int16]
    names: tuple[str, ...]
    seams: NDArray[np.float64]
    fabric_thickness: tuple[float, ...]
    split: NDArray[np.float64]
    #: (m,) float, 1: a band row's own skin friction (`cloth.case.pieces.Band.friction`),
    #: NaN where the case's contact friction holds.
    row_friction: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "curve_set", CurveSet(self.curves, self.index))

    @property
    def thickness(self) -> NDArray[np.float64]:
        """(W,) float, m: the thickness of each weft and warp spring's own fabric."""
        return np.asarray(self.fabric_thickness)[self.fabric]


class _Recipes:
    """Composite curves by recipe, each built once (springs of one recipe share a curve)."""

    def __init__(self) -> None:
        self.curves: list[StressStrainCurve] = []
        self.keys: dict[tuple, int] = {}

    def add(self, key: tuple, build) -> int:
        k = self.keys.get(key)
        if k is None:
            k = self.keys[key] = len(self.curves)
            self.curves.append(build())
        return k


@dataclass(frozen=True)
class _Garment:
    """What the springs' recipes are read from (module docstring)."""

    pieces: Pieces
    fabrics: Mapping[str, Fabric]  # name -> fabric as the grid sees it (weft around)

    def thickness(self, name: str) -> float:
        return self.fabrics[name].thickness

    def curve(self, name: str, family: int) -> StressStrainCurve:
        fabric = self.fabrics[name]
        return fabric.weft if family == WEFT else fabric.warp


def _around_pieces(
    pieces: Pieces, circumference: float, body: str
) -> list[tuple[float, float, tuple[tuple[str, float], ...]]]:
    """The row's pieces around, from the centre back: (start share, end share, stack), a stack
    being (material, plies) pairs in parallel: the panels' fabrics, and the seam strips
    (the two fabrics in parallel, or the seam strip's material)."""
    if not pieces.panels:
        return [(0.0, 1.0, ((body, 1.0),))]
    cuts = []
    for panel in pieces.panels:
        start = share_of(panel.from_deg)
        cuts.append((start, start + panel.share, panel.material))
    cuts.sort()
    half = 0.5 * pieces.seams.width / circumference
    out = []
    for k, (start, end, material) in enumerate(cuts):
        before = cuts[k - 1][2]
        after = cuts[(k + 1) % len(cuts)][2]
        if end - start < 2 * half:
            raise InputError(
                f"the seam allowance ({pieces.seams.allowance_mm:g} mm) leaves nothing of the "
                f"panel of {material} ({(end - start) * circumference * 1e3:.4g} mm at its "
                "narrowest row); give a smaller allowance_mm",
                field="garment.seams.allowance_mm",
            )
        seam_in = _seam_stack(pieces, before, material)
        seam_out = _seam_stack(pieces, material, after)
        if half > 0:
            out.append((start, start + half, seam_in))
        out.append((start + half, end - half, ((material, 1.0),)))
        if half > 0:
            out.append((end - half, end, seam_out))
    # laid from the centre back: shift by whole turns into [0, 1) and split at 1
    laid = []
    for start, end, stack in out:
        offset = np.floor(start)
        start, end = start - offset, end - offset
        if end > 1.0:
            laid += [(start, 1.0, stack), (0.0, end - 1.0, stack)]
        else:
            laid.append((start, end, stack))
    laid.sort(key=lambda piece: piece[0])
    return [p for p in laid if p[1] - p[0] > 1e-15]


def _seam_stack(pieces: Pieces, a: str, b: str) -> tuple[tuple[str, float], ...]:
    if pieces.seams.material is not None:
        return ((pieces.seams.material, 1.0),)
    return ((a, 1.0), (b, 1.0))


def _overlaps(
    low: float, high: float, spans: Sequence[tuple[float, float, object]]
) -> list[tuple[float, object]]:
    """The pieces of [low, high] (shares of a turn, high - low <= 1, low in [0, 1)) that each
    span covers, as (length share of [low, high], payload)."""
    out = []
    length = high - low
    for shift in (0.0, 1.0):
        for start, end, payload in spans:
            a, b = max(low, start + shift), min(high, end + shift)
            if b > a:
                out.append(((b - a) / length, payload))
    return out


def _layer_share(layer, low: float, high: float) -> float:
    """The share of [low, high] (shares of a turn) that ``layer``'s sector covers."""
    start = share_of(layer.from_deg)
    end = start + (layer.to_deg - layer.from_deg) / 360.0
    return sum(w for w, _ in _overlaps(low, high, [(start, end, None), (start - 1, end - 1, None)]))


def _stack_curve(
    garment: _Garment, stack: tuple[tuple[str, float], ...], family: int, own: float
) -> StressStrainCurve:
    """The curve of materials side by side (``stack``: (material, plies x share) pairs), over
    the thickness ``own`` (m)."""
    parts = [
        (plies * garment.thickness(name) / own, garment.curve(name, family))
        for name, plies in stack
    ]
    if len(parts) == 1:
        return scaled(parts[0][1], parts[0][0])
    return parallel(parts)


def _key(stack: tuple[tuple[str, float], ...]) -> tuple:
    return tuple((name, round(w, ROUND)) for name, w in stack if w > 0)


def spring_materials(
    grid: Grid,
    pieces: Pieces,
    fabrics: Mapping[str, Fabric],
    body: str,
    heights: NDArray[np.float64],
    zone: NDArray,
    boundary: NDArray[np.float64],
) -> tuple[SpringMaterials, NDArray[np.float64]]:
    """The springs' fabrics (module docstring) and their areas ((S,), m2) on ``grid``.

    Parameters
    ----------
    grid : Grid
        The garment's grid, built with the case's fabric (``body``) for every spring.
    pieces : Pieces
    fabrics : mapping of str to Fabric
        Every fabric by the name the case gives it (``body`` among them), as the grid sees it.
    body : str
        The case's material.
    heights : (m,) float, m
        The rows' cut heights.
    zone : (m,) int
        Each row's band (`row_zones`), -1 outside every band.
    boundary : (m + 1,) float, m
        The rows' tributary strips in rest v: row j stands for [boundary[j], boundary[j+1]].
    """
    n, m = grid.n, grid.m
    names = tuple(dict.fromkeys([body, *pieces.materials]))
    number = {name: k for k, name in enumerate(names)}
    garment = _Garment(pieces, fabrics)
    v = grid.rest_uv[::n, 1]
    width = grid.rest_length[grid.family_slices[WEFT]].reshape(m, n).sum(axis=1)
    layers_v = [
        (np.interp(lay.bottom, heights, v), np.interp(lay.top, heights, v), lay)
        for lay in pieces.layers
    ]
    recipes = _Recipes()
    thick = grid.thickness
    area = np.array(grid.area)
    weft = grid.family_slices[WEFT]
    warp = grid.family_slices[WARP]
    index = np.empty(weft.stop - weft.start + warp.stop - warp.start, dtype=np.intp)
    fabric = np.empty(index.size, dtype=np.int16)
    node_fabric = np.empty(n * m, dtype=np.int16)
    edges = np.arange(n + 1) / n
    garment_thickness = [garment.thickness(name) for name in names]

    def row_pieces(j: int):
        if zone[j] >= 0:
            band = pieces.bands[zone[j]]
            return [(0.0, 1.0, ((band.material, float(band.layers)),))]
        return _around_pieces(pieces, float(width[j]), body)

    def layer_weights(j_low: float, j_high: float) -> list[tuple[float, object]]:
        """(share of the v-strip [j_low, j_high] covered, layer) for each layer over it."""
        out = []
        for lo, hi, layer in layers_v:
            share = max(0.0, min(hi, j_high) - max(lo, j_low)) / max(j_high - j_low, 1e-300)
            if share > 0:
                out.append((share, layer))
        return out

    def assign(k, family: int, own_name: str, parts) -> None:
        """Springs ``k`` (an index or indices among the weft and warp springs) of ``family``:
        their curve, the series of ``parts`` ((rest-length share, stack) pairs) over their own
        fabric's thickness."""
        own = garment.thickness(own_name)
        key = (family, own_name, tuple((round(f, ROUND), _key(st)) for f, st in parts))
        index[k] = recipes.add(
            key,
            lambda: series([(f, _stack_curve(garment, st, family, own)) for f, st in parts]),
        )
        fabric[k] = number[own_name]

    # weft springs: row j, column i spans shares [i, i + 1] / n; a spring within one piece
    # (all but those across a seam or a layer's side) takes that piece's curve, found once
    for j in range(m):
        around = row_pieces(j)
        strip = (
            dict((id(layer), w) for w, layer in layer_weights(boundary[j], boundary[j + 1]))
            if zone[j] < 0
            else {}
        )
        laid = (
            _with_layers(around, pieces.layers)
            if strip
            else [(a, b, (st, ())) for a, b, st in around]
        )
        tributary = boundary[j + 1] - boundary[j]

        def stack_of(payload, strip=strip):
            stack, over = payload
            extra = [
                (layer.material, strip[id(layer)] * layer.layers)
                for layer in over
                if strip.get(id(layer), 0.0) > 0
            ]
            return (*stack, *extra)

        starts = np.array([a for a, _, _ in laid])
        ends = np.array([b for _, b, _ in laid])
        holder = np.searchsorted(starts, 0.5 * (edges[:-1] + edges[1:]), side="right") - 1
        pure = (starts[holder] <= edges[:-1] + 1e-12) & (edges[1:] <= ends[holder] + 1e-12)
        for piece in np.unique(holder[pure]):
            stack = stack_of(laid[piece][2])
            mine = j * n + np.flatnonzero(pure & (holder == piece))
            assign(mine, WEFT, stack[0][0], [(1.0, stack)])
        for i in np.flatnonzero(~pure):
            parts = [
                (f, stack_of(payload)) for f, payload in _overlaps(edges[i], edges[i + 1], laid)
            ]
            assign(j * n + i, WEFT, _at(around, 0.5 * (edges[i] + edges[i + 1])), parts)
        area[weft.start + j * n : weft.start + (j + 1) * n] = (
            tributary * np.asarray(garment_thickness)[fabric[j * n : (j + 1) * n]]
        )
        node_fabric[j * n : (j + 1) * n] = [number[name] for name in _at_many(around, edges[:-1])]
    # warp springs: column i between rows j and j + 1, its tributary [i - 1/2, i + 1/2] / n;
    # where both rows are one fabric there (no band's edge, no layer's edge or side, no seam)
    # the column takes that fabric's curve, found once
    offset = weft.stop - weft.start
    lows, highs = (np.arange(n) - 0.5) / n, (np.arange(n) + 0.5) / n
    for j in range(m - 1):
        cut = boundary[j + 1]  # where row j's strip meets row j + 1's
        spans = [(v[j], cut, j), (cut, v[j + 1], j + 1)]
        fast = np.zeros(n, bool)
        split = any(v[j] < x < v[j + 1] for lo, hi, _ in layers_v for x in (lo, hi))
        if zone[j] == zone[j + 1] and not split:
            below, above = row_pieces(j), row_pieces(j + 1)
            over = [] if zone[j] >= 0 else _split_layers(v[j], v[j + 1], layers_v)[0][2]
            mid = 0.5 * (lows + highs)
            found = []
            for pieces_row in (below, above):
                starts = np.array([a for a, _, _ in pieces_row])
                ends = np.array([b for _, b, _ in pieces_row])
                k = np.searchsorted(starts, mid, side="right") - 1
                inside = (starts[k] <= lows + 1e-12) & (highs <= ends[k] + 1e-12)
                found.append((k, inside, pieces_row))
            (k_b, in_b, _), (k_a, in_a, _) = found
            same = np.array([below[p][2] == above[q][2] for p, q in zip(k_b, k_a, strict=True)])
            covers = [_full_or_none(layer, lows, highs) for layer in over]
            whole = np.all([c >= 0 for c in covers], axis=0) if covers else np.ones(n, bool)
            fast = in_b & in_a & same & whole & (lows >= 0)
            cover = np.stack(covers, axis=1) if covers else np.zeros((n, 0), int)
            groups: dict[tuple, list[int]] = {}
            for i in np.flatnonzero(fast):
                groups.setdefault((int(k_b[i]), tuple(cover[i])), []).append(int(i))
            for (piece, layer_cover), columns in groups.items():
                extra = [
                    (layer.material, float(layer.layers))
                    for layer, c in zip(over, layer_cover, strict=True)
                    if c == 1
                ]
                stack = (*below[piece][2], *extra)
                mine = offset + j * n + np.asarray(columns)
                assign(mine, WARP, stack[0][0], [(1.0, stack)])
        for i in np.flatnonzero(~fast):
            low, high = lows[i], highs[i]
            if low < 0:
                low, high = low + 1.0, high + 1.0
            parts = []
            own_name = body
            for a, b, row in spans:
                if b - a <= 0:
                    continue
                around = row_pieces(row)
                pieces_v = _split_layers(a, b, layers_v) if zone[row] < 0 else [(a, b, [])]
                for pa, pb, over in pieces_v:
                    stack = [
                        (name, plies * share)
                        for share, st in _overlaps(low, high, around)
                        for name, plies in st
                    ]
                    for layer in over:
                        cover = _layer_share(layer, low, high)
                        if cover > 0:
                            stack.append((layer.material, cover * layer.layers))
                    parts.append(((pb - pa) / (v[j + 1] - v[j]), tuple(stack)))
                if a <= 0.5 * (v[j] + v[j + 1]) <= b:
                    own_name = _at(around, i / n)
            assign(offset + j * n + i, WARP, own_name, parts)
        rows_of = slice(warp.start + j * n, warp.start + (j + 1) * n)
        area[rows_of] = (
            grid.area[rows_of]
            / thick
            * np.asarray(garment_thickness)[fabric[offset + j * n : offset + (j + 1) * n]]
        )
    seams = np.array(sorted(share_of(p.from_deg) for p in pieces.panels)) if pieces.panels else None
    split = (boundary[1:-1] - v[:-1]) / np.diff(v)
    materials = SpringMaterials(
        tuple(recipes.curves),
        index,
        fabric,
        node_fabric,
        names,
        np.zeros(0) if seams is None else seams,
        tuple(garment.thickness(name) for name in names),
        split,
        np.array(
            [
                np.nan if z < 0 or pieces.bands[z].friction is None else pieces.bands[z].friction
                for z in zone
            ]
        ),
    )
    return materials, area


def _at(around, share: float) -> str:
    """The material of the row's piece at ``share``: a panel's, a seam's first, a band's."""
    share = float(np.mod(share, 1.0))
    for start, end, stack in around:
        if start <= share < end or (end == 1.0 and share >= start):
            return stack[0][0]
    return around[-1][2][0][0]


def _with_layers(around, layers) -> list[tuple[float, float, tuple]]:
    """The row's pieces around (`_around_pieces`) split at the layers' sector edges: (start,
    end, (stack, the layers whose sector covers it))."""
    sectors = []
    for layer in layers:
        start = share_of(layer.from_deg)
        end = start + (layer.to_deg - layer.from_deg) / 360.0
        sectors.append((start, end, layer))
    cuts = {0.0, 1.0}
    for a, b, _ in around:
        cuts |= {a, b}
    for a, b, _ in sectors:
        cuts |= {float(np.mod(a, 1.0)), float(np.mod(b, 1.0))}
    cuts = sorted(c for c in cuts if 0.0 <= c <= 1.0)
    out = []
    for a, b in itertools.pairwise(cuts):
        if b - a <= 1e-15:
            continue
        mid = 0.5 * (a + b)
        stack = next(st for s0, s1, st in around if s0 <= mid < s1)
        over = tuple(layer for s0, s1, layer in sectors if s0 <= mid < s1 or s0 <= mid + 1.0 < s1)
        out.append((a, b, (stack, over)))
    return out


def _at_many(around, shares: NDArray[np.float64]) -> list[str]:
    """`_at` at each of ``shares``."""
    starts = np.array([a for a, _, _ in around])
    k = np.clip(np.searchsorted(starts, np.mod(shares, 1.0), side="right") - 1, 0, None)
    return [around[q][2][0][0] for q in k]


def _full_or_none(layer, lows: NDArray, highs: NDArray) -> NDArray:
    """Per span [lows, highs] (shares of a turn, within [0, 1]): 1 where ``layer``'s sector
    covers it whole, 0 where it misses it, -1 where it covers a part."""
    start = share_of(layer.from_deg)
    end = start + (layer.to_deg - layer.from_deg) / 360.0
    out = np.zeros(lows.size, dtype=int)
    partial = np.zeros(lows.size, bool)
    for shift in (0.0, -1.0):
        a, b = start + shift, end + shift
        whole = (lows >= a - 1e-12) & (highs <= b + 1e-12)
        touch = (highs > a + 1e-12) & (lows < b - 1e-12)
        out[whole] = 1
        partial |= touch & ~whole
    out[partial & (out == 0)] = -1
    return out


def _split_layers(a: float, b: float, layers_v) -> list[tuple[float, float, list]]:
    """[a, b] in rest v split at the layers' edges: (start, end, the layers over it)."""
    cuts = sorted({a, b, *[x for lo, hi, _ in layers_v for x in (lo, hi) if a < x < b]})
    out = []
    for lo, hi in itertools.pairwise(cuts):
        mid = 0.5 * (lo + hi)
        out.append((lo, hi, [lay for l0, l1, lay in layers_v if l0 <= mid <= l1]))
    return out


def garment_grid(
    grid: Grid,
    layout: Layout,
    fabric: Fabric,
    fabrics: Mapping[str, Fabric],
    cut_heights: NDArray[np.float64],
    zone: NDArray,
) -> Grid:
    """``grid`` (of the case's ``fabric`` alone, rows cut at ``cut_heights``, m, each in its
    band ``zone``, `cloth.garment.layout.row_zones`) with the fabrics of its ``layout``'s
    bands, panels, layers and seams, ``fabrics`` by name (as ingested; each seen by the grid as
    the layout's ``around`` says)."""
    pieces = layout.pieces
    missing = [name for name in pieces.materials if name not in fabrics and name != layout.material]
    if missing:
        raise ValueError(f"the garment's fabrics {missing} are missing (fabrics=...)")
    seen = {name: grid_fabric(f, layout.around) for name, f in fabrics.items()}
    seen[layout.material] = grid_fabric(fabric, layout.around)
    rest_v = grid.rest_uv[:: grid.n, 1]
    boundary = tributary_boundaries(cut_heights, rest_v, zone, pieces, layout.bottom, layout.top)
    materials, area = spring_materials(
        grid, pieces, seen, layout.material, cut_heights, zone, boundary
    )
    log.info(
        "a garment of %d fabrics (%s), %d curves for its springs",
        len(materials.names),
        ", ".join(materials.names),
        len(materials.curves),
    )
    return with_pieces(grid, materials, area)


def with_pieces(grid: Grid, materials: SpringMaterials, area: NDArray[np.float64]) -> Grid:
    """``grid`` with its springs' fabrics (`spring_materials`) and their areas."""
    area = np.asarray(area, dtype=float)
    area.setflags(write=False)
    return replace(grid, area=area, materials=materials)


__all__ = [
    "BODY",
    "SpringMaterials",
    "garment_grid",
    "spring_materials",
    "with_pieces",
]
