"""Rows that point at other rows: a CSV row that names a girth line carries that line's own
height and values, as its source netCDF holds them, found from the CSV file alone.

`problems` knows each CSV the tool writes with a girth-line column (`RULES`, by the file's
family) and where its source is (a file beside it, or one it names); it reads the row's line by
name in the source, never by position, and returns every disagreement as a line of text. A CSV
with a girth-line column and no rule is a problem too: a new file needs its rule.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.results.pressure import MMHG

#: The columns that name a girth line.
LINE_COLUMNS = ("landmark", "point", "error_line")
#: Relative agreement of a CSV's number (written to 6 significant digits) with its source.
RELATIVE = 2e-5


def rows_of(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def _differs(text: str, value: float, scale: float = 1.0) -> bool:
    if text in ("", "nan") or not math.isfinite(value):
        return (text in ("", "nan")) != (not math.isfinite(value))
    return not math.isclose(float(text), value / scale, rel_tol=RELATIVE, abs_tol=1e-9)


def _line(ds: xr.Dataset, name: str, variable: str) -> float:
    names = [str(v) for v in ds["landmark"].values]
    return float(ds[variable].values[names.index(name)])


def _check_lines(
    path: Path, rows: list[dict[str, str]], source: Callable[[dict], Path], columns: dict
) -> list[str]:
    """Each row's ``landmark`` read by name in its source (``source(row)``): ``columns`` maps a
    CSV column to (source variable, the CSV's unit factor)."""
    out = []
    opened: dict[Path, xr.Dataset] = {}
    for k, row in enumerate(rows):
        where = source(row)
        if where not in opened:
            opened[where] = xr.load_dataset(where)
        ds = opened[where]
        names = [str(v) for v in ds["landmark"].values]
        if row["landmark"] not in names:
            out.append(f"{path.name} row {k + 1}: {row['landmark']} is not a line of {where}")
            continue
        for column, (variable, scale) in columns.items():
            if column in row and variable in ds:
                value = _line(ds, row["landmark"], variable)
                if _differs(row[column], value, scale):
                    out.append(
                        f"{path.name} row {k + 1} ({row['landmark']}): {column} {row[column]} "
                        f"is not {variable} {value / scale:.6g} of {where}"
                    )
    return out


def summary(path: Path) -> list[str]:
    """summary.csv: its result.nc beside it."""
    columns = {
        "height_m": ("landmark_height", 1.0),
        "pressure_mean_Pa": ("pressure_mean", 1.0),
        "pressure_max_Pa": ("pressure_max", 1.0),
        "pressure_min_Pa": ("pressure_min", 1.0),
        "pressure_mean_mmHg": ("pressure_mean", MMHG),
        "tension_weft_mean_N_per_m": ("tension_mean", 1.0),
        "pressure_mean_error_Pa": ("pressure_mean_error", 1.0),
    }
    return _check_lines(path, rows_of(path), lambda row: path.parent / "result.nc", columns)


def design_confirmed(path: Path) -> list[str]:
    """A design's design_confirmed.csv (a profile's, or a chart's with a ``size`` column): the
    confirmation's result.nc, ``confirmed/`` (``{size}/confirmed/``) beside it. The sweep's
    design_confirmed.csv (``material`` and ``body`` columns) names cases, not a confirmation
    folder: its rows are read in their cases' result.nc."""
    rows = rows_of(path)
    if rows and "material" in rows[0]:
        return []  # the sweep's: its values are checked against sweep.nc by test_workflow
    columns = {
        "height_m": ("landmark_height", 1.0),
        "confirmed_mmHg": ("pressure_mean", MMHG),
        "confirmed_error_mmHg": ("pressure_mean_error", MMHG),
    }

    def source(row: dict) -> Path:
        if row.get("size"):
            return path.parent / row["size"] / "confirmed" / "result.nc"
        return path.parent / "confirmed" / "result.nc"

    return _check_lines(path, rows, source, columns)


def compare(path: Path) -> list[str]:
    """compare.csv: the result.nc its compare.nc names; a row named by a girth line is at that
    line's height, and its stated error is its ``error_line``'s relative error."""
    with xr.open_dataset(path.parent / "compare.nc") as ds:  # its sources: from its folder
        result = path.parent / ds.attrs["result_file"] if "result_file" in ds.attrs else None
    if result is None:
        return []  # a study's rows: each subject's own result.nc (test_study checks them)
    ds = xr.load_dataset(result)
    names = [str(v) for v in ds["landmark"].values]
    relative = np.nanmax(
        [
            ds[f"{f}_error"].values / np.abs(ds[f].values)
            if f"{f}_error" in ds
            else np.full(len(names), np.nan)
            for f in ("pressure_max", "pressure_min", "pressure_mean")
        ],
        axis=0,
    )
    out = []
    for k, row in enumerate(rows_of(path)):
        if row["point"]:
            height = _line(ds, row["point"], "landmark_height")
            if _differs(row["height_m"], height):
                out.append(f"{path.name} row {k + 1}: {row['point']} is at {height} m")
        if row["error_line"]:
            expected = float(row["model_mmHg"]) * relative[names.index(row["error_line"])]
            if _differs(row["model_error_mmHg"], expected):
                out.append(f"{path.name} row {k + 1}: the error of {row['error_line']}")
    return out


#: The rule of each CSV family with a girth-line column.
RULES: dict[str, Callable[[Path], list[str]]] = {
    "summary.csv": summary,
    "design_confirmed.csv": design_confirmed,
    "compare.csv": compare,
}
#: CSV families whose girth-line rows are checked elsewhere, by the test named.
ELSEWHERE = {
    "sweep.csv": "test_workflow.py::test_the_sweep_s_files_are_each_case_s_result_nc",
    "design.csv": "test_workflow.py::test_the_design_s_files_are_the_sweep_interpolated_by_hand",
    "wearers.csv": "test_wearers.py::test_wearers_csv_is_the_range_of_wearers_nc",
    "robust.csv": "test_wearers.py (robust design's rows against its confirmations)",
}


def problems(path: Path) -> list[str]:
    """Every row of the CSV ``path`` whose girth line's height or values are not its source's
    (module docstring); a CSV with a girth-line column and no rule is one problem."""
    rows = rows_of(path)
    if not rows or not any(c in rows[0] for c in LINE_COLUMNS):
        return []
    if path.name in ELSEWHERE:
        return []
    rule = RULES.get(path.name)
    if rule is None:
        return [f"{path}: a girth-line column and no rule in tests/crossrefs.py"]
    return rule(path)
