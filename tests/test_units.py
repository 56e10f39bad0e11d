"""Every unit a lab table's columns may be in converts as its name says: one curve written in
each of the reader's units (`cloth.materials.labcsv`'s tables, iterated, not a chosen few) reads
back as the same curve in SI. The factors are this test's own, from the units' names."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from cloth.materials import labcsv
from cloth.materials.labtables import ingest

#: SI factor of each unit as its name spells it (after the quantity's ``_``): a bare quantity
#: is SI; ``pa``, ``kpa``, ``mpa`` are pascals, kilo- and megapascals (a lab table's MPa,
#: lower-cased); ``n``, ``cn``, ``kn`` newtons, centi- and kilonewtons; ``mm`` millimetres;
#: ``percent`` hundredths.
FACTORS = {"": 1.0, "pa": 1.0, "kpa": 1e3, "mpa": 1e6, "n": 1.0, "cn": 1e-2, "kn": 1e3}
FACTORS |= {"mm": 1e-3, "percent": 1e-2}
#: The specimen of force and extension columns: strip width and thickness, gauge length (mm).
WIDTH_MM, THICKNESS_MM, GAUGE_MM = 50.0, 0.5, 100.0
#: The curve: strain (1) and stress (Pa).
STRAIN = np.array([0.0, 0.1, 0.25, 0.4, 0.6, 0.8])
STRESS = 2.0e5 * STRAIN + 6.0e5 * STRAIN**2


def factor(column: str) -> float:
    """The SI factor ``column``'s name says (its unit after the quantity)."""
    unit = column.partition("_")[2]
    assert unit in FACTORS, f"{column}: a unit this test has no rule for; add it to FACTORS"
    return FACTORS[unit]


def strain_columns() -> list[str]:
    return sorted(labcsv.STRAIN_UNITS) + sorted(labcsv.EXTENSION_UNITS)


def stress_columns() -> list[str]:
    return sorted(labcsv.STRESS_UNITS) + sorted(labcsv.FORCE_UNITS)


def test_every_unit_column_of_the_reader_is_in_these_tables():
    units = set(strain_columns()) | set(stress_columns())
    assert units == labcsv.KNOWN_COLUMNS - {"direction", "cycle", "branch", "time_s"}
    assert all(any(c.startswith(p) for p in labcsv.UNIT_PREFIXES) or "_" not in c for c in units)


@pytest.mark.parametrize(
    ("strain_column", "stress_column"), list(itertools.product(strain_columns(), stress_columns()))
)
def test_a_curve_written_in_any_unit_reads_back_in_si(tmp_path, strain_column, stress_column):
    if strain_column in labcsv.EXTENSION_UNITS:
        first = STRAIN * GAUGE_MM * 1e-3 / factor(strain_column)  # extension, in its unit
    else:
        first = STRAIN / factor(strain_column)
    if stress_column in labcsv.FORCE_UNITS:
        second = STRESS * (WIDTH_MM * THICKNESS_MM * 1e-6) / factor(stress_column)  # force
    else:
        second = STRESS / factor(stress_column)
    header = (
        f"# thickness_mm: {THICKNESS_MM}\n# specimen_width_mm: {WIDTH_MM}\n"
        f"# gauge_length_mm: {GAUGE_MM}\n{strain_column},{stress_column}\n"
    )
    rows = "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(first, second, strict=True))
    path = tmp_path / "table.csv"
    path.write_text(header + rows)
    curve = ingest([path, path], ["weft", "warp"]).fabric.weft
    np.testing.assert_allclose(curve.knot_strain, STRAIN, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(curve.knot_stress, STRESS, rtol=1e-12, atol=1e-9)
