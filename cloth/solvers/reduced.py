"""Newton's matrix factorised on the moves the constraints allow, not on all 3N unknowns.

Newton's matrix (`cloth.solvers.newton.newton_matrix`) is M = P A P + (I - P) + mu I, with P
the block-diagonal orthogonal projector onto each node's allowed moves (all of them for a free
node, the tangent plane of a held one, the horizontal normal's complement of a held sliding
one, none for a fixed one), A the stiffness with the contact curvature term, and mu the
regulariser (a Levenberg-Marquardt shift adds to it). With T (3N, D) an orthonormal basis of
P's range, node by node (P = T T^T), and C (3N, 3N - D) one of its complement,

    M = T (T^T A T + mu I) T^T + (1 + mu) C C^T,
    M^-1 = T (T^T M T)^-1 T^T + C (C^T M C)^-1 C^T,  C^T M C = (1 + mu) I,

so a factor of M is a factor of the D x D matrix T^T M T and a diagonal. On a body nearly
every node is held, so D is about 2/3 of 3N, and a sparse Cholesky's work (the cubes of its
dense fronts) about (2/3)^3 of the full matrix's. Measured on the torso at 448 x 224 (the
fine level's first Newton matrix, 201,278 of 301,056 unknowns kept): cholespy factorises the
reduced matrix in 1.5 s against 5.1 s for M, solves with it in 0.032 s against 0.049 s, and the
reduction itself takes 0.09 s; the two answers agree to 1e-11 (docs/performance.md, "The
reduced Newton matrix").

The factor's inertia is the reduced matrix's plus 3N - D positive eigenvalues (1 + mu): its
negative eigenvalues, the unstable modes `cloth.solvers.stability` counts, are the same.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

#: How far each projector block's eigenvalues may be from 0 or 1 for it to count as an
#: orthogonal projector (else the matrix is factorised whole).
PROJECTOR_TOLERANCE = 1e-8


class Factor(Protocol):
    """A factor with SuperLU's ``solve``: rhs (n,) or (n, k) -> A^-1 rhs."""

    def solve(self, rhs: NDArray[np.float64]) -> NDArray[np.float64]: ...


class Reduction:
    """The node-by-node orthonormal bases of a projector's range (``kept``, (3N, D)) and of
    its complement (``dropped``, (3N, 3N - D)), both CSR (module docstring)."""

    def __init__(self, kept: sp.csr_matrix, dropped: sp.csr_matrix) -> None:
        self.kept = kept
        self.dropped = dropped

    @property
    def size(self) -> int:
        """The unknowns of the reduced matrix (D)."""
        return self.kept.shape[1]

    def reduce(self, matrix: sp.spmatrix) -> tuple[sp.csc_matrix, NDArray[np.float64]]:
        """T^T M T ((D, D), CSC, indices sorted) and the diagonal of C^T M C ((3N - D,)) of
        the Newton ``matrix`` M ((3N, 3N)) built on this projector."""
        reduced = (self.kept.T @ (matrix @ self.kept)).tocsc()
        reduced.sort_indices()
        complement = np.asarray((self.dropped.multiply(matrix @ self.dropped)).sum(axis=0))
        return reduced, complement.ravel()


def reduction(projector: NDArray[np.float64]) -> Reduction | None:
    """The `Reduction` of the projector blocks ``projector`` ((N, 3, 3)), or None where a block
    is not an orthogonal projector (symmetric, eigenvalues 0 or 1) or nothing is dropped."""
    projector = np.asarray(projector, dtype=np.float64)
    if projector.ndim != 3 or projector.shape[1:] != (3, 3):
        return None
    if not np.allclose(projector, projector.transpose(0, 2, 1), rtol=0.0, atol=1e-12):
        return None
    values, vectors = np.linalg.eigh(projector)  # (N, 3) ascending, (N, 3, 3) columns
    keep = values > 0.5
    if np.abs(values - keep).max(initial=0.0) > PROJECTOR_TOLERANCE or np.all(keep):
        return None
    count = len(projector)
    rows = np.broadcast_to(
        (3 * np.arange(count)[:, None, None] + np.arange(3)[None, :, None]), (count, 3, 3)
    )
    columns = np.broadcast_to(
        (3 * np.arange(count)[:, None, None] + np.arange(3)[None, None, :]), (count, 3, 3)
    )
    rotation = sp.csc_matrix(
        (vectors.ravel(), (rows.ravel(), columns.ravel())), shape=(3 * count, 3 * count)
    )
    kept = keep.ravel()
    return Reduction(
        rotation[:, np.flatnonzero(kept)].tocsr(), rotation[:, np.flatnonzero(~kept)].tocsr()
    )


class ReducedFactor:
    """A factor of Newton's matrix M from a factor ``inner`` of T^T M T and the diagonal
    ``complement`` of C^T M C (module docstring), with SuperLU's ``solve``."""

    def __init__(self, inner: Factor, basis: Reduction, complement: NDArray[np.float64]) -> None:
        self.inner = inner
        self.basis = basis
        self.complement = complement
        self.size = basis.kept.shape[0]

    def solve(self, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
        rhs = np.asarray(rhs, dtype=np.float64)
        kept, dropped = self.basis.kept, self.basis.dropped
        inner = self.inner.solve(np.ascontiguousarray(kept.T @ rhs))
        scale = self.complement if rhs.ndim == 1 else self.complement[:, None]
        return kept @ inner + dropped @ ((dropped.T @ rhs) / scale)

    def lift(self, move: NDArray[np.float64]) -> NDArray[np.float64]:
        """A move of the reduced unknowns ((D,)) as one of all of them ((3N,))."""
        return self.basis.kept @ move
