"""A population of measured people (issue 52, item 2): who wears a size.

A CSV of one person a row (``#`` comment lines left out), as the shipped
``data/bodies/population/nhanes_2017_2020_women.csv`` (US NHANES 2017-2020, CDC, public
domain). The columns this module reads, each optional but the first kind:

* ``{girth}_cm``: a girth the chart has too, by the chart's name (``waist_cm``, ``hip_cm``,
  ``bust_cm``; a leg chart's ``B_cm``, ``C_cm``), or by an anthropometric survey's name that
  `ALIASES` maps to the chart's (``ankle_cm`` -> B, ``calf_cm`` -> C, ``thigh_cm`` -> G,
  ``chest_cm`` -> bust; a column by the chart's own name wins), cm;
* ``{point}_height_cm``: a girth line's height above the floor, by the chart's name or a
  survey's that `ALIASES` maps (``knee_height_midpatella_cm`` -> E, ``crotch_height_cm`` -> G),
  cm; read as the measure ``{point}_height``;
* ``height_cm`` (or ``stature_cm``): standing height, cm;
* ``exam_weight`` (or ``survey_weight``, ``weight``): the survey weight, the number of people a
  row stands for; every row 1 where absent. Not the body mass: ``weight_kg`` is never read;
* ``age_years``: keeps the ages asked (`AGES` by default) where present;
* ``pregnant``: 1 leaves the row out where present.

A row with an empty cell in a measure is left out of that measure's use only where it is not
needed (`Population.complete`). Refused in one line naming the file and the column: no measure
column, a cell that is not a number, a girth or height past any adult's (a file in mm or
inches: each named girth has its own adult range, `GIRTH_RANGES_CM`, so an ankle in mm or a
waist in inches is caught), a negative weight, no person left (an empty file, or no one of the
ages asked). The shipped files are ``data/bodies/population/nhanes_2017_2020_women.csv`` (the
torso's default) and ``ansur2_women.csv`` (US Army ANSUR II, the leg's default).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError

#: Survey-weight columns, in the order looked for.
WEIGHT_COLUMNS = ("exam_weight", "survey_weight", "weight")
#: A person's name, in the order looked for (else her row).
ID_COLUMNS = ("subject_id", "seqn", "id", "subject")
#: Standing-height columns, in the order looked for; read as the measure ``stature``.
STATURE_COLUMNS = ("height_cm", "stature_cm")
#: Ages (years, inclusive) kept by default: the adults who buy shapewear and compression
#: garments' sizes, as the issue's table took them.
AGES = (18.0, 45.0)
#: What a human girth (cm) and stature (cm) may be; past these a file is in other units.
GIRTH_CM = (10.0, 250.0)
STATURE_CM = (100.0, 230.0)
#: What a girth line's height above the floor may be, cm.
HEIGHT_CM = (0.5, 200.0)
#: Adult ranges (cm) of the girths charts name, narrower than `GIRTH_CM`: an ankle in mm
#: (about 215) or a waist in inches (about 33) falls outside its own.
GIRTH_RANGES_CM = {
    "B": (12.0, 45.0),
    "B1": (14.0, 55.0),
    "C": (20.0, 75.0),
    "D": (18.0, 70.0),
    "E": (20.0, 80.0),
    "F": (25.0, 110.0),
    "G": (30.0, 120.0),
    "waist": (40.0, 200.0),
    "hip": (55.0, 210.0),
    "bust": (55.0, 200.0),
    "underbust": (50.0, 180.0),
}
#: A survey's measure names -> the chart's (module docstring): girths, and heights of girth
#: lines (``{point}_height``).
ALIASES = {
    "ankle": "B",
    "calf": "C",
    "thigh": "G",
    "chest": "bust",
    "knee_height_midpatella": "E_height",
    "crotch_height": "G_height",
    "chest_height": "bust_height",
    "waist_height_omphalion": "waist_height",
}


@dataclass(frozen=True)
class Population:
    """The people of a file (module docstring): ``measures`` name -> (P,) float, m (NaN where
    the cell was empty; ``stature`` the standing height), ``weight`` (P,) survey weights."""

    path: str
    measures: dict[str, NDArray[np.float64]]
    weight: NDArray[np.float64]
    #: (P,) each person's name: her `ID_COLUMNS` cell, else ``row N`` (N her row in the
    #: file's table, the header row 1, comment lines not counted)
    ids: tuple[str, ...] = ()

    def complete(self, names: list[str]) -> NDArray[np.bool_]:
        """(P,) bool: the people with every one of ``names`` measured."""
        keep = np.ones(len(self.weight), dtype=bool)
        for name in names:
            keep &= np.isfinite(self.measures[name])
        return keep


def _float(text: str | None, path: Path, column: str, number: int) -> float:
    text = (text or "").strip()
    if not text:
        return float("nan")
    try:
        return float(text)
    except ValueError:
        raise InputError(
            f"row {number}: {text!r} is not a number; give {column} as a number",
            path,
            column,
        ) from None


def _measure_name(column: str, columns: list[str]) -> str | None:
    """The chart's name of a ``*_cm`` column (`ALIASES`), None where a column by the chart's
    own name is there too (it wins) or the column is the stature."""
    if column in STATURE_COLUMNS:
        return None
    name = column.removesuffix("_cm")
    alias = ALIASES.get(name)
    if alias is None:
        return name
    return None if f"{alias}_cm" in columns else alias


def _bounds(name: str) -> tuple[float, float]:
    """The adult range (cm) of the measure ``name`` (chart's name)."""
    if name == "stature":
        return STATURE_CM
    if name.endswith("_height"):
        return HEIGHT_CM
    return GIRTH_RANGES_CM.get(name, GIRTH_CM)


def read_population(path: str | Path, ages: tuple[float, float] | None = AGES) -> Population:
    """The people of ``path`` (module docstring) aged within ``ages`` (years; None: all) where
    the file gives ages, the pregnant left out."""
    path = Path(path)
    if not path.is_file():
        raise InputError("population file not found; check the path", path, "population")
    lines = [line for line in path.read_text().splitlines() if not line.lstrip().startswith("#")]
    reader = csv.DictReader(lines)
    columns = [c.strip() for c in reader.fieldnames or []]
    names = {c: _measure_name(c, columns) for c in columns if c.endswith("_cm")}
    girths = {c: n for c, n in names.items() if n is not None}
    stature = next((c for c in STATURE_COLUMNS if c in columns), None)
    if not girths and stature is None:
        raise InputError(
            "no measure column: give girths as {name}_cm (the chart's names, e.g. waist_cm, "
            "hip_cm, B_cm, or ankle_cm, calf_cm) and the standing height as height_cm",
            path,
            "header",
        )
    weight_column = next((c for c in WEIGHT_COLUMNS if c in columns), None)
    rows = list(reader)
    if not rows:
        raise InputError("no person: the file has a header and no rows", path, "rows")
    columns_read = {**girths, **({stature: "stature"} if stature else {})}
    values = {
        c: np.array([_float(r.get(c), path, c, k + 2) for k, r in enumerate(rows)])
        for c in columns_read
    }
    for column, data in values.items():
        low, high = _bounds(columns_read[column])
        bad = np.isfinite(data) & ((data < low) | (data > high))
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"row {k + 2}: {data[k]:g} is past any adult's ({low:g}-{high:g} cm); give "
                f"{column} in cm (not mm or inches)",
                path,
                column,
            )
    if weight_column is None:
        weight = np.ones(len(rows))
    else:
        weight = np.array(
            [_float(r.get(weight_column), path, weight_column, k + 2) for k, r in enumerate(rows)]
        )
        if np.any(weight < 0):
            k = int(np.flatnonzero(weight < 0)[0])
            raise InputError(
                f"row {k + 2}: a survey weight must be >= 0, found {weight[k]:g}",
                path,
                weight_column,
            )
        weight = np.where(np.isfinite(weight), weight, 0.0)
    keep = np.ones(len(rows), dtype=bool)
    if ages is not None and "age_years" in columns:
        age = np.array(
            [_float(r.get("age_years"), path, "age_years", k + 2) for k, r in enumerate(rows)]
        )
        keep &= (age >= ages[0]) & (age <= ages[1])
        if not keep.any():
            raise InputError(
                f"no person left: none is aged {ages[0]:g}-{ages[1]:g} years; widen --ages",
                path,
                "age_years",
            )
    if "pregnant" in columns:
        keep &= np.array([(r.get("pregnant") or "").strip() != "1" for r in rows])
    measures = {name: 0.01 * values[c][keep] for c, name in columns_read.items()}
    id_column = next((c for c in ID_COLUMNS if c in columns), None)
    ids = tuple(
        (r.get(id_column) or "").strip() if id_column else f"row {k + 2}"
        for k, r in enumerate(rows)
        if keep[k]
    )
    return Population(str(path), measures, weight[keep], ids)


__all__ = ["AGES", "ALIASES", "GIRTH_RANGES_CM", "Population", "read_population"]
