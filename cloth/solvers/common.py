"""What both solvers share: constraints, the residual, history and stop rules.

Residual. One definition for both methods: the largest force on a node that is free to move, in
the directions it may move, relative to the typical spring force:

    r = max_i |P_i R_i| / mean_k |S_k|

R_i is the resultant spring force on node i (the paper's eq. 2); P_i removes what the
constraints carry: everything for a fixed node, the vertical component for a sliding edge node,
and the normal component of a node on the body when that component pushes into the body (the
body's reaction balances it; a node pulled away from the body is free). S_k = sigma_k A_k over
the weft and warp springs. r is dimensionless; 1e-8 means every free node is balanced to 1e-8
of a typical spring force.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from cloth.garment.grid import FIXED, SLIDING

log = logging.getLogger(__name__)

#: A node within this distance (m) of the surface, or inside, is on the body.
CONTACT_TOLERANCE = 1e-9


class Diverged(RuntimeError):
    """The iteration produced NaN or a growing energy; ``state`` is the last finite one."""

    def __init__(self, message: str, x: NDArray[np.float64], history: History):
        super().__init__(message)
        self.x = x
        self.history = history


@dataclass
class History:
    """Per-iteration record (one entry per iteration, the initial state first).

    residual (1), energy (J), penetration (m, largest depth inside the body), contacts (count of
    nodes on the body), step (m, largest node displacement of the iteration), method (0 explicit,
    1 newton), turning (N, the force on the turning gauge along its turn: what friction would
    carry; 0 without a gauge).
    """

    residual: list[float] = field(default_factory=list)
    energy: list[float] = field(default_factory=list)
    penetration: list[float] = field(default_factory=list)
    contacts: list[int] = field(default_factory=list)
    step: list[float] = field(default_factory=list)
    method: list[int] = field(default_factory=list)
    turning: list[float] = field(default_factory=list)

    def record(self, residual, energy, penetration, contacts, step, method, turning=0.0) -> None:
        self.residual.append(float(residual))
        self.energy.append(float(energy))
        self.penetration.append(float(penetration))
        self.contacts.append(int(contacts))
        self.step.append(float(step))
        self.method.append(int(method))
        self.turning.append(float(turning))

    def __len__(self) -> int:
        return len(self.residual)


def constraint_basis(
    constraint: NDArray[np.int8], normal: NDArray[np.float64], on_body: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """Per node, the projector P_i ((N, 3, 3)) onto the directions it may move in.

    Fixed: 0. Sliding: removes z. On the body: removes the normal (after z for a sliding node,
    Gram-Schmidt, so both are removed exactly).
    """
    count = len(constraint)
    projector = np.broadcast_to(np.eye(3), (count, 3, 3)).copy()
    ez = np.array([0.0, 0.0, 1.0])
    sliding = constraint == SLIDING
    projector[sliding] -= np.outer(ez, ez)
    if np.any(on_body):
        n = normal[on_body].copy()
        n[sliding[on_body]] -= n[sliding[on_body]][:, 2:3] * ez  # orthogonal to z
        length = np.linalg.norm(n, axis=1)
        usable = length > 1e-12
        n[usable] /= length[usable, None]
        n[~usable] = 0.0
        projector[on_body] -= n[:, :, None] * n[:, None, :]
    projector[constraint == FIXED] = 0.0
    return projector


def body_push(
    forces: NDArray[np.float64], normal: NDArray[np.float64], constraint: NDArray[np.int8]
) -> NDArray[np.float64]:
    """(N,) N: lambda, the body's normal reaction lambda n that would balance each node.

    A node balanced by the body alone: R + lambda n = 0 along n, lambda = -R . n. A sliding
    edge node is balanced by the body and by its edge's support, which carries any vertical
    force: R + lambda n + mu e_z = 0, so lambda comes from the horizontal balance alone,
    lambda = -R_h . n_h / |n_h|^2 (the full -R . n differs by mu n_z: under an overhang, n_z < 0,
    a node pushed sideways into the body would look pulled off). Where n_h vanishes (a ledge)
    the support and the body push along one line: -R . n.
    """
    push = -np.einsum("ij,ij->i", forces, normal)
    sliding = np.flatnonzero(constraint == SLIDING)
    if sliding.size:
        horizontal = normal[sliding, :2]
        squared = np.einsum("ij,ij->i", horizontal, horizontal)
        steep = squared > 1e-12
        rows = sliding[steep]
        push[rows] = -np.einsum("ij,ij->i", forces[rows, :2], horizontal[steep]) / squared[steep]
    return push


def pushing(push: NDArray[np.float64], distance: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Nodes on or inside the body that it must push back (``push``: `body_push`, N)."""
    return (distance <= CONTACT_TOLERANCE) & (push > 0.0)


def typical_force(spring_force: NDArray[np.float64], families: NDArray[np.int8]) -> float:
    """Mean |S_k| over weft and warp springs, N (1 N when the fabric is slack)."""
    main = np.abs(spring_force[families <= 1])
    value = float(np.mean(main)) if main.size else 0.0
    return value if value > 0 else 1.0


def relative_residual(free_force: NDArray[np.float64], typical: float) -> float:
    return float(np.max(np.linalg.norm(free_force, axis=1))) / typical if len(free_force) else 0.0
