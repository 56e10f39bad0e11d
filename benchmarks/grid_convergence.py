"""Girth-line means over grids: the torso M, 0.86-1.22 m, reduction 0.20, power net, Newton with
continuation and reuse (issue 29's table), each line read at its height (the summary's
definition, `cloth.results.landmarks.girth_line`), with the case's own error estimate beside it
(its two coarser levels, `cloth.stages.levels`): value +- stated error (observed order), or the
reason no error was given. With ``--nearest``, the row nearest the line too (the definition
before), to show which of the two moves smoothly with the grid.

    .venv/bin/python benchmarks/grid_convergence.py [--grids 48x24 96x48 192x96 384x192]

Prints a markdown table of the mean pressure (Pa) per girth line and grid, and whether each
grid's stated error contains the finest grid's value.
"""

from __future__ import annotations

import argparse
import logging
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from cloth.results.landmarks import nearest_row
from cloth.results.richardson import REASONS
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]
LINES = ("hip", "waist", "underbust", "bust")


def case(n: int, m: int) -> dict:
    return {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {"bottom": 0.86, "top": 1.22, "reduction": 0.20, "grid": [n, m]},
        "solver": {"method": "newton", "continuation": True, "reuse": True},
    }


def girth_means(n: int, m: int) -> dict[str, tuple[float, float, float, float, str]]:
    """line -> (at its height, at the nearest row) mean pressure, its stated error (Pa), its
    observed order and the reason where no error was given."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "case.yaml"
        path.write_text(yaml.safe_dump(case(n, m)))
        run_case(path, Path(tmp) / "out", {}, ROOT, stop_after="aggregate")
        with xr.open_dataset(Path(tmp) / "out" / "result.nc") as ds:
            rows_z = ds["z"].values.mean(axis=1)
            on = np.where(ds["contact"].values.astype(bool), ds["pressure"].values, 0.0)
            out = {}
            for index, name in enumerate(ds["landmark"].values.tolist()):
                row = nearest_row(rows_z, float(ds["landmark_height"][index]))
                code = int(ds["pressure_mean_estimate"][index])
                out[str(name)] = (
                    float(ds["pressure_mean"][index]), float(on[row].mean()),
                    float(ds["pressure_mean_error"][index]),
                    float(ds["pressure_mean_order"][index]), REASONS.get(code, ""),
                )  # fmt: skip
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["48x24", "96x48", "192x96"])
    parser.add_argument("--nearest", action="store_true", help="also the nearest row's value")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    print("| grid | " + " | ".join(LINES) + " |")
    print("|---" * (len(LINES) + 1) + "|")
    found = {}
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        found[grid] = means = girth_means(n, m)
        cells = []
        for line in LINES:
            value, nearest, error, order, reason = means[line]
            cell = f"{value:.0f} +- {error:.0f} (p {order:.2f})" if reason == "" else (
                f"{value:.0f} (no error: {reason})"
            )  # fmt: skip
            cells.append(cell + (f" / nearest row {nearest:.0f}" if args.nearest else ""))
        print(f"| {grid} | " + " | ".join(cells) + " |", flush=True)
    finest = found[args.grids[-1]]
    print(f"\nWhether each grid's stated error contains the {args.grids[-1]} value:")
    for grid in args.grids[:-1]:
        verdict = []
        for line in LINES:
            value, _, error, _, reason = found[grid][line]
            miss = finest[line][0] - value
            verdict.append(f"{line} {'-' if reason else ('yes' if abs(miss) <= error else 'NO')}"
                           f" ({miss:+.0f} Pa)")  # fmt: skip
        print(f"- {grid}: " + ", ".join(verdict))


if __name__ == "__main__":
    main()
