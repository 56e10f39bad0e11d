"""Every command of every tutorial runs, at CI size (as scikit-fem runs its examples): each
page's files (its ``yaml title="NAME"`` blocks) are written as given but for their grids,
which `ci_size` coarsens, and each line of its ``sh`` blocks is run in order, from a folder
laid out as a checkout's top (data/, the Snakefile and workflow/ linked), with the venv first
on the path; then the files the page tells the reader to open are read back."""

from __future__ import annotations

import csv
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TUTORIALS = ROOT / "docs" / "tutorials"
#: A tutorial's grid is divided by this, to at least `MIN_GRID` (nodes around, rows).
SHRINK, MIN_GRID = 8, (16, 8)

pytestmark = pytest.mark.slow


def ci_size(text: str) -> str:
    """``text`` with every ``grid: [n, m]`` divided by `SHRINK` (rounded up, at least
    `MIN_GRID`)."""

    def smaller(match: re.Match) -> str:
        n, m = (int(v) for v in match.groups())
        n = max(MIN_GRID[0], math.ceil(n / SHRINK))
        m = max(MIN_GRID[1], math.ceil(m / SHRINK))
        return f"grid: [{n}, {m}]"

    return re.sub(r"grid: \[(\d+), (\d+)\]", smaller, text)


def blocks(page: Path) -> tuple[dict[str, str], list[str]]:
    """A tutorial's files (title -> text) and its shell lines, in order (``export`` lines,
    which put the venv on the path, are left out: the test does)."""
    text = page.read_text()
    files = dict(re.findall(r'```yaml title="([^"]+)"\n(.*?)```', text, flags=re.S))
    lines = []
    for block in re.findall(r"```sh\n(.*?)```", text, flags=re.S):
        joined = block.replace("\\\n", " ")
        lines += [ln.strip() for ln in joined.splitlines() if ln.strip()]
    return files, [ln for ln in lines if not ln.startswith("export ")]


def test_ci_size_coarsens_every_grid_and_nothing_else():
    text = "grid: [288, 144] # nodes\nreduction: 0.20\n  grid: [96, 288]"
    assert ci_size(text) == "grid: [36, 18] # nodes\nreduction: 0.20\n  grid: [16, 36]"


def run_tutorial(name: str, where: Path) -> None:
    files, lines = blocks(TUTORIALS / f"{name}.md")
    assert lines, f"{name}.md has no commands"
    for link in ("data", "Snakefile", "workflow"):
        (where / link).symlink_to(ROOT / link)
    for title, text in files.items():
        (where / title).write_text(ci_size(text))
    env = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}",
        "MPLBACKEND": "Agg",
    }
    for line in lines:
        done = subprocess.run(
            ["bash", "-c", line], cwd=where, env=env, capture_output=True, text=True, timeout=900
        )
        assert done.returncode == 0, f"{name}.md: {line}\n{done.stderr[-3000:]}"


def rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


def test_your_fabric_on_the_torso(tmp_path):
    run_tutorial("fabric", tmp_path)
    assert (tmp_path / "powernet.png").stat().st_size > 10_000
    waist = [r for r in rows(tmp_path / "shapewear" / "summary.csv") if r["landmark"] == "waist"]
    assert len(waist) == 1 and float(waist[0]["pressure_mean_mmHg"]) > 0
    (answer,) = rows(tmp_path / "results-myfabric" / "design_confirmed.csv")
    assert 0.15 <= float(answer["reduction"]) <= 0.25
    assert abs(float(answer["confirmed_mmHg"]) - 20.0) < 3.0  # coarse grid: near the target
    assert (tmp_path / "pattern.pdf").read_bytes().startswith(b"%PDF")


def test_a_class_two_stocking(tmp_path):
    run_tutorial("stocking", tmp_path)
    points = {r["landmark"] for r in rows(tmp_path / "stocking" / "summary.csv")}
    assert {"B", "C", "F"} <= points
    confirmed = {r["landmark"]: r for r in rows(tmp_path / "design" / "design_confirmed.csv")}
    assert set(confirmed) >= {"B", "C", "F"}
    knitting = rows(tmp_path / "tube_knitting.csv")
    assert knitting and {"B", "C", "F"} <= {r["girth_point"] for r in knitting}


def test_your_own_scan(tmp_path):
    run_tutorial("scan", tmp_path)
    assert (tmp_path / "me_curvature.png").stat().st_size > 10_000
    lines = {r["landmark"] for r in rows(tmp_path / "onme" / "summary.csv")}
    assert {"hip", "waist", "bust"} <= lines
