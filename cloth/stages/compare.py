"""``cloth compare``: a relaxed garment's sensor readings against measured ones.

For each reading of a measurements file (`cloth.files.measured`) on a result.nc, the model's
probe reading at that place with that probe and its stated discretisation error
(`cloth.results.sensing`); repeats averaged, their spread the measurement's own noise; then the
agreement's statistics (`cloth.results.agreement`) per subject and pooled. `cloth.files.compared`
writes compare.csv, agreement.csv and compare.nc, `cloth.figures.agreement` compare.png.

A study (`cloth.stages.study`) runs one garment on several subjects and compares each with her
own readings through `compare_result`, pooling the rows.
"""

from __future__ import annotations

import json
import logging
import os
from pathlib import Path

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from cloth.case.reading import Reading
from cloth.files.compared import (
    AGREEMENT_COLUMNS,
    COMPARE_COLUMNS,
    agreement_rows,
    compare_dataset,
    compare_rows,
)
from cloth.files.measured import Measurements, read_measurements
from cloth.io import atomic_folder, read_netcdf, write_netcdf
from cloth.pipeline.sweep import write_rows
from cloth.results.agreement import Agreement, Compared, average_repeats
from cloth.results.pressure import MMHG
from cloth.results.sensing import locate, model_readings, transferred_errors

log = logging.getLogger(__name__)

#: What compare reads of a result.nc.
RESULT_VARIABLES = ("x", "y", "z", "pressure", "contact", "node_area", "landmark_height")
#: The girth-line values whose stated relative errors a reading takes (`cloth.results.sensing`).
ERROR_FIELDS = ("pressure_max", "pressure_min", "pressure_mean")


def line_relative_errors(ds: xr.Dataset) -> NDArray[np.float64]:
    """(L,) 1: each girth line's largest stated relative error of `ERROR_FIELDS` (NaN where the
    result states none)."""
    out = np.full(ds.sizes.get("landmark", 0), np.nan)
    for field in ERROR_FIELDS:
        if f"{field}_error" not in ds:
            continue
        value = np.abs(ds[field].values)
        with np.errstate(divide="ignore", invalid="ignore"):
            relative = np.where(value > 0, ds[f"{field}_error"].values / value, np.nan)
        out = np.fmax(out, relative)
    return out


def compare_result(result: xr.Dataset, measured: Measurements) -> Compared:
    """The readings of ``measured`` placed on ``result`` (a result.nc's dataset), the model's
    at each place and its error, averaged over repeats (module docstring)."""
    shape = result["x"].shape
    x = np.stack([result[a].values.ravel() for a in "xyz"], axis=1)
    names = tuple(str(v) for v in result["landmark"].values) if "landmark" in result else ()
    heights = result["landmark_height"].values if names else np.zeros(0)
    places = locate(measured, dict(zip(names, heights.tolist(), strict=True)), x, shape)
    on_body = result["contact"].values.ravel() == 1
    area = result["node_area"].values.ravel()
    force = np.where(on_body, result["pressure"].values.ravel(), 0.0) * area
    case = json.loads(result.attrs.get("case", "{}"))
    reading = Reading.from_blocks(case.get("girth_reading"), None)
    model = model_readings(places, x, force, area, reading)
    errors, lines = transferred_errors(
        places.height, model, heights, line_relative_errors(result), names
    )
    keys = list(
        zip(
            measured.subject,
            np.round(places.height, 9),
            np.round(places.angle, 9),
            np.round(places.probe, 9),
            strict=True,
        )
    )
    averaged = average_repeats(keys, measured.pressure)
    first = averaged.first
    return Compared(
        tuple(measured.subject[k] for k in first),
        tuple(measured.point[k] for k in first),
        places.height[first],
        places.angle[first],
        places.probe[first],
        averaged.count,
        averaged.mean,
        averaged.sd,
        model[first],
        errors[first],
        tuple(lines[k] for k in first),
    )


def compare(result_path: Path, measured_path: Path, output: Path) -> dict[str, Path]:
    """result.nc + a measurements file -> ``output``/compare.csv, agreement.csv, compare.nc
    and compare.png; the paths written, by name."""
    measured = read_measurements(measured_path)
    result = read_netcdf(result_path, "result", RESULT_VARIABLES)
    table = compare_result(result, measured)
    sources = {"result": result_path, "measurements": measured_path}
    with atomic_folder(output) as folder:  # the four files together or none
        paths = write_compared(table, folder, sources, output)
    return {key: output / value.relative_to(folder) for key, value in paths.items()}


def write_compared(
    table: Compared, output: Path, sources: dict[str, Path], published: Path | None = None
) -> dict[str, Path]:
    """compare.csv, agreement.csv, compare.nc (`cloth.files.compared`) and compare.png
    (`cloth.figures.agreement`) into ``output``; the paths written, by name. compare.nc names
    the ``sources`` relative to the folder it is published in (``published``, default
    ``output``), so that a folder moved with its inputs still finds them."""
    from cloth.figures.agreement import agreement_figure  # late: matplotlib

    home = (published or output).resolve()
    sources = {k: os.path.relpath(Path(v).resolve(), home) for k, v in sources.items()}

    paths = {
        "compare_csv": write_rows(compare_rows(table), output / "compare.csv", COMPARE_COLUMNS),
        "agreement": write_rows(agreement_rows(table), output / "agreement.csv", AGREEMENT_COLUMNS),
        "compare_nc": write_netcdf(compare_dataset(table, sources), output / "compare.nc"),
        "figure": agreement_figure(table, output / "compare.png"),
    }
    log_agreement(table)
    return paths


def log_agreement(table: Compared) -> None:
    """One log line of the pooled agreement, mmHg."""
    stats = Agreement.of(table.model, table.measured)
    log.info(
        "model - measured over %d places: bias %.2f mmHg, limits of agreement %.2f to %.2f "
        "mmHg, RMSE %.2f mmHg, r %.3f",
        stats.n,
        stats.bias / MMHG,
        stats.loa_low / MMHG,
        stats.loa_high / MMHG,
        stats.rmse / MMHG,
        stats.r,
    )


def synthetic(
    result: xr.Dataset, places: Measurements, noise: float, seed: int, repeats: int
) -> Measurements:
    """What a sensor with Gaussian noise of standard deviation ``noise`` (Pa; seeded by
    ``seed``) would read ``repeats`` times at each place of ``places`` (their pressures are
    not used) on ``result``: the model's reading plus noise, clipped at 0. The shipped example
    (data/measurements) is made so."""
    table = compare_result(result, places)
    rng = np.random.default_rng(seed)
    count = len(table.model) * repeats
    order = np.repeat(np.arange(len(table.model)), repeats)
    return Measurements(
        places.source,
        tuple(table.point[k] for k in order),
        np.where([bool(table.point[k]) for k in order], np.nan, table.height[order]),
        table.angle[order],
        np.maximum(table.model[order] + rng.normal(0.0, noise, count), 0.0),
        table.probe[order],
        tuple(table.subject[k] for k in order),
        np.tile(np.arange(1, repeats + 1), len(table.model)),
    )
