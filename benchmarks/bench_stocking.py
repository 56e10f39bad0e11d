"""The stocking (issue 31, benchmarks): time to equilibrium of a 96 x 96 stocking by plain
Newton and by the fast path (continuation + reuse), and the pressure at B, C and F against the
grid, with the error estimates.

    .venv/bin/python benchmarks/bench_stocking.py [--grids 24x24 48x48 96x96]

The parametric leg M (data/bodies/leg_chart.csv), the power net at a reduction of 0.16, pulled
up by a lengthwise reduction of 0.15, from 0.09 m (2 cm below B) to 0.77 m (2 cm above G).
"""

from __future__ import annotations

import argparse
import logging

import xarray as xr
from _case import case_result

from cloth.results.pressure import MMHG

PATHS = {
    "plain": {"method": "newton", "continuation": False, "reuse": False},
    "continuation+reuse": {"method": "newton", "continuation": True, "reuse": True},
}


def run(
    grid: tuple[int, int],
    solver: dict,
    estimate: bool,
    body: dict | None = None,
    level_ratio: float = 2.0,
    row_grading: float = 0.0,
) -> tuple[xr.Dataset, float]:
    """The stocking on ``body`` (the parametric leg M by default) on ``grid``: its result and
    the seconds of predeform, relax (with the estimate's levels at ``level_ratio`` where
    ``estimate``), aggregate; rows graded by ``row_grading``."""
    case = {
        "material": "powernet",
        "body": body or {"leg": {"size": "M"}},
        "solver": solver,
        "garment": {
            "bottom": 0.09,
            "top": 0.77,
            "grid": list(grid),
            "reduction": 0.16,
            "lengthwise_reduction": 0.15,
            "error_estimate": estimate,
            "level_ratio": level_ratio,
            "row_grading": row_grading,
        },
    }
    return case_result(case)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["24x24", "48x48", "96x96"])
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    print("| grid | line | mean (mmHg) | estimated error (mmHg) |")
    print("|---|---|---|---|")
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        ds, _ = run((n, m), PATHS["plain"], True)
        for line in ("B", "C", "F"):
            k = list(ds["landmark"].values).index(line)
            error = float(ds["pressure_mean_error"].values[k]) / MMHG
            print(
                f"| {grid} | {line} | {float(ds['pressure_mean'].values[k]) / MMHG:.2f} | "
                f"{error:.2f} |",
                flush=True,
            )
    print()
    print("| grid | path | predeform + relax + aggregate (s) | B, C, F (mmHg) | unstable modes |")
    print("|---|---|---|---|---|")
    for name, solver in PATHS.items():
        ds, seconds = run((96, 96), solver, False)
        pairs = zip(ds["landmark"].values, ds["pressure_mean"].values, strict=True)
        marks = {str(k): float(v) / MMHG for k, v in pairs}
        print(
            f"| 96x96 | {name} | {seconds:.1f} | {marks['B']:.3f}, {marks['C']:.3f}, "
            f"{marks['F']:.3f} | {ds.attrs.get('unstable_modes')} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
