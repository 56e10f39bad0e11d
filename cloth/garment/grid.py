"""The paper's spring grid: node numbering, springs, rest lengths and areas.

Nodes: n along the weft (x, i = 0..n-1, left to right), m along the warp (y, j = 0..m-1, bottom
to top); node k = j*n + i (the paper's Figure 1).

Springs are numbered family by family, each family bottom to top, left to right:

* ``weft``: (i, j)-(i+1, j). A tube (``closed=True``) adds the seam spring (n-1, j)-(0, j) as
  the last weft spring of each row, so every row is a ring of n springs.
* ``warp``: (i, j)-(i, j+1).
* ``shear`` (optional): the two diagonals of each cell, (i, j)-(i+1, j+1) and (i+1, j)-(i, j+1).
* ``bend`` (optional): skip-one springs (i, j)-(i+2, j) and (i, j)-(i, j+2).

Rest geometry comes from a pattern: each row j has a rest width W_j (the flat width of an open
piece, or the circumference of a tube) and a rest height v_j. Weft rest length in row j is
W_j/(n-1) (open) or W_j/n (tube); warp rest length between rows j and j+1 is v_{j+1} - v_j.

Areas: A_k = thickness x tributary width, the width of fabric the spring stands for across its
direction. A weft spring in row j stands for half the warp spacing on each side of the row,
0.5 (dv_{j-1} + dv_j), with the missing side counting zero at the bottom and top edges (half
width there). A warp spring at column i stands for 0.5 (dx_j + dx_{j+1}), halved at the left and
right edges of an open piece. With these areas the weft springs crossing any vertical cut of a
uniformly stretched patch carry exactly sigma x thickness x height (the patch test).

Shear and bend springs are off by default; when on, they are linear springs of a given modulus
(Pa) with area thickness x the mean rest spacing of their cell, stabilisers whose effect on the
stresses is measured in the tests, never silently on.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.errors import InputError, require_positive
from cloth.materials.curves import Fabric, StressStrainCurve

#: Node kinds: free, held on the body's surface at its height (sliding), fixed.
FREE, SLIDING, FIXED = 0, 1, 2

FAMILIES: tuple[str, ...] = ("weft", "warp", "shear", "bend")
WEFT, WARP, SHEAR, BEND = range(4)


@dataclass(frozen=True, eq=False)
class Grid:
    """A frozen spring network: topology, rest geometry, areas and a curve per family.

    Attributes
    ----------
    n, m : int
        Nodes along the weft and along the warp.
    closed : bool
        True for a tube (seam springs join column n-1 to column 0).
    rest_uv : (n*m, 2) float, m
        Rest coordinates (u along the weft, v along the warp) of each node in the flat pattern.
    ends : (S, 2) int
        Node indices (a, b) of each spring; the spring vector is x[b] - x[a].
    rest_length : (S,) float, m
    area : (S,) float, m2
    family : (S,) int8
        Index into `FAMILIES`.
    family_slices : tuple of slice
        Contiguous spring range of each family (empty slice when absent).
    curves : tuple of (StressStrainCurve or None)
        Curve of each family, indexed like `FAMILIES`.
    thickness : float, m
    materials : SpringMaterials, optional
        The fabrics of the weft and warp springs of a garment of several
        (`cloth.garment.pieces`): each spring's own composite curve in place of the family's.
    """

    n: int
    m: int
    closed: bool
    rest_uv: NDArray[np.float64]
    ends: NDArray[np.intp]
    rest_length: NDArray[np.float64]
    area: NDArray[np.float64]
    family: NDArray[np.int8]
    family_slices: tuple[slice, ...]
    curves: tuple[StressStrainCurve | None, ...]
    thickness: float
    materials: Any = None

    @property
    def n_nodes(self) -> int:
        return self.n * self.m

    @property
    def n_springs(self) -> int:
        return int(self.ends.shape[0])

    def node(self, i: ArrayLike, j: ArrayLike) -> NDArray[np.intp]:
        """Node index k = j*n + i (i wraps around for a tube)."""
        i = np.asarray(i)
        if self.closed:
            i = np.mod(i, self.n)
        return np.asarray(j) * self.n + i

    @property
    def convex(self) -> bool:
        """Whether the network's energy is convex in the node positions: every family present
        carries no compression (`StressStrainCurve.tension_only`), so its stiffness is positive
        semi-definite at every state (`cloth.solvers.linear.SPD` backends then apply)."""
        return all(curve.tension_only for _, curve in self.segments())

    def segments(self) -> list[tuple[slice, StressStrainCurve]]:
        """(slice, curve) for every family present, in spring order; for a garment of several
        fabrics the weft and warp springs are one slice evaluated by their `CurveSet`
        (`cloth.materials.curveset`), which answers as a curve does."""
        out = [
            (sl, curve)
            for sl, curve in zip(self.family_slices, self.curves, strict=True)
            if curve is not None and sl.stop > sl.start
        ]
        if self.materials is None:
            return out
        woven = slice(0, self.family_slices[WARP].stop)
        return [(woven, self.materials.curve_set), *out[2:]]


def _checked_rows(values: ArrayLike, m: int, what: str) -> NDArray[np.float64]:
    array = np.asarray(values, dtype=np.float64)
    if array.ndim == 0:
        array = np.full(m, float(array))
    if array.shape != (m,):
        raise InputError(f"{what} must have one value per row ({m}), got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputError(f"{what} must be finite")
    return array


def build_grid(
    n: int,
    m: int,
    row_width: ArrayLike,
    row_height: ArrayLike,
    fabric: Fabric,
    *,
    closed: bool = False,
    shear_modulus: float | None = None,
    bend_modulus: float | None = None,
) -> Grid:
    """Build the spring grid of a pattern.

    Parameters
    ----------
    n, m : int
        Nodes along the weft (>= 3 for a tube, >= 2 otherwise) and along the warp (>= 2).
    row_width : float or (m,) float, m
        Rest width of each row: the flat width of an open piece, or a tube's circumference.
    row_height : (m,) float, m
        Rest warp coordinate v_j of each row, strictly increasing.
    fabric : Fabric
        Weft and warp curves and the thickness.
    closed : bool
        Add seam springs, making each row a ring (a tube).
    shear_modulus, bend_modulus : float, Pa, optional
        Add linear shear (diagonal) / bending (skip-one) springs of this modulus.

    Returns
    -------
    Grid
    """
    if n < (3 if closed else 2) or m < 2:
        raise InputError(
            f"grid {n} x {m} is too small; need at least {3 if closed else 2} x 2 nodes",
            field="grid",
        )
    width = _checked_rows(row_width, m, "row width")
    v = _checked_rows(row_height, m, "row height")
    if np.any(width <= 0):
        raise InputError("every row's rest width must be positive", field="row_width")
    if np.any(np.diff(v) <= 0):
        raise InputError("row heights must be strictly increasing", field="row_height")
    dx = width / (n if closed else n - 1)  # (m,) weft rest spacing per row
    dv = np.diff(v)  # (m-1,) warp rest spacing

    i = np.arange(n)
    j = np.arange(m)
    if closed:
        u = i[None, :] * dx[:, None]
    else:
        u = (i[None, :] - 0.5 * (n - 1)) * dx[:, None]
    rest_uv = np.stack([u.ravel(), np.repeat(v, n)], axis=1)

    def node(ii: NDArray, jj: NDArray) -> NDArray:
        return jj * n + (np.mod(ii, n) if closed else ii)

    ends, lengths, areas, families = [], [], [], []

    # weft: per row, i -> i+1 (plus the seam n-1 -> 0 for a tube)
    n_weft = n if closed else n - 1
    jw, iw = np.meshgrid(j, np.arange(n_weft), indexing="ij")
    ends.append(np.stack([node(iw, jw), node(iw + 1, jw)], axis=-1).reshape(-1, 2))
    lengths.append(np.repeat(dx, n_weft))
    below = np.concatenate(([0.0], dv))
    above = np.concatenate((dv, [0.0]))
    areas.append(np.repeat(0.5 * (below + above), n_weft) * fabric.thickness)
    families.append(np.full(m * n_weft, WEFT))

    # warp: per row j = 0..m-2, column i -> row j+1
    jv, iv = np.meshgrid(j[:-1], i, indexing="ij")
    ends.append(np.stack([node(iv, jv), node(iv, jv + 1)], axis=-1).reshape(-1, 2))
    lengths.append(np.repeat(dv, n))
    side = np.ones(n)
    if not closed:
        side[[0, -1]] = 0.5
    cell = 0.5 * (dx[:-1] + dx[1:])
    areas.append((cell[:, None] * side[None, :]).ravel() * fabric.thickness)
    families.append(np.full((m - 1) * n, WARP))

    curves: list[StressStrainCurve | None] = [fabric.weft, fabric.warp, None, None]
    if shear_modulus is not None:
        n_cells = n if closed else n - 1
        js, is_ = np.meshgrid(j[:-1], np.arange(n_cells), indexing="ij")
        a = np.stack([node(is_, js), node(is_ + 1, js + 1)], axis=-1).reshape(-1, 2)
        b = np.stack([node(is_ + 1, js), node(is_, js + 1)], axis=-1).reshape(-1, 2)
        ends.append(np.stack([a, b], axis=1).reshape(-1, 2))
        mean_dx = np.repeat(cell, n_cells)
        diagonal = np.hypot(mean_dx, np.repeat(dv, n_cells))
        lengths.append(np.repeat(diagonal, 2))
        areas.append(np.repeat(0.5 * (mean_dx + np.repeat(dv, n_cells)), 2) * fabric.thickness)
        families.append(np.full(2 * js.size, SHEAR))
        curves[SHEAR] = StressStrainCurve.linear(_modulus(shear_modulus, "shear_modulus"))
    if bend_modulus is not None:
        n_skip = n if closed else n - 2
        parts_e, parts_l, parts_a = [], [], []
        if n_skip > 0:
            jb, ib = np.meshgrid(j, np.arange(n_skip), indexing="ij")
            parts_e.append(np.stack([node(ib, jb), node(ib + 2, jb)], axis=-1).reshape(-1, 2))
            parts_l.append(np.repeat(2 * dx, n_skip))
            parts_a.append(np.repeat(0.5 * (below + above), n_skip))
        if m > 2:
            jb, ib = np.meshgrid(j[:-2], i, indexing="ij")
            parts_e.append(np.stack([node(ib, jb), node(ib, jb + 2)], axis=-1).reshape(-1, 2))
            parts_l.append(np.repeat(dv[:-1] + dv[1:], n))
            parts_a.append(np.repeat(dx[:-2], n))
        if parts_e:
            ends.extend(parts_e)
            lengths.extend(parts_l)
            areas.extend(a * fabric.thickness for a in parts_a)
            families.append(np.full(sum(p.shape[0] for p in parts_e), BEND))
            curves[BEND] = StressStrainCurve.linear(_modulus(bend_modulus, "bend_modulus"))

    family = np.concatenate(families).astype(np.int8)
    counts = np.bincount(family, minlength=len(FAMILIES))
    starts = np.concatenate(([0], np.cumsum(counts)))
    slices = tuple(slice(int(starts[f]), int(starts[f + 1])) for f in range(len(FAMILIES)))
    grid = Grid(
        n=n,
        m=m,
        closed=closed,
        rest_uv=rest_uv,
        ends=np.concatenate(ends).astype(np.intp),
        rest_length=np.concatenate(lengths),
        area=np.concatenate(areas),
        family=family,
        family_slices=slices,
        curves=tuple(curves),
        thickness=fabric.thickness,
    )
    for array in (grid.rest_uv, grid.ends, grid.rest_length, grid.area, grid.family):
        array.setflags(write=False)
    return grid


def _modulus(value: float, name: str) -> float:
    return require_positive(value, name, "stiffness in Pa")


def rectangle(
    n: int, m: int, width: float, height: float, fabric: Fabric, **options: object
) -> Grid:
    """An open rectangular piece of ``width`` x ``height`` m at rest (the paper's setting)."""
    return build_grid(n, m, width, np.linspace(0.0, height, m), fabric, **options)  # type: ignore[arg-type]


def node_area(x: NDArray[np.float64], grid: Grid) -> NDArray[np.float64]:
    """(N,) float, m2: deformed tributary area of every node.

    A quarter of each adjacent grid cell (cells are the quads (i, j), (i+1, j), (i+1, j+1),
    (i, j+1), closed around a tube); a cell's area is half the norm of the cross product of its
    diagonals (exact for planar quads). Edge rows get half cells. Beside a band's edge
    (`cloth.garment.pieces`) a cell is shared between its rows as their strips of fabric share
    it (``grid.materials.split``), not in halves.
    """
    pts = x.reshape(grid.m, grid.n, 3)
    nxt = np.roll(pts, -1, axis=1) if grid.closed else pts[:, 1:]
    here = pts if grid.closed else pts[:, :-1]
    d1 = nxt[1:] - here[:-1]  # (i, j) -> (i+1, j+1)
    d2 = here[1:] - nxt[:-1]  # (i+1, j) -> (i, j+1)
    cell = 0.5 * np.linalg.norm(np.cross(d1, d2), axis=2)  # (m-1, cells)
    area = np.zeros((grid.m, grid.n))
    cols = np.arange(cell.shape[1])
    split = getattr(grid.materials, "split", None)
    shares = (0.5, 0.5) if split is None else (split[:, None], 1.0 - split[:, None])
    for dj in (0, 1):
        part = 0.5 * shares[dj] * cell
        for di in (0, 1):
            np.add.at(area, (slice(dj, dj + grid.m - 1), (cols + di) % grid.n), part)
    return area.ravel()


def spring_thickness(grid: Grid) -> NDArray[np.float64]:
    """(S,) float, m: the thickness of each spring's own fabric (the grid's, but for the weft
    and warp springs of a garment of several fabrics, `cloth.garment.pieces`)."""
    out = np.full(grid.n_springs, grid.thickness)
    if grid.materials is not None:
        own = grid.materials.thickness
        out[: own.size] = own
    return out
