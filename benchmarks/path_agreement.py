"""One answer, whatever the path (issues 29 and 40): the torso case relaxed by plain Newton and
by the default fast path (continuation and reuse), every reported quantity side by side.

    .venv/bin/python benchmarks/path_agreement.py [--grids 96x48 192x96] [--band 0.86 1.22]
        [--lengthwise 0 0.1] [--bend-modulus 1e4]

Prints one markdown row per grid, band and lengthwise reduction: the largest relative
difference of the girth lines' band values (mean, probe max and min, tension) and of the normal
force, each path's relax time (s) and factorisations, and the unstable modes of each path
(docs/validation.md, "Path agreement").
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
    grid: tuple[int, int],
    band: tuple[float, float],
    solver: dict,
    bend_modulus: float,
    lengthwise: float = 0.0,
) -> xr.Dataset:
    garment = {
        "bottom": band[0],
        "top": band[1],
        "reduction": 0.20,
        "grid": list(grid),
        "lengthwise_reduction": lengthwise,
        "error_estimate": False,
    }
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
    parser.add_argument("--lengthwise", nargs="+", type=float, default=[0.0])
    parser.add_argument("--bend-modulus", type=float, default=0.0, help="garment.bend_modulus")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    band = f"{args.band[0]}-{args.band[1]}"
    print(
        "| grid | band (m) | lengthwise | largest difference of a band value (which) | "
        "normal force | plain: relax s, factorisations | fast: relax s, factorisations | "
        "unstable modes (plain, fast) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        for lengthwise in args.lengthwise:
            plain, fast = (
                result((n, m), tuple(args.band), s, args.bend_modulus, lengthwise)
                for s in PATHS.values()
            )
            worst, which = 0.0, ""
            for name in QUANTITIES:
                a, b = plain[name].values, fast[name].values
                rel = np.abs(b - a) / np.maximum(np.abs(a), 1e-12)
                k = int(np.argmax(rel))
                if rel[k] >= worst:
                    worst, which = float(rel[k]), f"{name}, {plain['landmark'].values[k]}"
            a, b = float(plain["normal_force"]), float(fast["normal_force"])
            cost = [
                f"{float(ds.attrs['solver_seconds']):.1f}, {ds.attrs['solver_factorisations']}"
                for ds in (plain, fast)
            ]
            modes = (plain.attrs.get("unstable_modes"), fast.attrs.get("unstable_modes"))
            print(
                f"| {grid} | {band} | {lengthwise:g} | {worst:.1e} ({which}) | "
                f"{abs(b - a) / abs(a):.1e} | {cost[0]} | {cost[1]} | {modes[0]}, {modes[1]} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
