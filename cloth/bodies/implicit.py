"""Bodies bounded by a smooth implicit surface G(q) = 0: exact closest points and curvature.

A subclass gives G with its gradient and Hessian (`ImplicitBody.implicit`), and for a set of
points a first guess of their closest points and which of them are outside
(`ImplicitBody.locate`, one look at the points for both); this base turns them into the
`cloth.bodies.base.Body` queries:

* closest points by Newton on the stationarity conditions q - p + mu grad G(q) = 0, G(q) = 0
  (a 4 x 4 system per point; quadratic, exact to rounding near the surface);
* the outward normal grad G / |grad G| at the closest point;
* the Hessian of the signed distance at surface points, P H_G P / |grad G| with P = I - n n^T
  (the shape operator in 3D): Newton's curvature term, which makes sliding on the body exact.

Shapes and units: points (P, 3) m; distances (P,) m, positive outside; normals unit, outward;
Hessians (P, 3, 3) 1/m.
"""

from __future__ import annotations

import logging

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.bodies.base import as_points

log = logging.getLogger(__name__)

#: Closest-point Newton: iteration cap and convergence threshold on the move, m.
PROJECTION_ITERATIONS = 25
PROJECTION_TOLERANCE = 1e-13


def _kkt_step(a: NDArray, g: NDArray, r: NDArray, c: NDArray) -> NDArray:
    """Per point, the solution (dq, dmu) ((P, 4)) of [[A, g], [g^T, 0]] [dq; dmu] = [r; c]
    for A ((P, 3, 3), symmetric), g and r ((P, 3)) and c ((P,)): dq = A^-1 (r - g dmu) with
    dmu = (g . A^-1 r - c) / (g . A^-1 g), A^-1 by its adjugate (closed form; with LAPACK's
    batched 4 x 4 solves instead, a query of 100k points near the torso took 0.48 s, not 0.35).
    NaN where the system is singular (a point where grad G vanishes) or overflows (a trial point
    metres off a fitted surface, whose polynomial pieces grow as its cube): the caller's
    fallback takes those points, and nothing is printed."""
    a00, a01, a02 = a[:, 0, 0], a[:, 0, 1], a[:, 0, 2]
    a11, a12, a22 = a[:, 1, 1], a[:, 1, 2], a[:, 2, 2]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        c00, c01, c02 = a11 * a22 - a12 * a12, a12 * a02 - a01 * a22, a01 * a12 - a11 * a02
        c11, c12, c22 = a00 * a22 - a02 * a02, a02 * a01 - a00 * a12, a00 * a11 - a01 * a01
        det = a00 * c00 + a01 * c01 + a02 * c02

        def inverse_times(v: NDArray) -> NDArray:
            x, y, z = v[:, 0], v[:, 1], v[:, 2]
            return (
                np.column_stack(
                    [
                        c00 * x + c01 * y + c02 * z,
                        c01 * x + c11 * y + c12 * z,
                        c02 * x + c12 * y + c22 * z,
                    ]
                )
                / det[:, None]
            )

        ar, ag = inverse_times(r), inverse_times(g)
        dmu = (np.einsum("ij,ij->i", g, ar) - c) / np.einsum("ij,ij->i", g, ag)
        step = np.column_stack([ar - ag * dmu[:, None], dmu])
    return np.where(np.isfinite(step), step, np.nan)


