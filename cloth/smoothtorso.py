"""The parametric torso as a smooth surface: exact closest points, normals and curvature.

The torso of `cloth.torso` is defined by smooth profiles; its mesh is one sampling of it. On the
mesh, frictionless contact has the mesh's edges: the body's reaction jumps from face to face, a
tensioned ring rests on edges, and Newton's active set settles slowly there (docs/solvers.md).
This body is the surface itself,

    G(x, y, z) = |x / a(z)|^p + |y / b(y, z)|^p - 1 = 0,   b = b_front (y >= 0), b_back (y < 0)

(p = `cloth.torso.EXPONENT`; a, b_front, b_back in m): each section is the superellipse of the
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

import logging
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline

from cloth.bodies import SECTION_POINTS, _Analytic, _points
from cloth.torso import EXPONENT, SizeChart, _profiles, superellipse

log = logging.getLogger(__name__)

#: Heights at which the section profiles are sampled for the splines (0.3 mm apart on 0.5 m).
PROFILE_SAMPLES = 1601
#: Closest-point Newton: iteration cap and convergence threshold on the move, m.
PROJECTION_ITERATIONS = 25
PROJECTION_TOLERANCE = 1e-13


def _section(angle: NDArray, a: ArrayLike, front: ArrayLike, back: ArrayLike):
    """Points x, y (m) of sections of half-width ``a``, front depth ``front`` and back depth
    ``back`` (m; broadcast against ``angle``) at parameter angles (rad)."""
    x, y = superellipse(angle)
    return a * x, np.where(y > 0, y * front, y * back)


def _unit_perimeter(depth: NDArray, front: NDArray, count: int) -> NDArray:
    """Perimeters ((Z,)) of unit rings (half-width 1) of `cloth.torso._unit_ring` by polygons
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
class SmoothTorso(_Analytic):
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
        object.__setattr__(
            self,
            "_splines",
            tuple(CubicSpline(z, v) for v in (scale, scale * 2 * d * f, scale * 2 * d * (1 - f))),
        )

    # -- the section profiles and the implicit function ------------------------------------

    def _profile(self, z: NDArray, derivative: int) -> NDArray:
        """(3, P): a, b_front, b_back (m) or their z derivatives at heights z; continued by
        their tangent lines below the bottom and above the top (the surface stays C^1)."""
        zc = np.clip(z, self.bottom, self.top)
        if derivative == 2:
            inside = (z > self.bottom) & (z < self.top)
            return np.where(inside, np.stack([s(zc, 2) for s in self._splines]), 0.0)
        slope = np.stack([s(zc, 1) for s in self._splines])
        if derivative == 1:
            return slope
        return np.stack([s(zc) for s in self._splines]) + slope * (z - zc)

    def _implicit(self, q: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """G ((P,)), its gradient ((P, 3), 1/m) and Hessian ((P, 3, 3), 1/m^2) at q."""
        p = EXPONENT
        x, y, z = q[:, 0], q[:, 1], q[:, 2]
        (a, bf, bb), (da, dbf, dbb), (dda, ddbf, ddbb) = (self._profile(z, k) for k in (0, 1, 2))
        front = y >= 0
        b, db, ddb = np.where(front, bf, bb), np.where(front, dbf, dbb), np.where(front, ddbf, ddbb)
        gradient = np.empty((len(q), 3))
        hessian = np.zeros((len(q), 3, 3))
        value = -np.ones(len(q))
        for axis, s, ds, dds in ((0, a, da, dda), (1, b, db, ddb)):
            u = q[:, axis] / s
            au, sg = np.abs(u), np.sign(u)
            power = au**p
            value += power
            gradient[:, axis] = p * au ** (p - 1) * sg / s
            hessian[:, axis, axis] = p * (p - 1) * au ** (p - 2) / s**2
            hessian[:, axis, 2] = hessian[:, 2, axis] = -(p**2) * au ** (p - 1) * sg * ds / s**2
            hessian[:, 2, 2] += p * power * ((p + 1) * ds**2 / s**2 - dds / s)
        gradient[:, 2] = -p * (np.abs(x / a) ** p * da / a + np.abs(y / b) ** p * db / b)
        return value, gradient, hessian

    def _level(self, p: NDArray) -> tuple[NDArray, NDArray]:
        """(|x/a|^p + |y/b|^p)^(1/p) at points p ((P,), < 1 inside, 1 on the surface, the
        factor by which p lies outside along the horizontal ray from the axis) and a (m)."""
        a, bf, bb = self._profile(p[:, 2], 0)
        x, y = p[:, 0], p[:, 1]
        b = np.where(y >= 0, bf, bb)
        return (np.abs(x / a) ** EXPONENT + np.abs(y / b) ** EXPONENT) ** (1 / EXPONENT), a

    def _radial(self, p: NDArray) -> NDArray:
        """The surface point on the horizontal ray from the axis through p (a first guess)."""
        level, a = self._level(p)
        x, y = p[:, 0], p[:, 1]
        on_axis = level < 1e-12
        t = 1.0 / np.where(on_axis, 1.0, level)
        q = np.column_stack([x * t, y * t, p[:, 2]])
        q[on_axis, 0], q[on_axis, 1] = a[on_axis], 0.0
        return q

    def closest(self, points: ArrayLike) -> NDArray[np.float64]:
        """Closest points ((P, 3), m) on the lateral surface: Newton on the stationarity
        conditions q - p + mu grad G(q) = 0, G(q) = 0, from the radial guess (exact to rounding
        near the surface; for far points that do not settle, a near surface point)."""
        p = _points(points)
        q = self._radial(p)
        _, g, _ = self._implicit(q)
        mu = -np.einsum("ij,ij->i", q - p, g) / np.einsum("ij,ij->i", g, g)
        active = np.arange(len(p))
        for _ in range(PROJECTION_ITERATIONS):
            value, g, h = self._implicit(q[active])
            lhs = np.zeros((len(active), 4, 4))
            lhs[:, :3, :3] = np.eye(3) + mu[active, None, None] * h
            lhs[:, :3, 3] = lhs[:, 3, :3] = g
            rhs = -np.concatenate(
                [q[active] - p[active] + mu[active, None] * g, value[:, None]], axis=1
            )
            step = np.linalg.solve(lhs, rhs[..., None])[..., 0]
            q[active] += step[:, :3]
            mu[active] += step[:, 3]
            moved = np.linalg.norm(step[:, :3], axis=1)
            active = active[moved > PROJECTION_TOLERANCE]
            if active.size == 0:
                break
        else:
            # far from the body (a line-search trial cm away, or deep inside near the axis) the
            # stationary point need not be unique: fall back to the surface point on the
            # horizontal ray through the last iterate (on the surface, near)
            guess = self._radial(q[active])
            first = self._radial(p[active])
            nearer = np.linalg.norm(guess - p[active], axis=1) <= np.linalg.norm(
                first - p[active], axis=1
            )
            q[active] = np.where(nearer[:, None], guess, first)
            log.debug("closest point: %d far points by the radial fallback", active.size)
        return q

    # -- the Body protocol -------------------------------------------------------------------

    def query(self, points: ArrayLike):
        p = _points(points)
        q = self.closest(p)
        _, g, _ = self._implicit(q)
        normal = g / np.linalg.norm(g, axis=1, keepdims=True)
        distance = np.linalg.norm(p - q, axis=1)
        return np.where(self._level(p)[0] < 1.0, -distance, distance), q, normal

    def hessian(self, surface_points: ArrayLike) -> NDArray[np.float64]:
        """Hessian of the signed distance at surface points ((P, 3, 3), 1/m): P H_G P / |grad G|
        with P = I - n n^T (the shape operator, in 3D)."""
        _, g, h = self._implicit(_points(surface_points))
        length = np.linalg.norm(g, axis=1)
        n = g / length[:, None]
        proj = np.eye(3) - n[:, :, None] * n[:, None, :]
        return np.einsum("pij,pjk,pkl->pil", proj, h, proj) / length[:, None, None]

    def _polygon(self, z: float) -> NDArray[np.float64]:
        t = 2 * np.pi * np.arange(SECTION_POINTS) / SECTION_POINTS
        a, front, back = self._profile(np.array([z]), 0)[:, 0]
        return np.column_stack(_section(t, a, front, back))

    def _perimeter(self, z: float) -> float:
        return float(self._girth(z))
