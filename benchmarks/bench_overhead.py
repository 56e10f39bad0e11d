"""The pipeline's per-case rules outside the solver, at two revisions side by side (issue 54):
each rule's command as that revision's workflow runs it (predeform, aggregate, figures with its
sweep's results as peers, view), on one case of a finished ``make run``, timed as a process
(imports included), ``--repeat`` times alternating between the revisions; prints the median of
each rule at each revision and their ratio. A revision whose figures take the sweep's
colour-range file (``cloth plot --ranges``) has it written first by its ``cloth ranges``, timed
on its own row (once a sweep, not once a case).

    .venv/bin/python benchmarks/bench_overhead.py BEFORE AFTER [--repeat 3]
        [--results results] [--case powernet__torso_M__r150]

BEFORE and AFTER are git revisions of this repository, each cloned to a temporary folder and run
with this checkout's .venv (PYTHONPATH set to the clone). The case's relaxed.nc and result.nc and
its sweep's results (the peers: every ``cases/*/result.nc`` but the design's) come from
``--results``, the output folder of a ``make run`` (192 x 96 on the torso by default).
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from make_run_time import clone

ROOT = Path(__file__).resolve().parents[1]
RULES = ("predeform", "aggregate", "colour_ranges", "figures", "view")


def commands(folder: Path, case: Path, peers: list[Path], out: Path) -> dict[str, list[str]]:
    """Each rule's command as the revision in ``folder`` runs it (its predeform drew
    initial.png where its rule passes ``--plot``; its figures read the peers, or the
    colour-range file its ``colour_ranges`` rule writes from them)."""
    rules = folder / "workflow" / "rules"
    plots = "--plot" in (rules / "predeform.smk").read_text()
    ranges = "rule colour_ranges" in (rules / "figures.smk").read_text()
    cloth = str(ROOT / ".venv" / "bin" / "cloth")
    colour = out / "colour_ranges.json"
    figures = [cloth, "plot", str(case / "result.nc")]
    figures += ["--ranges", str(colour)] if ranges else ["--peers", *[str(p) for p in peers]]
    found = {
        "predeform": [cloth, "predeform", str(case / "case.yaml"), "-o", str(out / "initial.nc")]
        + (["--plot", str(out / "initial.png")] if plots else []),
        "aggregate": [
            cloth,
            "aggregate",
            str(case / "relaxed.nc"),
            "-o",
            str(out / "result.nc"),
            "--summary",
            str(out / "summary.csv"),
        ],
        "colour_ranges": [cloth, "ranges", *[str(p) for p in peers], "-o", str(colour)],
        "figures": [*figures, "-o", str(out / "figures")],
        "view": [cloth, "view", str(case / "result.nc"), "-o", str(out / "garment.html")],
    }
    if not ranges:
        del found["colour_ranges"]
    return found


def timed(command: list[str], folder: Path) -> float:
    env = {**os.environ, "PYTHONPATH": str(folder), "MPLBACKEND": "Agg"}
    start = time.perf_counter()
    done = subprocess.run(command, cwd=folder, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode:
        sys.exit(f"{folder.name}: {' '.join(command[:3])} failed:\n{done.stderr[-2000:]}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("revisions", nargs=2)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--results", type=Path, default=ROOT / "results")
    parser.add_argument("--case", default="powernet__torso_M__r150")
    args = parser.parse_args()
    source = args.results / "cases" / args.case
    if not (source / "relaxed.nc").is_file():
        sys.exit(f"{source}: no relaxed.nc; run `make run` first (or pass --results, --case)")
    peers = sorted(
        p for p in (args.results / "cases").glob("*/result.nc") if "design" not in p.parent.name
    )
    times: dict[tuple[str, str], list[float]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        folders = [clone(r, work) for r in args.revisions]
        case = work / "results" / "cases" / args.case  # the material ../../materials/ as written
        shutil.copytree(source, case)
        shutil.copytree(args.results / "materials", work / "results" / "materials")
        for _ in range(args.repeat):
            for revision, folder in zip(args.revisions, folders, strict=True):
                out = work / f"out_{revision}"
                shutil.rmtree(out, ignore_errors=True)
                out.mkdir()
                for rule, command in commands(folder, case, peers, out).items():
                    seconds = timed(command, folder)
                    times.setdefault((revision, rule), []).append(seconds)
                    print(f"{revision} {rule}: {seconds:.2f} s", flush=True)
    before, after = args.revisions
    print(f"\n| rule | {before} [s] | {after} [s] | after / before |")
    print("|---|---|---|---|")
    for rule in RULES:
        a, b = (statistics.median(times.get((r, rule), [math.nan])) for r in (before, after))
        print(f"| {rule} | {a:.2f} | {b:.2f} | {b / a:.2f} |")
    print(f"\nmedians of {args.repeat} runs each, {len(peers)} peers")


if __name__ == "__main__":
    main()
