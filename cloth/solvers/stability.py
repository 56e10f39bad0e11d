"""Whether an equilibrium is stable: the inertia of Newton's matrix, by Sylvester's law.

A garment at rest on the body is stable when no move its constraints allow lowers its energy
to second order: the exact constrained Hessian P (K - sum_i lambda_i H_i) P is positive
semi-definite on the allowed moves (P, K, lambda, H as in `cloth.solvers.newton`). Newton's
matrix adds I - P (eigenvalue 1 along every constrained direction) and mu I (1e-10 of its
largest diagonal entry), so its negative eigenvalues are the equilibrium's unstable modes.
Newton converges to any stationary point, a saddle as well as a minimum (its step need only
descend along the residual), and a residual of 1e-12 says nothing about which it found; the
count does. Measured on the torso (docs/solvers.md, "Stability"): compressed warp springs at
the waist make saddles on fine grids (a compressed spring's Hessian is A sigma / l < 0 across
it: a membrane without bending stiffness buckles).

The count comes from one unpivoted LU of the symmetric matrix (SuperLU in symmetric mode with
no pivoting, `cloth.solvers.linear.lu_factor`): Q A Q^T = L U with U = D L^T, so by Sylvester's
law of inertia the signs of U's diagonal are those of A's eigenvalues. A factor whose rows
SuperLU pivoted after all (it met an exact zero) is not a congruence, and is refused.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from cloth.bodies import MeshBody
from cloth.solvers.activeset import held_nodes
from cloth.solvers.cholesky import CholeskyFactor
from cloth.solvers.linear import PermutedLU, lu_factor, spd_factor
from cloth.solvers.newton import newton_matrix, stiffness_at
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.reduced import ReducedFactor


def negative_eigenvalues(matrix: sp.spmatrix) -> int:
    """The number of negative eigenvalues of the symmetric ``matrix`` ((n, n); its inertia's
    negative index), from the signs of the pivots of its unpivoted LU (module docstring).
    ValueError where the matrix is not square or the factorisation had to pivot."""
    if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1]:
        raise ValueError(f"expected a square (n, n) matrix, got shape {matrix.shape}")
    return factor_inertia(lu_factor(sp.csr_matrix(matrix)))


def _unpivoted(factor):
    """SuperLU's own LU of ``factor`` (`cloth.solvers.linear.lu_factor`), or None where it
    pivoted rows after all (an exactly zero pivot): its pivots are then no congruence."""
    lu = factor.lu if isinstance(factor, PermutedLU) else factor
    return lu if np.array_equal(lu.perm_r, lu.perm_c) else None


def factor_inertia(factor) -> int:
    """The negative eigenvalues of the symmetric matrix SuperLU's unpivoted ``factor``
    (`cloth.solvers.linear.lu_factor`) is of: its negative pivots (module docstring); none for a
    Cholesky factor (`cloth.solvers.cholesky.CholeskyFactor`: its matrix is positive definite).
    ValueError where SuperLU pivoted rows after all. A reduced factor
    (`cloth.solvers.reduced.ReducedFactor`) has its inner factor's: what it drops is positive."""
    if isinstance(factor, ReducedFactor):
        return factor_inertia(factor.inner)
    if isinstance(factor, CholeskyFactor):
        return 0
    lu = _unpivoted(factor)
    if lu is None:
        raise ValueError(
            "SuperLU pivoted rows (an exactly zero pivot), so its pivots do not give the "
            "inertia; shift the matrix slightly"
        )
    return int(np.count_nonzero(lu.U.diagonal() < 0.0))


def negative_direction(factor, size: int) -> NDArray[np.float64] | None:
    """A move ((size,)) of negative curvature of the symmetric matrix A of SuperLU's unpivoted
    ``factor``, from its negative pivots (None where it has none, is a Cholesky factor, or
    pivoted). With P A P^T =
    L D L^T (the factor's U is D L^T), the vectors y_i with L^T y_i = e_i for the negative
    pivots d_i are A-conjugate with y_i^T (P A P^T) y_i = d_i, so their sum, mapped back by P,
    has curvature sum_i d_i < 0 and spans every unstable mode at once. One solve with the
    factor gives it: A^-1 P^T L (sum_i d_i e_i) = P^T sum_i y_i. A reduced factor's is its
    inner factor's, lifted to every unknown."""
    if isinstance(factor, ReducedFactor):
        inner = negative_direction(factor.inner, factor.basis.size)
        return None if inner is None else factor.lift(inner)
    if isinstance(factor, CholeskyFactor):
        return None
    lu = _unpivoted(factor)
    if lu is None:
        return None
    pivots = lu.U.diagonal()
    negative = np.flatnonzero(pivots < 0.0)
    if negative.size == 0:
        return None
    rhs = lu.L.tocsc()[:, negative] @ pivots[negative]
    permute = sp.csc_matrix((np.ones(size), (np.arange(size), lu.perm_c)), shape=(size, size))
    inner = lu.solve(permute @ rhs)
    if not isinstance(factor, PermutedLU):
        return inner
    move = np.empty(size)
    move[factor.order] = inner
    return move


def counts(problem: Problem) -> bool:
    """Whether `unstable_modes` counts on ``problem``: a smooth body and no skin model."""
    return not (isinstance(problem.body, MeshBody) or problem.lagged)


def unstable_modes(problem: Problem, ev: Evaluation) -> int:
    """The unstable modes of the garment at ``ev`` (an equilibrium, or any state): the negative
    eigenvalues of the exact Newton matrix on the moves its constraints and the body's
    contact allow (module docstring); 0 at a stable equilibrium. With the tension field
    (`cloth.garment.grid.Grid.convex`) a Cholesky factorisation is tried first
    (`cloth.solvers.linear.spd_factor`): where it succeeds the matrix is positive definite, 0
    (half an LU's memory, at 100k nodes); where it does not, the LU it falls back to counts.
    Smooth bodies (closed-form, the torso, the smooth surfaces of meshes) and no skin model:
    ValueError for faceted contact (``surface: mesh``, whose constraints are face planes) or a
    tissue layer or friction."""
    if not counts(problem):
        raise ValueError(
            "unstable_modes takes a smooth body without tissue or friction (faceted contact and "
            "the skin models change the constrained Hessian)"
        )
    matrix, projector = exact_system(problem, ev)
    if problem.grid.convex:  # the tension field: a Cholesky factor, where there is one, says 0
        return factor_inertia(spd_factor(matrix, projector))
    return negative_eigenvalues(matrix)


def exact_matrix(problem: Problem, ev: Evaluation) -> sp.csr_matrix:
    """The exact constrained Newton matrix at ``ev`` ((3N, 3N), N/m): the one whose negative
    eigenvalues are the unstable modes (module docstring)."""
    return exact_system(problem, ev)[0]


def exact_system(problem: Problem, ev: Evaluation) -> tuple[sp.csr_matrix, NDArray[np.float64]]:
    """`exact_matrix` and the projector blocks ((N, 3, 3)) of the moves it is built on."""
    k = stiffness_at(problem, ev)
    held = held_nodes(problem, ev, k)
    projector, _ = problem.basis(ev.x, ev.normal, held)
    return newton_matrix(problem, ev, held, projector, k(False)), projector
