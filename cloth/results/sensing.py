"""Measured readings placed on a relaxed garment: what the model's sensor reads there.

A reading (`cloth.files.measured.Measurements`) names a girth line or a height, an angle and a
probe. `locate` turns each into a place, a height (m), an angle (degrees) and a diameter (m),
checking what needs the garment: the girth line must be one of the result's, the place must lie
on the garment (between its lowest and highest row), and the probe must be smaller than the
girth there (the row nearest the height, measured around its nodes). `model_readings` is then
what the case's ``sensors`` report (`cloth.results.bands.probe_readings`: the contact force
under a probe's footprint over its area, Pa).

Each model reading's discretisation error is its nearest girth line's (`transferred_errors`):
the largest relative error the result states for the line's probe readings and band mean
(``pressure_max_error``, ``pressure_min_error``, ``pressure_mean_error`` over their values,
`cloth.files.levels`), times the reading. A probe reads the same field as the line's probe
does, on the same grid, so its relative error is the line's where the two are near; NaN where
no line states an error (a result without levels).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.case.reading import Reading
from cloth.results.bands import probe_readings


@dataclass(frozen=True)
class Places:
    """Where readings are taken: ``height`` (R,) m, ``angle`` (R,) degrees from +x towards +y,
    ``probe`` (R,) m (footprint diameters)."""

    height: NDArray[np.float64]
    angle: NDArray[np.float64]
    probe: NDArray[np.float64]


def row_girths(x: NDArray[np.float64], shape: tuple[int, int]) -> NDArray[np.float64]:
    """(m,) m: each row's girth, the closed polygon through its nodes (``x`` (N, 3), m;
    ``shape`` (m, n))."""
    rows = x.reshape(*shape, 3)
    step = np.roll(rows, -1, axis=1) - rows
    return np.linalg.norm(step, axis=2).sum(axis=1)


def locate(
    measured,
    lines: dict[str, float],
    x: NDArray[np.float64],
    shape: tuple[int, int],
) -> Places:
    """The places of ``measured``'s readings (`cloth.files.measured.Measurements`) on a garment
    at ``x`` ((N, 3), m; ``shape`` (m, n) rows by columns) whose girth lines are ``lines``
    (name -> height, m). `InputError` in one line naming the file, row and column where a
    point is not one of ``lines``, a place is off the garment, or a probe is larger than the
    girth there."""
    rows_z = x.reshape(*shape, 3)[..., 2].mean(axis=1)
    girths = row_girths(x, shape)
    low, high = float(rows_z.min()), float(rows_z.max())
    heights = np.array(measured.height, dtype=float)
    stated = getattr(measured, "stated_height", None)
    half_row = 0.5 * float(np.median(np.abs(np.diff(rows_z)))) if len(rows_z) > 1 else 0.0
    for k, name in enumerate(measured.point):
        if not name:
            continue
        if name not in lines:
            known = ", ".join(sorted(lines, key=lines.__getitem__)) or "none"
            raise measured.error(
                k, "point", f"unknown girth line {name!r}; the result's are {known}"
            )
        heights[k] = lines[name]
        given = float(stated[k]) if stated is not None else float("nan")
        if np.isfinite(given) and abs(given - lines[name]) > half_row:
            raise measured.error(
                k,
                "height_m",
                f"point {name} is at {lines[name]:.4g} m on this result, but the row gives "
                f"{given:.4g} m, more than half a row ({1e3 * half_row:.3g} mm) from it; give "
                "one of them, or make them agree",
            )
    for k, height in enumerate(heights):
        column = "point" if measured.point[k] else "height_m"
        if not low - 1e-9 <= height <= high + 1e-9:
            raise measured.error(
                k,
                column,
                f"{height:.4g} m is off the garment, which covers {low:.4g}-{high:.4g} m",
            )
        girth = float(girths[np.argmin(np.abs(rows_z - height))])
        if measured.probe[k] >= girth:
            raise measured.error(
                k,
                "probe_mm",
                f"a {1e3 * measured.probe[k]:g} mm probe is larger than the girth there "
                f"({1e3 * girth:.0f} mm); give the probe's diameter in mm",
            )
    return Places(heights, np.array(measured.angle, dtype=float), measured.probe)


def model_readings(
    places: Places,
    x: NDArray[np.float64],
    force: NDArray[np.float64],
    area: NDArray[np.float64],
    reading: Reading,
) -> NDArray[np.float64]:
    """(R,) Pa: what the model's probe reads at each place, from the nodes' positions ``x``
    ((N, 3), m), contact forces ``force`` ((N,), N) and areas ``area`` ((N,), m2), with the
    case's ``reading`` kernel (`cloth.results.bands.probe_readings`)."""
    return np.array(
        [
            probe_readings(x, force, area, h, np.array([a]), d, reading)[0]
            for h, a, d in zip(places.height, places.angle, places.probe, strict=True)
        ]
    )


def transferred_errors(
    heights: NDArray[np.float64],
    values: NDArray[np.float64],
    line_heights: NDArray[np.float64],
    line_relative: NDArray[np.float64],
    line_names: tuple[str, ...],
) -> tuple[NDArray[np.float64], tuple[str, ...]]:
    """Each reading's stated error ((R,), ``values``' units) and the girth line it is taken
    from (module docstring): ``line_relative`` (L,) each line's relative error (1; NaN where
    it states none), at ``line_heights`` (L,) m."""
    stated = np.isfinite(line_relative)
    if not stated.any():
        return np.full(len(heights), np.nan), tuple("" for _ in heights)
    idx = np.flatnonzero(stated)
    nearest = idx[np.argmin(np.abs(line_heights[idx][None, :] - heights[:, None]), axis=1)]
    return np.abs(values) * line_relative[nearest], tuple(line_names[k] for k in nearest)
