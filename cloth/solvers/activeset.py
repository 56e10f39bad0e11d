"""The contact active set of Newton's step: which nodes the rigid body holds this iteration.

`held_nodes`: a node on or inside the body whose spring force pushes into it is held, and so
is one within `GAP` (1 % of the shortest rest length) pushed hard enough to stay pushed once on
it. `entering`: a node the set would release but whose Newton move goes into the body stays
held (`cloth.solvers.newton` redoes the move). With tissue the skin gives way and neither holds
a node. Shapes: (N,) bool over the grid's nodes.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from cloth.garment.grid import FIXED
from cloth.solvers.common import CONTACT_TOLERANCE
from cloth.solvers.problem import Evaluation, Problem

#: ``k(project)``: the stiffness at one state, exact (False) or PSD-projected (True).
Stiffness = Callable[[bool], sp.csr_matrix]

#: Hovering nodes within this share of the shortest rest length may be held.
GAP = 0.01


def held_nodes(problem: Problem, ev: Evaluation, k: Stiffness) -> NDArray[np.bool_]:
    """Nodes the body holds this iteration: pushed into it and on it (or inside), or within
    the gap and pushed hard enough to stay pushed once on it.

    A node hovering at distance d above the body with an inward push f = -R . n is held (and
    put on the surface by the step's correction) only if f >= k_n d, k_n = n^T K_ii n its
    normal stiffness: otherwise the springs would pull it back off once there. A node where
    the fabric bridges a hollow (the cleavage) otherwise hovers with a near-zero push, is put
    down, pulled off, and costs an iteration each time (measured on the smooth torso).
    ``k(True)`` is the projected stiffness, assembled only if some node hovers. With tissue the
    skin gives way and holds no node (the layer's force is in the loads).
    """
    if problem.tissue is not None:
        return np.zeros(problem.grid.n_nodes, bool)
    gap = GAP * float(problem.grid.rest_length.min())
    push = ev.push
    held = (ev.distance <= CONTACT_TOLERANCE) & (push > 0.0)
    hovering = np.flatnonzero((ev.distance > CONTACT_TOLERANCE) & (ev.distance <= gap) & (push > 0))
    if hovering.size:
        projected = k(True)
        normal = ev.normal[hovering]
        k_n = np.zeros(hovering.size)
        for a in range(3):  # n^T K_ii n from the entries of each node's diagonal block
            for b in range(3):
                entry = np.asarray(projected[3 * hovering + a, 3 * hovering + b]).ravel()
                k_n += normal[:, a] * entry * normal[:, b]
        held[hovering] = push[hovering] >= k_n * ev.distance[hovering]
    return held


def entering(
    problem: Problem, ev: Evaluation, held: NDArray[np.bool_], dx: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Nodes on the body that the active set releases (not ``held``) but whose Newton move
    ``dx`` ((N, 3), m) goes into the body: released, they would be stepped inside and projected
    back, and the line search would halve the step every iteration; they stay held."""
    if problem.tissue is not None:
        return np.zeros(problem.grid.n_nodes, bool)
    touching = (ev.distance <= CONTACT_TOLERANCE) & (problem.constraint != FIXED)
    inward = np.einsum("ij,ij->i", dx, ev.normal) < -CONTACT_TOLERANCE
    return touching & ~held & inward
