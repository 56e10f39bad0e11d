"""Coarse-to-fine continuation against plain Newton, side by side (docs/performance.md).

Torso M (the smooth parametric torso), power net, 15 % reduction, 0.80-1.25 m, sliding edges,
Newton to relative residual ``--tolerance`` (1e-8) with the linear solver ``--solver`` (auto:
the fastest installed), plain and with continuation (coarsest level at most ``--coarsest``
nodes). Wall time (median of ``--repeat`` runs, alternating the two), Newton iterations on
the fine grid, the run's factorisations (all levels), and the largest position difference
between the two equilibria. Writes the table into docs/performance.md (section
``continuation``) unless ``--no-write``. Run:

    .venv/bin/python benchmarks/bench_continuation.py [--grids 192x96 384x192 448x224]
        [--coarsest 5000] [--solver auto] [--repeat 1] [--tolerance 1e-8] [--no-write]
"""

from __future__ import annotations

import argparse
import platform
import statistics
from dataclasses import replace

import numpy as np
from _table import markdown_table, replace_section

from cloth.bodies import body_from_config
from cloth.predeform import predeform
from cloth.solvers import Settings, relax


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["192x96", "384x192", "448x224"])
    parser.add_argument("--coarsest", type=int, default=5000)
    parser.add_argument("--solver", default="auto")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    args = parser.parse_args()
    rows = []
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        case = {
            "material": "powernet",
            "body": {"torso": {"size": "M"}},
            "garment": {"bottom": 0.80, "top": 1.25, "reduction": 0.15, "grid": [n, m],
                        "edges": "sliding"},
        }  # fmt: skip
        state = predeform(case)
        body, _ = body_from_config(state.case["body"])
        plain = Settings(tolerance=args.tolerance, max_iterations=100, progress=False, log_every=0,
                         linear_solver=args.solver, coarsest=args.coarsest)  # fmt: skip
        times: dict[bool, list[float]] = {False: [], True: []}
        last = {}
        for _ in range(args.repeat):
            for continued in (False, True):
                result = relax(state, body, replace(plain, continuation=continued))
                times[continued].append(result.seconds)
                last[continued] = result
        gap = float(np.abs(last[True].final.x - last[False].final.x).max())
        base = statistics.median(times[False])
        for continued in (False, True):
            result = last[continued]
            seconds = statistics.median(times[continued])
            rows.append([
                grid, f"{n * m:,}", "continuation" if continued else "plain",
                result.linear_solver, str(result.iterations), str(result.factorisations),
                f"{result.final.residual:.1e}", f"{seconds:.1f}", f"{seconds / base:.2f}",
                f"{result.peak_memory / 2**20:.0f}", f"{gap:.1e}" if continued else "",
            ])  # fmt: skip
            print(rows[-1], flush=True)
    table = markdown_table(
        ["grid", "nodes", "start", "solver", "fine iterations", "factorisations", "residual",
         "time [s]", "time / plain", "peak memory [MiB]", "max position gap [m]"],
        rows,
    )  # fmt: skip
    note = (
        f"{args.repeat} run(s) each, medians, on {platform.machine()}, 2 cores; coarsest level "
        f"at most {args.coarsest:,} nodes."
    )
    if not args.no_write:
        replace_section("continuation", note + "\n\n" + table)


if __name__ == "__main__":
    main()
