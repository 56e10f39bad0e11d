"""A size chart for a measured population (issue 62): the stocking config's ``size_charts``
entry (class II at B for ANSUR II's women, the power net, 96 x 288) run by ``cloth sizes``,
timed, with what it answers.

One run per call (2 cores, noisy: the time is one run's, not a median; the equilibria it
solved are counted from its folders). Writes docs/performance.md, section ``size_chart``.

Run:

    .venv/bin/python benchmarks/bench_sizes.py [--entry class_II] [--rounds 2] [--no-write]

Sizes not confirmed after the rounds are counted (the command runs with ``--report-unmet``);
``recut`` counts the sizes recut from their confirmations (issue 71).
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml
from _table import markdown_table, publish

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def start_case(entry: str, folder: Path) -> Path:
    """The stocking config's size chart entry as a case: its body and material, the sweep's
    garment and solver."""
    config = yaml.safe_load((ROOT / "config" / "stocking.yaml").read_text())
    spec = config["size_charts"][entry]
    body = config["bodies"][spec["body"]]
    table = ROOT / config["materials"][spec["material"]]["table"]
    garment = {**config["sweep"]["garment"], **spec.get("garment", {}), "reduction": 0.16}
    case = {"material": str(table), "body": body, "garment": garment}
    case["solver"] = config["sweep"]["solver"]
    path = folder / "case.yaml"
    path.write_text(yaml.safe_dump(case, sort_keys=False))
    return path, spec


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--entry", default="class_II")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        case, spec = start_case(args.entry, folder)
        command = [str(BIN / "cloth"), "--log-level", "WARNING", "sizes", str(case)]
        for target in spec["targets"]:
            command += ["--target", target]
        command += ["--by", spec.get("by", spec["targets"][0].split("=")[0])]
        command += ["--max-sizes", str(spec.get("max_sizes", 8)), "--rounds", str(args.rounds)]
        command += ["--report-unmet"]  # a size not confirmed is a row of the table, not a crash
        out = folder / "out"
        start = time.perf_counter()
        done = subprocess.run([*command, "-o", str(out)], capture_output=True, text=True)
        if done.returncode:
            sys.exit(f"bench_sizes: cloth sizes exited {done.returncode}: {done.stderr.strip()}")
        seconds = time.perf_counter() - start
        runs = len(list(out.rglob("summary.csv")))
        with (out / "sizes.csv").open() as handle:
            sizes = list(csv.DictReader(handle))
        share = sum(float(r["fit_share"]) for r in sizes)
        confirmed = sum(int(r["confirmed"]) for r in sizes)
        tells = sum(int(r["grid_tells"]) for r in sizes)
        recut = sum(int(r["recut"]) > 0 for r in sizes)
    rows = [
        [
            args.entry,
            f"{seconds:.0f}",
            str(runs),
            str(len(sizes)),
            f"{100 * share:.1f}",
            f"{confirmed} of {len(sizes)}",
            str(recut),
            f"{tells} of {len(sizes)}",
        ]
    ]
    header = ["entry", "wall [s]", "equilibria", "sizes", "fit [%]", "confirmed", "recut"]
    header += ["grid tells"]
    publish(markdown_table(header, rows), "size_chart", not args.no_write)


if __name__ == "__main__":
    main()
