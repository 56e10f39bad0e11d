"""The relaxation settings: the case's ``solver`` block."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cloth.errors import InputError

METHODS = ("explicit", "newton", "explicit+newton")
LINEAR_SOLVERS = ("auto", "superlu", "cholespy", "cholmod", "pardiso", "amg")


@dataclass(frozen=True)
class Settings:
    """Relaxation settings (the case's ``solver`` block).

    Attributes
    ----------
    method : {'explicit', 'newton', 'explicit+newton'}
    tolerance : float
        Stop when the relative residual (`cloth.solvers.common`) is at most this.
    max_iterations : int
        Iteration limit (of each phase for explicit+newton).
    linear_solver : {'auto', 'superlu', 'cholespy', 'cholmod', 'pardiso', 'amg'}
        Newton's sparse solver; auto takes cholmod where installed, else cholespy (sparse
        Cholesky), where the case's Newton matrix is positive definite by construction (the
        tension field, no skin model), else pardiso where installed, else superlu
        (`cloth.solvers.linear.choose`).
    warm_start : int
        Explicit iterations before Newton in explicit+newton.
    log_every : int
        Log a line every this many iterations (0: never).
    progress : bool or None
        tqdm progress bar; None = only when stderr is a terminal.
    continuation : bool
        Start from the equilibrium of coarser grids of the same pattern
        (`cloth.solvers.continuation`).
    coarsest : int
        With continuation: coarsen until at most this many nodes.
    reuse : bool
        Keep the factor for the next Newton systems, solved by GMRES preconditioned with it
        (conjugate gradients on cholespy's Cholesky factor; `cloth.solvers.linear.Reuse`);
        refactorise when the Krylov solve needs too many iterations.
    leave_saddles : bool
        Where Newton converges to a saddle, move along its unstable modes and converge again
        (`cloth.solvers.saddle`); off by default.
    blas_threads : int or None
        Threads each BLAS library may use while relaxing (None: the libraries' own choice).
        1 by default: numpy's OpenBLAS and CHOLMOD's spin-wait against each other and against
        the solver's own work (docs/solvers.md: cholmod 0.72 of the time on 2 cores).
    """

    method: str = "newton"
    tolerance: float = 1e-8
    max_iterations: int = 300
    linear_solver: str = "auto"
    warm_start: int = 20
    log_every: int = 10
    progress: bool | None = None
    continuation: bool = False
    coarsest: int = 5000
    reuse: bool = False
    leave_saddles: bool = False
    blas_threads: int | None = 1

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(
                f"unknown method {self.method!r}; use one of {', '.join(METHODS)}",
                field="method",
            )
        if self.linear_solver not in LINEAR_SOLVERS:
            raise InputError(
                f"unknown linear solver {self.linear_solver!r}; use one of "
                f"{', '.join(LINEAR_SOLVERS)}",
                field="linear_solver",
            )
        if not (np.isfinite(self.tolerance) and self.tolerance > 0):
            raise InputError(
                f"tolerance must be a positive number, got {self.tolerance}", field="tolerance"
            )
        if self.blas_threads is not None and not (
            isinstance(self.blas_threads, int) and self.blas_threads >= 1
        ):
            raise InputError(
                f"blas_threads must be a whole number >= 1 or null, got {self.blas_threads!r}",
                field="blas_threads",
            )
        if self.max_iterations < 1:
            raise InputError(
                f"max_iterations must be >= 1, got {self.max_iterations}", field="max_iterations"
            )
