"""Helpers of the benchmark scripts: medians of repeated timings, Markdown tables in docs."""

from __future__ import annotations

import re
import statistics
import time
from collections.abc import Callable
from pathlib import Path

PERFORMANCE = Path(__file__).resolve().parents[1] / "docs" / "measurements" / "performance-log.md"


def median_seconds(work: Callable[[], object], repeat: int = 7, warmup: int = 1) -> float:
    """Median wall time of ``work()`` over ``repeat`` runs after ``warmup`` runs, s."""
    for _ in range(warmup):
        work()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def markdown_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def replace_section(marker: str, body: str, path: Path = PERFORMANCE) -> None:
    """Replace the text between ``<!-- marker:start -->`` and ``<!-- marker:end -->``."""
    text = path.read_text()
    start, end = f"<!-- {marker}:start -->", f"<!-- {marker}:end -->"
    pattern = re.compile(re.escape(start) + ".*?" + re.escape(end), re.S)
    if not pattern.search(text):
        raise SystemExit(f"{path}: markers {start} ... {end} not found")
    path.write_text(pattern.sub(lambda _: f"{start}\n{body}\n{end}", text))


def publish(body: str, section: str, write: bool = True, path: Path = PERFORMANCE) -> None:
    """Print a benchmark's ``body`` and, where ``write``, put it in ``section`` of ``path``."""
    print(body)
    if write:
        replace_section(section, body, path)
