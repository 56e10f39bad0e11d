"""The garment's rows along the warp: the heights they are cut at, equally spaced or graded
toward the garment's two edges (issue 54).

A girth line at an edge row (a torso's hip and bust, a stocking's G 2 cm below its top) sits in
the edge layer, where the fabric's stress turns from the body's hold to the free edge, and it
converges slowest as the rows are refined. Graded rows put more of the same m rows there: row j
of m is cut at

    z_j = bottom + (top - bottom) s(xi_j),   xi_j = j / (m - 1),
    s(xi) = xi - g sin(2 pi xi) / (2 pi),

so the spacing follows ds/dxi = 1 - g cos(2 pi xi): (1 - g) at both edges, (1 + g) at the
middle, their ratio (1 - g) / (1 + g) (g = 0.5: edge rows a third of the middle's). For g in
[0, 1) the rows increase strictly. The map is one smooth function of xi for every m, so the
coarser grids of the error estimate (`cloth.stages.levels`) are the same map sampled coarser
and the error still falls as h^2 (h = 1 / (m - 1)); g = 0 gives numpy's equally spaced rows, bit
for bit.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: The grading where a case gives none: equally spaced rows.
UNIFORM = 0.0
#: The largest grading accepted (edge rows a 19th of the middle's).
MAX_GRADING = 0.9


def row_heights(bottom: float, top: float, m: int, grading: float = UNIFORM) -> NDArray[np.float64]:
    """The cut heights ((m,), m, increasing) of ``m`` rows from ``bottom`` to ``top`` (m),
    graded toward both edges by ``grading`` g (module docstring; 0: equally spaced)."""
    if not 0.0 <= grading <= MAX_GRADING:
        raise ValueError(f"row grading must be in [0, {MAX_GRADING}], got {grading}")
    if grading == UNIFORM:
        return np.linspace(bottom, top, m)
    xi = np.linspace(0.0, 1.0, m)
    s = xi - grading * np.sin(2.0 * np.pi * xi) / (2.0 * np.pi)
    s[0], s[-1] = 0.0, 1.0  # the edges exactly where the case puts them
    return bottom + (top - bottom) * s


def edge_ratio(grading: float) -> float:
    """The edge rows' spacing over the middle rows' (1) at ``grading``: (1 - g) / (1 + g)."""
    return (1.0 - grading) / (1.0 + grading)


__all__ = ["MAX_GRADING", "UNIFORM", "edge_ratio", "row_heights"]
