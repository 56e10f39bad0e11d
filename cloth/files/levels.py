"""The grid levels and error estimates in the files (`cloth.stages.levels`,
`cloth.results.richardson`).

``relaxed.nc`` carries the coarser levels' girth-line values (dims ``level``, ``landmark``):
``level_n``, ``level_m`` (nodes around and rows), ``level_converged`` (flag) and, per
`cloth.results.landmarks.LANDMARK_FIELDS` name f, ``level_f`` (its units). ``result.nc`` carries
the same with the reported grid as level 0, and per field f along ``landmark``: ``f_order`` (1,
the observed order), ``f_extrapolated`` (the converged value), ``f_error`` (the stated error
of the reported value, f's units: the grid convergence index, `Estimate.uncertainty`) and
``f_estimate`` (flag: 0 observed, 6 stated from the finest difference of levels that converge
without an order, 7 from the range of levels that do not, else why not,
`cloth.results.richardson.REASONS`); NaN where no error was stated. `estimate_columns` gives
summary.csv's columns.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

from cloth.io import variable
from cloth.results.landmarks import LANDMARK_FIELDS, Landmark
from cloth.results.pressure import MMHG
from cloth.results.richardson import FLAG_MEANINGS, NOTES, REASONS, Estimate, estimate_levels

log = logging.getLogger(__name__)


def _flags(meanings: str) -> dict[str, object]:
    return {
        "flag_values": np.arange(len(meanings.split()), dtype=np.int8),
        "flag_meanings": meanings,
    }


def mark_values(marks: Sequence[Sequence[Landmark]], names: Sequence[str]) -> dict[str, np.ndarray]:
    """Per `LANDMARK_FIELDS` name, a (len(marks), len(names)) array of the levels' girth-line
    summaries ``marks`` along ``names`` (NaN where a level lacks a line)."""
    out = {}
    for field, (attribute, _, _) in LANDMARK_FIELDS.items():
        values = np.full((len(marks), len(names)), np.nan)
        for k, level in enumerate(marks):
            by_name = {mark.name: getattr(mark, attribute) for mark in level}
            values[k] = [by_name.get(name, np.nan) for name in names]
        out[field] = values
    return out


def level_variables(
    grids: Sequence[tuple[int, int]], converged: Sequence[bool], values: dict[str, np.ndarray]
) -> dict[str, xr.Variable]:
    """The level variables (module docstring) of ``grids`` ((n, m) each, finest first), whether
    each ``converged``, and per field its (levels, landmarks) ``values`` (`mark_values`)."""
    out = {
        "level_n": variable(
            "level",
            np.asarray([g[0] for g in grids], np.int32),
            "1",
            "nodes around on the grid level",
        ),
        "level_m": variable(
            "level", np.asarray([g[1] for g in grids], np.int32), "1", "rows on the grid level"
        ),
        "level_converged": variable(
            "level",
            np.asarray(converged, np.int8),
            "1",
            "grid level relaxed to the tolerance",
            **_flags("no yes"),
        ),
    }
    for field, (_, units, long_name) in LANDMARK_FIELDS.items():
        out[f"level_{field}"] = variable(
            ("level", "landmark"), values[field], units, f"{long_name} on the grid level"
        )
    return out


def read_levels(
    ds: xr.Dataset, names: Sequence[str]
) -> tuple[list[tuple[int, int]], list[bool], dict[str, np.ndarray]]:
    """The coarser levels a relaxed.nc holds: their grids, whether each converged, and per field
    a (levels, len(names)) array (NaN where a level lacks a line); none in a file written
    without them."""
    if "level_n" not in ds:
        return [], [], {}
    grids = [
        (int(n), int(m)) for n, m in zip(ds["level_n"].values, ds["level_m"].values, strict=True)
    ]
    known = ds["landmark"].values.tolist() if "landmark" in ds.coords else []
    values = {}
    for field in LANDMARK_FIELDS:
        array = np.full((len(grids), len(names)), np.nan)
        for j, name in enumerate(names):
            if name in known:
                array[:, j] = ds[f"level_{field}"].values[:, known.index(name)]
        values[field] = array
    return grids, [bool(c) for c in ds["level_converged"].values], values


def estimates(
    marks: Sequence[Landmark], grid: tuple[int, int], grids: list[tuple[int, int]], values: dict
) -> dict[str, list[Estimate]]:
    """Per field, the estimate of each of ``marks`` (on ``grid``) from the coarser ``grids``
    and their ``values`` (`read_levels`)."""
    out: dict[str, list[Estimate]] = {}
    for field, (attribute, _, _) in LANDMARK_FIELDS.items():
        out[field] = [
            estimate_levels(
                [getattr(mark, attribute), *(values[field][:, j] if values else [])],
                [grid, *grids],
            )
            for j, mark in enumerate(marks)
        ]
    return out


def estimate_variables(found: dict[str, list[Estimate]]) -> dict[str, xr.Variable]:
    """result.nc's estimate variables (module docstring) of `estimates`."""
    out = {}
    for field, (_, units, long_name) in LANDMARK_FIELDS.items():
        rows = found[field]
        out[f"{field}_order"] = variable(
            "landmark",
            [e.order for e in rows],
            "1",
            f"observed order of convergence of the {long_name}",
        )
        out[f"{field}_extrapolated"] = variable(
            "landmark",
            [e.extrapolated for e in rows],
            units,
            f"{long_name}, Richardson extrapolated",
        )
        out[f"{field}_error"] = variable(
            "landmark",
            [e.uncertainty for e in rows],
            units,
            f"estimated discretisation error of the {long_name} (grid convergence index)",
        )
        out[f"{field}_estimate"] = variable(
            "landmark",
            np.asarray([e.code for e in rows], np.int8),
            "1",
            f"whether the {long_name}'s error was estimated",
            **_flags(FLAG_MEANINGS),
        )
    return out


