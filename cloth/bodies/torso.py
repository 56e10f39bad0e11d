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
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline, PchipInterpolator

from cloth.bodies.base import SECTION_POINTS, AnalyticBody
from cloth.bodies.implicit import ImplicitBody
from cloth.errors import InputError

log = logging.getLogger(__name__)

EXPONENT = 2.4
#: Heights at which the section profiles are sampled for the splines (0.3 mm apart on 0.5 m).
PROFILE_SAMPLES = 1601
DEFAULT_CHART = Path(__file__).resolve().parents[2] / "data" / "bodies" / "size_chart.csv"
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


def _ring_heights(bottom: float, top: float, rings: int, marks: list[float]) -> NDArray:
    """``rings`` heights (m) from ``bottom`` to ``top`` through every landmark in ``marks``,
    as evenly spaced as that allows: each gap between landmarks takes rings in turn, the one
    whose spacing is widest first (all the landmarks, if there are more than ``rings``)."""
    anchors = np.unique(np.clip([bottom, top, *marks], bottom, top))
    gaps = np.diff(anchors)
    inside = np.zeros(gaps.size, dtype=int)
    for _ in range(max(rings - anchors.size, 0)):
        inside[np.argmax(gaps / (inside + 1))] += 1
    parts = [
        np.linspace(low, low + gap, n + 1, endpoint=False)
        for low, gap, n in zip(anchors, gaps, inside, strict=False)
    ]
    return np.concatenate([*parts, anchors[-1:]])


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
    heights = _ring_heights(bottom, top, rings, [chart.height[k] for k in LANDMARKS])
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
        # quads split along alternate diagonals (a checkerboard): the same diagonal everywhere
        # makes the creases run in helices, a handedness the torso does not have, and a
        # frictionless garment on a coarse mesh turned about the body without end
        other = (r + i) % 2 == 1
        first = np.where(other[:, None], np.stack([a, b, c], axis=1), np.stack([a, b, d], axis=1))
        second = np.where(other[:, None], np.stack([b, d, c], axis=1), np.stack([a, d, c], axis=1))
        faces += [first, second]
    low, high = len(side), len(side) + 1
    faces.append(np.stack([np.full(around, low), i1, i], axis=1))
    last = (n_rings - 1) * around
    faces.append(np.stack([np.full(around, high), last + i, last + i1], axis=1))
    return vertices, np.concatenate(faces).astype(np.int64)


def _section(angle: NDArray, a: ArrayLike, front: ArrayLike, back: ArrayLike):
    """Points x, y (m) of sections of half-width ``a``, front depth ``front`` and back depth
    ``back`` (m; broadcast against ``angle``) at parameter angles (rad)."""
    x, y = superellipse(angle)
    return a * x, np.where(y > 0, y * front, y * back)


def _unit_perimeter(depth: NDArray, front: NDArray, count: int) -> NDArray:
    """Perimeters ((Z,)) of unit rings (half-width 1) of `cloth.bodies.torso._unit_ring` by polygons
    of ``count`` and 2 ``count`` points, Richardson-extrapolated (the error is O(h^2))."""
    values = []
    for k in (count, 2 * count):
        angle = 2 * np.pi * np.arange(k) / k
        x, y = _section(
            angle, 1.0, (2 * depth * front)[:, None], (2 * depth * (1 - front))[:, None]
        )
        x = np.broadcast_to(x, y.shape)
        values.append(np.hypot(np.roll(x, -1, axis=1) - x, np.roll(y, -1, axis=1) - y).sum(axis=1))
    return (4 * values[1] - values[0]) / 3


