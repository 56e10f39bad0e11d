"""Closed-form bodies for validation: cylinder, elliptic cylinder, truncated cone about z.

Exact: distance to 1e-12 m (the ellipse by a bisection root solve converged to machine
precision), normals and the Hessian of the signed distance in closed form. Caps are ignored.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.bodies.base import (
    SECTION_POINTS,
    AnalyticBody,
    as_points,
    height_span,
    positive_length,
)


@dataclass(frozen=True)
class Cylinder(AnalyticBody):
    """Circular cylinder of ``radius`` (m) about the z axis, from ``bottom`` to ``top`` (m).

    Distances are to the lateral surface (caps ignored), exact.
    """

    radius: float
    bottom: float = 0.0
    top: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", positive_length(self.radius, "radius"))
        height_span(self.bottom, self.top)

    def query(self, points: ArrayLike):
        p = as_points(points)
        r = np.hypot(p[:, 0], p[:, 1])
        safe = np.where(r > 0, r, 1.0)
        radial = np.stack([p[:, 0] / safe, p[:, 1] / safe, np.zeros(len(p))], axis=1)
        radial[r == 0] = (1.0, 0.0, 0.0)
        closest = radial * self.radius
        closest[:, 2] = p[:, 2]
        return r - self.radius, closest, radial

    def _polygon(self, z: float) -> NDArray[np.float64]:
        t = 2 * np.pi * np.arange(SECTION_POINTS) / SECTION_POINTS
        return self.radius * np.stack([np.cos(t), np.sin(t)], axis=1)

    def hessian(self, surface_points: ArrayLike) -> NDArray[np.float64]:
        """Hessian of the signed distance at surface points ((P, 3, 3), m-1): (1/r) t t^T."""
        return _circumferential(as_points(surface_points), 1.0 / self.radius)

    def _perimeter(self, z: float) -> float:
        return 2 * np.pi * self.radius


def _circumferential(
    p: NDArray[np.float64], curvature, tx: NDArray | None = None, ty: NDArray | None = None
) -> NDArray[np.float64]:
    """kappa t t^T with t the horizontal tangent (default: perpendicular to the radius)."""
    if tx is None:
        tx, ty = p[:, 0], p[:, 1]
    t = np.stack([-ty, tx, np.zeros(len(p))], axis=1)
    t /= np.linalg.norm(t, axis=1)[:, None]
    return np.asarray(curvature)[..., None, None] * t[:, :, None] * t[:, None, :]


def _ellipse_root(r0: NDArray, z0: NDArray, z1: NDArray, g: NDArray) -> NDArray:
    """Root s of (r0 z0/(s+r0))^2 + (z1/(s+1))^2 = 1 by bisection (D. Eberly's bracket)."""
    n0 = r0 * z0
    s0 = z1 - 1.0
    s1 = np.where(g < 0, 0.0, np.hypot(n0, z1) - 1.0)
    for _ in range(1100):  # the bracket halves every step: converged to float64 well before
        s = 0.5 * (s0 + s1)
        if np.all((s == s0) | (s == s1)):
            break
        ratio = (n0 / (s + r0)) ** 2 + (z1 / (s + 1.0)) ** 2 - 1.0
        s0 = np.where(ratio > 0, s, s0)
        s1 = np.where(ratio > 0, s1, s)
    return 0.5 * (s0 + s1)


@dataclass(frozen=True)
class EllipticCylinder(AnalyticBody):
    """Elliptic cylinder x^2/a^2 + y^2/b^2 = 1 (semi-axes a along x, b along y, m) along z."""

    a: float
    b: float
    bottom: float = 0.0
    top: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", positive_length(self.a, "a"))
        object.__setattr__(self, "b", positive_length(self.b, "b"))
        height_span(self.bottom, self.top)

    def closest_xy(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Closest points on the ellipse to (P, 2) points, exact to rounding."""
        swap = self.a < self.b
        e0, e1 = (self.b, self.a) if swap else (self.a, self.b)
        pts = xy[:, ::-1] if swap else xy
        sign = np.where(pts < 0, -1.0, 1.0)
        y0, y1 = np.abs(pts[:, 0]), np.abs(pts[:, 1])
        x0, x1 = np.empty_like(y0), np.empty_like(y1)
        general = (y0 > 0) & (y1 > 0)
        z0, z1 = y0[general] / e0, y1[general] / e1
        g = z0**2 + z1**2 - 1.0
        r0 = (e0 / e1) ** 2
        s = _ellipse_root(np.full_like(z0, r0), z0, z1, g)
        x0[general] = r0 * y0[general] / (s + r0)
        x1[general] = y1[general] / (s + 1.0)
        on_minor = (y0 == 0) & ~general
        x0[on_minor], x1[on_minor] = 0.0, e1
        on_major = (y1 == 0) & (y0 > 0)
        numer, denom = e0 * y0[on_major], e0**2 - e1**2
        inside_focus = numer < denom
        with np.errstate(invalid="ignore", divide="ignore"):
            xde = np.where(inside_focus, numer / denom, 1.0)
        x0[on_major] = e0 * xde
        x1[on_major] = e1 * np.sqrt(np.clip(1.0 - xde**2, 0.0, None))
        out = np.stack([x0, x1], axis=1) * sign
        return out[:, ::-1] if swap else out

    def query(self, points: ArrayLike):
        p = as_points(points)
        q = self.closest_xy(p[:, :2])
        inside = (p[:, 0] / self.a) ** 2 + (p[:, 1] / self.b) ** 2 < 1.0
        distance = np.hypot(*(p[:, :2] - q).T) * np.where(inside, -1.0, 1.0)
        gradient = np.stack([q[:, 0] / self.a**2, q[:, 1] / self.b**2, np.zeros(len(p))], axis=1)
        normal = gradient / np.linalg.norm(gradient, axis=1)[:, None]
        return distance, np.column_stack([q, p[:, 2]]), normal

    def hessian(self, surface_points: ArrayLike) -> NDArray[np.float64]:
        """Hessian of the signed distance at surface points ((P, 3, 3), m-1): kappa t t^T."""
        p = as_points(surface_points)
        return _circumferential(
            p, self.curvature(p[:, :2]), self.b**2 * p[:, 0], self.a**2 * p[:, 1]
        )

    def curvature(self, xy: ArrayLike) -> NDArray[np.float64]:
        """Curvature (m-1) of the ellipse at points on it ((P, 2), m)."""
        xy = np.asarray(xy, dtype=np.float64)
        a, b = self.a, self.b
        return a * b / (b**2 * xy[:, 0] ** 2 / a**2 + a**2 * xy[:, 1] ** 2 / b**2) ** 1.5

    def _polygon(self, z: float) -> NDArray[np.float64]:
        t = 2 * np.pi * np.arange(SECTION_POINTS) / SECTION_POINTS
        return np.stack([self.a * np.cos(t), self.b * np.sin(t)], axis=1)

    def _perimeter(self, z: float) -> float:
        from scipy.integrate import quad

        value, _ = quad(
            lambda t: np.hypot(self.a * np.sin(t), self.b * np.cos(t)), 0, 2 * np.pi, limit=200
        )
        return float(value)


@dataclass(frozen=True)
class Cone(AnalyticBody):
    """Truncated cone about z: radius ``radius_bottom`` at ``bottom``, ``radius_top`` at ``top``.

    Distances are to the lateral surface (its infinite extension; caps ignored), exact.
    """

    radius_bottom: float
    radius_top: float
    bottom: float = 0.0
    top: float = 1.0

    def __post_init__(self) -> None:
        positive_length(self.radius_bottom, "radius_bottom")
        positive_length(self.radius_top, "radius_top")
        height_span(self.bottom, self.top)

    def radius(self, z: float | NDArray) -> float | NDArray:
        t = (np.asarray(z) - self.bottom) / (self.top - self.bottom)
        return self.radius_bottom + t * (self.radius_top - self.radius_bottom)

    def query(self, points: ArrayLike):
        p = as_points(points)
        dr, dz = self.radius_top - self.radius_bottom, self.top - self.bottom
        length = np.hypot(dr, dz)
        n_r, n_z = dz / length, -dr / length  # outward normal in the (r, z) half-plane
        r = np.hypot(p[:, 0], p[:, 1])
        safe = np.where(r > 0, r, 1.0)
        ux, uy = np.where(r > 0, p[:, 0] / safe, 1.0), np.where(r > 0, p[:, 1] / safe, 0.0)
        distance = (r - self.radius_bottom) * n_r + (p[:, 2] - self.bottom) * n_z
        cr, cz = r - distance * n_r, p[:, 2] - distance * n_z
        closest = np.stack([cr * ux, cr * uy, cz], axis=1)
        normal = np.stack([n_r * ux, n_r * uy, np.full(len(p), n_z)], axis=1)
        return distance, closest, normal

    def _polygon(self, z: float) -> NDArray[np.float64]:
        t = 2 * np.pi * np.arange(SECTION_POINTS) / SECTION_POINTS
        return float(self.radius(z)) * np.stack([np.cos(t), np.sin(t)], axis=1)

    def hessian(self, surface_points: ArrayLike) -> NDArray[np.float64]:
        """Hessian of the signed distance at surface points ((P, 3, 3), m-1): the normal
        curvature n_r / r of the circumferential direction (the generators are straight)."""
        p = as_points(surface_points)
        dr, dz = self.radius_top - self.radius_bottom, self.top - self.bottom
        n_r = dz / np.hypot(dr, dz)
        return _circumferential(p, n_r / np.hypot(p[:, 0], p[:, 1]))

    def _perimeter(self, z: float) -> float:
        return float(2 * np.pi * self.radius(z))
