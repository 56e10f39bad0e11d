"""The relaxation problem: a grid, a body, the nodes' constraints; evaluated at positions x."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import Body, MeshBody
from cloth.contact import polyhedral as contact
from cloth.contact.friction import Friction
from cloth.contact.skin import skin_models
from cloth.contact.tissue import Layer
from cloth.garment.grid import FIXED, SLIDING, Grid
from cloth.garment.mechanics import SpringState, energy, operators, spring_forces, spring_state
from cloth.garment.state import State
from cloth.solvers.common import (
    CONTACT_TOLERANCE,
    body_push,
    constraint_basis,
    pushing,
    relative_residual,
    typical_force,
)

#: Newton corrections along the horizontal normal that put a sliding edge node on the body.
LEVEL_ITERATIONS = 3

#: A body's query at N points: signed distance (N,) m, closest points (N, 3) m, unit normals
#: (N, 3) (`cloth.bodies.Body.query`).
Query = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


@dataclass(frozen=True)
class Evaluation:
    """Everything the solvers need at positions x ((N, 3), m).

    forces (N, 3) N: resultant spring force R; loads (N, 3) N: what the solver balances
    against the rigid body, R plus the tissue's push and the skin's friction (R itself without
    them); distance (N,) m, closest (N, 3) m, normal (N, 3): body query (the undeformed skin's
    with tissue); push (N,) N: the body's reaction lambda that would balance each node
    (`cloth.solvers.common.body_push`; the tissue's push k u with tissue); on_body (N,) bool:
    nodes held by the body (on or inside it, lambda > 0; with tissue: indenting it);
    projector (N, 3, 3): allowed directions; free (N, 3) N: P loads; unbalanced (N, 3) N: loads
    less the rigid body's reaction (no edge constraints); residual (1); energy (J: strain energy,
    plus the tissue's and the friction potential with them); penetration (m, >= 0: into the
    rigid body, or past the tissue into its core); springs: the spring state; turning (N): the
    force on the gauge node along its turn, which the gauge carries (`turning_gauge`; 0 without
    one); friction (N, 3) N: the skin's friction force (None without friction); indentation
    (N,) m: how far each node presses the tissue in (None without tissue).
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
    turning: float = 0.0
    loads: NDArray[np.float64] | None = None
    friction: NDArray[np.float64] | None = None
    indentation: NDArray[np.float64] | None = None


def turning_gauge(grid: Grid, constraint: NDArray[np.int8]) -> int | None:
    """The node held against turning about the body, or None.

    A tube (``grid.closed``) with no fixed node can turn about the body: with frictionless
    contact its material slides round the body's sections, and for a uniform tube that costs
    nothing but discretisation effects, so the turn is undetermined (Newton's matrix is
    singular along it; on a coarse mesh the garment wandered round the body without end). Node
    0 (bottom row, first column) fixes it, as a skin's friction would; its reaction
    (`Evaluation.turning`) is what that friction carries.
    """
    return 0 if grid.closed and not np.any(constraint == FIXED) else None


