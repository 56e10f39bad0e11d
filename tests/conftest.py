"""Shared fixtures: an example fabric with distinctly different weft and warp curves."""

from __future__ import annotations

import itertools
import logging

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from cloth.materials.curves import Fabric, StressStrainCurve
from tests.test_log_numbers import too_long

#: 1 mmHg in Pa by its definition, typed here for the tests' own expectations (not the
#: library's constant): 13.5951 g/cm3 x 9.80665 m/s2 x 1 mm = 133.322387415 Pa.
MMHG_BY_DEFINITION = 13.5951e3 * 9.80665 * 1e-3


def make_fabric(thickness: float = 5.0e-4, compression: float | None = None) -> Fabric:
    """A J-shaped elastane-knit-like fabric: weft softer than warp (numbers illustrative);
    ``compression``: its compression modulus as a fraction of each curve's first slope
    (default the library's, 1 %; 0 a pure tension field)."""
    weft_slope, warp_slope = 0.05e6 / 0.1, 0.12e6 / 0.15
    weft = StressStrainCurve(
        [0.0, 0.1, 0.3, 0.6, 1.0],
        [0.0, 0.05e6, 0.2e6, 0.6e6, 1.6e6],
        None if compression is None else compression * weft_slope,
    )
    warp = StressStrainCurve(
        [0.0, 0.15, 0.4, 0.8],
        [0.0, 0.12e6, 0.5e6, 1.8e6],
        None if compression is None else compression * warp_slope,
    )
    return Fabric("test knit", weft=weft, warp=warp, thickness=thickness)


def write_obj(path, vertices, faces):
    """Write a mesh as OBJ at full float64 precision (STL and trimesh's PLY store float32)."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def capped_cylinder(radius: float, height: float, segments: int, bottom: float = 0.0):
    """Vertices ((V, 3), m) and outward faces of a closed cylinder about z: ``segments`` around,
    rings about one segment apart (regular triangles, as a scanner's), fan caps."""
    import numpy as np

    rings = max(2, round(height / (2 * np.pi * radius / segments)) + 1)
    angle = 2 * np.pi * np.arange(segments) / segments
    z = bottom + np.linspace(0.0, height, rings)
    ring = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    side = np.concatenate([np.column_stack([ring, np.full(segments, h)]) for h in z])
    vertices = np.vstack([side, [[0.0, 0.0, bottom], [0.0, 0.0, bottom + height]]])
    i, i1 = np.arange(segments), (np.arange(segments) + 1) % segments
    faces = []
    for r in range(rings - 1):
        a, b = r * segments + i, r * segments + i1
        c, d = a + segments, b + segments
        faces += [np.stack([a, b, d], axis=1), np.stack([a, d, c], axis=1)]
    low, high, last = len(side), len(side) + 1, (rings - 1) * segments
    faces.append(np.stack([np.full(segments, low), i1, i], axis=1))
    faces.append(np.stack([np.full(segments, high), last + i, last + i1], axis=1))
    return vertices, np.concatenate(faces)


def run_result(folder, case: dict, stop: str = "aggregate"):
    """Run ``case`` (a case mapping; relative paths from the repository) up to ``stop`` in
    ``folder``/out, its case.yaml in ``folder``: the output folder."""
    from pathlib import Path

    import yaml

    from cloth.stages.case import run_case

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "case.yaml").write_text(yaml.safe_dump(case))
    run_case(
        folder / "case.yaml",
        folder / "out",
        {},
        Path(__file__).resolve().parents[1],
        stop_after=stop,
    )
    return folder / "out"


def load_result(folder, case: dict):
    """`run_result` to the aggregate stage, and its result.nc loaded."""
    import xarray as xr

    return xr.load_dataset(run_result(folder, case) / "result.nc")


@pytest.fixture
def fabric() -> Fabric:
    return make_fabric()


@pytest.fixture(autouse=True, scope="session")
def _surface_cache(tmp_path_factory):
    """Fitted mesh surfaces go to a folder of the test session, not the user's cache."""
    import os

    os.environ["CLOTH_CACHE_DIR"] = str(tmp_path_factory.mktemp("cache"))


class _LongNumbers(logging.Handler):
    """Keeps each message logged under ``cloth`` at INFO or above with a decimal number of
    more digits than the log-digits rule allows (`tests.test_log_numbers.too_long`)."""

    def __init__(self) -> None:
        super().__init__(logging.INFO)
        self.found: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        message = record.getMessage()
        if too_long(message):
            self.found.append(f"{record.name}: {message}")


_LONG_NUMBERS = _LongNumbers()


@pytest.fixture(autouse=True, scope="session")
def _every_log_line_at_info():
    """Every command the suite runs logs at INFO, its default level (issue 71, item 3), for
    `_sensible_log_digits`."""
    logger = logging.getLogger("cloth")
    level = logger.level
    logger.setLevel(logging.INFO)
    logger.addHandler(_LONG_NUMBERS)
    yield
    logger.removeHandler(_LONG_NUMBERS)
    logger.setLevel(level)


@pytest.fixture(autouse=True)
def _sensible_log_digits(_every_log_line_at_info):
    """The log-digits rule over every line the library logs in the whole suite, at CI size:
    a test whose commands (or its fixtures') logged a number printed with more digits than
    `tests.test_log_numbers.DIGITS` fails, naming the line."""
    yield
    found, _LONG_NUMBERS.found[:] = list(_LONG_NUMBERS.found), []
    assert not found, f"a number logged with too many digits: {found}"


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory):
    """The tiny pipeline (config/ci.yaml) run once locally from an empty working directory
    (``snakemake -s .../Snakefile --directory``: the workflow finds its bundled data beside
    itself): (folder, result, wall seconds), shared by the pipeline's end-to-end test and the
    cluster test's reference."""
    import time

    from tests.pipeline import from_checkout, snakemake

    where = tmp_path_factory.mktemp("tiny")
    start = time.perf_counter()
    result = snakemake(where, *from_checkout(where))
    return where, result, time.perf_counter() - start


#: Relative residuals below this are rounding (measured 6e-13 to 3e-11 on 4k-74k nodes).
ROUNDING_FLOOR = 1e-11


def assert_quadratic_tail(residual) -> None:
    """Newton's last steps converge quadratically: the last step from r >= 1e-6 (where C r^2
    is still above the rounding floor) has r_next <= e^2 r^1.6 (quadratic gives C r^2; the
    exponent leaves room for C; measured on the ellipse: 2.8e-2 -> 7e-8 -> 1.7e-13), and every
    later step ends there too or on the floor. Steps before it may be damped (measured at
    384 x 192: five steps between 7e-4 and 1e-4, then 1.3e-4 -> 1.5e-8 -> 3e-12)."""
    r = np.asarray(residual, dtype=float)
    pairs = list(itertools.pairwise(r))
    starts = [k for k, (a, _) in enumerate(pairs) if a >= 1e-6]
    assert starts, r
    for a, b in pairs[starts[-1] :]:
        assert b <= max(ROUNDING_FLOOR, np.exp(2) * a**1.6), r
