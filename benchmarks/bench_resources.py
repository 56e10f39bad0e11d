"""Peak memory and wall time of the per-case stages against the grid: the data behind
`cloth.pipeline.resources` (what a cluster job asks for).

Each stage runs as its own `cloth` process (as a Snakemake job does), and its peak resident
memory is the process's own VmHWM (`cloth.pipeline.resources.measure_stage`). Case: power net on the
smooth torso M (the default body), 0.80-1.25 m, reduction 0.15, Newton to 1e-8. Writes
docs/performance.md (section ``resources``) and prints the fitted model next to the estimate.
Run (minutes; the largest grid dominates):

    .venv/bin/python benchmarks/bench_resources.py [--grids 48x24 96x48 192x96 384x192]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml
from _table import markdown_table, replace_section

from cloth.case.case import validate_case
from cloth.pipeline.resources import measure_stage, stage_resources


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["48x24", "96x48", "192x96", "384x192"])
    args = parser.parse_args()
    rows, nodes, memory = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        material = folder / "powernet.nc"
        root = Path(__file__).resolve().parents[1]
        measure_stage(
            sys.executable,
            "material",
            "ingest",
            str(root / "data/materials/powernet.csv"),
            "-o",
            str(material),
        )
        for grid in args.grids:
            n, m = (int(v) for v in grid.split("x"))
            case = {
                "material": str(material),
                "body": {"torso": {"size": "M"}},
                "garment": {"bottom": 0.80, "top": 1.25, "reduction": 0.15, "grid": [n, m]},
                "solver": {"method": "newton", "tolerance": 1e-8, "max_iterations": 100},
            }
            path = folder / f"{grid}.yaml"
            path.write_text(yaml.safe_dump(case))
            initial, relaxed, result = (folder / f"{grid}.{s}.nc" for s in ("i", "r", "a"))
            stages = {
                "predeform": ["predeform", str(path), "-o", str(initial)],
                "relax": ["relax", str(initial), "-o", str(relaxed)],
                "aggregate": ["aggregate", str(relaxed), "-o", str(result)],
            }
            for stage, command in stages.items():
                seconds, peak = measure_stage(sys.executable, *command)
                estimate = stage_resources(stage, validate_case(case, path))
                rows.append(
                    [
                        stage,
                        grid,
                        f"{n * m:,}",
                        f"{seconds:.1f}",
                        f"{peak:.0f}",
                        f"{estimate.mem_mb}",
                        f"{estimate.runtime}",
                    ]
                )
                print(rows[-1], flush=True)
                if stage == "relax":
                    nodes.append(n * m)
                    memory.append(peak)
    if len(nodes) >= 2:
        slope, base = np.polyfit(nodes, memory, 1)
        print(f"relax peak memory ~ {base:.0f} MiB + {slope * 1e3:.2f} MiB per 1000 nodes")
    table = markdown_table(
        [
            "stage",
            "grid",
            "nodes",
            "wall [s]",
            "peak memory [MiB]",
            "asks mem_mb",
            "asks runtime [min]",
        ],
        rows,
    )
    replace_section("resources", table)


if __name__ == "__main__":
    main()
