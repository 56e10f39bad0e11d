"""A fill-reducing ordering for Newton's matrices: nested dissection of the grid's node graph.

Sparse LU (and Cholesky) fill in the factor along the elimination order. On the n x m spring
grid, SuperLU's own best ordering (minimum degree on A^T + A) leaves 73.4 million entries in
L + U at 448 x 224 and takes 9.4-10.5 s to factorise; nested dissection leaves 63.5 million
and takes 4.1 s (measured, `benchmarks/bench_ordering.py`, docs/performance.md). Nested
dissection (George 1973) orders a graph by cutting it in two with a small separator, ordering
each half the same way, then the separator last: the fill stays inside the halves and the
separators, O(N log N) on a planar graph.

The separator here is a level of a breadth-first search (George and Liu's automatic nested
dissection): from a pseudo-peripheral node (the far end of a search from any node), the level
at which half the nodes have been reached. Every edge joins nodes of the same or neighbouring
levels, so removing one level separates those before it from those after it, whatever the
springs (weft and warp, shear diagonals, skip-one bending springs) and whether the grid is
open or a tube. A part of at most `LEAF` nodes is kept in its own (grid) order.

The ordering is of nodes; each node's 3 unknowns stay together (`dof_permutation`). It depends
on the matrix's pattern only, which is the grid's for every Newton step, so it is computed once
per pattern and kept (`reordering_for`, the last `KEPT` patterns: one per continuation level).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import shortest_path

#: Parts of at most this many nodes are not cut further.
LEAF = 64
#: Patterns whose orderings are kept.
KEPT = 6

_kept: OrderedDict[bytes, Reordering] = OrderedDict()


def nested_dissection(graph: sp.spmatrix, leaf: int = LEAF) -> NDArray[np.intp]:
    """An elimination order of ``graph``'s nodes ((N,) permutation; ``graph`` (N, N), its
    nonzero pattern the edges, symmetric): each part before the separator that cuts it."""
    graph = sp.csr_matrix(graph)
    order: list[NDArray[np.intp]] = []
    stack: list[tuple[bool, NDArray[np.intp]]] = [(False, np.arange(graph.shape[0]))]
    while stack:
        final, nodes = stack.pop()
        if final or nodes.size <= leaf:
            order.append(nodes)
            continue
        first, second, separator = _bisect(graph[nodes][:, nodes])
        # popped in turn: the first part, the second, then the separator
        stack.append((True, nodes[separator]))
        stack.append((False, nodes[second]))
        stack.append((False, nodes[first]))
    return np.concatenate(order) if order else np.zeros(0, np.intp)


def _bisect(graph: sp.csr_matrix) -> tuple[NDArray, NDArray, NDArray]:
    """(first part, second part, separator) as index arrays into ``graph``'s nodes; an
    unconnected graph is split into a component and the rest with an empty separator; a graph
    no level can cut (diameter below 2) is all separator."""
    none = np.zeros(0, np.intp)
    far = _levels(graph, 0)
    reached = np.isfinite(far)
    if not np.all(reached):
        return np.flatnonzero(reached), np.flatnonzero(~reached), none
    level = _levels(graph, int(np.argmax(far))).astype(np.intp)
    if level.max() < 2:
        return none, none, np.arange(graph.shape[0])
    cumulative = np.cumsum(np.bincount(level))
    cut = int(np.clip(np.searchsorted(cumulative, graph.shape[0] / 2), 1, level.max() - 1))
    return np.flatnonzero(level < cut), np.flatnonzero(level > cut), np.flatnonzero(level == cut)


def _levels(graph: sp.csr_matrix, start: int) -> NDArray[np.float64]:
    """Breadth-first level of every node from ``start`` (inf where unreached)."""
    return shortest_path(graph, method="D", directed=False, unweighted=True, indices=start)


def dof_permutation(matrix: sp.spmatrix, block: int = 3) -> NDArray[np.intp]:
    """A fill-reducing permutation of ``matrix``'s rows and columns ((block N,)): nested
    dissection of the graph of its (block x block) node blocks, each node's unknowns kept
    together and in order."""
    coo = sp.coo_matrix(matrix)
    count = matrix.shape[0] // block
    nodes = sp.csr_matrix(
        (np.ones(coo.nnz), (coo.row // block, coo.col // block)), shape=(count, count)
    )
    order = nested_dissection(nodes)
    return (block * order[:, None] + np.arange(block)).ravel()


class Reordering:
    """A pattern's nested-dissection order (``order``, (3N,)) and where each entry of a
    matrix of that pattern goes in the reordered one (``source``: the reordered matrix's data
    is the matrix's ``data[source]``), so a matrix is reordered by one gather."""

    def __init__(self, matrix: sp.csc_matrix) -> None:
        block = 3 if matrix.shape[0] % 3 == 0 else 1
        self.order = dof_permutation(matrix, block)
        numbered = sp.csc_matrix(
            (np.arange(1.0, matrix.nnz + 1.0), matrix.indices, matrix.indptr),  # none 0
            shape=matrix.shape,
        )
        reordered = numbered[self.order][:, self.order].tocsc()
        reordered.sort_indices()
        self.indptr, self.indices = reordered.indptr, reordered.indices
        self.source = reordered.data.astype(np.intp) - 1
        assert self.source.size == matrix.nnz, "reordering lost entries"

    def apply(self, matrix: sp.csc_matrix) -> sp.csc_matrix:
        """P A P^T for ``matrix`` (CSC, indices sorted, of this pattern)."""
        return sp.csc_matrix(
            (matrix.data[self.source], self.indices, self.indptr), shape=matrix.shape
        )


def reordering_for(matrix: sp.csc_matrix) -> Reordering:
    """The `Reordering` of ``matrix``'s pattern (CSC, indices sorted), kept for it."""
    digest = hashlib.blake2b(digest_size=16)
    digest.update(np.asarray(matrix.shape, np.int64).tobytes())
    digest.update(np.ascontiguousarray(matrix.indptr).tobytes())
    digest.update(np.ascontiguousarray(matrix.indices).tobytes())
    key = digest.digest()
    if key in _kept:
        _kept.move_to_end(key)
        return _kept[key]
    found = _kept[key] = Reordering(matrix)
    while len(_kept) > KEPT:
        _kept.popitem(last=False)
    return found
