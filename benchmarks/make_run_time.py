"""`make run`'s wall time at two revisions, side by side in one run on this machine: each revision
cloned to a temporary folder and its default pipeline (``snakemake --cores 2`` on
config/config.yaml, the work of ``make run`` with the install excluded: both use this checkout's
.venv) run ``--repeat`` times, alternating; prints the median of each and their ratio, each
run's job time by rule (from Snakemake's records of its jobs), and what each run's numbers
say of their accuracy (`accuracy`): the largest stated error of a girth-line mean over every
case (% of its value), how many are over the criterion max(1 %, 0.1 mmHg), the lines without
one, and the widest design interval.

    .venv/bin/python benchmarks/make_run_time.py BEFORE AFTER [--repeat 1] [--config PATH]

BEFORE and AFTER are git revisions of this repository (e.g. ``a757ceb HEAD``). A revision's
outputs stay in its clone until the script ends.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def clone(revision: str, where: Path) -> Path:
    folder = where / revision.replace("/", "_")
    subprocess.run(["git", "clone", "-q", str(ROOT), str(folder)], check=True)
    subprocess.run(["git", "-C", str(folder), "checkout", "-q", revision], check=True)
    return folder


def run(folder: Path, config: str) -> float:
    """One pipeline run from nothing (its results, Snakemake's records and cloth's bytecode
    removed), seconds."""
    subprocess.run(["rm", "-rf", "results", ".snakemake"], cwd=folder, check=True)
    subprocess.run(
        ["find", "cloth", "-name", "__pycache__", "-prune", "-exec", "rm", "-rf", "{}", "+"],
        cwd=folder,
        check=True,
    )
    env = {
        **os.environ,
        "PYTHONPATH": str(folder),
        "MPLBACKEND": "Agg",
        "PATH": f"{ROOT / '.venv' / 'bin'}:{os.environ['PATH']}",
    }
    start = time.perf_counter()
    if "\nbytecode:" in (folder / "Makefile").read_text():  # make run compiles cloth first
        python = str(ROOT / ".venv/bin/python")
        subprocess.run([python, "-m", "compileall", "-q", "cloth"], cwd=folder, check=True)
    done = subprocess.run(
        [str(ROOT / ".venv/bin/snakemake"), "--cores", "2", "--configfile", config, "-q"],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
    )
    if done.returncode:
        sys.exit(f"{folder.name}: the pipeline failed:\n{done.stderr[-2000:]}")
    return time.perf_counter() - start


def rule_times(folder: Path) -> dict[str, list[float]]:
    """Job time (s) of every job of the clone's last Snakemake run, by rule: each job's start
    and end as Snakemake records them with its outputs (``.snakemake/metadata``, one record per
    output file; a job's outputs share its hash)."""
    jobs: dict[tuple[str, int], float] = {}
    for record in (folder / ".snakemake" / "metadata").iterdir():
        data = json.loads(record.read_text())
        if data.get("starttime") and data.get("endtime"):
            key = (data["rule"], data.get("job_hash", record.name))
            jobs[key] = data["endtime"] - data["starttime"]
    times: dict[str, list[float]] = {}
    for (rule, _), seconds in jobs.items():
        times.setdefault(rule, []).append(seconds)
    return times


def rule_table(times: dict[str, list[float]]) -> str:
    rows = ["| rule | jobs | total [s] | median per job [s] |", "|---|---|---|---|"]
    for rule, spans in sorted(times.items(), key=lambda kv: -sum(kv[1])):
        rows.append(
            f"| {rule} | {len(spans)} | {sum(spans):.0f} | {statistics.median(spans):.0f} |"
        )
    total = sum(sum(spans) for spans in times.values())
    return "\n".join([*rows, f"| all | | {total:.0f} | |"])


def accuracy(folder: Path) -> str:
    """The largest stated error of a girth-line mean over every case's summary.csv (%, with the
    case and line), how many are over max(1 %, 0.1 mmHg), how many lines have none, and the
    widest design interval (+- reduction, design.csv and the profile designs' confirmations)."""
    worst, where, missing, lines, errors, outside = 0.0, "", [], 0, [], 0
    for summary in sorted((folder / "results" / "cases").glob("*/summary.csv")):
        with summary.open(newline="") as handle:
            for row in csv.DictReader(handle):
                lines += 1
                error = float(row.get("pressure_mean_error_percent") or "nan")
                errors.append(error)
                mmhg = float(row.get("pressure_mean_error_mmHg") or "nan")
                if not mmhg <= max(0.01 * float(row["pressure_mean_mmHg"]), 0.1):
                    outside += 1  # the criterion: max(1 %, 0.1 mmHg); no error is outside too
                if not math.isfinite(error):
                    missing.append(f"{summary.parent.name}:{row['landmark']}")
                elif error > worst:
                    worst, where = error, f"{summary.parent.name}:{row['landmark']}"
    interval = 0.0
    design = folder / "results" / "design.csv"
    if design.is_file():
        with design.open(newline="") as handle:
            for row in csv.DictReader(handle):  # a target out of the sweep's range: no answer
                value = float(row.get("reduction_error") or "nan")
                if row.get("status") == "ok":
                    interval = max(interval, value) if math.isfinite(value) else math.inf
    over = sum(1 for e in errors if e > 1.0)
    return (
        f"{lines} girth lines, {over} with a stated error over 1 %, {outside} over max(1 %, "
        f"0.1 mmHg): "
        f"largest {worst:.2f} % ({where}); "
        f"{len(missing)} without one{': ' + ', '.join(missing[:6]) if missing else ''}; "
        f"widest design interval +- {interval:.4f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("revisions", nargs=2)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--config", default="config/config.yaml")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folders = [clone(r, Path(tmp)) for r in args.revisions]
        times: dict[str, list[float]] = {r: [] for r in args.revisions}
        for _ in range(args.repeat):
            for revision, folder in zip(args.revisions, folders, strict=True):
                times[revision].append(run(folder, args.config))
                print(f"{revision}: {times[revision][-1]:.1f} s; {accuracy(folder)}", flush=True)
                print(rule_table(rule_times(folder)), flush=True)
    before, after = (statistics.median(times[r]) for r in args.revisions)
    print(f"\n| revision | median wall time [s] (of {args.repeat}) |\n|---|---|")
    for revision in args.revisions:
        print(f"| {revision} | {statistics.median(times[revision]):.1f} |")
    print(f"\nafter / before: {after / before:.2f}")


if __name__ == "__main__":
    main()
