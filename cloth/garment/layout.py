"""Where a garment's pieces lie on its pattern (issue 69; `cloth.case.pieces`): which rows are a
band's, the share of the circumference an angle falls at, and each row's strip of fabric.

**Rows and bands.** A row belongs to a band when its cut height lies within the band; a band
that would hold no row at a coarse grid has the nearest interior row moved to its middle
(`band_heights`), so every band holds a row at every grid. A band's rows are cut with its own
reduction (`band_circumference`). Between a body row and a band row the boundary of their
tributary strips is the band's edge (mapped to the rest coordinate v), not their midpoint
(`tributary_boundaries`), so a band's rows stand for exactly its width of fabric.

**Around.** A point of a row at rest coordinate u is at the share s = u / W of its rest
circumference W from the centre back (where the wrap starts, `cloth.garment.predeform`); its
angle from the centre front is 360 s - 180 degrees (`share_of`).

`Layout` is what a grid of several fabrics is rebuilt from (the continuation's coarse levels,
`cloth.solvers.continuation`): the pieces, the case's material, the grid's direction around and
the garment's edges, copied from the case by predeform as the skin models are.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.case.pieces import Pieces
from cloth.errors import InputError


@dataclass(frozen=True)
class Layout:
    """A garment's pieces and what places them: the case's ``material`` (the body fabric's
    name), the fabric direction ``around`` the body, and the garment's ``bottom`` and ``top``
    (m, cut frame)."""

    pieces: Pieces
    material: str
    around: str
    bottom: float
    top: float

    @classmethod
    def of(cls, case) -> Layout:
        """The layout of a `cloth.case.Case`."""
        garment = case.garment
        return cls(garment.pieces, case.material, garment.around, garment.bottom, garment.top)


def share_of(angle_deg: float) -> float:
    """The share of the circumference (1, in [0, 1)) from the centre back at ``angle_deg``
    from the centre front (module docstring)."""
    return float(np.mod((angle_deg + 180.0) / 360.0, 1.0))


def band_heights(
    heights: NDArray[np.float64], pieces: Pieces, bottom: float, top: float
) -> NDArray[np.float64]:
    """The rows' cut heights ((m,), m) with a row moved to the middle of every band that holds
    none (module docstring); the edge rows stay."""
    out = np.array(heights, dtype=float)
    for band in pieces.bands:
        low, high = band.span(bottom, top)
        if np.any((out >= low - 1e-12) & (out <= high + 1e-12)):
            continue
        middle = 0.5 * (low + high)
        interior = np.arange(1, len(out) - 1)
        if interior.size == 0:
            continue
        j = int(interior[np.argmin(np.abs(out[interior] - middle))])
        out[j] = middle
        if not np.all(np.diff(out) > 0):
            raise InputError(
                f"band {band.name!r} is too narrow for the grid's {len(out)} rows to hold one; "
                "give more rows (grid) or a wider band",
                field="garment.grid",
            )
    return out


def row_zones(heights: NDArray[np.float64], pieces: Pieces, bottom: float, top: float) -> NDArray:
    """(m,) int: the band each row belongs to (its index), -1 outside every band."""
    zone = np.full(len(heights), -1)
    for k, band in enumerate(pieces.bands):
        low, high = band.span(bottom, top)
        zone[(heights >= low - 1e-12) & (heights <= high + 1e-12)] = k
    return zone


def band_circumference(
    circumference: NDArray[np.float64],
    girth: NDArray[np.float64],
    zone: NDArray,
    pieces: Pieces,
) -> NDArray[np.float64]:
    """The rows' rest circumferences ((m,), m) with each band's rows cut as the band is: its
    reduction of the cut body's ``girth`` ((m,), m), or its circumference."""
    out = np.array(circumference, dtype=float)
    for k, band in enumerate(pieces.bands):
        rows = zone == k
        if band.circumference is not None:
            out[rows] = band.circumference
        else:
            out[rows] = (1.0 - float(band.reduction)) * girth[rows]
    return out


def tributary_boundaries(
    heights: NDArray[np.float64],
    rest_v: NDArray[np.float64],
    zone: NDArray,
    pieces: Pieces,
    bottom: float,
    top: float,
) -> NDArray[np.float64]:
    """(m + 1,) float, m: the rows' tributary strips in rest v (module docstring): midpoints,
    except between rows of different zones, where the band's edge is."""
    mid = 0.5 * (rest_v[:-1] + rest_v[1:])
    for j in range(len(heights) - 1):
        if zone[j] == zone[j + 1]:
            continue
        if zone[j] >= 0:  # the band below ends (another may start there)
            edge = pieces.bands[zone[j]].span(bottom, top)[1]
        else:  # the band above starts
            edge = pieces.bands[zone[j + 1]].span(bottom, top)[0]
        mid[j] = np.interp(edge, heights, rest_v)
    return np.concatenate(([rest_v[0]], mid, [rest_v[-1]]))


__all__ = [
    "Layout",
    "band_circumference",
    "band_heights",
    "row_zones",
    "share_of",
    "tributary_boundaries",
]
