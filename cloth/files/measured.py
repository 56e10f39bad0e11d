"""A measurements file: what a pressure sensor read under a garment, one reading a row.

A CSV (``#`` comment lines left out, as the shipped ``data/measurements/example_cone.csv``),
placed as a case's ``sensors`` are (`cloth.case.reading`):

* where: ``point``, a girth line's name (``B``, ``waist``; its height is the result's), or
  ``height_m``, the probe centre's height on the body (m); one of the two columns at least,
  and a row gives one of them; where it gives both, the point's height on the result must be
  within half a row of the given height (else the row is refused: one of them is wrong), and
  the point's is taken;
* ``angle_deg``: the probe centre's angle about the body's up axis, degrees from +x towards +y
  (the parametric bodies face +y, so 90 is the front); angles wrap, 270 is -90;
* ``pressure_mmHg``: what the sensor read, mmHg: finite, from 0 to `MAX_MMHG` (200 mmHg, far
  above any garment's, RAL class IV's 49 mmHg included; a value past it was most likely typed
  in kPa or Pa);
* ``probe_mm``: the probe's diameter, mm (a PicoPress bladder 50, a Kikuhime 30);
* optionally ``subject`` (who wore it; empty: one subject) and ``repeat`` (which reading of
  several at one place, 1, 2, ...).

Refused in one line naming the file, the row (the first data row is row 1) and the column: a
missing column, a pressure that is not a finite number, below zero or above `MAX_MMHG`, an
angle or a height
that is not a finite number, a probe that is not a positive number, a row that names no place.
What needs the result to check (an unknown girth line, a probe larger than the girth, a place
off the garment, a point whose height disagrees with the row's ``height_m``) is refused by
`cloth.results.sensing.locate`, in the same form.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.io import atomic_output
from cloth.results.pressure import MMHG

#: Columns every measurements file has.
REQUIRED = ("angle_deg", "pressure_mmHg", "probe_mm")
#: Where a reading is: a girth line's name, or a height (m); one of them at least.
PLACES = ("point", "height_m")
#: Columns read where present.
OPTIONAL = ("subject", "repeat")
#: The largest pressure a reading may give, mmHg: no garment presses a body this hard (a
#: medical class IV stocking, the firmest, is 49 mmHg and up), so a larger value is a unit
#: slip (kPa or Pa typed as mmHg).
MAX_MMHG = 200.0


@dataclass(frozen=True)
class Measurements:
    """The readings of a measurements file (module docstring), one entry per row, in SI:
    ``point`` (R,) girth-line names ('' where the row gives a height), ``height`` (R,) m (NaN
    where it names a point), ``angle`` (R,) degrees in (-180, 180], ``pressure`` (R,) Pa,
    ``probe`` (R,) m, ``subject`` (R,) names ('' for one subject), ``repeat`` (R,) whole
    numbers, ``source`` the file."""

    source: str
    point: tuple[str, ...]
    height: NDArray[np.float64]
    angle: NDArray[np.float64]
    pressure: NDArray[np.float64]
    probe: NDArray[np.float64]
    subject: tuple[str, ...]
    repeat: NDArray[np.int64]
    #: (R,) m: the ``height_m`` a row gives beside its ``point`` (NaN where it gives none), which
    #: `cloth.results.sensing.locate` checks against the point's height on the result.
    stated_height: NDArray[np.float64] | None = None

    def __len__(self) -> int:
        return len(self.point)

    def error(self, row: int, column: str, message: str) -> InputError:
        """An `InputError` naming the file, ``row`` (0-based index; reported from 1) and
        ``column``."""
        return InputError(message, self.source, f"row {row + 1}, {column}")

    @property
    def subjects(self) -> tuple[str, ...]:
        """The subjects in the order they first appear."""
        return tuple(dict.fromkeys(self.subject))


def wrap_angle(degrees: float) -> float:
    """``degrees`` wrapped to (-180, 180]: 270 is -90."""
    wrapped = math.remainder(degrees, 360.0)
    return 180.0 if wrapped == -180.0 else wrapped


def _number(text: str | None, path: Path, row: int, column: str, what: str) -> float:
    try:
        value = float((text or "").strip())
    except ValueError:
        value = float("nan")
    if not math.isfinite(value):
        raise InputError(
            f"{what} must be a finite number, got {text!r}; fix or remove the row",
            path,
            f"row {row + 1}, {column}",
        )
    return value


def read_measurements(path: str | Path) -> Measurements:
    """The readings of the measurements file ``path`` (module docstring); `InputError` in one
    line naming the file, the row and the column."""
    path = Path(path)
    if not path.is_file():
        raise InputError("measurements file not found; check the path", path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"not a readable text file ({type(exc).__name__})", path) from None
    lines = [line for line in text.splitlines() if line.strip() and not line.startswith("#")]
    reader = csv.DictReader(lines)
    columns = [c.strip() for c in reader.fieldnames or []]
    reader.fieldnames = columns
    for column in REQUIRED:
        if column not in columns:
            raise InputError(
                f"missing column {column!r}; a measurements file has "
                f"{', '.join(REQUIRED)} and point or height_m (docs/outputs.md)",
                path,
                column,
            )
    if not any(c in columns for c in PLACES):
        raise InputError(
            "missing column 'point' or 'height_m': say where each reading was taken",
            path,
            "point",
        )
    point, height, angle, pressure, probe, subject, repeat = [], [], [], [], [], [], []
    stated = []
    for k, row in enumerate(reader):
        name = (row.get("point") or "").strip()
        raw = (row.get("height_m") or "").strip()
        if not name and not raw:
            raise InputError(
                "no place: give the girth line's name in 'point' or a height in 'height_m'",
                path,
                f"row {k + 1}, point",
            )
        point.append(name)
        given = _number(raw, path, k, "height_m", "the height (m)") if raw else float("nan")
        height.append(float("nan") if name else given)
        stated.append(given if name else float("nan"))
        angle.append(wrap_angle(_number(row.get("angle_deg"), path, k, "angle_deg", "the angle")))
        value = _number(row.get("pressure_mmHg"), path, k, "pressure_mmHg", "the pressure")
        if value < 0:
            raise InputError(
                f"a pressure cannot be below zero, got {value:g} mmHg; check the sensor's zero",
                path,
                f"row {k + 1}, pressure_mmHg",
            )
        if value > MAX_MMHG:
            raise InputError(
                f"{value:g} mmHg is beyond any garment's pressure on a body (0-{MAX_MMHG:g} "
                f"mmHg); was it typed in kPa or Pa? (1 kPa = {1e3 / MMHG:.2f} mmHg)",
                path,
                f"row {k + 1}, pressure_mmHg",
            )
        pressure.append(value * MMHG)
        size = _number(row.get("probe_mm"), path, k, "probe_mm", "the probe's diameter (mm)")
        if size <= 0:
            raise InputError(
                f"the probe's diameter must be positive, got {size:g} mm",
                path,
                f"row {k + 1}, probe_mm",
            )
        probe.append(size * 1e-3)
        subject.append((row.get("subject") or "").strip())
        count = (row.get("repeat") or "").strip()
        number = _number(count, path, k, "repeat", "the repeat") if count else 1.0
        if number != int(number) or number < 1:
            raise InputError(
                f"a repeat is a whole number from 1, got {count!r}", path, f"row {k + 1}, repeat"
            )
        repeat.append(int(number))
    if not point:
        raise InputError("no reading: the file has a header and no rows", path, "rows")
    return Measurements(
        str(path),
        tuple(point),
        np.array(height),
        np.array(angle),
        np.array(pressure),
        np.array(probe),
        tuple(subject),
        np.array(repeat, dtype=np.int64),
        np.array(stated),
    )


def write_measurements(measured: Measurements, path: str | Path, header: str) -> Path:
    """Write ``measured`` as a measurements file (module docstring) at ``path``, atomically,
    ``header``'s lines as ``#`` comments first; pressures to 0.01 mmHg."""
    lines = [f"# {line}" for line in header.splitlines()]
    lines.append("subject,point,height_m,angle_deg,pressure_mmHg,probe_mm,repeat")
    for k in range(len(measured)):
        height = "" if measured.point[k] else f"{measured.height[k]:.4f}"
        lines.append(
            f"{measured.subject[k]},{measured.point[k]},{height},{measured.angle[k]:g},"
            f"{measured.pressure[k] / MMHG:.2f},{1e3 * measured.probe[k]:g},{measured.repeat[k]}"
        )
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return Path(path)
