"""A size chart's girths given as one value or as a range (issue 52, item 1).

A size gives each girth either as one value (``{point}_cm``) or as a range (``{point}_min_cm``
and ``{point}_max_cm``): the girths of the bodies the size fits. A range's centre is the size's
body (the parametric torso or leg, an avatar); both may be given, the value then the size's
body, inside its range. Both chart formats read their girths here (`cloth.bodies.torso`,
`cloth.bodies.leg`).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from cloth.errors import InputError


def _number(row: Mapping[str, str | None], key: str) -> float | None:
    text = (row.get(key) or "").strip()
    if not text:
        return None
    try:
        return float(text)
    except ValueError:
        return float("nan")


def girth_cells(
    row: Mapping[str, str | None], point: str, path: str | Path, size: str
) -> tuple[float, tuple[float, float] | None]:
    """Size ``size``'s girth at ``point`` from its chart ``row`` (cm): the value (a range's
    centre where only the range is given) and the range (low, high) or None; `InputError`
    naming the chart, the size and the column where neither is given, half a range, a range
    whose minimum passes its maximum, or a value outside its range."""
    at = f"size {size}, point {point}"
    value = _number(row, f"{point}_cm")
    low, high = _number(row, f"{point}_min_cm"), _number(row, f"{point}_max_cm")
    for key, number in (
        (f"{point}_cm", value),
        (f"{point}_min_cm", low),
        (f"{point}_max_cm", high),
    ):
        if number is not None and not number == number:  # NaN: text that is not a number
            raise InputError(
                f"{at}: {key} {row.get(key)!r} is not a number; give it in cm",
                path,
                key,
            )
    if (low is None) != (high is None):
        given, missing = (
            (f"{point}_min_cm", f"{point}_max_cm")
            if high is None
            else (f"{point}_max_cm", f"{point}_min_cm")
        )
        raise InputError(
            f"{at}: {given} without {missing}; a range needs both (cm)",
            path,
            missing,
        )
    if low is None or high is None:
        if value is None:
            raise InputError(
                f"{at}: no {point} girth; give {point}_cm or {point}_min_cm and "
                f"{point}_max_cm (cm)",
                path,
                f"{point}_cm",
            )
        return value, None
    if not low <= high:
        raise InputError(
            f"{at}: {point}_min_cm {low:g} is above {point}_max_cm {high:g}; give the "
            "range low to high (cm)",
            path,
            f"{point}_min_cm",
        )
    if value is None:
        value = 0.5 * (low + high)
    elif not low <= value <= high:
        raise InputError(
            f"{at}: {point}_cm {value:g} is outside its range {low:g}-{high:g} cm; give "
            "the size's body within the girths it fits",
            path,
            f"{point}_cm",
        )
    return value, (low, high)


__all__ = ["girth_cells"]
