"""The paper's explicit iteration, eq. (2): N <- N + p R/|R| for every node that may move.

Step rule. p_i = omega |P_i R_i| / k_i, capped at ``MAX_STEP`` x the node's shortest incident
rest length, where k_i = d_i^T K_ii d_i is the node's own stiffness along its move direction
d_i = P_i R_i / |P_i R_i| (K_ii its 3x3 block of the PSD-projected stiffness matrix). Reasoning:
|R_i|/k_i is the move along d_i that would balance node i if its neighbours stood still (a
Jacobi step of the linearised equations; a tensioned fabric is stiff along itself and soft across,
so the stiffness must be taken along the move, not averaged over directions);
omega = 0.8 < 1 damps the overshoot when all nodes move at once, and the cap keeps a node from
jumping past its neighbours while the grid is far from equilibrium. The direction is the paper's
R/|R|, with the constrained components removed (P_i). After the move, nodes the body held (the
paper's nodes "restricted by the surface") are put back on its surface at the closest point (a
tangential move on a convex body would lift them off by p^2 kappa / 2), and any other node that
entered the body is projected onto its surface; fixed nodes stay.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cloth.garment.mechanics import stiffness
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.stepper import Step

OMEGA = 0.8
MAX_STEP = 0.25


def node_stiffness(
    problem: Problem, ev: Evaluation, direction: NDArray[np.float64]
) -> NDArray[np.float64]:
    """k_i = d_i^T K_ii d_i, N m-1, from the PSD-projected stiffness's diagonal blocks."""
    k = stiffness(ev.x, problem.grid, project=True, state=ev.springs)
    n = problem.grid.n_nodes
    rows = np.repeat(np.arange(3 * n), 3)
    cols = (3 * np.repeat(np.arange(n), 9) + np.tile(np.arange(3), 3 * n)).astype(np.intp)
    blocks = np.asarray(k[rows, cols]).reshape(n, 3, 3)
    along = np.einsum("ni,nij,nj->n", direction, blocks, direction)
    floor = 1e-12 * max(float(np.abs(blocks).max()), 1e-300)
    return np.maximum(along, floor)


def shortest_rest(problem: Problem) -> NDArray[np.float64]:
    grid = problem.grid
    shortest = np.full(grid.n_nodes, np.inf)
    np.minimum.at(shortest, grid.ends[:, 0], grid.rest_length)
    np.minimum.at(shortest, grid.ends[:, 1], grid.rest_length)
    return shortest


def explicit_step(
    problem: Problem, ev: Evaluation, cap: NDArray[np.float64]
) -> tuple[Evaluation, float]:
    """One iteration of eq. (2); returns the evaluation at the new positions and the largest
    move (m)."""
    magnitude = np.linalg.norm(ev.free, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        direction = np.where(magnitude[:, None] > 0, ev.free / magnitude[:, None], 0.0)
    p = np.minimum(OMEGA * magnitude / node_stiffness(problem, ev, direction), cap)
    new = problem.evaluate(*problem.settle(ev.x + p[:, None] * direction, hold=ev.on_body))
    return new, float(p.max()) if len(p) else 0.0


class Explicit:
    """The paper's explicit iteration as a `cloth.solvers.stepper.Stepper`; moves are capped at
    ``cap`` ((N,), m: `MAX_STEP` x each node's shortest rest spring)."""

    name = "explicit"
    code = 0

    def __init__(self, cap: NDArray[np.float64]) -> None:
        self.cap = cap

    def step(self, problem: Problem, ev: Evaluation) -> Step:
        new, move = explicit_step(problem, ev, self.cap)
        return Step(new, move)
