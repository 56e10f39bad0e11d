"""One case dictionary run through ``cloth run`` in process, to its result (the benchmarks' way
of reading what the pipeline states of a case)."""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import xarray as xr
import yaml

from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]


def case_result(case: dict) -> tuple[xr.Dataset, float]:
    """``case`` (a case file's content) run in a temporary folder up to its aggregate: its
    result.nc, loaded, and the seconds it took (predeform, relax with its levels, aggregate)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "case.yaml"
        path.write_text(yaml.safe_dump(case))
        start = time.perf_counter()
        run_case(path, Path(tmp) / "out", {}, ROOT, stop_after="aggregate")
        seconds = time.perf_counter() - start
        return xr.load_dataset(Path(tmp) / "out" / "result.nc"), seconds
