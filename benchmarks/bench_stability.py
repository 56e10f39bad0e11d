"""Which equilibrium Newton finds: the unstable modes of the torso case at equilibrium, by grid
(docs/solvers.md, section ``stability``).

The benchmarks' torso case (`_torso.torso_case`) relaxed by Newton (SuperLU) to ``--tolerance``
(1e-10) on each of ``--grids``, plain or with continuation and reuse (``--variants``); at its
equilibrium, the negative eigenvalues of the exact constrained Newton matrix
(`cloth.solvers.stability.unstable_modes`: 0 at a stable equilibrium, else a saddle), the
compressed springs of each family, the most compressed strain and the heights where the
compressed warp springs lie. Run:

    .venv/bin/python benchmarks/bench_stability.py [--grids 96x48 224x112 448x224]
        [--variants plain continuation+reuse] [--tolerance 1e-10] [--plain-up-to 30000]
        [--no-write]
"""

from __future__ import annotations

import argparse
import platform
from dataclasses import replace
from pathlib import Path

import numpy as np
from _table import markdown_table, replace_section
from _torso import VARIANTS, torso_case

from cloth.garment.grid import WARP, WEFT
from cloth.solvers import Settings, relax
from cloth.solvers.problem import Problem
from cloth.solvers.stability import unstable_modes

SOLVERS_DOC = Path(__file__).resolve().parents[1] / "docs" / "solvers.md"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["96x48", "224x112", "448x224"])
    parser.add_argument(
        "--variants", nargs="+", default=["continuation+reuse"], choices=list(VARIANTS)
    )
    parser.add_argument("--tolerance", type=float, default=1e-10)
    parser.add_argument(
        "--plain-up-to",
        type=int,
        default=30_000,
        help="plain Newton only on grids of at most this many nodes",
    )
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    args = parser.parse_args()
    rows = []
    for grid in args.grids:
        n, m, state, body = torso_case(grid)
        base = Settings(
            tolerance=args.tolerance,
            max_iterations=100,
            progress=False,
            log_every=0,
            linear_solver="superlu",
        )
        for variant in args.variants:
            if variant == "plain" and n * m > args.plain_up_to:
                continue
            continued, reuse = VARIANTS[variant]
            result = relax(state, body, replace(base, continuation=continued, reuse=reuse))
            ev = result.final  # the fine grid's last evaluation
            modes = unstable_modes(Problem.of(state, body), ev)
            strain = ev.springs.strain
            weft, warp = (
                strain[state.grid.family_slices[WEFT]],
                strain[state.grid.family_slices[WARP]],
            )
            squeezed = np.flatnonzero(warp < 0)  # warp spring k joins rows k // n and k // n + 1
            heights = ev.x[(squeezed // n) * n, 2] if squeezed.size else np.array([np.nan])
            rows.append(
                [
                    grid,
                    f"{n * m:,}",
                    variant,
                    str(result.iterations),
                    f"{result.final.residual:.1e}",
                    f"{result.final.energy:.9f}",
                    str(modes),
                    f"{np.count_nonzero(weft < 0):,}",
                    f"{squeezed.size:,} of {warp.size:,}",
                    f"{strain.min():.3f}",
                    f"{np.nanmin(heights):.3f}-{np.nanmax(heights):.3f}",
                ]
            )
            print(rows[-1], flush=True)
    table = markdown_table(
        [
            "grid",
            "nodes",
            "variant",
            "iterations",
            "residual",
            "energy [J]",
            "unstable modes",
            "compressed weft springs",
            "compressed warp springs",
            "least strain",
            "compressed warp at heights [m]",
        ],
        rows,
    )
    note = (
        f"One run each on {platform.machine()}, Newton (SuperLU) to {args.tolerance:g}; "
        "unstable modes: negative eigenvalues of the exact constrained Newton matrix at the "
        "equilibrium."
    )
    if not args.no_write:
        replace_section("stability", note + "\n\n" + table, SOLVERS_DOC)


if __name__ == "__main__":
    main()
