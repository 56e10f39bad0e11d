"""Newton's matrix factorised on the moves the constraints allow (`cloth.solvers.reduced`): the
factor is exact for the whole matrix, shifted or not, keeps the inertia, and is what the
positive-definite path factorises on a body."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from cloth.solvers import linear
from cloth.solvers.cholesky import CholeskyFactor
from cloth.solvers.linear import spd_factor
from cloth.solvers.reduced import ReducedFactor, reduction
from cloth.solvers.stability import factor_inertia, negative_direction

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("cholespy") is None, reason="cholespy is not installed"
)
MU = 1e-6  # the regulariser of these systems (Newton's: 1e-10 x the largest diagonal entry)


def projectors(count: int, rng: np.random.Generator) -> np.ndarray:
    """(count, 3, 3) projector blocks of every kind a grid has: free (I), held (I - n n^T),
    held on a line (a sliding node held by the body: one direction), fixed (0)."""
    blocks = np.empty((count, 3, 3))
    kinds = rng.integers(0, 4, count)
    normal = rng.normal(size=(count, 3))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    line = np.cross(normal, (0.0, 0.0, 1.0))
    line /= np.linalg.norm(line, axis=1)[:, None]
    blocks[kinds == 0] = np.eye(3)
    plane = np.eye(3) - np.einsum("ni,nj->nij", normal, normal)
    blocks[kinds == 1] = plane[kinds == 1]
    blocks[kinds == 2] = np.einsum("ni,nj->nij", line, line)[kinds == 2]
    blocks[kinds == 3] = 0.0
    return blocks


def stiffness(count: int, rng: np.random.Generator, shift: float = 0.0) -> sp.csr_matrix:
    """A chain of ``count`` nodes joined by random positive semi-definite 3 x 3 springs (N/m),
    less ``shift`` x I: like a fabric's stiffness, indefinite for a large enough shift."""
    rows, cols, values = [], [], []
    for i in range(count - 1):
        a = rng.normal(size=(3, 3))
        block = 1e3 * a @ a.T
        for (r, c), sign in (((i, i), 1), ((i + 1, i + 1), 1), ((i, i + 1), -1), ((i + 1, i), -1)):
            rr, cc = np.meshgrid(3 * r + np.arange(3), 3 * c + np.arange(3), indexing="ij")
            rows.append(rr.ravel())
            cols.append(cc.ravel())
            values.append(sign * block.ravel())
    size = 3 * count
    k = sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), (size, size)
    )
    return (k - shift * sp.identity(size)).tocsr()


def newton(k: sp.csr_matrix, blocks: np.ndarray, mu: float = MU) -> sp.csr_matrix:
    """Newton's matrix P K P + (I - P) + mu I (`cloth.solvers.newton.newton_matrix`)."""
    count = len(blocks)
    p = sp.block_diag(list(blocks), format="csr")
    identity = sp.identity(3 * count, format="csr")
    return (p @ k @ p + (identity - p) + mu * identity).tocsr()


@pytest.mark.parametrize("shift", [0.0, 0.37], ids=["newton", "levenberg-shifted"])
def test_the_reduced_factor_solves_the_whole_newton_matrix_exactly(shift):
    """Whatever the mix of free, held, sliding and fixed nodes, and with a Levenberg-Marquardt
    shift s I on top (which the dropped directions' diagonal carries, 1 + mu + s): the
    reduced factor's answer is M^-1 b to rounding, for one right-hand side or several."""
    rng = np.random.default_rng(3)
    blocks = projectors(60, rng)
    matrix = (newton(stiffness(60, rng), blocks) + shift * sp.identity(180)).tocsr()
    factor = spd_factor(matrix, blocks)
    assert isinstance(factor, ReducedFactor) and isinstance(factor.inner, CholeskyFactor)
    ranks = int(np.round(np.trace(blocks, axis1=1, axis2=2).sum()))
    assert factor.basis.size == ranks < 180
    rhs = rng.normal(size=(180, 2))
    x = factor.solve(rhs)
    assert x.shape == rhs.shape
    assert np.linalg.norm(matrix @ x - rhs) <= 1e-12 * np.linalg.norm(rhs)
    np.testing.assert_allclose(factor.solve(rhs[:, 1]), x[:, 1], rtol=0, atol=1e-13)
    np.testing.assert_allclose(x[:, 0], spla.spsolve(matrix.tocsc(), rhs[:, 0]), atol=1e-12)


def test_blocks_that_are_not_orthogonal_projectors_or_drop_nothing_are_not_reduced():
    rng = np.random.default_rng(4)
    k = stiffness(20, rng)
    free = np.broadcast_to(np.eye(3), (20, 3, 3))
    assert reduction(free) is None  # nothing to drop
    assert reduction(0.5 * free) is None  # not idempotent
    skew = projectors(20, rng)
    skew[3, 0, 1] += 0.1  # not symmetric
    assert reduction(skew) is None
    matrix = newton(k, free)
    assert isinstance(spd_factor(matrix, free), CholeskyFactor)  # the whole matrix, as before


def test_a_reduced_factor_keeps_the_inertia_and_the_unstable_direction():
    """An indefinite stiffness: a reduced factor whose inner factor is SuperLU's LU of
    T^T M T has the whole matrix's negative eigenvalues as its negative pivots (the dropped
    ones are 1 + mu), and its lifted direction has negative curvature for the whole matrix.
    `spd_factor`, refused by Cholesky, factorises the whole matrix by LU, with the same count."""
    rng = np.random.default_rng(5)
    blocks = projectors(40, rng)
    matrix = newton(stiffness(40, rng, shift=150.0), blocks)
    negative = int(np.sum(np.linalg.eigvalsh(matrix.toarray()) < 0.0))
    assert negative > 0
    before = linear.lu_fallbacks()
    whole = spd_factor(matrix, blocks)
    assert not isinstance(whole, ReducedFactor | CholeskyFactor)
    assert linear.lu_fallbacks() == before + 1 and factor_inertia(whole) == negative
    basis = reduction(blocks)
    reduced, complement = basis.reduce(matrix)
    factor = ReducedFactor(linear.lu_factor(reduced), basis, complement)
    assert factor_inertia(factor) == negative
    move = negative_direction(factor, 120)
    assert move.shape == (120,) and move @ (matrix @ move) < 0.0
    rhs = rng.normal(size=120)
    assert np.linalg.norm(matrix @ factor.solve(rhs) - rhs) <= 1e-10 * np.linalg.norm(rhs)


def test_newton_on_a_body_factorises_the_reduced_matrix(monkeypatch):
    """The torso at 24 x 12 by cholespy: every factorisation is of fewer unknowns than 3N (the
    held nodes' normals dropped), and the equilibrium is superlu's, which factorises it whole."""
    from cloth.files.body import body_from_config
    from cloth.solvers import Settings, relax
    from cloth.stages.case import initial_state
    from tests.test_cholesky import _case

    state = initial_state(_case("torso", Path("."), grid=(24, 12)))
    body, _ = body_from_config(state.case.body.block)
    sizes = []
    real = linear.cholesky_factor
    monkeypatch.setattr(linear, "cholesky_factor", lambda m: sizes.append(m.shape[0]) or real(m))
    settings = Settings(tolerance=1e-10, progress=False, linear_solver="cholespy")
    by_cholesky = relax(state, body, settings)
    whole = relax(state, body, Settings(tolerance=1e-10, progress=False, linear_solver="superlu"))
    assert sizes and max(sizes) < 3 * state.grid.n_nodes
    np.testing.assert_allclose(by_cholesky.final.x, whole.final.x, rtol=0, atol=1e-9)
