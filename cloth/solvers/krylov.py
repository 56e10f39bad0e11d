"""Krylov solves preconditioned by a kept factor: the Krylov half of factorisation reuse
(`cloth.solvers.linear.Reuse`), with the limits that decide when a factor no longer serves.

* `gmres_on`: GMRES right-preconditioned by an LU factor, for a Newton matrix that may be
  indefinite. Right preconditioning, A M y = b, x = M y: GMRES minimises the true residual, the
  one the inexact-Newton forcing term bounds (left-preconditioned, it minimised |M r|, which went
  below rtol with |r| still at 0.1-0.7 where the contact set had moved).
* `cg_on`: conjugate gradients preconditioned by a Cholesky factor (`cloth.solvers.cholesky`),
  for a positive-definite matrix and preconditioner (the tension field): one matrix product and
  one solve per iteration, no basis kept (GMRES keeps up to `KRYLOV_LIMIT` vectors and
  orthogonalises against them). Its residual r = b - A x is updated, not minimised; it is the
  true residual to rounding, and is what the limits below read. A direction of non-positive
  curvature p^T A p <= 0 (the contact curvature term made this matrix indefinite) ends it: the
  caller factorises afresh.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

#: Reuse: GMRES iterations (each one solve with the kept factor) before refactorising, and the
#: relative residual it must reach (tight: Newton's last steps stay quadratic). A solve costs a
#: 40th to a 60th of a factorisation at 100k nodes (issue 12), so up to 30 are worth trying.
KRYLOV_LIMIT = 30
KRYLOV_RTOL = 1e-12
#: GMRES is given up early, from `KRYLOV_CHECK` iterations, where its residual at the mean rate
#: so far would reach the tolerance only past `KRYLOV_PATIENCE` x `KRYLOV_LIMIT` iterations.
#: Measured on the torso (448 x 224 and its levels): the solves that failed at 30 iterations had
#: |r| / |b| at 0.2 after 9-12 with 1e-3 to 1e-5 to reach (projected: 39-64 iterations), the
#: longest that succeeded (22-29 iterations) 0.04-0.2 with 1e-2 to 2e-3 (projected: 12-26).
KRYLOV_CHECK = 10
KRYLOV_PATIENCE = 1.5
#: A kept factor is given up before it is tried where the last Krylov solve on it needed more
#: than KRYLOV_STALE iterations: the matrix only drifts further from it, and the next solve
#: failed at the limit or took longer (measured on the torso at 448 x 224 with cholmod: solves
#: 628 -> 420, factorisations 13 -> 15, the relax 0.87 of the median time of 6 alternating
#: pairs; the equilibrium the same to 3e-15 m).
KRYLOV_STALE = 15
#: Inexact Newton: a reused solve need only reach FORCING x the relative residual (at most
#: KRYLOV_LOOSEST); the forcing term shrinks with the residual, so the last steps stay quadratic.
FORCING = 0.1
KRYLOV_LOOSEST = 1e-2


class _GiveUp(Exception):
    """GMRES would not reach its tolerance within its limit (`_hopeless`)."""


def stale(krylov: list[int]) -> bool:
    """Whether a kept factor is given up before it is tried: the last Krylov solve on it (the
    last of ``krylov``, the iterations of every solve) needed more than `KRYLOV_STALE`."""
    return bool(krylov) and krylov[-1] > KRYLOV_STALE


def _hopeless(residual: float, iterations: int, rtol: float) -> bool:
    """Whether GMRES, at relative residual ``residual`` after ``iterations``, would reach
    ``rtol`` only past `KRYLOV_PATIENCE` x `KRYLOV_LIMIT` iterations at its mean rate so far."""
    if not 0.0 < residual < 1.0:
        return residual >= 1.0
    needed = iterations * np.log(rtol) / np.log(residual)
    return bool(needed > KRYLOV_PATIENCE * KRYLOV_LIMIT)


def gmres_on(
    matrix: sp.csr_matrix, factor, rhs: NDArray[np.float64], rtol: float
) -> tuple[NDArray[np.float64] | None, int]:
    """``matrix^-1 rhs`` by GMRES preconditioned by ``factor`` (any object with ``solve``),
    to relative residual ``rtol`` within `KRYLOV_LIMIT` iterations, or None where it does not
    get there (or would not: `_hopeless`); and the iterations it took."""
    from scipy.sparse.linalg import LinearOperator, gmres

    count = [0]

    def tick(residual: float) -> None:  # |r| / |b| after each iteration
        count[0] += 1
        if count[0] >= KRYLOV_CHECK and _hopeless(residual, count[0], rtol):
            raise _GiveUp

    # dtype given: else LinearOperator finds it by a trial product (a solve, wasted)
    operator = LinearOperator(
        matrix.shape, matvec=lambda y: matrix @ factor.solve(y), dtype=np.float64
    )
    with np.errstate(all="ignore"):
        try:
            y, info = gmres(
                operator,
                rhs,
                rtol=rtol,
                atol=0.0,
                restart=KRYLOV_LIMIT,
                maxiter=1,
                callback=tick,
                callback_type="pr_norm",
            )
        except _GiveUp:
            return None, count[0]
    if info != 0:
        return None, count[0]
    x = factor.solve(y)
    return (x if np.all(np.isfinite(x)) else None), count[0]


def cg_on(
    matrix: sp.csr_matrix, factor, rhs: NDArray[np.float64], rtol: float
) -> tuple[NDArray[np.float64] | None, int]:
    """``matrix^-1 rhs`` by conjugate gradients preconditioned by ``factor`` (``solve``; both
    positive definite), to relative residual ``rtol`` within `KRYLOV_LIMIT` iterations, or None
    where it does not get there (or would not: `_hopeless`, or a direction of non-positive
    curvature); and the iterations it took."""
    norm = float(np.linalg.norm(rhs))
    if norm == 0.0:
        return np.zeros_like(rhs, dtype=np.float64), 0
    x = np.zeros_like(rhs, dtype=np.float64)
    r = np.array(rhs, dtype=np.float64)
    z = factor.solve(r)
    p = z.copy()
    rz = float(r @ z)
    with np.errstate(all="ignore"):
        for iteration in range(1, KRYLOV_LIMIT + 1):
            q = matrix @ p
            curvature = float(p @ q)
            if not (np.isfinite(curvature) and curvature > 0.0 and rz > 0.0):
                return None, iteration
            alpha = rz / curvature
            x += alpha * p
            r -= alpha * q
            residual = float(np.linalg.norm(r)) / norm
            if residual <= rtol:
                return (x if np.all(np.isfinite(x)) else None), iteration
            if iteration >= KRYLOV_CHECK and _hopeless(residual, iteration, rtol):
                return None, iteration
            z = factor.solve(r)
            rz, previous = float(r @ z), rz
            p = z + (rz / previous) * p
    return None, KRYLOV_LIMIT