@dataclass(frozen=True, eq=False)
class Problem:
    """The grid, the body, the nodes' constraints (`cloth.files.state`: free, sliding, fixed), the
    node held against turning (`turning_gauge`; None: none), and the lagged skin models: the
    tissue layer under each node (`cloth.contact.tissue.Layer`; None: a rigid body) and the friction
    (`cloth.contact.friction.Friction`; None: frictionless)."""

    grid: Grid
    body: Body
    constraint: NDArray[np.int8]
    gauge: int | None = None
    tissue: Layer | None = None
    friction: Friction | None = None

    @classmethod
    def of(cls, state: State, body: Body) -> Problem:
        """The problem of relaxing ``state`` on ``body``, with its turning gauge and the skin
        models under it (`cloth.contact.skin.skin_models`)."""
        tissue, friction = skin_models(state.skin, state.grid, state.x)
        gauge = turning_gauge(state.grid, state.constraint)
        return cls(state.grid, body, state.constraint, gauge, tissue, friction)

    @property
    def lagged(self) -> bool:
        """Whether the problem has lagged quantities (tissue areas, friction normal forces)."""
        return self.tissue is not None or self.friction is not None

    def basis(
        self, x: NDArray[np.float64], normal: NDArray[np.float64], on_body: NDArray[np.bool_]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """`constraint_basis` with the gauge held (`hold_turning`): ((N, 3, 3), (3,))."""
        projector = constraint_basis(self.constraint, normal, on_body)
        return projector, self.hold_turning(x, projector)

    def hold_turning(
        self, x: NDArray[np.float64], projector: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Remove the gauge node's turn from its allowed moves (``projector``, (N, 3, 3), in
        place) and return that direction ((3,), unit; zeros without a gauge): its turn about
        the vertical through its row's centre, within the moves its constraints allow."""
        turn = np.zeros(3)
        if self.gauge is not None:
            n = self.grid.n
            row = x[(self.gauge // n) * n : (self.gauge // n + 1) * n]
            radial = x[self.gauge] - row.mean(axis=0)
            along = projector[self.gauge] @ np.array([-radial[1], radial[0], 0.0])
            length = float(np.linalg.norm(along))
            if length > 1e-12 * float(np.linalg.norm(radial)):
                turn = along / length
                projector[self.gauge] -= np.outer(turn, turn)
        return turn

    def evaluate(self, x: NDArray[np.float64], query: Query | None = None) -> Evaluation:
        """The `Evaluation` at ``x`` ((N, 3), m); ``query``: the body's query at ``x`` where it
        is known (`settle`), else the body is queried."""
        springs = spring_state(x, self.grid)
        spring_force = spring_forces(springs, self.grid)
        forces = -(operators(self.grid).incidence_t @ spring_force)
        distance, closest, normal = self.body.query(x) if query is None else query
        work = energy(x, self.grid, springs)
        loads, friction, indentation = forces, None, None
        if self.friction is not None:
            friction, dissipation = self.friction.response(x)
            loads, work = loads + friction, work + dissipation
        if self.tissue is not None:  # the layer is the body's only reaction: no rigid contact
            indentation, push_force, stored = self.tissue.response(distance, normal)
            loads, work = loads + push_force, work + stored
            push = self.tissue.stiffness * indentation
            on_body = indentation > 0.0
            projector, turn = self.basis(x, normal, np.zeros(len(x), bool))
            free = np.einsum("nij,nj->ni", projector, loads)
            unbalanced = loads.copy()
            penetration = float(max(0.0, np.max(indentation - self.tissue.thickness)))
        else:
            push = body_push(loads, normal, self.constraint)
            on_body = pushing(push, distance)
            projector, turn = self.basis(x, normal, on_body)
            free = np.einsum("nij,nj->ni", projector, loads)
            # what the body cannot balance (before edge constraints): R + lambda n on held nodes
            unbalanced = loads + np.where(on_body, push, 0.0)[:, None] * normal
            if isinstance(self.body, MeshBody) and np.any(on_body):
                self._mesh_remainder(x, loads, normal, on_body, free, unbalanced, turn)
            penetration = float(max(0.0, -distance.min())) if len(distance) else 0.0
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
            energy=work,
            penetration=penetration,
            turning=float(loads[self.gauge] @ turn) if self.gauge is not None else 0.0,
            loads=loads,
            friction=friction,
            indentation=indentation,
        )

    def _mesh_remainder(self, x, loads, normal, on_body, free, unbalanced, turn) -> None:
        """The exact frictionless residual on a polyhedron (``free`` and ``unbalanced`` of the
        held nodes, in place): remove the normal cone, then what the edge constraints carry."""
        held = np.flatnonzero(on_body)
        unbalanced[held] = contact.remainder(self.body, x[held], loads[held])
        remainder = unbalanced[held].copy()
        sliding = np.flatnonzero(self.constraint[held] == SLIDING)
        if sliding.size:  # their vertical reaction comes from the edge support
            rows = held[sliding]
            remainder[sliding] = contact.remainder(
                self.body, x[rows], loads[rows], np.ones(sliding.size, bool)
            )
        edge_only = constraint_basis(self.constraint[held], normal[held], np.zeros(len(held), bool))
        free[held] = np.einsum("nij,nj->ni", edge_only, remainder)
        if self.gauge is not None:  # the gauge holds it against turning
            free[self.gauge] -= (free[self.gauge] @ turn) * turn

    def project_out(
        self, x: NDArray[np.float64], hold: NDArray[np.bool_] | None = None
    ) -> NDArray[np.float64]:
        """``x`` with nodes inside the body, and the ``hold`` nodes, moved onto it (`settle`)."""
        return self.settle(x, hold)[0]

    def settle(
        self, x: NDArray[np.float64], hold: NDArray[np.bool_] | None = None
    ) -> tuple[NDArray[np.float64], Query | None]:
        """Move nodes inside the body, and the ``hold`` nodes wherever they are, onto its
        surface: to the closest point, or for a sliding edge node, along its horizontal normal
        (its height is the edge's: Newton on the distance, ``LEVEL_ITERATIONS`` queries). With
        tissue the skin gives way: nothing is moved.

        Returns the positions and the body's query at them (`evaluate`'s ``query``; None with
        tissue): a node left where it was keeps its query, a node put on a smooth body has
        distance 0, its closest point itself and the normal there (the one the query that moved
        it found), and on a mesh the moved nodes are queried again (the normal at a point on an
        edge is not the one from outside it)."""
        if self.tissue is not None:
            return x, None
        distance, closest, normal = self.body.query(x)
        move = distance < 0.0
        if hold is not None:
            move |= hold
        if not np.any(move):
            return x, (distance, closest, normal)
        x = x.copy()
        distance, closest, normal = distance.copy(), closest.copy(), normal.copy()
        placed = move & (self.constraint != SLIDING)  # onto their closest points
        x[placed] = closest[placed]
        distance[placed] = 0.0
        rows = np.flatnonzero(move & (self.constraint == SLIDING))
        for _ in range(LEVEL_ITERATIONS):
            horizontal = normal[rows].copy()
            horizontal[:, 2] = 0.0
            along = np.einsum("ij,ij->i", horizontal, normal[rows])
            steep = along > 1e-6  # else (a cap, a ledge): the closest point
            flat = rows[~steep]
            x[flat], distance[flat] = closest[flat], 0.0
            rows, horizontal, along = rows[steep], horizontal[steep], along[steep]
            x[rows] -= (distance[rows] / along)[:, None] * horizontal
            if rows.size == 0:
                break
            distance[rows], closest[rows], normal[rows] = self.body.query(x[rows])
        if isinstance(self.body, MeshBody):  # the sliding rows still in ``rows`` were just queried
            again = move.copy()
            again[rows] = False
            distance[again], closest[again], normal[again] = self.body.query(x[again])
        return x, (distance, closest, normal)

    def contacts(self, ev: Evaluation) -> int:
        return int(np.count_nonzero(ev.distance <= CONTACT_TOLERANCE))
