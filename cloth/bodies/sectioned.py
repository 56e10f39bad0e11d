"""Bodies of horizontal sections: superellipses along a vertical axis, from smooth profiles.

Each cross-section at height z is the superellipse |x/a|^p + |y/b|^p = 1 with half-width a(z),
front depth b_front(z) (y > 0) and back depth b_back(z) (y < 0); p is the body's exponent (2
an ellipse, larger towards a rounded rectangle). The parametric torso (`cloth.bodies.torso`)
and leg (`cloth.bodies.leg`) are such bodies: each gives its girth, depth ratio and front
share of the depth along the height as monotone cubic (PCHIP) profiles through its chart's
measuring points (smooth, no overshoot), and `SectionedBody` scales each section so that its
perimeter is the girth there.

The surface (`SectionedBody`):

    G(x, y, z) = |x / a(z)|^p + |y / b(y, z)|^p - 1 = 0,   b = b_front (y >= 0), b_back (y < 0)

in m. It is C^1 everywhere and its curvature is continuous around (|y|^p has two continuous
derivatives at y = 0 for p >= 2), so the closed-form contact path of the Newton solver applies:
one constraint per node, with the curvature term that makes sliding exact.

Profiles a(z), b_front(z), b_back(z) are cubic splines (C2) through `PROFILE_SAMPLES` heights of
the PCHIP profiles; below the bottom and above the top they continue along their tangents (caps
are ignored, as on the other closed-form bodies).

The mesh (`ring_mesh`): rings of the sections at given heights, quads split in a checkerboard
of diagonals, flat caps; each ring scaled so that its polygon's perimeter is the girth.

Shapes and units: points (P, 3) m; distances (P,) m, positive outside; normals unit, outward;
the Hessian of the signed distance (P, 3, 3) in 1/m.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline

from cloth.bodies.base import SECTION_POINTS, AnalyticBody
from cloth.bodies.implicit import ImplicitBody

#: Heights at which the section profiles are sampled for the splines (0.3 mm apart on 0.5 m).
PROFILE_SAMPLES = 1601

#: A profile along the height: heights (m) -> values.
Profile = Callable[[ArrayLike], NDArray[np.float64]]


def superellipse(angle: NDArray, exponent: float) -> tuple[NDArray, NDArray]:
    """Points x, y (each shaped like ``angle``) of |x|^p + |y|^p = 1 (p = ``exponent``) at
    parameter angles (rad): x = sgn(cos t) |cos t|^(2/p), y likewise with sin t."""
    c, s = np.cos(angle), np.sin(angle)
    return np.sign(c) * np.abs(c) ** (2 / exponent), np.sign(s) * np.abs(s) ** (2 / exponent)


def unit_ring(angle: NDArray, depth: float, front: float, exponent: float) -> NDArray:
    """Superellipse ring of half-width 1 (x) and total depth 2*depth split front/back."""
    x, y = superellipse(angle, exponent)
    y = np.where(y > 0, y * 2 * depth * front, y * 2 * depth * (1 - front))
    return np.stack([x, y], axis=1)


def perimeter(xy: NDArray) -> float:
    return float(np.sum(np.linalg.norm(np.roll(xy, -1, axis=0) - xy, axis=1)))


def section(angle: NDArray, a: ArrayLike, front: ArrayLike, back: ArrayLike, exponent: float):
    """Points x, y (m) of sections of half-width ``a``, front depth ``front`` and back depth
    ``back`` (m; broadcast against ``angle``) at parameter angles (rad)."""
    x, y = superellipse(angle, exponent)
    return a * x, np.where(y > 0, y * front, y * back)


def unit_perimeter(depth: NDArray, front: NDArray, count: int, exponent: float) -> NDArray:
    """Perimeters ((Z,)) of unit rings (half-width 1, `unit_ring`) by polygons of ``count``
    and 2 ``count`` points, Richardson-extrapolated (the error is O(h^2))."""
    values = []
    for k in (count, 2 * count):
        angle = 2 * np.pi * np.arange(k) / k
        x, y = section(
            angle, 1.0, (2 * depth * front)[:, None], (2 * depth * (1 - front))[:, None], exponent
        )
        x = np.broadcast_to(x, y.shape)
        values.append(np.hypot(np.roll(x, -1, axis=1) - x, np.roll(y, -1, axis=1) - y).sum(axis=1))
    return (4 * values[1] - values[0]) / 3


def ring_heights(bottom: float, top: float, rings: int, marks: list[float]) -> NDArray:
    """``rings`` heights (m) from ``bottom`` to ``top`` through every measuring point in ``marks``,
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


