"""Nested dissection (cloth.solvers.ordering): a permutation, separators that separate, the
fill George's theorem bounds, and SuperLU's solves in that order exact."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from cloth.solvers import ordering
from cloth.solvers.linear import lu_factor


def grid_graph(n: int, m: int, tube: bool = False, skip: bool = False) -> sp.csr_matrix:
    """The node graph of an n x m spring grid (weft, warp; skip-one bending springs)."""
    index = np.arange(n * m).reshape(m, n)
    pairs = [(index[:, :-1], index[:, 1:]), (index[:-1], index[1:])]
    if tube:
        pairs.append((index[:, -1], index[:, 0]))
    if skip:
        pairs += [(index[:, :-2], index[:, 2:]), (index[:-2], index[2:])]
    rows = np.concatenate([a.ravel() for a, _ in pairs])
    cols = np.concatenate([b.ravel() for _, b in pairs])
    graph = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n * m, n * m))
    return (graph + graph.T).tocsr()


def laplacian(graph: sp.csr_matrix) -> sp.csc_matrix:
    """Graph Laplacian plus identity: symmetric positive definite, the graph's pattern."""
    degree = np.asarray(graph.sum(axis=1)).ravel()
    return (sp.diags(degree + 1.0) - graph).tocsc()


@pytest.mark.parametrize(
    "graph",
    [
        grid_graph(40, 30),
        grid_graph(48, 20, tube=True, skip=True),
        sp.csr_matrix((5, 5)),
        sp.block_diag([grid_graph(9, 9), grid_graph(20, 11)]).tocsr(),
    ],
    ids=["grid", "tube with bending springs", "no edges", "two pieces"],
)
def test_the_order_is_a_permutation(graph):
    order = ordering.nested_dissection(graph, leaf=8)
    assert np.array_equal(np.sort(order), np.arange(graph.shape[0]))


@pytest.mark.parametrize("tube, skip", [(False, False), (True, False), (True, True)])
def test_a_separator_separates_the_two_parts(tube, skip):
    graph = grid_graph(30, 20, tube=tube, skip=skip)
    first, second, separator = ordering._bisect(graph)
    assert first.size + second.size + separator.size == graph.shape[0]
    assert min(first.size, second.size) > 0.3 * graph.shape[0]  # balanced
    assert graph[first][:, second].nnz == 0  # no spring crosses the separator
    # a level of a breadth-first search: not much longer than a cut across the grid
    assert separator.size <= (2 if skip else 1) * 2 * 30


def test_fill_within_georges_bound():
    """George (1973): nested dissection of a k x k five-point grid fills the Cholesky factor
    with 31/4 k^2 log2 k + O(k^2) entries; the grid's own (banded) order fills about k^3."""
    k = 127
    matrix = laplacian(grid_graph(k, k))
    order = ordering.nested_dissection(grid_graph(k, k))
    options = {
        "permc_spec": "NATURAL",
        "diag_pivot_thresh": 0.0,
        "options": {"SymmetricMode": True},
    }
    dissected = splu(matrix[order][:, order].tocsc(), **options)
    banded = splu(matrix, **options)
    lower = dissected.L.nnz
    assert lower <= 31 / 4 * k**2 * np.log2(k) + 2 * k**2
    assert banded.L.nnz > k**3 / 2
    assert lower < 0.5 * banded.L.nnz


def test_superlu_in_dissection_order_solves_exactly():
    rng = np.random.default_rng(1)
    graph = grid_graph(24, 16, tube=True)
    block = np.array([[3.0, 0.4, 0.1], [0.4, 2.5, 0.2], [0.1, 0.2, 1.5]])
    matrix = sp.kron(laplacian(graph), block).tocsr()
    rhs = rng.normal(size=matrix.shape[0])
    for scale in (1.0, 3.0):  # the second factorisation reuses the pattern's reordering
        x = lu_factor(scale * matrix, dissect=True).solve(rhs)
        assert np.linalg.norm(scale * matrix @ x - rhs) <= 1e-12 * np.linalg.norm(rhs)
    kept = ordering.reordering_for(matrix.tocsc())
    assert ordering.reordering_for((3.0 * matrix).tocsc()) is kept
    other = sp.kron(laplacian(grid_graph(24, 16)), block).tocsc()  # no seam: a new pattern
    assert ordering.reordering_for(other) is not kept
    # each node's three unknowns stay together and in order
    assert np.array_equal(kept.order.reshape(-1, 3) % 3, np.tile(np.arange(3), (24 * 16, 1)))