@dataclass(frozen=True, eq=False)
class SmoothTorso(ImplicitBody, AnalyticBody):
    """The smooth lateral surface of the parametric torso of ``chart`` (heights in m)."""

    chart: SizeChart
    bottom: float = field(init=False)
    top: float = field(init=False)

    def __post_init__(self) -> None:
        bottom, top = self.chart.height["bottom"], self.chart.height["top"]
        object.__setattr__(self, "bottom", float(bottom))
        object.__setattr__(self, "top", float(top))
        girth, depth, front = _profiles(self.chart)
        z = np.linspace(bottom, top, PROFILE_SAMPLES)
        d, f = depth(z), front(z)
        scale = girth(z) / _unit_perimeter(d, f, 1024)
        object.__setattr__(self, "_girth", girth)
        profiles = np.column_stack([scale, scale * 2 * d * f, scale * 2 * d * (1 - f)])
        spline = CubicSpline(z, profiles)  # a, b_front, b_back together
        # its pieces' coefficients, (pieces, 4 powers, 3 profiles), highest power first
        object.__setattr__(self, "_pieces", np.ascontiguousarray(spline.c.transpose(1, 0, 2)))
        object.__setattr__(self, "_knots", spline.x)

    # -- the section profiles and the implicit function ------------------------------------

    def _profile(self, z: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """a, b_front, b_back (m), their z derivatives (1) and second derivatives (1/m) at
        heights z ((P,)), each (3, P); continued by their tangent lines below the bottom and
        above the top (the surface stays C^1; the second derivatives are 0 there). One look-up
        of the spline piece (the samples are evenly spaced) and Horner's rule for all three."""
        zc = np.clip(z, self.bottom, self.top)
        knots, pieces = self._knots, self._pieces
        spacing = (self.top - self.bottom) / (len(knots) - 1)
        index = np.clip(((zc - self.bottom) / spacing).astype(np.intp), 0, len(pieces) - 1)
        t = (zc - knots[index])[:, None]
        c = pieces[index]  # (P, 4, 3)
        value = ((c[:, 0] * t + c[:, 1]) * t + c[:, 2]) * t + c[:, 3]
        slope = (3.0 * c[:, 0] * t + 2.0 * c[:, 1]) * t + c[:, 2]
        inside = ((z > self.bottom) & (z < self.top))[:, None]
        bend = np.where(inside, 6.0 * c[:, 0] * t + 2.0 * c[:, 1], 0.0)
        value += slope * (z - zc)[:, None]
        return value.T, slope.T, bend.T

    def implicit(self, q: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """G ((P,)), its gradient ((P, 3), 1/m) and Hessian ((P, 3, 3), 1/m^2) at q."""
        p = EXPONENT
        x, y, z = q[:, 0], q[:, 1], q[:, 2]
        (a, bf, bb), (da, dbf, dbb), (dda, ddbf, ddbb) = self._profile(z)
        front = y >= 0
        b, db, ddb = np.where(front, bf, bb), np.where(front, dbf, dbb), np.where(front, ddbf, ddbb)
        gradient = np.empty((len(q), 3))
        hessian = np.zeros((len(q), 3, 3))
        value = -np.ones(len(q))
        for axis, s, ds, dds in ((0, a, da, dda), (1, b, db, ddb)):
            u = q[:, axis] / s
            au, sg = np.abs(u), np.sign(u)
            second = au ** (p - 2)  # one power; the others from it (p > 2: 0 at u = 0)
            first = second * au
            power = first * au
            value += power
            gradient[:, axis] = p * first * sg / s
            hessian[:, axis, axis] = p * (p - 1) * second / s**2
            hessian[:, axis, 2] = hessian[:, 2, axis] = -(p**2) * first * sg * ds / s**2
            hessian[:, 2, 2] += p * power * ((p + 1) * ds**2 / s**2 - dds / s)
        gradient[:, 2] = -p * (np.abs(x / a) ** p * da / a + np.abs(y / b) ** p * db / b)
        return value, gradient, hessian

    def _level(self, p: NDArray) -> tuple[NDArray, NDArray]:
        """(|x/a|^p + |y/b|^p)^(1/p) at points p ((P,), < 1 inside, 1 on the surface, the
        factor by which p lies outside along the horizontal ray from the axis) and a (m)."""
        a, bf, bb = self._profile(p[:, 2])[0]
        x, y = p[:, 0], p[:, 1]
        b = np.where(y >= 0, bf, bb)
        return (np.abs(x / a) ** EXPONENT + np.abs(y / b) ** EXPONENT) ** (1 / EXPONENT), a

    def locate(self, p: NDArray) -> tuple[NDArray, NDArray[np.bool_]]:
        """The surface point on the horizontal ray from the axis through p (a first guess), and
        whether p lies outside (its level is at least 1)."""
        level, a = self._level(p)
        x, y = p[:, 0], p[:, 1]
        on_axis = level < 1e-12
        t = 1.0 / np.where(on_axis, 1.0, level)
        q = np.column_stack([x * t, y * t, p[:, 2]])
        q[on_axis, 0], q[on_axis, 1] = a[on_axis], 0.0
        return q, level >= 1.0

    # -- the Body protocol (queries from `ImplicitBody`) -------------------------------------

    def _polygon(self, z: float) -> NDArray[np.float64]:
        t = 2 * np.pi * np.arange(SECTION_POINTS) / SECTION_POINTS
        a, front, back = self._profile(np.array([z]))[0][:, 0]
        return np.column_stack(_section(t, a, front, back))

    def _perimeter(self, z: float) -> float:
        return float(self._girth(z))
