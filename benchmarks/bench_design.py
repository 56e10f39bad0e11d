"""The design loop's cost (issue 30, benchmarks): time and equilibria against the number of
target lines (control knots), and one adjoint gradient against central differences.

    .venv/bin/python benchmarks/bench_design.py [--grids 96x48 192x96] [--lines 1 2 4 8]

Torso M, 0.86-1.22 m, power net, from a uniform reduction of 0.2. The target lines are spread
evenly between 0.90 and 1.18 m (the case's landmarks), each asking for a pressure on a smooth
profile from 15 mmHg at the bottom to 20 at the middle and 16 at the top. Per grid and line
count: the loop's wall time, its equilibria (the confirmation from scratch not included), the
Newton iterations they took, and the largest miss; then at the design's equilibrium, the
adjoint Jacobian's time against the 2K equilibria of central differences, as a ratio.
"""

from __future__ import annotations

import argparse
import logging
import time
from dataclasses import replace

import numpy as np

from cloth.files.body import body_from_record
from cloth.results.pressure import MMHG
from cloth.results.sensitivity import sensitivities
from cloth.results.targets import Target
from cloth.solvers.relax import relax
from cloth.stages.case import initial_state
from cloth.stages.design import design, finite_difference_jacobian

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


def profile(z: np.ndarray) -> np.ndarray:
    """Target mmHg at heights z: 15 at 0.90 m, 20 at 1.04 m, 16 at 1.18 m (piecewise linear)."""
    return np.interp(z, [0.90, 1.04, 1.18], [15.0, 20.0, 16.0])


def run(grid: tuple[int, int], count: int) -> dict[str, float]:
    heights = np.linspace(0.90, 1.18, count) if count > 1 else np.array([1.04])
    lines = {f"l{k}": float(z) for k, z in enumerate(heights)}
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "landmarks": lines,
        "garment": {
            "bottom": 0.86,
            "top": 1.22,
            "grid": list(grid),
            "reduction": 0.2,
            "error_estimate": False,
        },
    }
    state = initial_state(case, ROOT)
    body = body_from_record(state.body)
    targets = [Target(name, p * MMHG) for name, p in zip(lines, profile(heights), strict=True)]
    start = time.perf_counter()
    result = design(state, body, targets)
    seconds = time.perf_counter() - start
    eq = result.state
    settings = replace(eq.case.solver, progress=False)
    final = relax(eq, body, settings)  # the design's last equilibrium, its factor kept
    start = time.perf_counter()
    sensitivities(eq, body, final.final, lines, final.factor)
    adjoint = time.perf_counter() - start
    start = time.perf_counter()
    finite_difference_jacobian(eq, body, settings, lines, 1e-5)
    differences = time.perf_counter() - start
    return {
        "seconds": seconds,
        "solves": result.solves,
        "newton": sum(it.iterations for it in result.iterates),
        "miss": float(np.max(np.abs(result.achieved - result.targets)) / MMHG),
        "adjoint": adjoint,
        "differences": differences,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["96x48", "192x96"])
    parser.add_argument("--lines", nargs="+", type=int, default=[1, 2, 4, 8])
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    print(
        "| grid | lines | design (s) | equilibria | Newton iterations | largest miss (mmHg) "
        "| adjoint (s) | differences, 2K equilibria (s) | ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        for count in args.lines:
            r = run((n, m), count)
            print(
                f"| {grid} | {count} | {r['seconds']:.1f} | {r['solves']} | {r['newton']} | "
                f"{r['miss']:.3f} | {r['adjoint']:.3f} | {r['differences']:.1f} | "
                f"{r['differences'] / r['adjoint']:.0f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
