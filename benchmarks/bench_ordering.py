"""SuperLU's factorisation in nested-dissection order against its own minimum-degree ordering,
side by side (docs/performance.md, section ``ordering``).

The benchmarks' torso case (`_torso.torso_case`) on each of ``--grids``: Newton's matrix at the
wrapped state (exact stiffness, contact terms, constraints, as Newton's first step builds it),
factorised by scipy's SuperLU with no pivoting in symmetric mode, (a) ordered by SuperLU's
MMD(A^T + A) as cloth did before and (b) in the nested-dissection order of
`cloth.solvers.ordering` (what `cloth.solvers.linear` now does). Medians of ``--repeat`` runs,
the two alternating; the ordering's own time (once per grid: it is kept for the pattern) apart.
Run:

    .venv/bin/python benchmarks/bench_ordering.py [--grids 224x112 384x192 448x224 640x320]
        [--repeat 3] [--no-write]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import scipy.sparse as sp
from _table import markdown_table, replace_section
from _torso import torso_case
from scipy.sparse.linalg import splu

from cloth.solvers.activeset import held_nodes
from cloth.solvers.linear import lu_factor
from cloth.solvers.newton import newton_matrix, stiffness_at
from cloth.solvers.ordering import dof_permutation
from cloth.solvers.problem import Problem


def newton_system(grid: str) -> tuple[int, sp.csc_matrix, np.ndarray]:
    """(nodes, Newton's first matrix (3N, 3N) N/m, its right-hand side (3N,) N)."""
    n, m, state, body = torso_case(grid)
    problem = Problem(state.grid, body, state.constraint)
    ev = problem.evaluate(state.x)
    k = stiffness_at(problem, ev)
    held = held_nodes(problem, ev, k)
    projector, _ = problem.basis(ev.x, ev.normal, held)
    matrix = newton_matrix(problem, ev, held, projector, k(False)).tocsc()
    matrix.sort_indices()
    rhs = np.einsum("nij,nj->ni", projector, ev.loads).ravel()
    return n * m, matrix, rhs


def timed(work):
    start = time.perf_counter()
    result = work()
    return result, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["224x112", "384x192", "448x224", "640x320"])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    args = parser.parse_args()
    rows = []
    for grid in args.grids:
        nodes, matrix, rhs = newton_system(grid)
        _, ordering = timed(lambda: dof_permutation(matrix))
        times: dict[str, list[float]] = {"mmd": [], "nd": [], "mmd solve": [], "nd solve": []}
        fill = {}
        for _ in range(args.repeat):
            mmd, seconds = timed(
                lambda: splu(
                    matrix,
                    permc_spec="MMD_AT_PLUS_A",
                    diag_pivot_thresh=0.0,
                    options={"SymmetricMode": True},
                )
            )
            times["mmd"].append(seconds)
            nd, seconds = timed(lambda: lu_factor(matrix, dissect=True))  # ordering kept
            times["nd"].append(seconds)
            for name, factor in (("mmd", mmd), ("nd", nd)):
                x, seconds = timed(lambda: factor.solve(rhs))
                times[f"{name} solve"].append(seconds)
                error = np.linalg.norm(matrix @ x - rhs) / np.linalg.norm(rhs)
                assert error < 1e-10, f"{name}: relative residual {error:.1e}"
            fill = {"mmd": mmd.L.nnz + mmd.U.nnz, "nd": nd.lu.L.nnz + nd.lu.U.nnz}
            del mmd, nd
        median = {key: statistics.median(value) for key, value in times.items()}
        rows.append(
            [
                grid,
                f"{nodes:,}",
                f"{fill['mmd'] / 1e6:.1f}",
                f"{fill['nd'] / 1e6:.1f}",
                f"{median['mmd']:.2f}",
                f"{median['nd']:.2f}",
                f"{median['nd'] / median['mmd']:.2f}",
                f"{ordering:.2f}",
                f"{median['mmd solve']:.3f}",
                f"{median['nd solve']:.3f}",
            ]
        )
        print(rows[-1], flush=True)
    table = markdown_table(
        [
            "grid",
            "nodes",
            "L+U MMD [1e6]",
            "L+U ND [1e6]",
            "factorise MMD [s]",
            "factorise ND [s]",
            "ND / MMD",
            "ND ordering, once [s]",
            "solve MMD [s]",
            "solve ND [s]",
        ],
        rows,
    )
    note = f"\nMedians of {args.repeat} runs each, alternating; Newton's first matrix on the torso."
    print(table + note)
    if not args.no_write:
        replace_section("ordering", table + "\n" + note.strip())


if __name__ == "__main__":
    main()
