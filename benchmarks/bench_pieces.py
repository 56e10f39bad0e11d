"""A garment of several pieces against the one-fabric garment (issue 69): the relax time of a
tube of 3 panels and 2 bands on the parametric torso M against the same tube of the power net
alone, side by side (A B A B ...), medians and their ratio; and predeform's time for each.

The garment is the default config's (0.86-1.22 m, reduction 0.20, 288 x 144, Newton with its
default continuation). The pieces: a power-net front panel (-60 to 60 degrees), light-net sides
(60 to 180 and 180 to 300 degrees) with 6 mm seams, a 25 mm elastic band at the top and a
20 mm one at the bottom. Writes the table into docs/performance.md (section ``pieces``) with
``--write``. Run:

    .venv/bin/python benchmarks/bench_pieces.py [--grid 288x144] [--repeat 3] [--write]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time
from dataclasses import replace

from _table import PERFORMANCE, markdown_table, publish

from cloth.files.body import body_from_config
from cloth.solvers import relax
from cloth.stages.case import initial_state

#: The page the table goes into.
PAGE = PERFORMANCE.parents[1] / "performance.md"

PIECES = {
    "panels": [
        {"material": "powernet", "from_deg": -60, "to_deg": 60},
        {"material": "lightnet", "from_deg": 60, "to_deg": 180},
        {"material": "lightnet", "from_deg": 180, "to_deg": 300},
    ],
    "seams": {"allowance_mm": 6},
    "bands": [
        {"name": "topband", "material": "elastic25", "width": 0.025, "reduction": 0.1},
        {
            "name": "legband",
            "material": "elastic25",
            "at": "bottom",
            "width": 0.02,
            "reduction": 0.1,
        },
    ],
}


def case(grid: tuple[int, int], pieces: bool) -> dict:
    garment = {"bottom": 0.86, "top": 1.22, "reduction": 0.20, "grid": list(grid)}
    garment["edges"] = "sliding"
    garment["error_estimate"] = False
    if pieces:
        garment.update(PIECES)
    return {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": garment,
        "solver": {"method": "newton", "tolerance": 1e-8, "max_iterations": 150},
    }


def timed(grid: tuple[int, int], pieces: bool) -> tuple[float, float, bool]:
    """(predeform s, relax s, converged) of one run."""
    start = time.perf_counter()
    state = initial_state(case(grid, pieces))
    made = time.perf_counter() - start
    body, _ = body_from_config(state.case.body.block, span=(0.86, 1.22))
    start = time.perf_counter()
    result = relax(state, body, replace(state.case.solver, progress=False))
    return made, time.perf_counter() - start, bool(result.converged)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", default="288x144")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--write", action="store_true")
    args = parser.parse_args()
    grid = tuple(int(v) for v in args.grid.split("x"))
    runs = {False: [], True: []}
    for _ in range(args.repeat):
        for pieces in (False, True):
            runs[pieces].append(timed(grid, pieces))
            print(pieces, runs[pieces][-1], flush=True)
    rows = []
    med = {}
    for pieces, label in ((False, "power net alone"), (True, "3 panels, 2 bands, 6 mm seams")):
        made = statistics.median(r[0] for r in runs[pieces])
        solved = statistics.median(r[1] for r in runs[pieces])
        med[pieces] = (made, solved)
        converged = all(r[2] for r in runs[pieces])
        rows.append([label, f"{made:.2f}", f"{solved:.1f}", "yes" if converged else "NO"])
    rows.append(
        [
            "ratio",
            f"{med[True][0] / med[False][0]:.2f}",
            f"{med[True][1] / med[False][1]:.2f}",
            "",
        ]
    )
    header = ["garment", "predeform s", "relax s (median)", "converged"]
    body = (
        f"Torso M, {grid[0]} x {grid[1]}, reduction 0.20, Newton (default continuation), "
        f"{args.repeat} runs each alternating, medians "
        f"({platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
        "`benchmarks/bench_pieces.py`):\n\n" + markdown_table(header, rows)
    )
    publish(body, "pieces", args.write, PAGE)


if __name__ == "__main__":
    main()
