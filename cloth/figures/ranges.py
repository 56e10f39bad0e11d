"""Colour ranges a sweep's figures share, read once for the sweep (no matplotlib here).

A sweep's figures compare when they share colour ranges: the stress range (Pa, weft and warp
on one scale) and the pressure range (mmHg), each from 0 (or the 1st percentile, where lower)
to the `HIGH_PERCENTILE` (95th) of every node of every result of the sweep (`shared_ranges`).
The 95th, not the 99th: the hems' line loads and an avatar's bust points are the top 1-5 % of
a torso's nodes, and at the 99th (60 mmHg on avatar M at 0.20, where its girth lines read
16-26) they left the rest of the map one dark colour; beyond the range is the colour bar's
arrow. The
pipeline reads the sweep's results once, in its ``colour_ranges`` rule (`write_ranges`,
``cloth ranges``), into one small JSON file that each case's figures read (`read_ranges`,
``cloth plot --ranges``): before, every case's figures read every result of the sweep (0.6 s
of 32 peers' fields a case at 192 x 96, docs/performance.md), and counted their own result
twice, so their ranges differed slightly from case to case.

The file::

    {"stress_Pa": [low, high], "pressure_mmHg": [low, high], "results": ["path", ...]}
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.errors import InputError
from cloth.io import atomic_output, read_fields

#: The variables of a sweep's results that set its colour ranges: all that is read of them.
RANGE_FIELDS = ("stress_weft", "stress_warp", "pressure_mmHg")

Range = tuple[float, float]

#: Percentiles of a field's nodes that bound its colour range (the low end also at most 0).
LOW_PERCENTILE, HIGH_PERCENTILE = 1, 95


def field_range(datasets: Sequence[xr.Dataset], variable: str, scale: float = 1.0) -> Range:
    """(low, high) colour range of ``variable`` x ``scale`` over ``datasets`` (a sweep's
    results): 0 or the `LOW_PERCENTILE`, to the `HIGH_PERCENTILE`, of every node of every one."""
    values = np.concatenate([np.ravel(ds[variable].values) * scale for ds in datasets])
    values = values[np.isfinite(values)]
    if not values.size:
        return 0.0, 1.0
    low, high = np.percentile(values, [LOW_PERCENTILE, HIGH_PERCENTILE])
    low = min(0.0, float(low))
    return low, max(float(high), low + 1e-9)


def shared_ranges(datasets: Sequence[xr.Dataset]) -> tuple[Range, Range]:
    """Colour ranges shared by ``datasets`` (a sweep's results, in any order): stress (Pa,
    weft and warp on one scale) and pressure (mmHg), by `field_range`."""
    weft, warp = (field_range(datasets, f"stress_{d}") for d in ("weft", "warp"))
    return (min(weft[0], warp[0]), max(weft[1], warp[1])), field_range(datasets, "pressure_mmHg")


def write_ranges(results: Sequence[str | Path], output: str | Path) -> tuple[Range, Range]:
    """The `shared_ranges` of the result files ``results``, written to ``output`` (JSON, the
    module docstring's; atomically): (stress range in Pa, pressure range in mmHg)."""
    if not results:
        raise InputError("no result files to take colour ranges from; give at least one")
    stress, pressure = shared_ranges([read_fields(p, "result", RANGE_FIELDS) for p in results])
    record = {
        "stress_Pa": list(stress),
        "pressure_mmHg": list(pressure),
        "results": [str(p) for p in results],
    }
    with atomic_output(output) as tmp:
        tmp.write_text(json.dumps(record, indent=1) + "\n")
    return stress, pressure


def _number(value: object) -> bool:
    """Whether a JSON value is a finite number (not a string, and not true or false)."""
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def read_ranges(path: str | Path) -> tuple[Range, Range]:
    """(stress range in Pa, pressure range in mmHg) from a file `write_ranges` wrote; one
    `InputError` naming the file and the field where it is missing or malformed."""
    path = Path(path)
    if not path.is_file():
        raise InputError("no such colour-range file; write it with `cloth ranges`", path)
    try:
        record = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"not a colour-range file (JSON): {error}", path) from None
    found = []
    for key in ("stress_Pa", "pressure_mmHg"):
        pair = record.get(key) if isinstance(record, dict) else None
        ok = isinstance(pair, list) and len(pair) == 2
        ok = ok and all(_number(v) for v in pair)
        if not ok or pair[0] >= pair[1]:
            raise InputError(
                "expected [low, high], two finite numbers, low below high; rewrite the file "
                "with `cloth ranges`",
                path,
                key,
            )
        found.append((float(pair[0]), float(pair[1])))
    return found[0], found[1]
