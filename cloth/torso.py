"""A parametric women's torso from a size chart: a smooth, watertight, convex-section mesh.

Each cross-section at height z is a superellipse |x/a|^p + |y/b|^p = 1 (p = `EXPONENT`, between
an ellipse and a rounded rectangle) with half-width a, front depth b_front (y > 0) and back depth
b_back (y < 0). Along the height, the girth, the depth/width ratio and the front share of the
depth are interpolated through the chart's landmarks (bottom, hip, waist, underbust, bust, top)
by monotone cubic (PCHIP) splines, so the surface is smooth and never overshoots the chart.

Each ring of the mesh is scaled so that its polygon's perimeter is the interpolated girth, and the
landmark heights are rings of the mesh: the mesh's measured girths equal the chart's there to
rounding. Bottom and top are closed by flat caps (watertight, outward normals).
"""

from __future__ import annotations

import csv
import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PchipInterpolator

from cloth.errors import InputError

EXPONENT = 2.4
DEFAULT_CHART = Path(__file__).resolve().parents[1] / "data" / "bodies" / "size_chart.csv"
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
        try:
            cm = {k: float(v) / 100 for k, v in row.items() if k.endswith("_cm")}
            ratio = {k: float(v) for k, v in row.items() if k.endswith(("_ratio", "_share"))}
            chart = SizeChart(
                name=row["size"],
                girth={lm: cm[f"{lm}_cm"] for lm in LANDMARKS},
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
    """Points x, y (each shaped like ``angle``) of |x|^p + |y|^p = 1 (p = `EXPONENT`) at
    parameter angles (rad): x = sgn(cos t) |cos t|^(2/p), y likewise with sin t."""
    c, s = np.cos(angle), np.sin(angle)
    return np.sign(c) * np.abs(c) ** (2 / EXPONENT), np.sign(s) * np.abs(s) ** (2 / EXPONENT)


def _unit_ring(angle: NDArray, depth: float, front: float) -> NDArray:
    """Superellipse ring of half-width 1 (x) and total depth 2*depth split front/back."""
    x, y = superellipse(angle)
    y = np.where(y > 0, y * 2 * depth * front, y * 2 * depth * (1 - front))
    return np.stack([x, y], axis=1)


def _perimeter(xy: NDArray) -> float:
    return float(np.sum(np.linalg.norm(np.roll(xy, -1, axis=0) - xy, axis=1)))


def torso_mesh(
    chart: SizeChart, around: int = 128, rings: int = 120
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices ((V, 3), m, z up, front towards +y) and outward faces ((F, 3)) of the torso."""
    if around < 8 or rings < 8:
        raise InputError("the torso needs at least 8 points around and 8 rings", field="torso")
    girth, depth, front = _profiles(chart)
    bottom, top = chart.height["bottom"], chart.height["top"]
    heights = np.union1d(np.linspace(bottom, top, rings), [chart.height[k] for k in LANDMARKS])
    angle = 2 * np.pi * np.arange(around) / around
    ring_list = []
    for z in heights:
        unit = _unit_ring(angle, float(depth(z)), float(front(z)))
        xy = unit * (float(girth(z)) / _perimeter(unit))
        ring_list.append(np.column_stack([xy, np.full(around, z)]))
    side = np.concatenate(ring_list)
    centres = np.array([[0.0, 0.0, bottom], [0.0, 0.0, top]])
    # keep the cap centres inside the rings (rings are not centred on the axis front/back)
    centres[0, :2] = ring_list[0][:, :2].mean(axis=0)
    centres[1, :2] = ring_list[-1][:, :2].mean(axis=0)
    vertices = np.concatenate([side, centres])
    n_rings = len(heights)
    i = np.arange(around)
    i1 = (i + 1) % around
    faces = []
    for r in range(n_rings - 1):
        a, b = r * around + i, r * around + i1
        c, d = (r + 1) * around + i, (r + 1) * around + i1
        faces += [np.stack([a, b, d], axis=1), np.stack([a, d, c], axis=1)]
    low, high = len(side), len(side) + 1
    faces.append(np.stack([np.full(around, low), i1, i], axis=1))
    last = (n_rings - 1) * around
    faces.append(np.stack([np.full(around, high), last + i, last + i1], axis=1))
    return vertices, np.concatenate(faces).astype(np.int64)
