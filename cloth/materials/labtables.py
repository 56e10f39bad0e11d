"""Read lab tables (clean curves or raw tensile-tester exports) into a `Fabric`.

Formats (documented with examples in ``docs/materials.md``):

* A CSV with a header row. Lines starting with ``#`` before it are comments; those of the form
  ``# key: value`` with a key of `HEADER_KEYS` set metadata (thickness, specimen width, ...).
* Clean tables: a strain column (``strain`` [1] or ``strain_percent`` [%]) and a stress column
  (``stress`` or ``stress_Pa`` [Pa], ``stress_kPa``, ``stress_MPa``).
* Raw exports: a force column (``force_N``, ``force_cN``, ``force_kN``) against
  ``elongation_percent`` or ``extension_mm`` (with ``gauge_length_mm``); stress = force /
  (specimen width x thickness).
* The direction comes from a ``direction`` column, a ``# direction:`` header line, or the caller.
* Optional ``cycle`` (integer) and ``branch`` (``load``/``unload``) columns; `IngestOptions`
  chooses which cycle and branch become the curve. Default: the unloading branch of the last
  cycle, which is what a garment follows once it has been pulled on (it was stretched further
  while dressing, then relaxes onto the body).

Without a ``n_knots`` option, a non-cyclic clean table, or a raw one of at most `DEFAULT_KNOTS`
points, is the curve itself (its points are the knots, strains must increase); anything else is
reduced by `cloth.materials.fitting.fit_monotone` to ``n_knots`` (default `DEFAULT_KNOTS`) knots.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.io import sha256
from cloth.materials.curves import DIRECTIONS, Fabric, StressStrainCurve
from cloth.materials.fitting import FitReport, curve_error, fit_monotone, zero_force_strain
from cloth.materials.labcsv import (
    STRESS_UNITS,
    LabTable,
    numbers,
    pick,
    positive_mm,
    read_table,
    setting,
    strain_stress,
)

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class IngestOptions:
    """How lab tables become curves.

    Attributes
    ----------
    n_knots : int or None
        Knots of the fitted curve (>= 2). None: clean tables keep their points as knots and raw
        exports are fitted with `DEFAULT_KNOTS` knots.
    branch : {'unload', 'load', 'all'}
        Which branch of cyclic data to use when a ``branch`` column exists.
    cycle : int or None
        Which cycle (the ``cycle`` column's value) to use; None = the last one.
    thickness_mm, specimen_width_mm, gauge_length_mm : float or None
        Override or supply the header values, mm.
    compression_ratio : float or None
        Compression modulus as a fraction of the initial slope (None: the library default).
    name : str or None
        Fabric name (default: the header's ``name`` or the first file's stem).
    """

    n_knots: int | None = None
    branch: str = "unload"
    cycle: int | None = None
    thickness_mm: float | None = None
    specimen_width_mm: float | None = None
    gauge_length_mm: float | None = None
    compression_ratio: float | None = None
    name: str | None = None


DEFAULT_KNOTS = 8
BRANCHES = ("unload", "load", "all")


@dataclass(frozen=True)
class DirectionData:
    """What one direction's data became.

    Attributes
    ----------
    raw_strain : (N,) float, 1
        The measured points used for the curve (after cycle/branch selection).
    raw_stress : (N,) float, Pa
    report : FitReport
        Curve error against those points.
    residual_strain : float, 1
        Strain at which the selected branch reaches zero stress (plastic set); 0 for load data.
    source : str
        The file the points came from.
    """

    raw_strain: NDArray[np.float64]
    raw_stress: NDArray[np.float64]
    report: FitReport
    residual_strain: float
    source: str


@dataclass(frozen=True)
class Material:
    """An ingested material: the fabric and, per direction, the data behind its curve."""

    fabric: Fabric
    data: dict[str, DirectionData] = field(default_factory=dict)


def _select(table: LabTable, options: IngestOptions, rows: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Rows of the chosen cycle and branch, among ``rows``."""
    if "cycle" in table.columns:
        cycles = numbers(table, "cycle")
        wanted = np.max(cycles[rows]) if options.cycle is None else float(options.cycle)
        if not np.any(rows & (cycles == wanted)):
            raise InputError(
                f"no rows of cycle {options.cycle}; the table has cycles "
                f"{', '.join(str(int(c)) for c in np.unique(cycles))}",
                table.path,
                "cycle",
            )
        rows = rows & (cycles == wanted)
    if "branch" in table.columns and options.branch != "all":
        branch = np.array([b.lower() for b in table.columns["branch"]])
        unknown = sorted(set(branch) - {"load", "unload"})
        if unknown:
            raise InputError(
                f"unknown branch {unknown[0]!r}; use load or unload", table.path, "branch"
            )
        rows = rows & (branch == options.branch)
        if not np.any(rows):
            raise InputError(
                f"no rows on the {options.branch} branch; choose branch load or all",
                table.path,
                "branch",
            )
    return rows


def _directions(table: LabTable, direction: str | None) -> NDArray[np.str_]:
    count = len(table.columns["_row"])
    if "direction" in table.columns:
        values = np.array([d.lower() for d in table.columns["direction"]])
    else:
        given = direction or table.header.get("direction")
        if given is None:
            raise InputError(
                "no direction: add a 'direction' column, a '# direction: weft' header line, "
                "or name the direction when ingesting",
                table.path,
                "direction",
            )
        values = np.full(count, given.lower())
    for index, value in enumerate(values):
        if value not in DIRECTIONS:
            raise InputError(
                f"unknown direction {value!r}; use one of {', '.join(DIRECTIONS)}",
                table.path,
                f"row {table.columns['_row'][index]}",
            )
    return values


def _clean_checks(table: LabTable, strain: NDArray, rows: NDArray[np.bool_]) -> None:
    """A clean curve must list strictly increasing strains (its rows are knots)."""
    index = np.flatnonzero(rows)
    steps = np.diff(strain[index])
    if np.any(steps <= 0):
        bad = int(np.flatnonzero(steps <= 0)[0])
        a, b = (table.columns["_row"][i] for i in index[bad : bad + 2])
        what = "repeats" if steps[bad] == 0 else "decreases after"
        raise InputError(
            f"strain {strain[index[bad + 1]]:g} at row {b} {what} {strain[index[bad]]:g} at row "
            f"{a}; strains of a curve must increase (sort the rows, remove duplicates, or add a "
            "'branch' column for load/unload cycles)",
            table.path,
            f"row {b}",
        )


def _set_strain(
    table: LabTable, strain: NDArray, stress: NDArray, rows: NDArray[np.bool_]
) -> float | None:
    """The set of a cyclic table's direction (``rows``): the strain at which the unloading branch
    of its last cycle reaches zero force (`cloth.materials.fitting.zero_force_strain`; None
    without unloading rows)."""
    try:
        unloading = _select(table, IngestOptions(branch="unload"), rows)
    except InputError:
        return None
    return zero_force_strain(strain[unloading], stress[unloading])


def _curve_from_points(
    strain: NDArray, stress: NDArray, dense: bool, options: IngestOptions, source: Path
) -> tuple[StressStrainCurve, DirectionData]:
    order = np.argsort(strain, kind="stable")
    strain, stress = strain[order], stress[order]
    residual = zero_force_strain(strain, stress) if dense else 0.0
    keep = strain >= 0.0
    strain, stress = strain[keep], stress[keep]
    n_knots = options.n_knots
    if n_knots is None and not dense:
        knots_x, knots_y = strain, stress
        if knots_x.size == 0 or knots_x[0] > 0:
            knots_x, knots_y = np.append(0.0, knots_x), np.append(0.0, knots_y)
        elif knots_y[0] != 0.0:
            raise InputError(
                f"the curve must pass through stress 0 at strain 0, got {knots_y[0]:g} Pa; "
                "remove the offset or let the fit handle it (--knots K)",
                source,
                "stress",
            )
        report = curve_error(knots_x, knots_y, strain, stress)
    else:
        knots_x, knots_y, report = fit_monotone(strain, stress, n_knots or DEFAULT_KNOTS)
    try:
        curve = StressStrainCurve(knots_x, knots_y, compression_modulus=None)
    except InputError as exc:
        raise InputError(exc.detail, source, exc.field) from None
    if options.compression_ratio is not None:
        rising = curve.slopes[curve.slopes > 0]
        curve = StressStrainCurve(
            knots_x,
            knots_y,
            compression_modulus=options.compression_ratio * (rising[0] if rising.size else 0.0),
        )
    data = DirectionData(strain, stress, report, residual, str(source))
    return curve, data


def ingest(
    paths: Sequence[str | Path],
    directions: Sequence[str | None] | None = None,
    options: IngestOptions | None = None,
) -> Material:
    """Read one or more lab tables into a `Material`.

    Parameters
    ----------
    paths : sequence of path
        CSV tables: one holding every direction (a ``direction`` column), or one per direction.
    directions : sequence of str or None, optional
        The direction of each file that has no ``direction`` column or header line.
    options : IngestOptions, optional
        Fitting, cycle/branch choice, and header overrides.

    Returns
    -------
    Material
        The fabric (weft and warp curves at least) with the data and fit error per direction.
    """
    options = options or IngestOptions()
    if options.branch not in BRANCHES:
        raise InputError(
            f"unknown branch {options.branch!r}; use one of {', '.join(BRANCHES)}", field="branch"
        )
    if options.n_knots is not None and options.n_knots < 2:
        raise InputError(f"knots must be >= 2, got {options.n_knots}", field="knots")
    if not paths:
        raise InputError("no lab table given", field="table")
    directions = list(directions) if directions else [None] * len(paths)
    if len(directions) != len(paths):
        raise InputError("give one direction per table, or none", field="direction")
    curves: dict[str, StressStrainCurve] = {}
    data: dict[str, DirectionData] = {}
    thickness: float | None = None
    set_strain: dict[str, float] = {}
    header: dict[str, str] = {}
    provenance: dict[str, str] = {"ingest_options": repr(options)}
    for index, (raw_path, direction) in enumerate(zip(paths, directions, strict=True)):
        table = read_table(Path(raw_path))
        header = {**table.header, **header}
        provenance[f"table_{index}"] = str(table.path)
        provenance[f"table_{index}_sha256"] = sha256(table.path)
        strain, stress = strain_stress(table, options)
        cyclic = "branch" in table.columns or "cycle" in table.columns
        clean = pick(table, STRESS_UNITS) is not None
        dirs = _directions(table, direction)
        for name in dict.fromkeys(dirs):
            if name in curves:
                raise InputError(
                    f"direction {name!r} is given twice (also in {data[name].source}); "
                    "give each direction once",
                    table.path,
                    "direction",
                )
            rows = _select(table, options, dirs == name)
            # a short or clean, non-cyclic table is the curve itself; anything else is fitted
            exact = (
                options.n_knots is None
                and not cyclic
                and (clean or np.count_nonzero(rows) <= DEFAULT_KNOTS)
            )
            if exact:
                _clean_checks(table, strain, rows)
            curves[name], data[name] = _curve_from_points(
                strain[rows], stress[rows], not exact, options, table.path
            )
            if cyclic:
                measured = _set_strain(table, strain, stress, dirs == name)
                if measured is not None:
                    set_strain[str(name)] = measured
            log.info(
                "%s %s: %d points -> %d knots, fit error max %.4g Pa (%.3g %%), rms %.4g Pa",
                table.path.name,
                name,
                data[name].report.n_points,
                curves[name].n_knots,
                data[name].report.max_error,
                data[name].report.max_error_percent,
                data[name].report.rms_error,
            )
        if thickness is None and setting(table, options, "thickness_mm") is not None:
            value = setting(table, options, "thickness_mm")
            thickness = positive_mm(value, "the thickness", table, "thickness_mm") * 1e-3
    missing = [d for d in ("weft", "warp") if d not in curves]
    if missing:
        raise InputError(
            f"no {' and no '.join(missing)} data; a fabric needs weft and warp curves",
            paths[0],
            "direction",
        )
    if thickness is None:
        raise InputError(
            "fabric thickness missing; set '# thickness_mm: <mm>' in the header or the "
            "thickness_mm option",
            paths[0],
            "thickness_mm",
        )
    density = header.get("areal_density_g_m2")
    if density is not None:
        try:
            density = float(density)
        except ValueError:
            raise InputError(
                f"areal density {density!r} is not a number of g m-2; fix the header line",
                paths[0],
                "areal_density_g_m2",
            ) from None
    name = options.name or header.get("name") or Path(paths[0]).stem
    if "source" in header:
        provenance["source"] = header["source"]
    fabric = Fabric(
        name=name,
        weft=curves["weft"],
        warp=curves["warp"],
        bias=curves.get("bias"),
        thickness=thickness,
        areal_density=density * 1e-3 if density is not None else float("nan"),
        provenance=provenance,
        set_strain=set_strain,
    )
    return Material(fabric, data)
