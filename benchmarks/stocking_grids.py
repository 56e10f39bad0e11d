"""The stocking's stated errors against its grid (issue 54, item 3): every measuring point B..G
with its band mean and stated error, flagged where the error is over max(1 %, 0.1 mmHg), and
the time of one case (predeform, relax with the estimate's levels, aggregate).

The stocking of config/stocking.yaml (power net, reduction 0.16, lengthwise reduction 0.15,
0.09-0.77 m, sliding edges: `bench_stocking.run`) on one body, on each of ``--grids``. Run:

    .venv/bin/python benchmarks/stocking_grids.py [--body leg|avatar] [--size M]
        [--grids 32x48 64x192 96x288] [--level-ratio 2] [--row-grading 0]
"""

from __future__ import annotations

import argparse
import logging

from bench_stocking import run

from cloth.results.pressure import MMHG

#: The criterion: a stated error within this share of the value, or this many mmHg.
SHARE, FLOOR = 0.01, 0.1


def body(kind: str, size: str) -> dict:
    if kind == "leg":
        return {"leg": {"size": size}}
    return {"avatar": {"chart": "data/bodies/leg_chart.csv", "size": size}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--body", choices=["leg", "avatar"], default="leg")
    parser.add_argument("--size", default="M")
    parser.add_argument("--grids", nargs="+", default=["32x48", "64x192", "96x288"])
    parser.add_argument("--level-ratio", type=float, default=2.0, help="garment.level_ratio")
    parser.add_argument("--row-grading", type=float, default=0.0, help="garment.row_grading")
    args = parser.parse_args()
    logging.basicConfig(level=logging.ERROR)
    lines = None
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        ds, seconds = run(
            (n, m),
            {"method": "newton"},
            True,
            body(args.body, args.size),
            args.level_ratio,
            args.row_grading,
        )
        if lines is None:
            lines = [str(v) for v in ds["landmark"].values]
            print(f"| grid | one case [s] | {' | '.join(lines)} | over the criterion |")
            print("|---" * (len(lines) + 3) + "|")
        cells, over = [], 0
        for k in range(len(lines)):
            value = float(ds["pressure_mean"].values[k]) / MMHG
            error = float(ds["pressure_mean_error"].values[k]) / MMHG
            within = error <= max(SHARE * value, FLOOR)  # NaN: not within
            over += not within
            cells.append(f"{value:.2f} ± {error:.2f}" + ("" if within else " (!)"))
        stalled = "" if int(ds.attrs.get("converged", 0)) else " (NOT converged)"
        print(f"| {grid}{stalled} | {seconds:.1f} | {' | '.join(cells)} | {over} |", flush=True)


if __name__ == "__main__":
    main()
