"""A parametric women's torso from a size chart: a smooth, watertight, convex-section mesh.

Each cross-section at height z is a superellipse |x/a|^p + |y/b|^p = 1 (p = `EXPONENT`, between
an ellipse and a rounded rectangle) with half-width a, front depth b_front (y > 0) and back depth
b_back (y < 0). Along the height, the girth, the depth/width ratio and the front share of the
depth are interpolated through the chart's landmarks (bottom, hip, waist, underbust, bust, top)
by monotone cubic (PCHIP) splines, so the surface is smooth and never overshoots the chart.

Each ring of the mesh is scaled so that its polygon's perimeter is the interpolated girth, and the
landmark heights are rings of the mesh: the mesh's measured girths equal the chart's there to
rounding. Bottom and top are closed by flat caps (watertight, outward normals).

The smooth surface (`SmoothTorso`).

The torso is defined by smooth profiles; its mesh is one sampling of it. On the
mesh, frictionless contact has the mesh's edges: the body's reaction jumps from face to face, a
tensioned ring rests on edges, and Newton's active set settles slowly there (docs/solvers.md).
This body is the surface itself,

    G(x, y, z) = |x / a(z)|^p + |y / b(y, z)|^p - 1 = 0,   b = b_front (y >= 0), b_back (y < 0)

(p = `EXPONENT`; a, b_front, b_back in m): each section is the superellipse of the
mesh's rings, scaled so that its perimeter is the chart's girth at that height. It is C^1
everywhere and its curvature is continuous around (|y|^p has two continuous derivatives at
y = 0), so the closed-form contact path of the Newton solver applies: one constraint per node,
with the curvature term that makes sliding exact.

Profiles a(z), b_front(z), b_back(z) are cubic splines through `PROFILE_SAMPLES` heights of
the PCHIP profiles; below the bottom and above the top they continue along their tangents (caps
are ignored, as on the other closed-form bodies).

Shapes and units: points (P, 3) m; distances (P,) m, positive outside; normals unit, outward;
the Hessian of the signed distance (P, 3, 3) in 1/m.
"""

from __future__ import annotations

import csv
import itertools
import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PchipInterpolator

from cloth.bodies import sectioned
from cloth.bodies.ranges import girth_cells
from cloth.bodies.sectioned import SectionedBody, ring_heights, ring_mesh
from cloth.errors import InputError
from cloth.shipped import shipped

log = logging.getLogger(__name__)

EXPONENT = 2.4
DEFAULT_CHART = shipped("bodies", "size_chart.csv")
#: The torso's girth lines, bottom to top: its landmarks, named in the size chart.
LANDMARKS = ("hip", "waist", "underbust", "bust")
GIRTH_KEYS = ("bust_cm", "underbust_cm", "waist_cm", "hip_cm")


