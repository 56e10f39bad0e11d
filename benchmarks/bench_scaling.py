"""How Newton's time grows with the grid: 12k to 200k nodes, plain and with continuation and
reuse, with the exponent of time against nodes (docs/performance.md, section ``scaling``).

The benchmarks' torso case (`_torso.torso_case`) on each of ``--grids``, relaxed to ``--tolerance``
(1e-8) by each of ``--variants`` (plain; continuation+reuse), one run each (a run at 100k nodes
takes minutes: medians of several are out of this benchmark's budget), the variants alternating
per grid. ``--skip VARIANT:GRID`` leaves a combination out (plain Newton at 200k nodes takes
longer than the rest together). The exponent is the least-squares slope of log time against log
nodes over the grids each variant ran. Run:

    .venv/bin/python benchmarks/bench_scaling.py [--grids 160x80 224x112 320x160 448x224 640x320]
        [--variants plain continuation+reuse] [--skip plain:640x320] [--solver superlu]
        [--no-write]
"""

from __future__ import annotations

import argparse
import platform

import numpy as np
from _table import markdown_table, replace_section
from _torso import VARIANTS, torso_case

from cloth.solvers import Settings, relax
from cloth.solvers.relax import reset_peak_memory


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--grids", nargs="+", default=["160x80", "224x112", "320x160", "448x224", "640x320"]
    )
    parser.add_argument(
        "--variants", nargs="+", default=["plain", "continuation+reuse"], choices=list(VARIANTS)
    )
    parser.add_argument("--skip", nargs="*", default=["plain:640x320"])
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument(
        "--solver", default="superlu", help="linear solver (auto: pardiso where it is installed)"
    )
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    args = parser.parse_args()
    rows, points = [], {v: [] for v in args.variants}
    for grid in args.grids:
        n, m, state, body = torso_case(grid)
        for variant in args.variants:
            if f"{variant}:{grid}" in args.skip:
                continue
            continued, reuse = VARIANTS[variant]
            settings = Settings(
                tolerance=args.tolerance,
                max_iterations=100,
                progress=False,
                log_every=0,
                continuation=continued,
                reuse=reuse,
                linear_solver=args.solver,
            )
            reset_peak_memory()
            result = relax(state, body, settings)
            points[variant].append((n * m, result.seconds))
            rows.append(
                [
                    grid,
                    f"{n * m:,}",
                    variant,
                    result.linear_solver,
                    str(result.iterations),
                    str(result.factorisations),
                    f"{result.final.residual:.1e}",
                    f"{result.seconds:.1f}",
                    f"{result.peak_memory / 2**20:.0f}",
                ]
            )
            print(rows[-1], flush=True)
    slopes = []
    for variant, data in points.items():
        if len(data) >= 2:
            nodes, seconds = np.log(np.array(data)).T
            slope = float(np.polyfit(nodes, seconds, 1)[0])
            span = f"{data[0][0]:,}-{data[-1][0]:,} nodes"
            slopes.append(f"{variant}: time ~ nodes^{slope:.2f} ({span})")
            print(slopes[-1])
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
            "peak memory [MiB]",
        ],
        rows,
    )
    note = (
        f"One run each on {platform.machine()}, 2 cores, tolerance {args.tolerance:.0e}. "
        f"Measured exponents: {'; '.join(slopes)}."
    )
    if not args.no_write:
        replace_section("scaling", note + "\n\n" + table)


if __name__ == "__main__":
    main()
