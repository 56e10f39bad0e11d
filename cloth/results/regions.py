"""Where the frictionless answer depends on what it leaves out: gathering and lifting.

Two regions of a worn garment carry pressures the model's friction decides:

* ``slack_warp``: the warp (the grid's vertical springs) is slack, its node-averaged strain
  below zero. With no friction nothing holds the fabric there: the rows gather down the
  slope of the body until the warp buckles (real skin, with a friction coefficient of about
  0.5, holds fabric on slopes where a frictionless one lets it slide).
* ``off_body``: the garment lifts off the body and bridges a hollow (the taut warp across the
  waist's hollow; the fabric across the cleavage), pressing nothing there.

For each region (`Region`): its share of the garment's deformed area (1), its height ranges
(m: runs of consecutive rows holding a flagged node, each from its lowest flagged node to its
highest) and the girth lines whose band (the line's height +- the band's half-width,
`cloth.case.reading.Reading`) meets a range. result.nc and summary.csv carry them
(`cloth.files.result`); the aggregate stage logs the lines touched in words.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: A node's warp is slack where its node-averaged warp strain is below this (1).
SLACK_STRAIN = -1e-9


@dataclass(frozen=True)
class Region:
    """One region (module docstring): ``flag`` ((N,) bool), ``share`` of the garment's area
    (1), ``ranges`` ((R, 2) m, bottom and top of each run) and the girth ``lines`` it touches."""

    name: str
    flag: NDArray[np.bool_]
    share: float
    ranges: NDArray[np.float64]
    lines: tuple[str, ...]


def height_ranges(flag: NDArray[np.bool_], z: NDArray[np.float64], m: int) -> NDArray:
    """(R, 2) m: the runs of consecutive rows (of ``m``) holding a flagged node, each from its
    lowest flagged node's height ``z`` ((N,), m) to its highest."""
    rows = flag.reshape(m, -1)
    heights = z.reshape(m, -1)
    marked = rows.any(axis=1)
    out = []
    j = 0
    while j < m:
        if not marked[j]:
            j += 1
            continue
        start = j
        while j < m and marked[j]:
            j += 1
        values = heights[start:j][rows[start:j]]
        out.append((float(values.min()), float(values.max())))
    return np.asarray(out, float).reshape(-1, 2)


def region(
    name: str,
    flag: NDArray[np.bool_],
    x: NDArray[np.float64],
    area: NDArray[np.float64],
    m: int,
    lines: dict[str, float],
    half_width: float,
) -> Region:
    """The region ``name`` of the nodes ``flag`` ((N,) bool) of a grid of ``m`` rows at ``x``
    ((N, 3), m) with areas ``area`` ((N,), m2), and which of ``lines`` (name -> height, m)
    its ranges meet within ``half_width`` (m)."""
    total = float(area.sum())
    share = float(area[flag].sum() / total) if total > 0 else 0.0
    ranges = height_ranges(flag, x[:, 2], m)
    touched = tuple(
        line
        for line, h in sorted(lines.items(), key=lambda item: item[1])
        if any(low - half_width <= h <= high + half_width for low, high in ranges)
    )
    return Region(name, flag, share, ranges, touched)


def regions(
    strain_warp: NDArray[np.float64],
    on_body: NDArray[np.int8],
    x: NDArray[np.float64],
    area: NDArray[np.float64],
    m: int,
    lines: dict[str, float],
    half_width: float,
) -> tuple[Region, Region]:
    """The ``slack_warp`` and ``off_body`` regions (module docstring) of a garment with node
    warp strains ``strain_warp`` ((N,), 1; NaN where no warp spring meets a node) and contact
    flags ``on_body`` ((N,))."""
    slack = np.nan_to_num(strain_warp, nan=0.0) < SLACK_STRAIN
    off = ~on_body.astype(bool)
    return (
        region("slack_warp", slack, x, area, m, lines, half_width),
        region("off_body", off, x, area, m, lines, half_width),
    )


def note(slack: bool, off: bool, friction: float) -> str:
    """summary.csv's words for a girth line that the slack warp (``slack``) or the lifted
    garment (``off``) touches, else ''; ``friction``: the case's coefficient."""
    parts = []
    if slack:
        parts.append("the warp is slack here, so the fabric gathers")
    if off:
        parts.append("the garment lifts off the body here and bridges")
    if not parts:
        return ""
    held = (
        f"friction mu = {friction:g} holds the fabric as modelled"
        if friction
        else "the pressure depends on the skin's friction, which this frictionless model leaves out"
    )
    return "; ".join(parts) + f": {held}"
