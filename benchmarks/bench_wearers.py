"""Every wearer of a size: the pipeline on one core against two, and the robust design against
the nominal one.

Two parts (``--parts``), each run once per row on this machine (2 cores, noisy: compare the
rows of one run as ratios):

- ``cores``: a config with one ``wearers`` entry (the stocking cut for leg S at 0.16, the
  stocking config's garment and grid, 32 x 48) run by Snakemake with ``--cores 1`` and
  ``--cores 2`` from a clean results folder each: wall seconds and their ratio (surface fits
  cached beforehand, so both runs pay the same). docs/performance.md, section ``wearers_cores``.
- ``robust``: on leg S at 32 x 48, ``cloth design --target B=27.5`` (the nominal design: the
  chart's leg only) against ``cloth design --wearers --target B=23:32`` (every wearer of S):
  wall seconds and the equilibria each solved, and what each answers. docs/performance.md,
  section ``wearers_robust``.

Run:

    .venv/bin/python benchmarks/bench_wearers.py [--parts cores robust] [--no-write]
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml
from _table import markdown_table, publish

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def _stocking_garment() -> dict:
    config = yaml.safe_load((ROOT / "config" / "stocking.yaml").read_text())
    return config["sweep"]["garment"], config["sweep"]["solver"]


def cores_part(write: bool) -> None:
    garment, solver = _stocking_garment()
    config = {
        "materials": {"powernet": {"table": str(ROOT / "data/materials/powernet.csv"), "knots": 8}},
        "bodies": {"leg_S": {"leg": {"size": "S"}}},
        "sweep": {
            "materials": ["powernet"],
            "bodies": ["leg_S"],
            "reductions": [0.16],
            "garment": garment,
            "solver": solver,
        },
        "wearers": {"leg_S": {"material": "powernet", "body": "leg_S", "reduction": 0.16}},
    }
    rows = []
    index = json.loads((ROOT / "data/bodies/wearers/leg_S/wearers.json").read_text())
    wearers = sum("mesh" in w for w in index["wearers"])
    env = {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ['PATH']}", "MPLBACKEND": "Agg"}
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        seconds = {}
        for cores in (2, 1, 2):  # the first run caches the wearers' surfaces for both
            config["results"] = str(work / f"results-{cores}")
            path = work / "wearers.yaml"
            path.write_text(yaml.safe_dump(config))
            subprocess.run(["rm", "-rf", config["results"]], check=True)
            start = time.perf_counter()
            subprocess.run(
                [
                    str(BIN / "snakemake"),
                    "--cores",
                    str(cores),
                    "--configfile",
                    str(path),
                    "-s",
                    str(ROOT / "Snakefile"),
                    sweep_target(config["results"]),
                ],
                cwd=work,
                env=env,
                check=True,
                capture_output=True,
            )
            seconds[cores] = time.perf_counter() - start
        rows.append(
            [
                f"leg S, {wearers} wearers + the chart's leg, 32 x 48",
                f"{seconds[1]:.1f}",
                f"{seconds[2]:.1f}",
                f"{seconds[1] / seconds[2]:.2f}",
            ]
        )
    body = markdown_table(["wearers run", "--cores 1 (s)", "--cores 2 (s)", "speed-up"], rows)
    publish(body, "wearers_cores", write)


def sweep_target(results: str) -> str:
    return f"{results}/wearers/leg_S/wearers.csv"


def robust_part(write: bool) -> None:
    garment, solver = _stocking_garment()
    case = {
        "material": "powernet",
        "body": {"leg": {"size": "S"}},
        "garment": {**garment, "reduction": 0.16},
        "solver": solver,
    }
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "case.yaml").write_text(yaml.safe_dump(case))
        runs = {
            "nominal (the chart's leg S), B=27.5": ["--target", "B=27.5"],
            "robust (every wearer of S), B=23:32": ["--wearers", "--target", "B=23:32"],
        }
        for label, extra in runs.items():
            out = work / label.split()[0]
            start = time.perf_counter()
            done = subprocess.run(
                [
                    str(BIN / "cloth"),
                    "--log-level",
                    "WARNING",
                    "design",
                    str(work / "case.yaml"),
                    *extra,
                    "-o",
                    str(out),
                ],
                capture_output=True,
                text=True,
            )
            seconds = time.perf_counter() - start
            if (out / "robust.csv").is_file():
                (row,) = list(csv.DictReader((out / "robust.csv").open()))
                answer = (
                    f"wearers {row['confirmed_min_mmHg']}-{row['confirmed_max_mmHg']} mmHg, "
                    f"{row['reduction']}, met {row['met']}"
                )
                equilibria = row["equilibria"]
            else:
                (row,) = list(csv.DictReader((out / "design_confirmed.csv").open()))
                answer = f"{row['confirmed_mmHg']} mmHg on the chart's leg, met {row['met']}"
                equilibria = row["equilibria"]
            if done.returncode:
                answer += f" (exit {done.returncode}: {done.stderr.strip().splitlines()[-1]})"
            rows.append([label, f"{seconds:.1f}", equilibria, answer])
    body = markdown_table(["design", "wall (s)", "equilibria", "answer"], rows)
    publish(body, "wearers_robust", write)


PARTS = {"cores": cores_part, "robust": robust_part}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", nargs="+", choices=sorted(PARTS), default=sorted(PARTS))
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args()
    for part in args.parts:
        PARTS[part](not args.no_write)


if __name__ == "__main__":
    main()
