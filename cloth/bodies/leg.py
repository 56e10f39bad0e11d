"""A parametric leg from a stocking size chart: the measuring points of RAL-GZ 387/1 and EN 17430.

The chart (`read_leg_chart`; default ``data/bodies/leg_chart.csv``) gives per size the
circumference and the height above the floor at B (the ankle above the malleoli), B1, C (the
calf), D (below the knee), E, F (mid-thigh) and G (top of the thigh), and the depth/width ratio
of the section at each. The leg's sections are ellipses (`EXPONENT` 2; no flatter shin), each
scaled so that its perimeter is the girth at its height; their centres lie on a vertical axis
or one leaning forward from B by ``lean_deg`` (the sections stay horizontal)
(`cloth.bodies.sectioned.SectionedBody`). The leg runs from `BELOW` under B to `ABOVE` over G,
its girth there `BELOW_GIRTH` x B's and `ABOVE_GIRTH` x G's.

Profiles along the height (`c2_profile`): through the points, a quintic Hermite piece between
each pair with PCHIP's slopes (Fritsch-Carlson: no overshoot where the chart is monotone) and,
at every point, the mean of PCHIP's second derivatives either side of it (at the ends, the one
side's). So the girth is C2 (its curvature continuous across the measuring points, where
PCHIP's jumps) and between two points stays within their values (checked for the bundled chart
in tests/test_leg.py). Zero second derivatives at the points, the first choice, were C2 too
but flattened the meridian within millimetres of each point: on a stocking the warp's pressure
term then changed by 500 Pa between neighbouring rows at D.
"""

from __future__ import annotations

import csv
import itertools
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import BPoly, PchipInterpolator

from cloth.bodies.ranges import girth_cells
from cloth.bodies.sectioned import SectionedBody, ring_heights, ring_mesh
from cloth.errors import InputError
from cloth.shipped import shipped

EXPONENT = 2.0
DEFAULT_LEG_CHART = shipped("bodies", "leg_chart.csv")
#: The measuring points, bottom to top: the leg's girth lines.
POINTS = ("B", "B1", "C", "D", "E", "F", "G")
#: The leg's ends: this far below B and above G (m), their girths these shares of B's and G's.
BELOW, ABOVE = 0.04, 0.04
BELOW_GIRTH, ABOVE_GIRTH = 1.08, 1.02


