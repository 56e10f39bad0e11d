"""One lab table as its CSV file gives it: ``# key: value`` header comments, the columns and their
units (`KNOWN_COLUMNS`), and the numbers, checked cell by cell (`read_table`, `numbers`,
`pick`), and the strain and stress they give in SI (`strain_stress`: from clean columns, or
force over the specimen's section). Cycles, branches and fitting are `cloth.materials.labtables`'.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError


class SectionOptions(Protocol):
    """What converting forces to stresses needs besides the table
    (`cloth.materials.labtables.IngestOptions` has these; None: from the table's header)."""

    thickness_mm: float | None
    specimen_width_mm: float | None
    gauge_length_mm: float | None


#: Header keys understood in ``# key: value`` comment lines, with their meaning.
HEADER_KEYS: dict[str, str] = {
    "name": "fabric name",
    "direction": "weft, warp or bias, for a file holding one direction",
    "thickness_mm": "fabric thickness, mm",
    "specimen_width_mm": "width of the tested strip, mm",
    "gauge_length_mm": "initial clamp distance, mm (needed with extension_mm)",
    "areal_density_g_m2": "mass per area, g m-2",
    "source": "where the data come from",
}

STRAIN_UNITS = {"strain": 1.0, "strain_percent": 0.01, "elongation_percent": 0.01}
STRESS_UNITS = {"stress": 1.0, "stress_pa": 1.0, "stress_kpa": 1e3, "stress_mpa": 1e6}
FORCE_UNITS = {"force_n": 1.0, "force_cn": 1e-2, "force_kn": 1e3}
EXTENSION_UNITS = {"extension_mm": 1e-3}
KNOWN_COLUMNS = (
    set(STRAIN_UNITS)
    | set(STRESS_UNITS)
    | set(FORCE_UNITS)
    | set(EXTENSION_UNITS)
    | {"direction", "cycle", "branch", "time_s"}
)
UNIT_PREFIXES = ("strain_", "stress_", "force_", "extension_", "elongation_")


@dataclass
class LabTable:
    """A table's file, header values (lower-case keys), columns as text (lower-case names;
    ``_row`` holds each row's line number) and the line of its first data row."""

    path: Path
    header: dict[str, str]
    columns: dict[str, list[str]]
    first_row: int  # 1-based line number of the first data row


def read_table(path: Path) -> LabTable:
    """Read and check a lab table's CSV (`InputError` naming the file, row or column)."""
    if not path.is_file():
        raise InputError("file not found; check the path", source=path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"not a UTF-8 text table ({exc.reason}); export it as CSV", path) from None
    lines = text.splitlines()
    header: dict[str, str] = {}
    body_start = 0
    for number, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            match = re.match(r"#\s*([A-Za-z_][\w]*)\s*[:=]\s*(.*?)\s*$", stripped)
            if match and match.group(1).lower() in HEADER_KEYS:
                header[match.group(1).lower()] = match.group(2)
            continue
        body_start = number
        break
    else:
        raise InputError("the file has no header row and no data; export the table again", path)
    reader = csv.reader(lines[body_start:])
    names = [name.strip() for name in next(reader)]
    keys = [name.lower() for name in names]
    for name, key in zip(names, keys, strict=True):
        if key in KNOWN_COLUMNS:
            continue
        if key.startswith(UNIT_PREFIXES):
            prefix = key.split("_", 1)[0]
            known = sorted(c for c in KNOWN_COLUMNS if c.startswith(prefix))
            raise InputError(
                f"unknown unit in column {name!r}; use one of {', '.join(known)}", path, name
            )
        if key:
            raise InputError(
                f"unknown column {name!r}; known columns are {', '.join(sorted(KNOWN_COLUMNS))}",
                path,
                name,
            )
    if len(set(keys)) != len(keys):
        raise InputError("a column name appears twice; rename one", path, "header")
    columns: dict[str, list[str]] = {key: [] for key in keys}
    for row_number, row in enumerate(reader, start=body_start + 2):
        if not row or all(not cell.strip() for cell in row) or row[0].lstrip().startswith("#"):
            continue
        if len(row) != len(keys):
            raise InputError(
                f"row has {len(row)} cells but the header has {len(keys)}; fix the row",
                path,
                f"row {row_number}",
            )
        for key, cell in zip(keys, row, strict=True):
            columns[key].append(cell.strip())
        columns.setdefault("_row", []).append(str(row_number))
    if not columns.get("_row"):
        raise InputError("the table has a header but no data rows; add the measurements", path)
    return LabTable(path, header, columns, body_start + 2)


def numbers(table: LabTable, key: str) -> NDArray[np.float64]:
    """Column ``key`` as finite numbers ((R,)), or `InputError` naming the cell's row."""
    values = np.empty(len(table.columns[key]))
    for index, cell in enumerate(table.columns[key]):
        try:
            values[index] = float(cell)
        except ValueError:
            raise InputError(
                f"cell {cell!r} in column {key!r} is not a number; fix or delete the row",
                table.path,
                f"row {table.columns['_row'][index]}",
            ) from None
        if not math.isfinite(values[index]):
            raise InputError(
                f"cell {cell!r} in column {key!r} is not finite; delete the row",
                table.path,
                f"row {table.columns['_row'][index]}",
            )
    return values


def pick(table: LabTable, units: dict[str, float]) -> tuple[str, float] | None:
    """The one column of ``units`` (name -> factor to SI) the table has, and its factor."""
    found = [key for key in units if key in table.columns]
    if len(found) > 1:
        raise InputError(
            f"columns {', '.join(found)} say the same thing; keep one", table.path, found[1]
        )
    return (found[0], units[found[0]]) if found else None


def positive_mm(value: object, what: str, table: LabTable, option: str) -> float:
    """``value`` (a length in mm) as a positive float, or `InputError` naming ``option``."""
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        number = float("nan")
    if not math.isfinite(number) or number <= 0:
        raise InputError(
            f"{what} must be a positive number in mm, got {value!r}; set '# {option}: <mm>' in "
            f"the header or the {option} option",
            table.path,
            option,
        )
    return number


def setting(table: LabTable, options: SectionOptions, key: str) -> object:
    """Option ``key``: given in ``options``, else from the table's header (or None)."""
    value = getattr(options, key)
    return value if value is not None else table.header.get(key)


def strain_stress(table: LabTable, options: SectionOptions) -> tuple[NDArray, NDArray]:
    """Strain (1) and stress (Pa) of every row."""
    strain_col = pick(table, STRAIN_UNITS)
    extension_col = pick(table, EXTENSION_UNITS)
    if strain_col is not None:
        strain = numbers(table, strain_col[0]) * strain_col[1]
    elif extension_col is not None:
        gauge = setting(table, options, "gauge_length_mm")
        if gauge is None:
            raise InputError(
                "extension_mm needs the gauge length; set '# gauge_length_mm: <mm>' in the header",
                table.path,
                "gauge_length_mm",
            )
        gauge_mm = positive_mm(gauge, "the gauge length", table, "gauge_length_mm")
        strain = numbers(table, extension_col[0]) * extension_col[1] / (gauge_mm * 1e-3)
    else:
        raise InputError(
            "missing strain column; add one of strain, strain_percent, elongation_percent or "
            "extension_mm",
            table.path,
            "header",
        )
    stress_col = pick(table, STRESS_UNITS)
    force_col = pick(table, FORCE_UNITS)
    if stress_col is not None:
        stress = numbers(table, stress_col[0]) * stress_col[1]
    elif force_col is not None:
        width = setting(table, options, "specimen_width_mm")
        thickness = setting(table, options, "thickness_mm")
        if width is None:
            raise InputError(
                "force data need the strip width; set '# specimen_width_mm: <mm>' in the header",
                table.path,
                "specimen_width_mm",
            )
        if thickness is None:
            raise InputError(
                "force data need the fabric thickness; set '# thickness_mm: <mm>' in the header",
                table.path,
                "thickness_mm",
            )
        area = (
            positive_mm(width, "the specimen width", table, "specimen_width_mm")
            * positive_mm(thickness, "the thickness", table, "thickness_mm")
            * 1e-6
        )
        stress = numbers(table, force_col[0]) * force_col[1] / area
    else:
        raise InputError(
            "missing stress column; add one of stress, stress_Pa, stress_kPa, stress_MPa, "
            "force_N, force_cN or force_kN",
            table.path,
            "header",
        )
    return strain, stress
