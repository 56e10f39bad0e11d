"""Stated against true errors of every girth line of `make run`'s cases (issue 54): each case
relaxed alone on 24 x 12, 48 x 24, 96 x 48, 192 x 96 and 384 x 192 (no estimate: the values
only), then the 192 x 96 value's error stated two ways and compared with its distance from the
384 x 192 value and with the criterion max(1 %, 0.1 mmHg):

* the three-level rule of `cloth.results.richardson` (levels 96 x 48 and 48 x 24, what the
  pipeline states);
* a least-squares fit of f = f0 + a h^p over the four levels (Eça and Hoekstra, J. Comput.
  Phys. 262, 2014: the weighted or unweighted fit with the smaller standard deviation sigma;
  U = 1.25 |f0 - f1| + sigma + |f1 - fit(h1)| where sigma is below the data range's step, else
  3 sigma / step times that sum; no U outside 0.5 <= p < 2.1, where their procedure switches to
  fixed-order fits, not built here).

    .venv/bin/python benchmarks/estimate_rules.py [--bodies torso_M avatar_M]
        [--lengthwise 0.0 0.10] [--reduction 0.15]

Prints one markdown table row per case and line (Pa).
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
import yaml
from scipy.optimize import least_squares

from cloth.results.pressure import MMHG
from cloth.results.richardson import estimate_levels
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]
GRIDS = [(192, 96), (96, 48), (48, 24), (24, 12)]  # finest first; the reference below
REFERENCE = (384, 192)
BODIES = {"torso_M": {"torso": {"size": "M"}}, "avatar_M": {"avatar": {"size": "M"}}}


def means(body: str, lengthwise: float, reduction: float, grid: tuple[int, int]) -> dict:
    """line -> the girth-line mean (Pa) of `make run`'s case on ``grid``, relaxed alone."""
    case = {
        "material": "powernet",
        "body": BODIES[body],
        "garment": {
            "bottom": 0.86,
            "top": 1.22,
            "reduction": reduction,
            "lengthwise_reduction": lengthwise,
            "grid": list(grid),
            "edges": "sliding",
            "error_estimate": False,
        },
        "solver": {"method": "newton", "tolerance": 1e-8, "max_iterations": 150},
    }
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "case.yaml"
        path.write_text(yaml.safe_dump(case))
        run_case(path, Path(tmp) / "out", {}, ROOT, stop_after="aggregate")
        with xr.open_dataset(Path(tmp) / "out" / "result.nc") as ds:
            names = [str(v) for v in ds["landmark"].values]
            return dict(zip(names, (float(v) for v in ds["pressure_mean"].values), strict=True))


def least_squares_error(values: np.ndarray) -> tuple[float, float]:
    """(order p, stated error U) of Eça and Hoekstra's fit (module docstring) of ``values``
    (finest first, spacings 1, 2, 4, 8); U NaN outside 0.5 <= p < 2.1."""
    h = 2.0 ** np.arange(len(values))
    fits = []
    for weights in (np.full(len(h), 1.0 / len(h)), (1 / h) / np.sum(1 / h)):

        def residual(x, w=weights):
            return np.sqrt(w) * (values - (x[0] + x[1] * h ** x[2]))

        best = None
        for p0 in (0.5, 1.0, 2.0, 3.0):
            a0 = (values[-1] - values[0]) / (h[-1] ** p0 - 1)
            start = [values[0] - a0, a0, p0]
            sol = least_squares(residual, start, bounds=([-np.inf, -np.inf, 0], [np.inf] * 2 + [8]))
            best = sol if best is None or sol.cost < best.cost else best
        f0, a, p = best.x
        sigma = math.sqrt(len(h) / (len(h) - 3) * np.sum(residual(best.x) ** 2))
        fits.append((sigma, f0, a, p))
    sigma, f0, a, p = min(fits)
    if not 0.5 <= p < 2.1:
        return p, math.nan
    step = (values.max() - values.min()) / (len(values) - 1)
    core = abs(f0 - values[0]) + sigma + abs(values[0] - (f0 + a))
    stated = 1.25 * abs(f0 - values[0]) + sigma + abs(values[0] - (f0 + a))
    return p, stated if sigma < step else 3.0 * sigma / step * core


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", nargs="+", default=list(BODIES), choices=list(BODIES))
    parser.add_argument("--lengthwise", nargs="+", type=float, default=[0.0, 0.10])
    parser.add_argument("--reduction", type=float, default=0.15)
    args = parser.parse_args()
    print(
        "| case | line | 192x96 | 384x192 | true error | three levels (p) | least squares (p) "
        "| max(1 %, 0.1 mmHg) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for body in args.bodies:
        for lengthwise in args.lengthwise:
            runs = {g: means(body, lengthwise, args.reduction, g) for g in [*GRIDS, REFERENCE]}
            for line, reference in runs[REFERENCE].items():
                values = np.array([runs[g][line] for g in GRIDS])
                three = estimate_levels(list(values[:3]), GRIDS[:3])
                p, fitted = least_squares_error(values)
                criterion = max(0.01 * abs(values[0]), 0.1 * MMHG)
                print(
                    f"| {body} lw {lengthwise:g} | {line} | {values[0]:.1f} | {reference:.1f} "
                    f"| {abs(values[0] - reference):.1f} "
                    f"| {three.uncertainty:.1f} ({three.order:.2f}) | {fitted:.1f} ({p:.2f}) "
                    f"| {criterion:.1f} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()
