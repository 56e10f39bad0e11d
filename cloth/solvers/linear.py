"""Sparse linear solvers for Newton's step, chosen by name; `auto` picks by what the case is.

* ``superlu`` (scipy, always there): LU in nested-dissection order (`cloth.solvers.ordering`),
  no pivoting and symmetric mode; faster than scipy's defaults on these symmetric systems
  (DESIGN.md 10; MMD(A^T + A) ~2x, nested dissection another 2.4x at 100k nodes).
* ``cholespy`` (a dependency; `cloth.solvers.cholesky`): sparse Cholesky of the Newton matrix
  where it is positive definite, and with ``reuse`` conjugate gradients on the kept factor; a
  system that is not positive definite (the contact curvature term far from equilibrium) is
  factorised by SuperLU instead (`lu_fallbacks` counts those).
* ``cholmod`` (scikit-sparse, optional; needs SuiteSparse): sparse Cholesky of the
  PSD-projected matrix, its symbolic analysis kept per pattern, as a preconditioner for GMRES
  on the exact one.
* ``pardiso`` (pypardiso, optional; x86-64, ~940 MB of MKL): LU of the exact matrix, its
  symbolic analysis kept per pattern (`Reuse._pardiso`).
* ``amg`` (pyamg, optional): conjugate gradients preconditioned by smoothed-aggregation AMG.

``auto`` takes cholmod where the ``cholmod`` extra is installed, else cholespy, where the case's
Newton matrix is positive definite by construction (`cloth.solvers.relax.positive_definite`: a
convex spring energy, every curve tension-only, and no skin model): CHOLMOD with the system's
OpenBLAS and its analysis kept refactorises the 100k-node torso's matrix in 1.1-1.3 s, cholespy
(its own ordering, the reference BLAS of its wheel) in about 4 s. Otherwise ``auto`` prefers
pardiso, then superlu: both take the exact Hessian, which is indefinite where
compressed springs soften the fabric or the contact curvature term outweighs it. There cholmod
and amg only on request: Cholesky and CG need the PSD-projected Hessian, and a step whose matrix is
still indefinite falls back to superlu; with cholmod as ``auto`` (before the tension field
was the default), the torso-mesh cases lost their quadratic convergence (measured: 5e-9 after
8e-6) and logged a fallback every few steps; amg's setup also costs seconds on small grids. The
tests run every installed backend against superlu; superlu, cholespy and amg always (amg is in
the test extra), pardiso where the ``pardiso`` extra is installed (checked with pypardiso
0.4.7, MKL 2026.2), cholmod where the ``cholmod`` extra is (scikit-sparse 0.4.16 against
Debian's SuiteSparse 5.12; 0.5 does not build against it).
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import logging
from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.solvers.cholesky import CholeskyFactor, NotPositiveDefinite, cholesky_factor
from cloth.solvers.krylov import KRYLOV_RTOL, cg_on, gmres_on, stale
from cloth.solvers.ordering import reordering_for
from cloth.solvers.reduced import ReducedFactor, reduction

log = logging.getLogger(__name__)

#: What a `PRECONDITIONED` backend factorises for a Newton matrix: the matrix, or a function that
#: assembles it (called only where a new factor is needed: a step GMRES solves on the kept one
#: never assembles it).
Factorise = sp.csr_matrix | Callable[[], sp.csr_matrix]

PACKAGES = {"cholespy": "cholespy", "cholmod": "sksparse", "pardiso": "pypardiso", "amg": "pyamg"}
#: The module that loads each backend's native libraries (and its BLAS).
BACKEND_MODULES = {
    "cholespy": "cholespy",
    "cholmod": "sksparse.cholmod",
    "pardiso": "pypardiso",
    "amg": "pyamg",
}
#: What ``auto`` takes, the first installed: backends that take the exact, indefinite Hessian.
AUTO = ("pardiso", "superlu")
#: What ``auto`` takes first where the Newton matrix is positive definite by construction, the
#: first installed: cholmod (an extra; the projected matrix's factor, which with the tension
#: field differs from the exact one by the contact curvature term alone, preconditions GMRES)
#: and cholespy (a dependency; the exact matrix, LU where it is not positive definite).
SPD = ("cholmod", "cholespy")
#: Backends that solve symmetric indefinite systems (Newton then uses the exact Hessian):
#: cholespy through its LU fallback.
INDEFINITE = ("superlu", "pardiso", "cholespy")
INSTALL = {
    "cholespy": "cholespy",
    "cholmod": "scikit-sparse",
    "pardiso": "pypardiso",
    "amg": "pyamg",
}
#: Backends that factorise each system themselves, with no analysis kept: ``solve`` without
#: `Reuse` goes through `_solve`, and ``keep`` gets their factor.
DIRECT = ("superlu", "cholespy")
#: Backends whose factor `Reuse` keeps.
REUSABLE = ("superlu", "cholespy", "cholmod", "pardiso")
#: Backends that keep their symbolic analysis (the fill-reducing ordering and the factor's
#: structure) for the next matrix of the same pattern, and factorise only the numbers: always,
#: with or without ``reuse`` (the Newton matrix's pattern is the grid's).
ANALYSED = ("cholmod", "pardiso")
#: Backends that take the exact Hessian through GMRES preconditioned by their (Cholesky) factor
#: of the PSD-projected one (`Reuse.solve`'s ``factorise``).
PRECONDITIONED = ("cholmod",)


def available(name: str) -> bool:
    return name == "superlu" or importlib.util.find_spec(PACKAGES[name]) is not None


def blas_threads(limit: int | None, name: str) -> contextlib.AbstractContextManager:
    """A context in which every BLAS library loaded, the linear solver ``name``'s own among
    them (imported first: CHOLMOD loads the system's BLAS), uses at most ``limit`` threads
    (None: no limit). Measured on 2 cores (docs/solvers.md): numpy's and CHOLMOD's OpenBLAS
    threads spin-wait against each other and the solver's own work; with one thread each, the
    torso at 448 x 224 relaxed on cholmod in 0.72 of the time (superlu: the same)."""
    if limit is None:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    if name in PACKAGES and available(name):
        importlib.import_module(BACKEND_MODULES[name])
    return threadpool_limits(limits=limit, user_api="blas")


def choose(name: str, positive_definite: bool = False) -> str:
    """The solver that ``name`` means here, for a case whose Newton matrix is
    ``positive_definite`` by construction (`cloth.solvers.relax.positive_definite`) or not; an
    error when it is not installed."""
    if name == "auto":
        return next(s for s in (SPD + AUTO if positive_definite else AUTO) if available(s))
    if not available(name):
        raise InputError(
            f"linear solver {name!r} is not installed; pip install {INSTALL[name]} or use "
            "superlu (always available) or auto",
            field="linear_solver",
        )
    return name


#: The first shift (x the largest diagonal entry) tried where CHOLMOD finds the matrix it is to
#: factorise for a preconditioner not positive definite (`Reuse._preconditioner`).
PRECONDITIONER_SHIFT = 1e-8


class Reuse:
    """A factorisation kept for the next Newton systems (``solver: {reuse: true}``; SuperLU,
    cholespy, CHOLMOD or Pardiso, ``backend``).

    A system of the same size is solved by GMRES preconditioned by the kept factor
    (`cloth.solvers.krylov.gmres_on`), or by conjugate gradients where the factor is cholespy's
    Cholesky factor (`cloth.solvers.krylov.cg_on`); when the Krylov solve needs more than its
    `KRYLOV_LIMIT` iterations to reach its tolerance (or would, at its rate so far), the matrix
    is factorised afresh and kept; so is it, untried, where the last solve on the kept factor
    needed more than `KRYLOV_STALE` iterations (`cloth.solvers.krylov.stale`). A factor costs
    40-60 solves at 100k nodes (issue 12), so a Newton step that reuses one costs a few solves
    instead of a factorisation.
    ``krylov`` lists the Krylov iterations of every solve (0 for a direct solve with a fresh
    factor of the matrix itself), ``abandoned`` those of the attempts given up. With ``gmres``
    False every system is factorised (CHOLMOD and Pardiso still keep their symbolic analysis:
    the Newton matrix's pattern is the grid's, so only the numbers are factorised again)."""

    def __init__(self, backend: str = "superlu", gmres: bool = True) -> None:
        self.backend = backend
        self.gmres = gmres
        self.factor = None
        self.size = -1
        self.krylov: list[int] = []
        self.abandoned: list[int] = []
        self.fallbacks = 0  # systems SuperLU solved where GMRES on ``factorise``'s factor failed
        self.rtol = KRYLOV_RTOL
        self.analysis = None  # CHOLMOD's symbolic factor, and the pattern it is of
        self.pattern: tuple[NDArray, NDArray] | None = None

    def solve(
        self,
        matrix: sp.csr_matrix,
        rhs: NDArray[np.float64],
        factorise: Factorise | None = None,
        projector: NDArray[np.float64] | None = None,
    ) -> NDArray[np.float64]:
        """``matrix^-1 rhs``: by GMRES on the kept factor where it serves, else from a fresh
        factor. ``factorise``: the matrix to factorise instead, or its assembly (`Factorise`;
        CHOLMOD: the PSD-projected Newton matrix, positive definite where ``matrix``, the exact
        one, need not be);
        ``matrix`` is then solved by GMRES preconditioned by that factor, and where GMRES
        fails there too, by SuperLU (``fallbacks`` counts those). ``projector``: the
        projector blocks ((N, 3, 3)) ``matrix`` was built on, for cholespy's reduced factor
        (`spd_factor`)."""
        kept = self.gmres and self.factor is not None and matrix.shape[0] == self.size
        if kept and not stale(self.krylov):
            x = self._krylov(matrix, rhs)
            if x is not None:
                return x
        self.factor = None  # let the old factor go before the new one is built (peak memory)
        if factorise is None:
            self.factor = self._fresh(matrix, projector)
        else:
            self.factor = self._preconditioner(factorise() if callable(factorise) else factorise)
        self.size = matrix.shape[0]
        if factorise is not None:
            x = self._krylov(matrix, rhs)
            if x is not None:
                return x
            # the exact matrix is too far from the projected one (measured on the torso at
            # 100k nodes, near the equilibrium: 30 iterations left |r| / |b| at 0.9): SuperLU
            # factorises the exact one, and its factor is kept for the next systems
            self.fallbacks += 1
            log.debug("GMRES on the Cholesky preconditioner gave up; SuperLU factorises")
            self.factor = None
            self.factor = lu_factor(matrix)
        self.krylov.append(0)
        return _direct(self.factor, rhs)

    def _fresh(self, matrix: sp.csr_matrix, projector: NDArray[np.float64] | None = None):
        """The backend's factor of ``matrix`` (counted); cholespy's on the moves ``projector``
        allows (`spd_factor`)."""
        if self.backend == "cholespy":
            return spd_factor(matrix, projector)
        if self.backend == "cholmod":
            return self._cholmod(matrix)
        if self.backend == "pardiso":
            return self._pardiso(matrix)
        return lu_factor(matrix)

    def _same_pattern(self, matrix: sp.csr_matrix | sp.csc_matrix) -> bool:
        """Whether ``matrix`` (indices sorted) has the analysed pattern; it is kept if not."""
        same = self.pattern is not None and (
            np.array_equal(self.pattern[0], matrix.indptr)
            and np.array_equal(self.pattern[1], matrix.indices)
        )
        if not same:
            self.pattern = (matrix.indptr.copy(), matrix.indices.copy())
        return same

    def _krylov(self, matrix: sp.csr_matrix, rhs: NDArray[np.float64]) -> NDArray | None:
        """`cloth.solvers.krylov.cg_on` a kept Cholesky factor (cholespy's), else
        `cloth.solvers.krylov.gmres_on` the kept factor, to ``rtol``: the answer (its
        iterations in ``krylov``) or None (in ``abandoned``)."""
        global _solves
        cholesky = isinstance(getattr(self.factor, "inner", self.factor), CholeskyFactor)
        krylov = cg_on if cholesky else gmres_on
        x, iterations = krylov(matrix, self.factor, rhs, self.rtol)
        _solves += iterations
        (self.krylov if x is not None else self.abandoned).append(iterations)
        return x

    def _preconditioner(self, matrix: sp.csr_matrix):
        """A factor of ``matrix`` (the projected Newton matrix), or of ``matrix`` + s I where
        CHOLMOD finds it not positive definite (a preconditioner need only be near; Newton's
        projected matrix without the curvature term is PSD plus 1e-10 of its largest diagonal
        entry, so this is a safety net): s from `PRECONDITIONER_SHIFT` x that entry, 100-fold,
        up to 1e-2 x it (beyond, the error goes up: `solve` then takes SuperLU). Another
        backend factorises ``matrix`` as it is (`_fresh`)."""
        if self.backend != "cholmod":
            return self._fresh(matrix)
        from sksparse.cholmod import CholmodNotPositiveDefiniteError

        scale = float(np.abs(matrix.diagonal()).max() or 1.0)
        shift = 0.0
        while True:
            try:
                shifted = matrix if shift == 0.0 else matrix + shift * sp.identity(matrix.shape[0])
                return self._cholmod(sp.csr_matrix(shifted))
            except CholmodNotPositiveDefiniteError:
                shift = PRECONDITIONER_SHIFT * scale if shift == 0.0 else 100.0 * shift
                if shift > 1e-2 * scale:
                    raise

    def _cholmod(self, matrix: sp.csr_matrix) -> _Cholesky:
        """CHOLMOD's factor of ``matrix`` (counted), on the kept symbolic analysis when the
        pattern is the analysed one's (raises CholmodNotPositiveDefiniteError where the matrix
        is not positive definite)."""
        from sksparse.cholmod import analyze

        global _factorisations
        _factorisations += 1
        csc = matrix.tocsc()
        csc.sort_indices()
        if not self._same_pattern(csc):
            self.analysis = None
            self.analysis = analyze(csc)
        self.analysis.cholesky_inplace(csc)
        return _Cholesky(self.analysis)

    def _pardiso(self, matrix: sp.csr_matrix) -> _Pardiso:
        """Pardiso's LU factor of ``matrix`` (counted; real unsymmetric, pypardiso's tested
        type), on the kept symbolic analysis (phase 22, numbers only) when the pattern is the
        analysed one's, else analysed afresh (phase 12). Measured at 448 x 224 on the torso's
        exact Newton matrices (MKL 2026.2, 2 threads): analysis and factorisation 2.1-2.9 s,
        the numbers alone 1.1-1.7 s. MKL's memory for it is freed with this `Reuse`."""
        import weakref

        from pypardiso import PyPardisoSolver

        global _factorisations
        _factorisations += 1
        csr = sp.csr_matrix(matrix, dtype=np.float64)
        csr.sort_indices()
        if self.analysis is None:
            self.analysis = PyPardisoSolver(mtype=11)
            weakref.finalize(self, self.analysis.free_memory, True)
        same = self._same_pattern(csr)
        self.analysis._check_A(csr)  # CSR, indices sorted, no empty row
        # phases other than pypardiso's factorize (12) and solve (13, 33) go through its
        # _call_pardiso, the call those make
        self.analysis.set_phase(22 if same else 12)
        self.analysis._call_pardiso(csr, np.zeros((csr.shape[0], 1), order="F"))
        return _Pardiso(self.analysis, csr)


