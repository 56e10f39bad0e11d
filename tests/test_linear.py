"""Reused factorisations (`cloth.solvers.linear.Reuse`): GMRES preconditioned by a kept factor
answers to the true residual, and a factor that no longer fits is replaced."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from cloth.solvers.krylov import (
    KRYLOV_CHECK,
    KRYLOV_LIMIT,
    KRYLOV_PATIENCE,
    KRYLOV_STALE,
    _hopeless,
    stale,
)
from cloth.solvers.linear import Reuse


def stiff_chain(n: int, stiffness: float = 1e4) -> sp.csr_matrix:
    """A stiff spring chain's matrix (N/m), positive definite: like a Newton matrix's free rows."""
    main = np.full(n, 2.0 * stiffness + 1.0)
    off = np.full(n - 1, -stiffness)
    return sp.diags([off, main, off], [-1, 0, 1], format="csr")


def held(matrix: sp.csr_matrix, rows: np.ndarray) -> sp.csr_matrix:
    """``matrix`` with ``rows`` constrained as a held node's normal is: identity rows and
    columns (1, against stiffnesses of 1e4 N/m)."""
    keep = np.ones(matrix.shape[0])
    keep[rows] = 0.0
    projector = sp.diags(keep)
    return (projector @ matrix @ projector + sp.diags(1.0 - keep)).tocsr()


@pytest.mark.parametrize("release", [False, True], ids=["taken-into-contact", "released"])
def test_a_kept_factor_solves_a_contact_change_to_the_true_residual(release):
    """Nodes taken into contact, or released, change a few rows by four orders of magnitude:
    the kept factor still solves the new system, without a fresh factor, to the true relative
    residual asked. (Left-preconditioned, GMRES minimised |M r|, which a released node's row
    hides: it gave up on one released node, and on the torso stopped with |r| / |b| at 0.1-0.7.)"""
    n = 400
    chain = stiff_chain(n)
    contact = held(chain, np.array([50, 200, 333]))
    first, second = (contact, chain) if release else (chain, contact)
    rhs = np.random.default_rng(1).normal(size=n)
    reuse = Reuse()
    reuse.rtol = 1e-8
    reuse.solve(first, rhs)
    assert reuse.krylov == [0]
    x = reuse.solve(second, rhs)
    assert 0 < reuse.krylov[-1] <= KRYLOV_LIMIT and reuse.krylov.count(0) == 1
    assert np.linalg.norm(second @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_a_factor_whose_last_solve_was_long_is_stale_and_replaced_untried():
    """After a Krylov solve of more than `KRYLOV_STALE` iterations on the kept factor, the next
    system is factorised afresh without trying the old factor (a direct solve, 0 iterations,
    nothing abandoned); after a short one, the kept factor serves."""
    n = 400
    chain = stiff_chain(n)
    contact = held(chain, np.array([50, 200, 333]))
    rhs = np.random.default_rng(4).normal(size=n)
    assert KRYLOV_STALE == 15 and KRYLOV_LIMIT == 30  # docs/solvers.md's values
    assert not stale([]) and not stale([0, 15]) and stale([15, 16]) and not stale([16, 0])
    for last, fresh in ((15, False), (16, True)):
        reuse = Reuse()
        reuse.rtol = 1e-8
        reuse.solve(chain, rhs)
        reuse.krylov.append(last)  # as if the last system had taken ``last`` iterations
        x = reuse.solve(contact, rhs)
        assert (reuse.krylov[-1] == 0) is fresh and reuse.abandoned == []
        assert np.linalg.norm(contact @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_a_factor_that_no_longer_fits_is_replaced():
    """A matrix far from the kept factor's (stiffness a hundredth, a random diagonal): GMRES
    is given up at `KRYLOV_CHECK` iterations (at its rate it would need far more than
    `KRYLOV_LIMIT`) and the matrix is factorised afresh; the answer is exact."""
    n = 400
    reuse = Reuse()
    reuse.rtol = 1e-8
    rhs = np.random.default_rng(2).normal(size=n)
    reuse.solve(stiff_chain(n), rhs)
    other = (stiff_chain(n, 1e2) + sp.diags(np.random.default_rng(3).uniform(1, 1e3, n))).tocsr()
    x = reuse.solve(other, rhs)
    assert reuse.abandoned == [KRYLOV_CHECK] and reuse.krylov == [0, 0]
    assert np.linalg.norm(other @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_gmres_is_given_up_early_only_where_its_mean_rate_misses_the_limit():
    """The projection is iterations x log(rtol) / log(residual) against 1.5 x 30: the solves
    measured on the torso that failed at 30 (0.2 after 12, rtol 1e-3: 51) are given up, those
    that succeeded (0.08 after 10, rtol 9e-3: 19) are not, nor a slow one within reach (0.2
    after 12, rtol 1e-2: 34); a residual that grew is hopeless."""
    assert KRYLOV_PATIENCE * KRYLOV_LIMIT == 45
    assert _hopeless(0.2, 12, 1e-3) and _hopeless(1.5, 10, 1e-2)
    assert not _hopeless(0.08, 10, 9e-3) and not _hopeless(0.2, 12, 1e-2)


def test_cholmod_keeps_its_symbolic_analysis_for_the_same_pattern():
    """CHOLMOD factorises a matrix of the analysed pattern on the kept analysis (the Newton
    matrix's pattern is the grid's), and analyses a new pattern afresh; every answer exact."""
    pytest.importorskip("sksparse")
    n = 300
    rhs = np.random.default_rng(4).normal(size=n)
    reuse = Reuse("cholmod", gmres=False)
    chain = stiff_chain(n)
    stiffer = (chain * 3.0).tocsr()
    for matrix in (chain, stiffer):
        x = reuse.solve(matrix, rhs)
        np.testing.assert_allclose(matrix @ x, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())
        if matrix is chain:
            analysis = reuse.analysis
    assert reuse.analysis is analysis and reuse.krylov == [0, 0]
    wider = (chain + sp.diags(np.full(n - 2, -1.0), 2) + sp.diags(np.full(n - 2, -1.0), -2)).tocsr()
    x = reuse.solve(wider, rhs)
    assert reuse.analysis is not analysis
    np.testing.assert_allclose(wider @ x, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())


def test_pardiso_keeps_its_symbolic_analysis_for_the_same_pattern():
    """Pardiso analyses a pattern once (phase 12) and factorises only the numbers of the next
    matrix of that pattern (phase 22), an indefinite one too (the exact Newton matrix), and
    analyses a new pattern afresh; every answer exact."""
    pytest.importorskip("pypardiso")
    n = 300
    rhs = np.random.default_rng(4).normal(size=n)
    reuse = Reuse("pardiso", gmres=False)
    chain = stiff_chain(n)
    soft = np.zeros(n)
    soft[[40, 41, 200]] = -3e4
    indefinite = (chain + sp.diags(soft)).tocsr()
    wider = (chain + sp.diags(np.full(n - 2, -1.0), 2) + sp.diags(np.full(n - 2, -1.0), -2)).tocsr()
    x = reuse.solve(chain, rhs)
    np.testing.assert_allclose(chain @ x, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())
    solver, phases = reuse.analysis, []
    original = solver.set_phase
    solver.set_phase = lambda phase: (phases.append(phase), original(phase))[1]
    for matrix in (indefinite, wider):
        x = reuse.solve(matrix, rhs)
        np.testing.assert_allclose(matrix @ x, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())
    assert reuse.analysis is solver and reuse.krylov == [0, 0, 0]
    assert [p for p in phases if p != 33] == [22, 12]


def test_cholmod_with_reuse_reaches_superlus_equilibrium():
    """Newton on CHOLMOD with its factor kept (GMRES on the next systems) ends where plain
    SuperLU Newton ends, with fewer factorisations than CHOLMOD without reuse (torso 96 x 48,
    measured 22 and 10)."""
    pytest.importorskip("sksparse")
    from cloth.files.body import body_from_config
    from cloth.solvers import Settings, relax
    from tests.test_continuation import state_on

    state = state_on({"torso": {"size": "M"}}, [96, 48], 0.80, 1.25)
    solid, _ = body_from_config(state.case.body.block)
    results = {}
    for name, reuse in (("superlu", False), ("cholmod", False), ("cholmod", True)):
        settings = Settings(
            tolerance=1e-10,
            max_iterations=60,
            progress=False,
            log_every=0,
            linear_solver=name,
            reuse=reuse,
        )
        results[name, reuse] = relax(state, solid, settings)
        assert results[name, reuse].converged
    assert results["cholmod", True].factorisations < results["cholmod", False].factorisations
    gap = results["cholmod", True].final.x - results["superlu", False].final.x
    assert np.abs(gap).max() < 1e-8


def test_cholmod_solves_the_exact_matrix_through_its_factor_of_the_projected_one():
    """A Cholesky backend factorises the positive definite (projected) matrix and solves the
    exact one, which compressed springs make indefinite, by GMRES preconditioned by that factor:
    the preconditioned operator is the identity plus a rank-5 term here, so GMRES ends within
    6 iterations, with one factorisation and the exact matrix's answer. Where the two are far
    apart, GMRES gives up and SuperLU solves the exact matrix; its factor is kept."""
    pytest.importorskip("sksparse")
    n = 400
    projected = stiff_chain(n)
    soft = np.zeros(n)
    soft[[40, 41, 200, 201, 330]] = -3e4  # five rows softer than zero
    exact = (projected + sp.diags(soft)).tocsr()
    assert np.linalg.eigvalsh(exact.toarray()).min() < 0  # indefinite: no Cholesky
    rhs = np.random.default_rng(5).normal(size=n)
    reuse = Reuse("cholmod", gmres=False)
    reuse.rtol = 1e-10
    x = reuse.solve(exact, rhs, factorise=projected)
    assert 0 < reuse.krylov[-1] <= 6 and reuse.fallbacks == 0
    assert np.linalg.norm(exact @ x - rhs) <= 1e-10 * np.linalg.norm(rhs)
    far = (projected + sp.diags(np.random.default_rng(6).uniform(-3e4, 0.0, n))).tocsr()
    x = reuse.solve(far, rhs, factorise=projected)
    assert reuse.abandoned == [KRYLOV_CHECK] and reuse.fallbacks == 1
    assert np.linalg.norm(far @ x - rhs) <= 1e-10 * np.linalg.norm(rhs)
    assert hasattr(reuse.factor, "L")  # SuperLU's (below DISSECT_FROM, its own order)


def test_newton_on_cholmod_keeps_the_exact_hessians_quadratic_convergence(caplog):
    """Torso S at 25 % reduction, 48 x 24: compressed warp springs make the exact Hessian
    indefinite; Newton on CHOLMOD's projected Hessian alone converged linearly (27 iterations,
    the residual falling 2.5-fold per step). Through GMRES on the exact matrix it converges as
    SuperLU's does: quadratically, in as many iterations (+1), to the same equilibrium, and
    never falls back to SuperLU."""
    pytest.importorskip("sksparse")
    from cloth.files.body import body_from_config
    from cloth.solvers import Settings, relax
    from cloth.stages.case import initial_state
    from tests.conftest import assert_quadratic_tail

    garment = {"bottom": 0.80, "top": 1.25, "reduction": 0.25, "grid": [48, 24], "edges": "sliding"}
    state = initial_state(
        {"material": "powernet", "body": {"torso": {"size": "S"}}, "garment": garment}
    )
    solid, _ = body_from_config(state.case.body.block)
    results = {}
    for name in ("superlu", "cholmod"):
        settings = Settings(
            tolerance=1e-10, max_iterations=40, progress=False, log_every=0, linear_solver=name
        )
        with caplog.at_level("WARNING", logger="cloth.solvers.linear"):
            results[name] = relax(state, solid, settings)
        assert results[name].converged
        assert_quadratic_tail(results[name].history.residual)
    assert "uses superlu" not in caplog.text
    assert results["cholmod"].iterations <= results["superlu"].iterations + 1
    gap = results["cholmod"].final.x - results["superlu"].final.x
    assert np.abs(gap).max() < 1e-8


def test_a_cholesky_preconditioner_is_shifted_until_cholmod_takes_it():
    """The matrix to factorise for a preconditioner is indefinite (smallest eigenvalue -0.5,
    largest diagonal entry 5e4; 10,000 unknowns, so CHOLMOD factorises supernodally and refuses
    it): it is shifted 100-fold from 1e-8 of that entry until CHOLMOD takes it (refused as it
    is and with 5e-4 and 5e-2, taken with 5), and GMRES solves the exact matrix (smallest
    eigenvalue +0.5) with that factor to the residual asked, without SuperLU."""
    pytest.importorskip("sksparse")
    from cloth.solvers.linear import factorisations
    from tests.test_ordering import grid_graph, laplacian

    k = 100
    stiffness = (1e4 * laplacian(grid_graph(k, k))).tocsr()  # smallest eigenvalue 1e4
    factorise = (stiffness - 1.00005e4 * sp.identity(k * k)).tocsr()
    exact = (factorise + sp.identity(k * k)).tocsr()
    rhs = np.random.default_rng(7).normal(size=k * k)
    reuse = Reuse("cholmod", gmres=False)
    reuse.rtol = 1e-10
    before = factorisations()
    x = reuse.solve(exact, rhs, factorise=factorise)
    assert factorisations() - before == 4  # three refused, the fourth taken
    assert reuse.fallbacks == 0 and 0 < reuse.krylov[-1] <= KRYLOV_LIMIT
    assert np.linalg.norm(exact @ x - rhs) <= 1e-10 * np.linalg.norm(rhs)


class _Diagonal:
    """A preconditioner that solves with a diagonal: ``solve(r) = r / d``."""

    def __init__(self, diagonal) -> None:
        self.diagonal = np.asarray(diagonal, dtype=float)

    def solve(self, r):
        return r / self.diagonal


@pytest.mark.parametrize("method", ["cg", "gmres"])
def test_krylov_on_k_distinct_eigenvalues_takes_k_iterations(method):
    """Without preconditioning (identity), a matrix with 3 distinct eigenvalues is solved in
    exactly 3 Krylov iterations; with its own inverse as the preconditioner in 1."""
    from cloth.solvers.krylov import cg_on, gmres_on

    solve = cg_on if method == "cg" else gmres_on
    diagonal = np.repeat([1.0, 4.0, 9.0], 20)
    matrix = sp.diags(diagonal, format="csr")
    rhs = np.random.default_rng(5).normal(size=60)
    x, iterations = solve(matrix, _Diagonal(np.ones(60)), rhs, 1e-10)
    assert iterations == 3
    np.testing.assert_allclose(x, rhs / diagonal, rtol=1e-9)
    x, iterations = solve(matrix, _Diagonal(diagonal), rhs, 1e-10)
    assert iterations == 1 and x.dtype == np.float64
    np.testing.assert_allclose(x, rhs / diagonal, rtol=1e-12)


def test_cg_gives_up_on_negative_curvature_and_past_its_limit_and_answers_zero_at_once():
    from cloth.solvers.krylov import cg_on

    rhs = np.random.default_rng(6).normal(size=40)
    assert cg_on(-sp.identity(40, format="csr"), _Diagonal(np.ones(40)), rhs, 1e-8) == (None, 1)
    spread = sp.diags(np.geomspace(1.0, 1e6, 40), format="csr")  # 40 eigenvalues, 1e6 apart
    x, iterations = cg_on(spread, _Diagonal(np.ones(40)), rhs, 1e-14)
    assert x is None and KRYLOV_CHECK <= iterations <= KRYLOV_LIMIT
    x, iterations = cg_on(spread, _Diagonal(np.ones(40)), np.zeros(40, dtype=int), 1e-8)
    assert iterations == 0 and x.dtype == np.float64 and x.shape == (40,) and not x.any()


def test_gmres_gives_up_where_it_would_not_reach_its_tolerance():
    from cloth.solvers.krylov import gmres_on

    rhs = np.random.default_rng(7).normal(size=40)
    spread = sp.diags(np.geomspace(1.0, 1e6, 40), format="csr")
    x, iterations = gmres_on(spread, _Diagonal(np.ones(40)), rhs, 1e-14)
    assert x is None and KRYLOV_CHECK <= iterations <= KRYLOV_LIMIT


@pytest.mark.parametrize(
    ("residual", "iterations", "rtol", "hopeless"),
    [
        (1.0, 10, 1e-3, True),  # no progress at all
        (0.999, 10, 1e-3, True),
        (0.0, 10, 1e-3, False),  # converged
        (0.1, 9, 1e-5, False),  # needs exactly 45 = 1.5 x 30 at its rate: not past the limit
        (0.1, 9, 1e-6, True),  # 54
    ],
)
def test_hopeless_is_a_projection_past_one_and_a_half_times_the_limit(
    residual, iterations, rtol, hopeless
):
    assert _hopeless(residual, iterations, rtol) is hopeless


@pytest.mark.parametrize("method", ["cg", "gmres"])
def test_krylov_stops_at_its_limit_and_answers_on_its_last_iteration(method):
    """Unpreconditioned, 40 eigenvalues in 1-10 to 1e-12: the mean rate projects 42 iterations
    at the 10th (not past 45: kept going), and the solve stops at the limit, exactly 30, with no
    answer; 40 eigenvalues in 1-5 to 1e-14 converge on the 30th iteration exactly, which
    answers (GMRES in one cycle of 30: no restart)."""
    from cloth.solvers.krylov import cg_on, gmres_on

    solve = cg_on if method == "cg" else gmres_on
    rhs = np.random.default_rng(1).normal(size=40)
    slow = sp.diags(np.geomspace(1.0, 10.0, 40), format="csr")
    assert solve(slow, _Diagonal(np.ones(40)), rhs, 1e-12) == (None, KRYLOV_LIMIT)
    diagonal = np.geomspace(1.0, 5.0, 40)
    x, iterations = solve(sp.diags(diagonal, format="csr"), _Diagonal(np.ones(40)), rhs, 1e-14)
    assert iterations == KRYLOV_LIMIT
    np.testing.assert_allclose(x, rhs / diagonal, rtol=1e-12)
