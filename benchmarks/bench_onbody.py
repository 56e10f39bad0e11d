"""An on-body figure's time at two revisions side by side: `body_figure` and its PNG at 150 dpi
(the layout passes, the fill's zoom, the drawing), on two bands wider than tall at CI size (the
CI config's avatar S band, 24 x 8; a 12 cm band on a meshed tube, 20 x 6), five times per
revision in one process, ``--repeat`` alternations; prints each revision's median and the ratio.

    .venv/bin/python benchmarks/bench_onbody.py BEFORE AFTER [--repeat 3]

BEFORE and AFTER are git revisions, each cloned to a temporary folder and run with this
checkout's .venv (PYTHONPATH set to the clone); the results are made once with this checkout.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import trimesh
import yaml

ROOT = Path(__file__).resolve().parents[1]
SOLVER = {"method": "newton", "tolerance": 1.0e-8, "max_iterations": 150}
COMMON = {"reduction": 0.15, "edges": "sliding", "error_estimate": False}
CHILD = """
import io, sys, time, statistics, matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt, xarray as xr
from cloth.figures.drawing import body_band
from cloth.figures.onbody import body_figure
for path in sys.argv[1:]:
    ds = xr.load_dataset(path)
    body = body_band(ds)
    times = []
    for _ in range(5):
        start = time.perf_counter()
        fig = body_figure(ds, "body_pressure", body=body)
        fig.savefig(io.BytesIO(), format="png", dpi=150)
        plt.close(fig)
        times.append(time.perf_counter() - start)
    print(statistics.median(times))
"""


def results(folder: Path) -> dict[str, Path]:
    """The two bands' result.nc, made with this checkout."""
    from cloth.stages.case import run_case

    tube = trimesh.creation.cylinder(radius=0.09, height=0.7, sections=40)
    tube.apply_translation([0.0, 0.0, 0.35])
    tube.export(folder / "tube.obj")
    cases = {
        "avatar band": {
            "body": {"avatar": {"size": "S"}, "smoothing": 0.012, "spacing": 0.005},
            "garment": {"bottom": 0.9, "top": 1.15, "grid": [24, 8], **COMMON},
        },
        "tube band": {
            "body": {"mesh": str(folder / "tube.obj"), "surface": "mesh"},
            "landmarks": {"mid": 0.36},
            "garment": {"bottom": 0.3, "top": 0.42, "grid": [20, 6], **COMMON},
        },
    }
    out = {}
    for name, case in cases.items():
        path = folder / f"{name.replace(' ', '_')}.yaml"
        path.write_text(yaml.safe_dump({"material": "powernet", "solver": SOLVER, **case}))
        run_case(path, folder / path.stem, {}, base_dir=ROOT, stop_after="aggregate")
        out[name] = folder / path.stem / "result.nc"
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        made = results(Path(tmp))
        trees = {}
        for rev in (args.before, args.after):
            trees[rev] = Path(tmp) / f"tree-{rev}"
            subprocess.run(["git", "clone", "-q", str(ROOT), str(trees[rev])], check=True)
            subprocess.run(["git", "-C", str(trees[rev]), "checkout", "-q", rev], check=True)
        times: dict[str, dict[str, list[float]]] = {r: {n: [] for n in made} for r in trees}
        for _ in range(args.repeat):
            for rev, tree in trees.items():
                run = subprocess.run(
                    [sys.executable, "-c", CHILD, *map(str, made.values())],
                    capture_output=True,
                    text=True,
                    check=True,
                    env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"},
                    cwd=tree,  # python -c puts its working folder first on the path
                )
                for name, line in zip(made, run.stdout.split(), strict=True):
                    times[rev][name].append(float(line))
    print("| figure | before [s] | after [s] | ratio |\n|---|---|---|---|")
    for name in made:
        before = statistics.median(times[args.before][name])
        after = statistics.median(times[args.after][name])
        print(f"| {name} | {before:.3f} | {after:.3f} | {after / before:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