class _Pardiso:
    """Pardiso's current factor (of ``matrix``) with SuperLU's ``solve``."""

    def __init__(self, solver, matrix: sp.csr_matrix) -> None:
        self.solver = solver
        self.matrix = matrix

    def solve(self, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
        self.solver.set_phase(33)
        b = np.asfortranarray(np.asarray(rhs, dtype=np.float64).reshape(len(rhs), -1))
        return self.solver._call_pardiso(self.matrix, b).reshape(np.shape(rhs))


class _Cholesky:
    """A CHOLMOD factor with SuperLU's ``solve``."""

    def __init__(self, factor) -> None:
        self.factor = factor

    def solve(self, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.factor(rhs)


def solve(
    matrix: sp.csr_matrix,
    rhs: NDArray[np.float64],
    name: str,
    reuse: Reuse | None = None,
    factorise: Factorise | None = None,
    keep: list | None = None,
    projector: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Solve ``matrix @ x = rhs`` (symmetric) with solver ``name`` (already `choose`n), or with
    ``reuse``'s kept factor (`Reuse`: SuperLU, CHOLMOD or Pardiso); ``factorise``: the
    positive definite matrix a `PRECONDITIONED` backend factorises instead, or its assembly
    (`Reuse.solve`). ``keep`` (a list) gets the factor of ``matrix`` itself where the solve
    made or used a fresh one (its inertia, `cloth.solvers.stability`): SuperLU's unpivoted LU,
    or a `CholeskyFactor` (cholespy's; no negative eigenvalue). ``projector``: the projector
    blocks ((N, 3, 3)) ``matrix`` was built on, for cholespy's reduced factor (`spd_factor`).

    An iterative or Cholesky backend can fail where the matrix is not positive definite (the
    curvature term of contact can make it indefinite far from equilibrium): that step is then
    solved by SuperLU, with a warning.
    """
    if reuse is None and name in ANALYSED:  # one factorisation, through the same code
        reuse = Reuse(name, gmres=False)
    if name in DIRECT:
        if reuse is None:
            return _solve(matrix, rhs, name, keep, projector)
        x = reuse.solve(matrix, rhs, projector=projector)
        if keep is not None and reuse.krylov[-1:] == [0]:  # a fresh factor of this matrix
            keep.append(reuse.factor)
        return x
    try:
        if reuse is not None and name in REUSABLE:
            return reuse.solve(matrix, rhs, factorise)
        return _solve(matrix, rhs, name)
    except Exception as exc:  # CG non-convergence, CHOLMOD not-positive-definite, ...
        log.warning("linear solver %s failed (%s); this step uses superlu", name, exc)
        return _solve(matrix, rhs, "superlu")


_factorisations = 0
_lu_fallbacks = 0
_solves = 0


def factorisations() -> int:
    """Linear systems factorised so far in this process (an AMG setup counts as one, a failed
    attempt too): `cloth.solvers.relax` records the difference over a run."""
    return _factorisations


def solves() -> int:
    """Newton systems' solves with a factor so far in this process: a direct solve counts one,
    a Krylov solve on a kept factor its iterations (each one solve with the factor)."""
    return _solves


def _direct(factor, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
    """``factor.solve(rhs)``, counted in `solves`."""
    global _solves
    _solves += 1
    return factor.solve(rhs)


def lu_fallbacks() -> int:
    """Systems so far in this process that cholespy found not positive definite and SuperLU
    factorised instead (`spd_factor`): `cloth.solvers.relax` records the difference."""
    return _lu_fallbacks


def spd_factor(
    matrix: sp.csr_matrix, projector: NDArray[np.float64] | None = None
) -> CholeskyFactor | ReducedFactor | object:
    """cholespy's Cholesky factor of ``matrix`` (counted), or where it is not positive definite
    SuperLU's LU of it (`lu_factor`; both attempts counted, and the fallback in
    `lu_fallbacks`). Given the ``projector`` blocks ((N, 3, 3)) Newton's ``matrix`` was built
    on, the Cholesky factor is of the reduced matrix on the moves they allow, wrapped as a
    factor of ``matrix`` (`cloth.solvers.reduced`: a third of the work where most nodes are
    held); the LU, where it is needed, is of the whole matrix."""
    global _factorisations
    _factorisations += 1
    basis = None if projector is None else reduction(projector)
    if basis is None:
        return _cholesky_or_lu(matrix)
    reduced, complement = basis.reduce(matrix)
    try:
        return ReducedFactor(cholesky_factor(reduced), basis, complement)
    except NotPositiveDefinite:
        # SuperLU factorises the whole matrix: its nested-dissection order is of the grid's
        # nodes, kept per grid; the reduced matrix's would be of its unknowns, made afresh for
        # each held set and worse (448 x 224: 2.3 s to order, 3.3 s to factorise, against
        # 2.7 s for the whole matrix in its kept order)
        return _lu_instead(matrix)


def _cholesky_or_lu(matrix: sp.spmatrix) -> CholeskyFactor | object:
    """cholespy's factor of ``matrix``, or SuperLU's where it is not positive definite."""
    try:
        return cholesky_factor(matrix)
    except NotPositiveDefinite:
        return _lu_instead(matrix)


def _lu_instead(matrix: sp.spmatrix):
    """SuperLU's factor of ``matrix``, which Cholesky found not positive definite (counted in
    `lu_fallbacks`)."""
    global _lu_fallbacks
    _lu_fallbacks += 1
    log.debug("the Newton matrix is not positive definite; SuperLU factorises it")
    return lu_factor(matrix)


#: Unknowns from which SuperLU factorises in nested-dissection order; below, its own
#: minimum-degree order is as fast (4,608 nodes: 1.07 of its time, docs/performance.md) and the
#: ordering, recomputed where the contact set changes the pattern, would cost more than it
#: saves (measured: a tissue test at 1.7x the time).
DISSECT_FROM = 30_000


def lu_factor(matrix: sp.csr_matrix, dissect: bool | None = None):
    """SuperLU's factor of ``matrix`` (counted; a SuperLU object or a `PermutedLU`, both with
    ``solve(rhs)``), tuned for these symmetric systems: no
    pivoting, symmetric mode, and from `DISSECT_FROM` unknowns (or where ``dissect``) in the
    nested-dissection order of its node graph (`cloth.solvers.ordering`; 2.4x faster to
    factorise at 100k nodes than SuperLU's minimum degree, MMD(A^T + A), taken below). Public:
    the adjoint, the saddle-point solve and the stability count (inertia) factorise through it."""
    from scipy.sparse.linalg import splu

    global _factorisations
    _factorisations += 1
    if not (matrix.shape[0] >= DISSECT_FROM if dissect is None else dissect):
        return splu(
            sp.csc_matrix(matrix),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    csc = sp.csc_matrix(matrix)
    csc.sort_indices()
    reordering = reordering_for(csc)
    lu = splu(
        reordering.apply(csc),
        permc_spec="NATURAL",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )
    return PermutedLU(lu, reordering.order)


class PermutedLU:
    """A factor of P A P^T (``order`` the permutation P's rows) with ``solve`` for A."""

    def __init__(self, lu, order: NDArray[np.intp]) -> None:
        self.lu = lu
        self.order = order

    def solve(self, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
        x = np.empty_like(rhs, dtype=np.result_type(rhs, np.float64))
        x[self.order] = self.lu.solve(np.asarray(rhs)[self.order])
        return x


def _solve(
    matrix: sp.csr_matrix,
    rhs: NDArray[np.float64],
    name: str,
    keep: list | None = None,
    projector: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    global _factorisations
    if name in DIRECT:
        factor = lu_factor(matrix) if name == "superlu" else spd_factor(matrix, projector)
        if keep is not None:
            keep.append(factor)
        return _direct(factor, rhs)
    _factorisations += 1
    if name == "amg":  # cholmod and pardiso factorise through `Reuse` (their analysis kept)
        import pyamg
        from scipy.sparse.linalg import cg

        hierarchy = pyamg.smoothed_aggregation_solver(matrix.tocsr(), max_coarse=500)
        x, info = cg(matrix, rhs, rtol=1e-12, maxiter=2000, M=hierarchy.aspreconditioner())
        if info != 0:
            raise RuntimeError(f"AMG-preconditioned CG did not converge (info {info})")
        return x
    raise InputError(f"unknown linear solver {name!r}", field="linear_solver")