def resolution_variables(rows: np.ndarray, mesh: np.ndarray | None) -> dict[str, xr.Variable]:
    """result.nc's ``row_spacing`` and, on a mesh body, ``mesh_spacing`` along ``landmark`` (m;
    `cloth.results.resolution`)."""
    out = {"row_spacing": variable("landmark", rows, "m", "garment row spacing at the girth line")}
    if mesh is not None:
        out["mesh_spacing"] = variable(
            "landmark", mesh, "m", "vertical sampling of the body's mesh at the girth line"
        )
    return out


def estimate_columns(ds: xr.Dataset, index: int) -> dict[str, object]:
    """summary.csv's error columns of the ``index``-th girth line of a result dataset: the
    stated error of the mean (Pa, mmHg, % of the value), its observed order and extrapolation,
    the stated errors of max, min (Pa) and tension (N m-1), and a note where none was
    estimated. Empty for a result without estimates."""
    if "pressure_mean_error" not in ds:
        return {}
    mean = float(ds["pressure_mean"][index])
    error = float(ds["pressure_mean_error"][index])
    code = int(ds["pressure_mean_estimate"][index])
    note = NOTES.get(code) or REASONS.get(code, "not estimated")
    notes = [] if code == 0 else [note]
    if "mesh_spacing" in ds and float(ds["mesh_spacing"][index]) > float(ds["row_spacing"][index]):
        notes.append(
            f"the mesh's vertices are {1e3 * float(ds['mesh_spacing'][index]):.3g} mm apart in "
            f"height, the rows {1e3 * float(ds['row_spacing'][index]):.3g} mm: not in the error"
        )
    return {
        "pressure_mean_error_Pa": error,
        "pressure_mean_error_mmHg": error / MMHG,
        "pressure_mean_error_percent": 100 * error / abs(mean) if mean else math.nan,
        "pressure_mean_order": float(ds["pressure_mean_order"][index]),
        "pressure_mean_extrapolated_Pa": float(ds["pressure_mean_extrapolated"][index]),
        "pressure_max_error_Pa": float(ds["pressure_max_error"][index]),
        "pressure_min_error_Pa": float(ds["pressure_min_error"][index]),
        "tension_weft_mean_error_N_per_m": float(ds["tension_mean_error"][index]),
        "error_note": "; ".join(notes),
        **(
            {"row_spacing_mm": 1e3 * float(ds["row_spacing"][index])} if "row_spacing" in ds else {}
        ),
        **(
            {"mesh_spacing_mm": 1e3 * float(ds["mesh_spacing"][index])}
            if "mesh_spacing" in ds
            else {}
        ),
    }


def log_estimates(names: Sequence[str], found: dict[str, list[Estimate]]) -> None:
    """One log line per girth line: its mean pressure's stated error, or why there is none."""
    for name, estimate in zip(names, found["pressure_mean"], strict=True):
        if estimate.code in NOTES:
            log.info(
                "%s: mean pressure %.4g Pa +- %.2g Pa (%.2g %%; %s)",
                name,
                estimate.reported,
                estimate.uncertainty,
                100 * estimate.relative_error,
                estimate.reason,
            )
        elif estimate.observed:
            log.info(
                "%s: mean pressure %.4g Pa +- %.2g Pa (%.2g %%; observed order %.2g, "
                "extrapolated %.4g Pa)",
                name,
                estimate.reported,
                estimate.uncertainty,
                100 * estimate.relative_error,
                estimate.order,
                estimate.extrapolated,
            )
        else:
            log.warning("%s: mean pressure error not estimated: %s", name, estimate.reason)