@dataclass(frozen=True)
class SizeChart:
    """One size: girths (m) and heights (m) of the landmarks, and cross-section shape ratios."""

    name: str
    girth: dict[str, float]  # landmark -> girth, m
    height: dict[str, float]  # landmark (plus bottom, top) -> height, m
    depth_ratio: dict[str, float]  # landmark -> depth / width
    front_share: dict[str, float]  # bust, waist, hip -> share of depth in front
    #: landmark -> (low, high) girth, m, of the bodies the size fits, where the chart gives a
    #: range (`cloth.bodies.ranges`); the girth is then its centre or the value given
    girth_range: dict[str, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        order = ["bottom", *LANDMARKS, "top"]
        heights = [self.height[key] for key in order]
        if any(b <= a for a, b in itertools.pairwise(heights)):
            raise InputError(
                f"size {self.name}: heights must increase bottom < hip < waist < underbust < "
                f"bust < top, got {heights}",
                field="height",
            )
        for key, value in self.girth.items():
            if not np.isfinite(value) or value <= 0:
                raise InputError(f"size {self.name}: {key} girth must be positive", field=key)


def read_chart(path: str | Path = DEFAULT_CHART) -> dict[str, SizeChart]:
    """All sizes of a size-chart CSV (cm), by size name."""
    path = Path(path)
    if not path.is_file():
        raise InputError("size chart not found; check the path", path)
    rows = [line for line in path.read_text().splitlines() if not line.lstrip().startswith("#")]
    sizes = {}
    for number, row in enumerate(csv.DictReader(rows), start=1):
        name = (row.get("size") or f"row {number}").strip()
        cells = {lm: girth_cells(row, lm, path, name) for lm in LANDMARKS}
        try:
            cm = {k: float(v) / 100 for k, v in row.items() if k.endswith("_height_cm")}
            ratio = {k: float(v) for k, v in row.items() if k.endswith(("_ratio", "_share"))}
            chart = SizeChart(
                name=name,
                girth={lm: cells[lm][0] / 100 for lm in LANDMARKS},
                girth_range={lm: (c[1][0] / 100, c[1][1] / 100) for lm, c in cells.items() if c[1]},
                height={key: cm[f"{key}_height_cm"] for key in ("bottom", *LANDMARKS, "top")},
                depth_ratio={lm: ratio[f"{lm}_depth_ratio"] for lm in LANDMARKS},
                front_share={k: ratio[f"{k}_front_share"] for k in ("bust", "waist", "hip")},
            )
        except (KeyError, ValueError, TypeError) as exc:
            raise InputError(
                f"size chart row {number} is incomplete or not numeric ({exc}); see "
                "data/bodies/size_chart.csv for the columns",
                path,
                f"row {number}",
            ) from None
        sizes[chart.name] = chart
    return sizes


def chart_size(size: str, path: str | Path = DEFAULT_CHART) -> SizeChart:
    sizes = read_chart(path)
    if size not in sizes:
        raise InputError(f"unknown size {size!r}; the chart has {', '.join(sizes)}", path, "size")
    return sizes[size]


def _profiles(chart: SizeChart):
    """PCHIP profiles of girth, depth ratio and front share along the height."""
    z = [chart.height[k] for k in ("bottom", *LANDMARKS, "top")]
    g = chart.girth
    girth = [0.97 * g["hip"], g["hip"], g["waist"], g["underbust"], g["bust"], 0.97 * g["bust"]]
    d = chart.depth_ratio
    depth = [d["hip"], d["hip"], d["waist"], d["underbust"], d["bust"], 0.9 * d["bust"]]
    f = chart.front_share
    front = [f["hip"], f["hip"], f["waist"], f["waist"], f["bust"], 0.5]
    return tuple(PchipInterpolator(z, values) for values in (girth, depth, front))


def superellipse(angle: NDArray) -> tuple[NDArray, NDArray]:
    """`cloth.bodies.sectioned.superellipse` with the torso's exponent."""
    return sectioned.superellipse(angle, EXPONENT)


def torso_mesh(
    chart: SizeChart, around: int = 128, rings: int = 120
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices ((V, 3), m, z up, front towards +y) and outward faces ((F, 3)) of the torso.

    ``around`` points on each of ``rings`` rings, as evenly spaced as rings at every landmark
    height allow (their girths are the chart's; rings added at the landmarks to a uniform set
    left slivers 3 mm high among 19 mm rings, where 1 mm of vertex noise makes slopes of 0.3,
    right on the girth lines); quads split in a checkerboard of diagonals: with ``around`` a
    multiple of 4 the mesh is left-right symmetric, as the torso is.
    """
    if around < 8 or rings < 8:
        raise InputError("the torso needs at least 8 points around and 8 rings", field="torso")
    girth, depth, front = _profiles(chart)
    bottom, top = chart.height["bottom"], chart.height["top"]
    heights = ring_heights(bottom, top, rings, [chart.height[k] for k in LANDMARKS])
    return ring_mesh(heights, around, girth, depth, front, EXPONENT)


@dataclass(frozen=True, eq=False)
class SmoothTorso(SectionedBody):
    """The smooth lateral surface of the parametric torso of ``chart`` (heights in m): its
    superellipse sections (`cloth.bodies.sectioned.SectionedBody`)."""

    chart: SizeChart
    bottom: float = field(init=False)
    top: float = field(init=False)
    exponent: float = field(init=False, default=EXPONENT)

    def __post_init__(self) -> None:
        chart = self.chart
        self._build(chart.height["bottom"], chart.height["top"], *_profiles(chart), EXPONENT)
