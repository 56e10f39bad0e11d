"""Every size of a chart designed at once (issue 42, benchmarks): per size, the design loop's
time, equilibria and Newton iterations, cold (from the case's uniform reduction) and warm
(from the designed profile of the size before it), side by side in one run.

    .venv/bin/python benchmarks/bench_chart.py [--charts torso leg] [--torso-grid 96x48]
        [--leg-grid 32x48] [--no-write]

Torso S, M, L, 0.86-1.22 m, power net, hip 15 / waist 20 / underbust 18 / bust 15 mmHg, from a
uniform 0.2 (the default config's design, `make run`). Leg S, M, L, 0.09-0.77 m, lengthwise
reduction 0.15, B 30 / C 21 / F 12 mmHg, from 0.16 (config/stocking.yaml's). The confirmation
from scratch, the same one equilibrium either way, is not timed. Each size's cold and warm
designs run one after the other, so the ratio is of one machine state.
"""

from __future__ import annotations

import argparse
import logging
import time

import numpy as np
from _table import markdown_table, publish

from cloth.case import Case
from cloth.case.case import validate_case
from cloth.files.body import body_from_record
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.stages.case import initial_state
from cloth.stages.chart import warm_case
from cloth.stages.design import design

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
SIZES = ("S", "M", "L")
CHARTS = {
    "torso": (
        {"torso": {"size": "M"}},
        {"bottom": 0.86, "top": 1.22, "reduction": 0.2},
        ["hip=15", "waist=20", "underbust=18", "bust=15"],
    ),
    "leg": (
        {"leg": {"size": "M"}},
        {
            "bottom": 0.09,
            "top": 0.77,
            "reduction": 0.16,
            "edges": "sliding",
            "lengthwise_reduction": 0.15,
        },
        ["B=30", "C=21", "F=12"],
    ),
}


def case_of(chart: str, size: str, grid: tuple[int, int]) -> Case:
    body, garment, _ = CHARTS[chart]
    kind = next(iter(body))
    return validate_case(
        {
            "material": "powernet",
            "body": {kind: {**body[kind], "size": size}},
            "garment": {**garment, "grid": list(grid), "error_estimate": False},
            "solver": {"max_iterations": 150},
        }
    )


def timed(case: Case, targets: list[Target]):
    state = initial_state(case, ROOT)
    start = time.perf_counter()
    result = design(state, body_from_record(state.body), targets)
    seconds = time.perf_counter() - start
    miss = float(np.max(np.abs(result.achieved - result.targets))) / MMHG
    newton = sum(it.iterations for it in result.iterates)
    return result, seconds, newton, miss


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--charts", nargs="+", default=list(CHARTS), choices=list(CHARTS))
    parser.add_argument("--torso-grid", default="96x48")
    parser.add_argument("--leg-grid", default="32x48")
    parser.add_argument("--section", default="chart")
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    rows = []
    for chart in args.charts:
        grid = tuple(int(v) for v in getattr(args, f"{chart}_grid").split("x"))
        targets = [Target.parse(text) for text in CHARTS[chart][2]]
        previous = None
        for size in SIZES:
            case = case_of(chart, size, grid)
            cold, t_cold, n_cold, m_cold = timed(case, targets)
            if previous is None:
                warm, t_warm, n_warm, m_warm = cold, t_cold, n_cold, m_cold
            else:
                warm, t_warm, n_warm, m_warm = timed(warm_case(case, previous), targets)
            rows.append(
                [
                    chart,
                    f"{grid[0]} x {grid[1]}",
                    size,
                    f"{t_cold:.1f}",
                    f"{cold.solves} ({n_cold})",
                    f"{t_warm:.1f}",
                    f"{warm.solves} ({n_warm})",
                    f"{t_warm / t_cold:.2f}",
                    f"{max(m_cold, m_warm):.3f}",
                ]
            )
            print(rows[-1], flush=True)
            previous = warm
    header = [
        "chart",
        "grid",
        "size",
        "cold s",
        "cold equilibria (Newton its)",
        "warm s",
        "warm equilibria (Newton its)",
        "warm / cold",
        "largest miss mmHg",
    ]
    note = (
        "`benchmarks/bench_chart.py`: the design loop per size (the confirmation from scratch "
        "not timed); warm = from the designed profile of the size before it, in the order "
        "S, M, L (S has none: its cold run)."
    )
    publish(f"{note}\n\n{markdown_table(header, rows)}", args.section, not args.no_write)


if __name__ == "__main__":
    main()