def ring_mesh(
    heights: NDArray,
    around: int,
    girth: Profile,
    depth: Profile,
    front: Profile,
    exponent: float,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices ((V, 3), m) and outward faces ((F, 3)) of the sections at ``heights`` (m,
    increasing), ``around`` points each, every ring's polygon perimeter the girth there; quads
    split in a checkerboard of diagonals (with ``around`` a multiple of 4 the mesh is
    left-right symmetric), flat caps."""
    angle = 2 * np.pi * np.arange(around) / around
    ring_list = []
    for z in heights:
        unit = unit_ring(angle, float(depth(z)), float(front(z)), exponent)
        xy = unit * (float(girth(z)) / perimeter(unit))
        ring_list.append(np.column_stack([xy, np.full(around, z)]))
    side = np.concatenate(ring_list)
    # the cap centres inside the rings (rings are not centred on the axis front/back)
    centres = np.array(
        [
            [*ring_list[0][:, :2].mean(axis=0), heights[0]],
            [*ring_list[-1][:, :2].mean(axis=0), heights[-1]],
        ]
    )
    vertices = np.concatenate([side, centres])
    n_rings = len(heights)
    i = np.arange(around)
    i1 = (i + 1) % around
    faces = []
    for r in range(n_rings - 1):
        a, b = r * around + i, r * around + i1
        c, d = (r + 1) * around + i, (r + 1) * around + i1
        # quads split along alternate diagonals (a checkerboard): the same diagonal everywhere
        # makes the creases run in helices, a handedness the body does not have, and a
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


class SectionedBody(ImplicitBody, AnalyticBody):
    """The smooth lateral surface of superellipse sections (module docstring). Subclasses call
    `_build` once with their profiles."""

    bottom: float
    top: float
    exponent: float
    #: The sections' centres lean forward: y_c(z) = lean (z - lean_origin) (1; 0 upright).
    lean: float = 0.0
    lean_origin: float = 0.0

    def _build(
        self,
        bottom: float,
        top: float,
        girth: Profile,
        depth: Profile,
        front: Profile,
        exponent: float,
        lean: float = 0.0,
        lean_origin: float = 0.0,
    ) -> None:
        """Sample the profiles (girth m, depth/width ratio, front share of the depth) into the
        splines of a, b_front and b_back between ``bottom`` and ``top`` (m); the centres lean
        by ``lean`` (dy/dz) from the height ``lean_origin`` (m)."""
        object.__setattr__(self, "bottom", float(bottom))
        object.__setattr__(self, "top", float(top))
        object.__setattr__(self, "exponent", float(exponent))
        object.__setattr__(self, "lean", float(lean))
        object.__setattr__(self, "lean_origin", float(lean_origin))
        z = np.linspace(bottom, top, PROFILE_SAMPLES)
        d, f = depth(z), front(z)
        scale = girth(z) / unit_perimeter(d, f, 1024, exponent)
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
        p = self.exponent
        z = q[:, 2]
        centred = self._centred(q)  # x, y - y_c(z): the section's own coordinates
        (a, bf, bb), (da, dbf, dbb), (dda, ddbf, ddbb) = self._profile(z)
        front = centred[:, 1] >= 0
        b, db, ddb = np.where(front, bf, bb), np.where(front, dbf, dbb), np.where(front, ddbf, ddbb)
        gradient = np.zeros((len(q), 3))
        hessian = np.zeros((len(q), 3, 3))
        value = -np.ones(len(q))
        # u = (coordinate - centre(z)) / s(z); k = the centre's slope (0 for x; the lean for y)
        for axis, s, ds, dds, k in ((0, a, da, dda, 0.0), (1, b, db, ddb, self.lean)):
            u = centred[:, axis] / s
            au, sg = np.abs(u), np.sign(u)
            second = au ** (p - 2)  # one power; the others from it (p > 2: 0 at u = 0)
            first = second * au
            power = first * au
            value += power
            gradient[:, axis] = p * first * sg / s
            gradient[:, 2] -= p * power * ds / s
            hessian[:, axis, axis] = p * (p - 1) * second / s**2
            hessian[:, axis, 2] = hessian[:, 2, axis] = -(p**2) * first * sg * ds / s**2
            hessian[:, 2, 2] += p * power * ((p + 1) * ds**2 / s**2 - dds / s)
            if k:
                gradient[:, 2] -= p * first * sg * k / s
                hessian[:, axis, 2] -= p * (p - 1) * second * k / s**2
                hessian[:, 2, axis] = hessian[:, axis, 2]
                hessian[:, 2, 2] += p * (p - 1) * second * k**2 / s**2
                hessian[:, 2, 2] += 2 * p**2 * k * first * sg * ds / s**2
        return value, gradient, hessian

    def _centred(self, q: NDArray) -> NDArray:
        """(P, 2): points' x and y less their height's section centre (0, y_c(z))."""
        out = q[:, :2].copy()
        if self.lean:
            out[:, 1] -= self.lean * (q[:, 2] - self.lean_origin)
        return out

    def _level(self, p: NDArray) -> tuple[NDArray, NDArray]:
        """(|x/a|^p + |y/b|^p)^(1/p) at points p ((P,), < 1 inside, 1 on the surface, the
        factor by which p lies outside along the horizontal ray from the axis) and a (m)."""
        a, bf, bb = self._profile(p[:, 2])[0]
        x, y = self._centred(p).T
        b = np.where(y >= 0, bf, bb)
        p = self.exponent
        return (np.abs(x / a) ** p + np.abs(y / b) ** p) ** (1 / p), a

    def locate(self, p: NDArray) -> tuple[NDArray, NDArray[np.bool_]]:
        """The surface point on the horizontal ray from the axis through p (a first guess), and
        whether p lies outside (its level is at least 1)."""
        level, a = self._level(p)
        x, y = self._centred(p).T
        on_axis = level < 1e-12
        t = 1.0 / np.where(on_axis, 1.0, level)
        q = np.column_stack([x * t, y * t, p[:, 2]])
        q[on_axis, 0], q[on_axis, 1] = a[on_axis], 0.0
        if self.lean:
            q[:, 1] += self.lean * (p[:, 2] - self.lean_origin)
        return q, level >= 1.0

    # -- the Body protocol (queries from `ImplicitBody`) -------------------------------------

    def _polygon(self, z: float) -> NDArray[np.float64]:
        t = 2 * np.pi * np.arange(SECTION_POINTS) / SECTION_POINTS
        a, front, back = self._profile(np.array([z]))[0][:, 0]
        x, y = section(t, a, front, back, self.exponent)
        return np.column_stack([x, y + self.lean * (z - self.lean_origin)])

    def _perimeter(self, z: float) -> float:
        return float(self._girth(z))
