"""The relaxation problem: a grid, a body, the nodes' constraints; evaluated at positions x."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth import contact
from cloth.bodies import Body, MeshBody
from cloth.grid import Grid
from cloth.mechanics import SpringState, energy, spring_forces, spring_state
from cloth.solvers.common import (
    CONTACT_TOLERANCE,
    body_push,
    constraint_basis,
    pushing,
    relative_residual,
    typical_force,
)
from cloth.state import SLIDING

#: Newton corrections along the horizontal normal that put a sliding edge node on the body.
LEVEL_ITERATIONS = 3


@dataclass(frozen=True)
class Evaluation:
    """Everything the solvers need at positions x ((N, 3), m).

    forces (N, 3) N: resultant spring force R; distance (N,) m, closest (N, 3) m, normal (N, 3):
    body query; push (N,) N: the body's reaction lambda that would balance each node
    (`cloth.solvers.common.body_push`); on_body (N,) bool: nodes held by the body (on or inside
    it, lambda > 0);
    projector (N, 3, 3): allowed directions; free (N, 3) N: P R; unbalanced (N, 3) N: R less
    the body's reaction (no edge constraints); residual (1); energy (J);
    penetration (m, >= 0); springs: the spring state.
    """

    x: NDArray[np.float64]
    springs: SpringState
    forces: NDArray[np.float64]
    distance: NDArray[np.float64]
    closest: NDArray[np.float64]
    normal: NDArray[np.float64]
    push: NDArray[np.float64]
    on_body: NDArray[np.bool_]
    projector: NDArray[np.float64]
    free: NDArray[np.float64]
    unbalanced: NDArray[np.float64]
    typical: float
    residual: float
    energy: float
    penetration: float


@dataclass(frozen=True, eq=False)
class Problem:
    grid: Grid
    body: Body
    constraint: NDArray[np.int8]

    def evaluate(self, x: NDArray[np.float64]) -> Evaluation:
        from cloth.mechanics import _operators

        springs = spring_state(x, self.grid)
        spring_force = spring_forces(springs, self.grid)
        forces = -(_operators(self.grid).incidence_t @ spring_force)
        distance, closest, normal = self.body.query(x)
        push = body_push(forces, normal, self.constraint)
        on_body = pushing(push, distance)
        projector = constraint_basis(self.constraint, normal, on_body)
        free = np.einsum("nij,nj->ni", projector, forces)
        # what the body cannot balance (before edge constraints): R + lambda n on held nodes
        unbalanced = forces + np.where(on_body, push, 0.0)[:, None] * normal
        if isinstance(self.body, MeshBody) and np.any(on_body):
            # the exact frictionless residual on a polyhedron: remove the normal cone, then
            # what the edge constraints carry
            held = np.flatnonzero(on_body)
            unbalanced[held] = contact.remainder(self.body, x[held], forces[held])
            remainder = unbalanced[held].copy()
            sliding = np.flatnonzero(self.constraint[held] == SLIDING)
            if sliding.size:  # their vertical reaction comes from the edge support
                rows = held[sliding]
                remainder[sliding] = contact.remainder(
                    self.body, x[rows], forces[rows], np.ones(sliding.size, bool)
                )
            edge_only = constraint_basis(
                self.constraint[held], normal[held], np.zeros(len(held), bool)
            )
            free[held] = np.einsum("nij,nj->ni", edge_only, remainder)
        typical = typical_force(np.linalg.norm(spring_force, axis=1), self.grid.family)
        return Evaluation(
            x=x,
            springs=springs,
            forces=forces,
            distance=distance,
            closest=closest,
            normal=normal,
            push=push,
            on_body=on_body,
            projector=projector,
            free=free,
            unbalanced=unbalanced,
            typical=typical,
            residual=relative_residual(free, typical),
            energy=energy(x, self.grid, springs),
            penetration=float(max(0.0, -distance.min())) if len(distance) else 0.0,
        )

    def project_out(
        self, x: NDArray[np.float64], hold: NDArray[np.bool_] | None = None
    ) -> NDArray[np.float64]:
        """Move nodes inside the body, and the ``hold`` nodes wherever they are, onto its
        surface: to the closest point, or for a sliding edge node, along its horizontal normal
        (its height is the edge's: Newton on the distance, ``LEVEL_ITERATIONS`` queries)."""
        distance, closest, normal = self.body.query(x)
        move = distance < 0.0
        if hold is not None:
            move |= hold
        if not np.any(move):
            return x
        x = x.copy()
        level = move & (self.constraint == SLIDING)
        x[move & ~level] = closest[move & ~level]
        rows = np.flatnonzero(level)
        d, n = distance[rows], normal[rows]
        for _ in range(LEVEL_ITERATIONS):
            horizontal = n.copy()
            horizontal[:, 2] = 0.0
            along = np.einsum("ij,ij->i", horizontal, n)
            steep = along > 1e-6  # else (a cap, a ledge): the closest point
            x[rows[~steep]] = closest[rows[~steep]]
            rows, d, horizontal, along = rows[steep], d[steep], horizontal[steep], along[steep]
            x[rows] -= (d / along)[:, None] * horizontal
            if rows.size == 0:
                break
            d, closest_rows, n = self.body.query(x[rows])
            closest[rows] = closest_rows
        return x

    def contacts(self, ev: Evaluation) -> int:
        return int(np.count_nonzero(ev.distance <= CONTACT_TOLERANCE))