class ImplicitBody:
    """Closest points, normals and curvature of the surface G = 0 (G < 0 inside)."""

    def implicit(self, q: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """G ((P,)), its gradient ((P, 3)) and Hessian ((P, 3, 3)) at points q ((P, 3), m)."""
        raise NotImplementedError

    def locate(self, p: NDArray) -> tuple[NDArray, NDArray[np.bool_]]:
        """For points p ((P, 3), m): a surface point near the closest one to each (Newton's
        start, (P, 3), m) and which points are outside the body ((P,), on the surface counts),
        from one look at p."""
        raise NotImplementedError

    def fallback(self, p: NDArray, q: NDArray) -> NDArray:
        """Surface points ((P, 3), m) for points p whose Newton iteration (last iterate q) did
        not settle: far from the body, where the stationary point need not be unique. Default:
        the nearer of the start point and the start from the last iterate."""
        guess, first = self.locate(q)[0], self.locate(p)[0]
        nearer = np.linalg.norm(guess - p, axis=1) <= np.linalg.norm(first - p, axis=1)
        return np.where(nearer[:, None], guess, first)

    def closest(self, points: ArrayLike) -> NDArray[np.float64]:
        """Closest points ((P, 3), m) on the surface: Newton on q - p + mu grad G(q) = 0,
        G(q) = 0 from the start of `locate` (exact to rounding near the surface; `fallback`
        where it does not settle)."""
        p = as_points(points)
        return self._newton(p, self.locate(p)[0])

    def _newton(self, p: NDArray, q: NDArray) -> NDArray:
        """The closest-point Newton iteration of `closest` from start points q (updated)."""
        if len(p) == 0:
            return q
        _, g, _ = self.implicit(q)
        mu = -np.einsum("ij,ij->i", q - p, g) / np.einsum("ij,ij->i", g, g)
        active = np.arange(len(p))
        failed = []  # singular systems (grad G = 0): to the fallback
        for _ in range(PROJECTION_ITERATIONS):
            value, g, h = self.implicit(q[active])
            block = np.eye(3) + mu[active, None, None] * h
            step = _kkt_step(block, g, p[active] - q[active] - mu[active, None] * g, -value)
            ok = np.all(np.isfinite(step), axis=1)
            failed.append(active[~ok])
            step[~ok] = 0.0
            q[active] += step[:, :3]
            mu[active] += step[:, 3]
            moved = np.linalg.norm(step[:, :3], axis=1)
            active = active[ok & (moved > PROJECTION_TOLERANCE)]
            if active.size == 0:
                break
        rest = np.concatenate([*failed, active])
        if rest.size:
            # far from the body (a line-search trial cm away, or deep inside) the stationary
            # point need not be unique, or the iteration met a point with no gradient
            q[rest] = self.fallback(p[rest], q[rest])
            log.debug("closest point: %d far points by the fallback", rest.size)
        return q

    def query(self, points: ArrayLike):
        p = as_points(points)
        start, outside = self.locate(p)
        q = self._newton(p, start)
        _, g, _ = self.implicit(q)
        with np.errstate(invalid="ignore", divide="ignore"):  # NaN points (a folded trial)
            normal = g / np.linalg.norm(g, axis=1, keepdims=True)
        distance = np.linalg.norm(p - q, axis=1)
        return np.where(outside, distance, -distance), q, normal

    def hessian(self, surface_points: ArrayLike) -> NDArray[np.float64]:
        """Hessian of the signed distance at surface points ((P, 3, 3), 1/m): P H_G P / |grad G|
        with P = I - n n^T (the shape operator, in 3D)."""
        _, g, h = self.implicit(as_points(surface_points))
        length = np.linalg.norm(g, axis=1)
        n = g / length[:, None]
        proj = np.eye(3) - n[:, :, None] * n[:, None, :]
        return proj @ h @ proj / length[:, None, None]

    def curvature(self, surface_points: ArrayLike) -> tuple[NDArray, NDArray]:
        """Principal curvatures ((P,), (P,), 1/m; k1 >= k2, positive where convex) at surface
        points: the two largest-magnitude eigenvalues of the distance Hessian."""
        eig = np.linalg.eigvalsh(self.hessian(surface_points))  # ascending; one is ~0 (normal)
        order = np.argsort(np.abs(eig), axis=1)
        pair = np.take_along_axis(eig, order[:, 1:], axis=1)
        return pair.max(axis=1), pair.min(axis=1)
