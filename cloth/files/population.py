"""A population of measured people (issue 52, item 2): who wears a size.

A CSV of one person a row (``#`` comment lines left out), as the shipped
``data/bodies/population/nhanes_2017_2020_women.csv`` (US NHANES 2017-2020, CDC, public
domain). The columns this module reads, each optional but the first kind:

* ``{girth}_cm``: a girth the chart has too, by the chart's name (``waist_cm``, ``hip_cm``,
  ``bust_cm``; a leg chart's ``B_cm``, ``C_cm``), cm;
* ``height_cm`` (or ``stature_cm``): standing height, cm;
* ``exam_weight`` (or ``survey_weight``, ``weight``): the survey weight, the number of people a
  row stands for; every row 1 where absent. Not the body mass: ``weight_kg`` is never read;
* ``age_years``: keeps the ages asked (`AGES` by default) where present;
* ``pregnant``: 1 leaves the row out where present.

A row with an empty cell in a measure is left out of that measure's use only where it is not
needed (`Population.complete`). Refused in one line naming the file and the column: no measure
column, a cell that is not a number, a girth or height past any adult's (a file in mm or
inches), a negative weight.
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
#: Standing-height columns, in the order looked for; read as the measure ``stature``.
STATURE_COLUMNS = ("height_cm", "stature_cm")
#: Ages (years, inclusive) kept by default: the adults who buy shapewear and compression
#: garments' sizes, as the issue's table took them.
AGES = (18.0, 45.0)
#: What a human girth (cm) and stature (cm) may be; past these a file is in other units.
GIRTH_CM = (10.0, 250.0)
STATURE_CM = (100.0, 230.0)


@dataclass(frozen=True)
class Population:
    """The people of a file (module docstring): ``measures`` name -> (P,) float, m (NaN where
    the cell was empty; ``stature`` the standing height), ``weight`` (P,) survey weights."""

    path: str
    measures: dict[str, NDArray[np.float64]]
    weight: NDArray[np.float64]

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


def read_population(path: str | Path, ages: tuple[float, float] | None = AGES) -> Population:
    """The people of ``path`` (module docstring) aged within ``ages`` (years; None: all) where
    the file gives ages, the pregnant left out."""
    path = Path(path)
    if not path.is_file():
        raise InputError("population file not found; check the path", path, "population")
    lines = [line for line in path.read_text().splitlines() if not line.lstrip().startswith("#")]
    reader = csv.DictReader(lines)
    columns = [c.strip() for c in reader.fieldnames or []]
    girths = [c for c in columns if c.endswith("_cm") and c not in STATURE_COLUMNS]
    stature = next((c for c in STATURE_COLUMNS if c in columns), None)
    if not girths and stature is None:
        raise InputError(
            "no measure column: give girths as {name}_cm (the chart's names, e.g. waist_cm, "
            "hip_cm) and the standing height as height_cm",
            path,
            "header",
        )
    weight_column = next((c for c in WEIGHT_COLUMNS if c in columns), None)
    rows = list(reader)
    values = {
        c: np.array([_float(r.get(c), path, c, k + 2) for k, r in enumerate(rows)])
        for c in [*girths, *([stature] if stature else [])]
    }
    for column, data in values.items():
        low, high = STATURE_CM if column == stature else GIRTH_CM
        bad = np.isfinite(data) & ((data < low) | (data > high))
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"row {k + 2}: {data[k]:g} is past any adult's ({low:g}-{high:g} cm); give "
                f"{column} in cm",
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
    if "pregnant" in columns:
        keep &= np.array([(r.get("pregnant") or "").strip() != "1" for r in rows])
    measures = {c.removesuffix("_cm"): 0.01 * values[c][keep] for c in girths}
    if stature is not None:
        measures["stature"] = 0.01 * values[stature][keep]
    return Population(str(path), measures, weight[keep])


__all__ = ["AGES", "Population", "read_population"]
