"""Fewer factorisations: coarse-to-fine continuation and factor reuse against plain Newton, side
by side (docs/performance.md).

Torso M (the smooth parametric torso), power net, 15 % reduction, 0.80-1.25 m, sliding edges,
Newton to relative residual ``--tolerance`` (1e-8) with the linear solver ``--solver`` (auto:
the fastest installed), for each of ``--variants``: plain, reuse (SuperLU's factor kept, GMRES
on the next systems), continuation (coarsest level at most ``--coarsest`` nodes), and both.
Wall time (median of ``--repeat`` runs, alternating the variants), Newton iterations on the
fine grid, the run's factorisations (all levels), and the largest position difference from
plain Newton's equilibrium. Writes the table into docs/performance.md (section ``--section``,
default ``continuation``) unless ``--no-write``. Run:

    .venv/bin/python benchmarks/bench_continuation.py [--grids 192x96 384x192 448x224]
        [--variants plain continuation] [--coarsest 5000] [--solver auto] [--repeat 1]
        [--tolerance 1e-8] [--section continuation] [--no-write] [--without-plain]
"""

from __future__ import annotations

import argparse
import platform
import statistics
from dataclasses import replace

import numpy as np
from _table import markdown_table, replace_section
from _torso import VARIANTS, torso_case

from cloth.solvers import Settings, relax
from cloth.solvers.relax import reset_peak_memory


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["192x96", "384x192", "448x224"])
    parser.add_argument("--coarsest", type=int, default=5000)
    parser.add_argument("--solver", default="auto")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    parser.add_argument(
        "--variants", nargs="+", default=["plain", "continuation"], choices=list(VARIANTS)
    )
    parser.add_argument("--section", default="continuation")
    parser.add_argument(
        "--without-plain",
        action="store_true",
        help="leave plain Newton out (no ratio or gap columns)",
    )
    args = parser.parse_args()
    rows = []
    for grid in args.grids:
        n, m, state, body = torso_case(grid)
        plain = Settings(
            tolerance=args.tolerance,
            max_iterations=100,
            progress=False,
            log_every=0,
            linear_solver=args.solver,
            coarsest=args.coarsest,
        )
        variants = [] if args.without_plain else ["plain"]
        variants += [v for v in args.variants if v != "plain"]
        times: dict[str, list[float]] = {v: [] for v in variants}
        last = {}
        for _ in range(args.repeat):
            for variant in variants:
                continued, reuse = VARIANTS[variant]
                reset_peak_memory()  # each variant's own peak
                result = relax(state, body, replace(plain, continuation=continued, reuse=reuse))
                times[variant].append(result.seconds)
                last[variant] = result
        base = statistics.median(times["plain"]) if "plain" in times else None
        for variant in variants:
            result = last[variant]
            seconds = statistics.median(times[variant])
            gap = float(np.abs(result.final.x - last["plain"].final.x).max()) if base else None
            rows.append(
                [
                    grid,
                    f"{n * m:,}",
                    variant,
                    result.linear_solver,
                    str(result.iterations),
                    str(result.factorisations),
                    f"{result.final.residual:.1e}",
                    f"{seconds:.1f}",
                    f"{seconds / base:.2f}" if base else "",
                    f"{result.peak_memory / 2**20:.0f}",
                    f"{gap:.1e}" if gap is not None and variant != "plain" else "",
                ]
            )
            print(rows[-1], flush=True)
    table = markdown_table(
        [
            "grid",
            "nodes",
            "variant",
            "solver",
            "fine iterations",
            "factorisations",
            "residual",
            "time [s]",
            "time / plain",
            "peak memory [MiB]",
            "max gap to plain [m]",
        ],
        rows,
    )
    note = (
        f"{args.repeat} run(s) each, medians, on {platform.machine()}, 2 cores; coarsest level "
        f"at most {args.coarsest:,} nodes."
    )
    if not args.no_write:
        replace_section(args.section, note + "\n\n" + table)


if __name__ == "__main__":
    main()
