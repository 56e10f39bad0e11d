"""Girth-line means over grids: the torso M, 0.86-1.22 m, reduction 0.20, power net, Newton with
continuation and reuse (issue 29's table), each line read at its height (the summary's
definition, `cloth.results.landmarks.girth_line`) and, beside it, from the row nearest it (the
definition before), to show which of the two moves smoothly with the grid.

    .venv/bin/python benchmarks/grid_convergence.py [--grids 48x24 96x48 192x96 384x192]

Prints a markdown table of the mean pressure (Pa) per girth line and grid.
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


def girth_means(n: int, m: int) -> dict[str, tuple[float, float]]:
    """line -> (at its height, at the nearest row) mean pressure, Pa."""
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
                out[str(name)] = (float(ds["pressure_mean"][index]), float(on[row].mean()))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["48x24", "96x48", "192x96"])
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    print("| grid | " + " | ".join(f"{line} (height / nearest row)" for line in LINES) + " |")
    print("|---" * (len(LINES) + 1) + "|")
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        means = girth_means(n, m)
        cells = [f"{means[line][0]:.0f} / {means[line][1]:.0f}" for line in LINES]
        print(f"| {grid} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
