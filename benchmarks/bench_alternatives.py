"""Newton against its alternatives in the same time budget (docs/performance.md, issue 12).

Torso M (smooth parametric torso), power net, 15 % reduction, 0.80-1.25 m, sliding edges.
Newton (SuperLU) runs to relative residual 1e-8; its wall time T is the budget. In T, the
paper's explicit iteration and scipy's ``minimize(method="L-BFGS-B")`` on the same strain
energy plus a penalty for penetration (0.5 k sum min(d, 0)^2, k = ``--penalty`` N/m; fixed
nodes and the sliding edges' heights held by bounds) each run as far as they get; the table
gives the relative residual each reaches (the solver's definition, after projecting the nodes
out of the body) and its ratio to 1e-8. Writes section ``alternatives`` unless
``--no-write``. Run:

    .venv/bin/python benchmarks/bench_alternatives.py [--grids 96x48 192x96] [--penalty 1e5]
        [--no-write]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np
from _table import markdown_table, replace_section
from _torso import torso_case
from scipy.optimize import minimize

from cloth.garment.grid import FIXED, SLIDING
from cloth.garment.mechanics import energy, forces
from cloth.solvers import Settings, relax
from cloth.solvers.problem import Problem

#: The residual Newton is run to; the table gives each method's residual over it.
TARGET = 1e-8


class Budget(Exception):
    """The time budget is spent."""


def lbfgsb(state, body, seconds: float, penalty: float):
    """L-BFGS-B on energy + penalty for ``seconds``; the final positions ((N, 3), m) and the
    number of function evaluations."""
    grid, x0 = state.grid, state.x.copy()
    bounds = [(None, None)] * x0.size
    for node in np.flatnonzero(state.constraint == FIXED):
        for c in range(3):
            bounds[3 * node + c] = (x0[node, c], x0[node, c])
    for node in np.flatnonzero(state.constraint == SLIDING):
        bounds[3 * node + 2] = (x0[node, 2], x0[node, 2])
    start = time.perf_counter()
    calls = [0]
    best = [x0.ravel().copy()]

    def objective(flat):
        if time.perf_counter() - start > seconds:
            raise Budget
        calls[0] += 1
        x = flat.reshape(-1, 3)
        distance, _, normal = body.query(x)
        inside = np.minimum(distance, 0.0)
        value = energy(x, grid) + 0.5 * penalty * float(inside @ inside)
        gradient = -forces(x, grid) + penalty * inside[:, None] * normal
        best[0] = flat.copy()
        return value, gradient.ravel()

    try:
        minimize(
            objective,
            x0.ravel(),
            jac=True,
            method="L-BFGS-B",
            bounds=bounds,
            options={"maxiter": 10**7, "maxfun": 10**7, "ftol": 0.0, "gtol": 0.0},
        )
    except Budget:
        pass
    return best[0].reshape(-1, 3), calls[0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["96x48", "192x96"])
    parser.add_argument("--penalty", type=float, default=1e5, help="penetration penalty, N/m")
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    rows = []
    for grid in args.grids:
        n, m, state, body = torso_case(grid)
        problem = Problem.of(state, body)
        base = Settings(
            tolerance=TARGET,
            max_iterations=150,
            progress=False,
            log_every=0,
            linear_solver="superlu",
        )
        newton = relax(state, body, base)
        budget = newton.seconds
        # the explicit iteration: as many steps as the budget holds (one step's cost measured)
        probe = relax(
            state,
            body,
            Settings(
                method="explicit", max_iterations=5, progress=False, log_every=0, tolerance=1e-14
            ),
        )
        steps = max(1, int(budget / (probe.seconds / 5)))
        paper = Settings(
            method="explicit", max_iterations=steps, progress=False, log_every=0, tolerance=1e-8
        )
        explicit = relax(state, body, paper)
        x, calls = lbfgsb(state, body, budget, args.penalty)
        quasi = problem.evaluate(problem.project_out(x)).residual
        reference = newton.history.residual[-1]
        for name, residual, seconds, work in (
            ("newton (superlu)", reference, newton.seconds, f"{newton.iterations} iterations"),
            (
                "explicit (the paper)",
                explicit.history.residual[-1],
                explicit.seconds,
                f"{explicit.iterations} iterations",
            ),
            ("L-BFGS-B + penalty", quasi, budget, f"{calls} evaluations"),
        ):
            rows.append(
                [
                    grid,
                    f"{n * m:,}",
                    name,
                    work,
                    f"{seconds:.1f}",
                    f"{residual:.1e}",
                    f"{residual / TARGET:.1e}",
                ]
            )
            print(rows[-1], flush=True)
    table = markdown_table(
        ["grid", "nodes", "method", "work", "time [s]", "residual reached", "/ 1e-8"], rows
    )
    note = (
        f"One run each on {platform.machine()}, 2 cores; the budget is Newton's time to 1e-8; "
        f"L-BFGS-B's penalty {args.penalty:.0e} N/m."
    )
    if not args.no_write:
        replace_section("alternatives", note + "\n\n" + table)


if __name__ == "__main__":
    main()
