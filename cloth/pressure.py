"""Contact pressure: the body's normal reaction on each node over the node's area on the body.

Node area: the deformed tributary area, a quarter of each adjacent grid cell (cells are the
quads (i, j), (i+1, j), (i+1, j+1), (i, j+1), closed around a tube), cell area = half the norm of
the cross product of its diagonals (exact for planar quads). Edge rows get half cells.

Reaction: what the springs push into the body and the body balances, -(R - r) with r the part
the body cannot balance (`Evaluation.free` before edge constraints): along the surface normal on
a smooth body, in the normal cone of the faces on a mesh.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cloth.grid import Grid


def node_area(x: NDArray[np.float64], grid: Grid) -> NDArray[np.float64]:
    """(N,) float, m2: deformed tributary area of every node."""
    pts = x.reshape(grid.m, grid.n, 3)
    nxt = np.roll(pts, -1, axis=1) if grid.closed else pts[:, 1:]
    here = pts if grid.closed else pts[:, :-1]
    d1 = nxt[1:] - here[:-1]  # (i, j) -> (i+1, j+1)
    d2 = here[1:] - nxt[:-1]  # (i+1, j) -> (i, j+1)
    cell = 0.5 * np.linalg.norm(np.cross(d1, d2), axis=2)  # (m-1, cells)
    area = np.zeros((grid.m, grid.n))
    quarter = 0.25 * cell
    cols = np.arange(cell.shape[1])
    for dj in (0, 1):
        for di in (0, 1):
            np.add.at(area, (slice(dj, dj + grid.m - 1), (cols + di) % grid.n), quarter)
    return area.ravel()


def contact_reaction(
    forces: NDArray[np.float64], unbalanced: NDArray[np.float64], held: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """(N, 3) float, N: the body's reaction on each held node (zero elsewhere)."""
    reaction = np.zeros_like(forces)
    reaction[held] = -(forces[held] - unbalanced[held])
    return reaction
