"""Sparse Cholesky of a positive-definite Newton matrix, through cholespy.

With the tension field (every curve `tension_only`) each spring's energy is convex in the node
positions, so the stiffness is positive semi-definite, and Newton's constrained, regularised
matrix P K P + (I - P) + mu I is positive definite: a Cholesky factor L L^T of it takes half the
memory of an LU and solves in half the time (docs/solvers.md, "Positive-definite systems").
The contact curvature term -lambda H of a held node on a convex patch of the body can still
make a matrix indefinite far from the equilibrium; the factorisation then raises
`NotPositiveDefinite` and the caller solves that system by LU (`cloth.solvers.linear`).

cholespy (a self-contained CHOLMOD with manylinux wheels, no system library) reads the lower
triangle of a CSC matrix and orders it itself. Where it meets a non-positive pivot, its CHOLMOD
prints a warning on the process's standard output (file descriptor 1, which a command's output
may be); `cholesky_factor` sends that descriptor to the null device for the call, and the
warning's content is the exception.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray


class NotPositiveDefinite(ValueError):
    """The matrix given to `cholesky_factor` is not (numerically) positive definite."""


class CholeskyFactor:
    """cholespy's factor L L^T of a positive-definite matrix of ``size`` rows, with SuperLU's
    ``solve(rhs)`` (rhs (size,) or (size, k)). Its inertia is known: no negative eigenvalue
    (`cloth.solvers.stability.factor_inertia`)."""

    def __init__(self, solver, size: int) -> None:
        self.solver = solver
        self.size = size

    def solve(self, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
        b = np.ascontiguousarray(rhs, dtype=np.float64)
        x = np.empty_like(b)
        self.solver.solve(b, x)
        return x


@contextlib.contextmanager
def _quiet_stdout() -> Iterator[None]:
    """File descriptor 1 on the null device for the block (CHOLMOD's C-level warnings)."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 1)
            try:
                yield
            finally:
                os.dup2(saved, 1)
    finally:
        os.close(saved)


def cholesky_factor(matrix: sp.spmatrix) -> CholeskyFactor:
    """The Cholesky factor of the symmetric ``matrix`` ((n, n)); `NotPositiveDefinite` where it
    has a non-positive pivot (an indefinite or singular matrix)."""
    import cholespy

    lower = sp.tril(matrix, format="csc")
    lower.sort_indices()
    try:
        with _quiet_stdout():
            solver = cholespy.CholeskySolverD(
                lower.shape[0],
                lower.indptr.astype(np.int32),
                lower.indices.astype(np.int32),
                np.ascontiguousarray(lower.data, dtype=np.float64),
                cholespy.MatrixType.CSC,
            )
    except ValueError as error:  # "Matrix is not positive definite!"
        raise NotPositiveDefinite(str(error)) from None
    return CholeskyFactor(solver, lower.shape[0])
