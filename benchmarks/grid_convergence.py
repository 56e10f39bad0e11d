"""Girth-line means over grids (issues 29 and 40): the torso M, reduction 0.20, power net, the
default path (continuation and reuse, the tension field). Each line is read on the body (the
summary's band value, `cloth.results.bands`) with the case's own stated error beside it (its two
coarser levels, `cloth.stages.levels`): value +- stated error (the observed order, or ``2g``
where the error is three times the finest difference of levels that converge without one), or
the reason none was given; after the slash the row value (``row_pressure_mean``, the definition
before issue 40), to show which of the two converges with the grid.

    .venv/bin/python benchmarks/grid_convergence.py [--grids 48x24 96x48 192x96 384x192]
        [--band 0.86 1.22] [--lengthwise 0.0]

Prints a markdown table of the mean pressure (Pa) per girth line and grid, and whether each
grid's stated error contains the finest grid's band value.
"""

from __future__ import annotations

import argparse
import logging
import math
import tempfile
from pathlib import Path

import xarray as xr
import yaml

from cloth.results.richardson import DATA_RANGE, FINEST_DIFFERENCE, REASONS
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]
LINES = ("hip", "waist", "underbust", "bust")


def case(n: int, m: int, band: tuple[float, float], lengthwise: float) -> dict:
    return {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {
            "bottom": band[0],
            "top": band[1],
            "reduction": 0.20,
            "lengthwise_reduction": lengthwise,
            "grid": [n, m],
        },
    }


def girth_means(n: int, m: int, band: tuple[float, float], lengthwise: float) -> dict:
    """line -> (band value, row value, stated error (Pa), order, code) on an n x m grid."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "case.yaml"
        path.write_text(yaml.safe_dump(case(n, m, band, lengthwise)))
        run_case(path, Path(tmp) / "out", {}, ROOT, stop_after="aggregate")
        with xr.open_dataset(Path(tmp) / "out" / "result.nc") as ds:
            return {
                str(name): (
                    float(ds["pressure_mean"][k]),
                    float(ds["row_pressure_mean"][k]),
                    float(ds["pressure_mean_error"][k]),
                    float(ds["pressure_mean_order"][k]),
                    int(ds["pressure_mean_estimate"][k]),
                )
                for k, name in enumerate(ds["landmark"].values.tolist())
            }


def cell(value: float, row: float, error: float, order: float, code: int) -> str:
    if code == FINEST_DIFFERENCE:
        stated = f"{value:.0f} +- {error:.0f} (2g)"
    elif code == DATA_RANGE:
        stated = f"{value:.0f} +- {error:.0f} (range)"
    elif math.isfinite(error):
        stated = f"{value:.0f} +- {error:.0f} (p {order:.2f})"
    else:
        stated = f"{value:.0f} (no error: {REASONS.get(code, '')})"
    return f"{stated} / {row:.0f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["48x24", "96x48", "192x96"])
    parser.add_argument("--band", nargs=2, type=float, default=[0.86, 1.22])
    parser.add_argument("--lengthwise", type=float, default=0.0)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    band = tuple(args.band)
    print(f"band {band[0]}-{band[1]} m, lengthwise reduction {args.lengthwise:g}\n")
    print("| grid | " + " | ".join(f"{line}: band / row" for line in LINES) + " |")
    print("|---" * (len(LINES) + 1) + "|")
    found = {}
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        found[grid] = means = girth_means(n, m, band, args.lengthwise)
        print(f"| {grid} | " + " | ".join(cell(*means[line]) for line in LINES) + " |", flush=True)
    finest = found[args.grids[-1]]
    print(f"\nWhether each grid's stated error contains the {args.grids[-1]} band value:")
    for grid in args.grids[:-1]:
        verdict = []
        for line in LINES:
            value, _, error, _, _ = found[grid][line]
            miss = finest[line][0] - value
            said = "-" if not math.isfinite(error) else ("yes" if abs(miss) <= error else "NO")
            verdict.append(f"{line} {said} ({miss:+.0f} Pa, {100 * miss / value:+.2f} %)")
        print(f"- {grid}: " + ", ".join(verdict))


if __name__ == "__main__":
    main()
