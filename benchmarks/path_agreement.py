"""One answer, whatever the path (issue 29, item 4): the torso case relaxed by plain Newton and
by Newton with continuation and reuse, every reported quantity side by side.

    .venv/bin/python benchmarks/path_agreement.py [--grids 96x48 192x96] [--band 0.86 1.22]
        [--bend-modulus 1e4]

Prints, per grid, the largest relative difference of the girth lines' mean, max and min pressure
and tension, the normal force on the body, and the unstable modes of each path.
"""

from __future__ import annotations

import argparse
import logging
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]
QUANTITIES = ("pressure_mean", "pressure_max", "pressure_min", "tension_mean")
PATHS = {
    "plain": {"method": "newton", "continuation": False, "reuse": False},
    "continuation+reuse": {"method": "newton", "continuation": True, "reuse": True},
}


def result(
    grid: tuple[int, int], band: tuple[float, float], solver: dict, bend_modulus: float
) -> xr.Dataset:
    garment = {"bottom": band[0], "top": band[1], "reduction": 0.20, "grid": list(grid)}
    if bend_modulus > 0:
        garment["bend_modulus"] = bend_modulus
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": garment,
        "solver": solver,
    }
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "case.yaml"
        path.write_text(yaml.safe_dump(case))
        run_case(path, Path(tmp) / "out", {}, ROOT, stop_after="aggregate")
        return xr.load_dataset(Path(tmp) / "out" / "result.nc")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["96x48"])
    parser.add_argument("--band", nargs=2, type=float, default=[0.86, 1.22])
    parser.add_argument("--bend-modulus", type=float, default=0.0, help="garment.bend_modulus")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    print("| grid | band (m) | quantity | largest relative difference | where |")
    print("|---|---|---|---|---|")
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        plain, fast = (
            result((n, m), tuple(args.band), s, args.bend_modulus) for s in PATHS.values()
        )
        for name in QUANTITIES:
            a, b = plain[name].values, fast[name].values
            rel = np.abs(b - a) / np.maximum(np.abs(a), 1e-12)
            k = int(np.argmax(rel))
            where = str(plain["landmark"].values[k])
            print(f"| {grid} | {args.band[0]}-{args.band[1]} | {name} | {rel[k]:.2e} | {where} |")
        a, b = float(plain["normal_force"]), float(fast["normal_force"])
        print(f"| {grid} | {args.band[0]}-{args.band[1]} | normal_force | "
              f"{abs(b - a) / abs(a):.2e} | |")  # fmt: skip
        modes = (plain.attrs.get("unstable_modes"), fast.attrs.get("unstable_modes"))
        print(f"| {grid} | {args.band[0]}-{args.band[1]} | unstable modes (plain, fast) | "
              f"{modes[0]}, {modes[1]} | |", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
