"""What every body shares: the `Body` protocol, cross-section polygons, the analytic base.

Every body lives in one frame: metres, z up. A `Body` answers

* ``query(points)`` -> signed distance (positive OUTSIDE; note trimesh's ``signed_distance`` is
  positive inside), closest surface point and outward unit normal, for (P, 3) points in m;
* ``z_range`` -> lowest and highest height of the body, m;
* ``sections(z)`` -> the cross-section at height z as closed loops, each a (K, 2, 2) array of
  segments in the xy plane, m;
* ``girth(z)`` -> perimeter of the cross-section and of its convex hull at height z, m.

Bodies whose surface is smooth also give ``hessian(surface_points)``, the Hessian of the signed
distance ((P, 3, 3), 1/m): Newton's curvature term (`cloth.solvers.newton`).
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull

from cloth.errors import InputError, require_positive

#: Points around the polygon that stands for a closed-form cross-section.
SECTION_POINTS = 2048

Segments = NDArray[np.float64]  # (K, 2, 2): K segments of a closed loop, xy, m


@runtime_checkable
class Body(Protocol):
    """What the fabric needs of a body (metres, z up)."""

    def query(
        self, points: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

    @property
    def z_range(self) -> tuple[float, float]: ...

    def sections(self, z: float) -> list[Segments]: ...

    def girth(self, z: float) -> tuple[float, float]: ...


def as_points(points: ArrayLike) -> NDArray[np.float64]:
    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"points must have shape (P, 3), got {p.shape}")
    return p


def polygon_segments(xy: NDArray[np.float64]) -> Segments:
    """(K, 2) closed polygon -> (K, 2, 2) segments."""
    return np.stack([xy, np.roll(xy, -1, axis=0)], axis=1)


def loop_length(segments: Segments) -> float:
    return float(np.sum(np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1)))


def hull_polygon(loops: list[Segments]) -> NDArray[np.float64]:
    """Counter-clockwise convex hull (H, 2) of the endpoints of ``loops``."""
    pts = np.concatenate([loop.reshape(-1, 2) for loop in loops])
    hull = ConvexHull(pts)
    return pts[hull.vertices]  # scipy returns 2-D hull vertices counter-clockwise


def polygon_perimeter(xy: NDArray[np.float64]) -> float:
    return float(np.sum(np.linalg.norm(np.roll(xy, -1, axis=0) - xy, axis=1)))


def check_height(body: Body, z: float) -> None:
    low, high = body.z_range
    if not low <= z <= high:
        raise InputError(
            f"height {z:.6g} m is outside the body ({low:.6g} to {high:.6g} m); choose garment "
            "heights within the body",
            field="garment",
        )


class AnalyticBody:
    """Shared behaviour of the closed-form bodies (vertical axis through the origin)."""

    bottom: float
    top: float

    @property
    def z_range(self) -> tuple[float, float]:
        return (self.bottom, self.top)

    def _polygon(self, z: float) -> NDArray[np.float64]:
        raise NotImplementedError

    def sections(self, z: float) -> list[Segments]:
        check_height(self, z)  # type: ignore[arg-type]
        return [polygon_segments(self._polygon(z))]

    def girth(self, z: float) -> tuple[float, float]:
        check_height(self, z)  # type: ignore[arg-type]
        perimeter = self._perimeter(z)
        return perimeter, perimeter  # convex: the hull is the section

    def _perimeter(self, z: float) -> float:
        raise NotImplementedError


def positive_length(value: float, name: str) -> float:
    return require_positive(value, name, "length in m")


def height_span(bottom: float, top: float) -> tuple[float, float]:
    bottom, top = float(bottom), float(top)
    if not bottom < top:
        raise InputError(f"body bottom ({bottom}) must be below its top ({top})", field="body")
    return bottom, top