@dataclass(frozen=True)
class LegChart:
    """One size: girth (m), height (m) and depth/width ratio at each point of `POINTS`."""

    name: str
    girth: dict[str, float]
    height: dict[str, float]
    depth_ratio: dict[str, float]
    source: str = "chart"
    #: point -> (low, high) girth, m, of the legs the size fits, where the chart gives a range
    #: (`cloth.bodies.ranges`); the girth is then its centre or the value given
    girth_range: dict[str, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for point in POINTS:
            for what, table in (
                ("circumference", self.girth),
                ("height", self.height),
                ("depth ratio", self.depth_ratio),
            ):
                value = table.get(point)
                if value is None or not np.isfinite(value) or value <= 0:
                    raise InputError(
                        f"size {self.name}, point {point}: the {what} must be a positive number, "
                        f"got {value}",
                        self.source,
                        f"{point}",
                    )
        for low, high in itertools.pairwise(POINTS):
            if self.height[high] <= self.height[low]:
                raise InputError(
                    f"size {self.name}, point {high}: its height {100 * self.height[high]:g} cm "
                    f"must be above {low}'s ({100 * self.height[low]:g} cm)",
                    self.source,
                    f"{high}_height_cm",
                )

    @property
    def bottom(self) -> float:
        return self.height["B"] - BELOW

    @property
    def top(self) -> float:
        return self.height["G"] + ABOVE


def read_leg_chart(path: str | Path = DEFAULT_LEG_CHART) -> dict[str, LegChart]:
    """All sizes of a leg chart CSV (cm; `cloth.bodies.leg` docstring), by size name;
    `InputError` naming the size and the point for a missing, zero or non-monotone value."""
    path = Path(path)
    if not path.is_file():
        raise InputError("leg chart not found; check the path", path)
    rows = [line for line in path.read_text().splitlines() if not line.lstrip().startswith("#")]
    sizes = {}
    for number, row in enumerate(csv.DictReader(rows), start=1):
        name = (row.get("size") or f"row {number}").strip()

        def number_of(key: str, name: str = name, row: dict = row) -> float:
            text = (row.get(key) or "").strip()
            try:
                return float(text)
            except ValueError:
                point = key.split("_", 1)[0]
                raise InputError(
                    f"size {name}, point {point}: {key} is missing or not a number "
                    f"({text!r}); give it in cm (ratios as numbers)",
                    path,
                    key,
                ) from None

        cells = {p: girth_cells(row, p, path, name) for p in POINTS}
        chart = LegChart(
            name=name,
            girth={p: cells[p][0] / 100 for p in POINTS},
            girth_range={p: (c[1][0] / 100, c[1][1] / 100) for p, c in cells.items() if c[1]},
            height={p: number_of(f"{p}_height_cm") / 100 for p in POINTS},
            depth_ratio={p: number_of(f"{p}_depth_ratio") for p in POINTS},
            source=str(path),
        )
        sizes[chart.name] = chart
    return sizes


def leg_size(size: str, path: str | Path = DEFAULT_LEG_CHART) -> LegChart:
    sizes = read_leg_chart(path)
    if size not in sizes:
        raise InputError(f"unknown size {size!r}; the chart has {', '.join(sizes)}", path, "size")
    return sizes[size]


def leg_of(spec: dict, chart_path: str | Path = DEFAULT_LEG_CHART) -> LegChart:
    """The leg of a case's ``leg`` block: its ``size`` in the chart, with any of
    ``circumference_cm``, ``height_cm`` and ``depth_ratio`` (point -> value) over it; without a
    size, the block's own values at every point (depth ratios default to the chart's first
    size's). `InputError` naming the point for a missing or bad value."""
    given = {
        key: dict(spec.get(key) or {}) for key in ("circumference_cm", "height_cm", "depth_ratio")
    }
    unknown = [p for values in given.values() for p in values if p not in POINTS]
    if unknown:
        raise InputError(
            f"unknown measuring point {unknown[0]!r}; the points are {', '.join(POINTS)}",
            field="body.leg",
        )
    if "size" in spec:
        base = leg_size(spec["size"], chart_path)
        name = str(spec["size"])
    else:
        missing = [
            p for p in POINTS for key in ("circumference_cm", "height_cm") if p not in given[key]
        ]
        if missing:
            raise InputError(
                f"point {missing[0]}: give size, or circumference_cm and height_cm at every "
                f"point ({', '.join(POINTS)})",
                field="body.leg",
            )
        base = next(iter(read_leg_chart(chart_path).values()))
        name = "given"
    return LegChart(
        name=name,
        girth={p: given["circumference_cm"].get(p, 100 * base.girth[p]) / 100 for p in POINTS},
        height={p: given["height_cm"].get(p, 100 * base.height[p]) / 100 for p in POINTS},
        depth_ratio={p: given["depth_ratio"].get(p, base.depth_ratio[p]) for p in POINTS},
        source="body.leg",
    )


def c2_profile(z: NDArray[np.float64], values: NDArray[np.float64]) -> BPoly:
    """The C2 profile through (z, values) (module docstring): quintic Hermite pieces with
    PCHIP's slopes and zero second derivatives at the points."""
    z, values = np.asarray(z, dtype=float), np.asarray(values, dtype=float)
    pchip = PchipInterpolator(z, values)
    slopes = pchip.derivative()(z)
    second = pchip.derivative(2)
    step = 1e-9 * float(z[-1] - z[0])
    bends = 0.5 * (second(z - step) + second(z + step))  # the mean of either side's
    bends[0], bends[-1] = second(z[0] + step), second(z[-1] - step)
    data = np.stack([values, slopes, bends], axis=1)
    return BPoly.from_derivatives(z, data, extrapolate=True)


def _profiles(chart: LegChart):
    """Girth (m), depth ratio and front share (0.5: the axis centred) along the height."""
    z = [chart.bottom, *(chart.height[p] for p in POINTS), chart.top]
    girth = [
        BELOW_GIRTH * chart.girth["B"],
        *(chart.girth[p] for p in POINTS),
        ABOVE_GIRTH * chart.girth["G"],
    ]
    ratio = [
        chart.depth_ratio["B"],
        *(chart.depth_ratio[p] for p in POINTS),
        chart.depth_ratio["G"],
    ]
    front = np.full(len(z), 0.5)
    return c2_profile(z, girth), c2_profile(z, ratio), PchipInterpolator(z, front)


def leg_mesh(
    chart: LegChart, around: int = 96, rings: int = 160, lean_deg: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices ((V, 3), m, z up, the shin towards +y) and outward faces ((F, 3)) of the leg:
    ``around`` points on ``rings`` rings, a ring at every measuring point; the sections'
    centres leaning forward by ``lean_deg`` from B (`SmoothLeg`)."""
    if around < 8 or rings < 8:
        raise InputError("the leg needs at least 8 points around and 8 rings", field="leg")
    girth, depth, front = _profiles(chart)
    heights = ring_heights(chart.bottom, chart.top, rings, [chart.height[p] for p in POINTS])
    vertices, faces = ring_mesh(heights, around, girth, depth, front, EXPONENT)
    vertices[:, 1] += lean_slope(lean_deg) * (vertices[:, 2] - chart.height["B"])
    return vertices, faces


def lean_slope(lean_deg: float) -> float:
    """The centres' forward slope dy/dz of a leg leaning ``lean_deg`` degrees (|lean| < 30)."""
    if not abs(lean_deg) < 30:
        raise InputError(
            f"a lean of {lean_deg} degrees; give less than 30", field="body.leg.lean_deg"
        )
    return float(np.tan(np.radians(lean_deg)))


@dataclass(frozen=True, eq=False)
class SmoothLeg(SectionedBody):
    """The smooth lateral surface of the parametric leg of ``chart`` (heights in m)."""

    chart: LegChart
    lean_deg: float = 0.0
    bottom: float = field(init=False)
    top: float = field(init=False)
    exponent: float = field(init=False, default=EXPONENT)

    def __post_init__(self) -> None:
        chart = self.chart
        self._build(
            chart.bottom,
            chart.top,
            *_profiles(chart),
            EXPONENT,
            lean_slope(self.lean_deg),
            chart.height["B"],
        )
