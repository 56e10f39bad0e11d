"""The inventory of what users read (docs/testing.md, "What users read"), parsed for the tests.

Each row of its tables names a file, a column or variable, its unit as the file states it, and
the tests that fail when it is wrong. `unlisted` reads a written CSV or netCDF file back and
names every column or variable it has that the inventory has no row for, or whose units
attribute differs from the row's: the tests that write files call it, so a column added with no
row fails them.
"""

from __future__ import annotations

import ast
import csv
import re
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "testing.md"
#: The heading of the inventory's section; its tables end at the next ``## `` heading.
SECTION = "## What users read"
#: Files named after their case or size that the inventory lists under one name.
FAMILIES = (
    (re.compile(r"^pattern_.*_knitting\.csv$|^pattern_knitting\.csv$"), "pattern_knitting.csv"),
    (re.compile(r"^pattern(_.+)?_pieces\.csv$"), "pattern_pieces.csv"),
    (re.compile(r"^pattern(_.+)?\.csv$"), "pattern.csv"),
)


@dataclass(frozen=True)
class Row:
    file: str
    name: str
    unit: str
    tests: tuple[str, ...]


def rows(doc: Path = DOC) -> list[Row]:
    """The inventory's rows: every table row of the section whose first cell is a file name."""
    text = doc.read_text()
    start = text.index(SECTION)
    end = text.find("\n## ", start + len(SECTION))
    out = []
    for line in text[start : end if end > 0 else None].splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 4 or not line.startswith("|") or set(cells[0]) <= {"-", " "}:
            continue
        file, name, unit, tests = cells
        if file == "file":
            continue  # a header row
        names = tuple(t.strip("` ") for t in tests.split(",") if t.strip())
        out.append(Row(file.strip("`"), name.strip("`"), unit.strip("`"), names))
    return out


def listed(doc: Path = DOC) -> dict[tuple[str, str], Row]:
    return {(row.file, row.name): row for row in rows(doc)}


def family(path: Path) -> str:
    """The inventory's name of the file ``path`` (a case's pattern is pattern.csv, a graded
    design's confirmation designs/design_confirmed.csv)."""
    if path.name == "design_confirmed.csv" and (
        "designs" in path.parts
        or (path.parent / "design_iterations.csv").exists()
        or any(path.parent.glob("*/design_iterations.csv"))
    ):
        return "designs/design_confirmed.csv"
    for pattern, name in FAMILIES:
        if pattern.match(path.name):
            return name
    return path.name


def names_and_units(path: Path) -> dict[str, str | None]:
    """A written file's columns (CSV; unit None) or variables and coordinates (netCDF: their
    units attribute, '' where it has none), read back from the file."""
    if path.suffix == ".csv":
        with open(path, newline="") as handle:
            lines = (line for line in handle if not line.startswith("#"))
            header = next(csv.reader(lines), [])
        return dict.fromkeys(header)
    with xr.open_dataset(path, decode_cf=False) as ds:
        return {name: str(ds[name].attrs.get("units", "")) for name in ds.variables}


def unlisted(paths: list[Path], doc: Path = DOC) -> list[str]:
    """Every column or variable of the files ``paths`` the inventory has no row for, or whose
    units attribute is not the row's (a netCDF file's), as ``file: name`` lines."""
    table = listed(doc)
    problems = []
    for path in paths:
        name = family(path)
        for column, units in names_and_units(path).items():
            row = table.get((name, column)) or _family_row(table, name, column)
            if row is None:
                problems.append(f"{name}: {column} has no row")
            elif units is not None and units != row.unit and not (units == "" and row.unit == "-"):
                problems.append(
                    f"{name}: {column} is in {units!r}, the inventory says {row.unit!r}"
                )
    return problems


def _family_row(table: dict[tuple[str, str], Row], file: str, column: str) -> Row | None:
    """The row of a family of columns (``reduction_{knot}``, ``{line}_mmHg``) ``column`` is of."""
    for (where, name), row in table.items():
        if where == file and "{" in name:
            pattern = re.sub(r"\\\{\w+\\\}", ".+", re.escape(name))
            if re.fullmatch(pattern, column):
                return row
    return None


def test_functions(root: Path = ROOT / "tests") -> set[str]:
    """Every test function of the suite as ``module.py::name``."""
    out = set()
    for path in root.glob("test_*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
                out.add(f"{path.name}::{node.name}")
    return out
