"""Rigid bodies the fabric is worn on: closed-form shapes for validation, and triangle meshes.

Every body lives in one frame: metres, z up. A `Body` answers

* ``query(points)`` -> signed distance (positive OUTSIDE; note trimesh's ``signed_distance`` is
  positive inside), closest surface point and outward unit normal, for (P, 3) points in m;
* ``z_range`` -> lowest and highest height of the body, m;
* ``sections(z)`` -> the cross-section at height z as closed loops, each a (K, 2, 2) array of
  segments in the xy plane, m;
* ``girth(z)`` -> perimeter of the cross-section and of its convex hull at height z, m.

Closed forms (`Cylinder`, `EllipticCylinder`, `Cone`) are exact: distance to 1e-12 m (the
ellipse by a bisection root solve converged to machine precision). `MeshBody` wraps any mesh
trimesh reads (OBJ, STL, PLY, GLB, ...), converted once at load to metres and z up, checked for
watertightness, consistent winding and degenerate faces, with an explicit ``repair`` option.
Its proximity queries are exact (closest point on triangles): libigl's AABB tree with
pseudonormal signs when installed (a core dependency, ~2 us per point), else the numpy/scipy
implementation in `cloth.proximity` (~30 us per point); see docs/bodies.md for measurements.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull

from cloth.errors import InputError, require_positive

log = logging.getLogger(__name__)

UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
UP_AXES = ("x", "y", "z")
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


def _points(points: ArrayLike) -> NDArray[np.float64]:
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


def _check_height(body: Body, z: float) -> None:
    low, high = body.z_range
    if not low <= z <= high:
        raise InputError(
            f"height {z:.6g} m is outside the body ({low:.6g} to {high:.6g} m); choose garment "
            "heights within the body",
            field="garment",
        )


class _Analytic:
    """Shared behaviour of the closed-form bodies (vertical axis through the origin)."""

    bottom: float
    top: float

    @property
    def z_range(self) -> tuple[float, float]:
        return (self.bottom, self.top)

    def _polygon(self, z: float) -> NDArray[np.float64]:
        raise NotImplementedError

    def sections(self, z: float) -> list[Segments]:
        _check_height(self, z)  # type: ignore[arg-type]
        return [polygon_segments(self._polygon(z))]

    def girth(self, z: float) -> tuple[float, float]:
        _check_height(self, z)  # type: ignore[arg-type]
        perimeter = self._perimeter(z)
        return perimeter, perimeter  # convex: the hull is the section

    def _perimeter(self, z: float) -> float:
        raise NotImplementedError


def _positive(value: float, name: str) -> float:
    return require_positive(value, name, "length in m")


def _span(bottom: float, top: float) -> tuple[float, float]:
    bottom, top = float(bottom), float(top)
    if not bottom < top:
        raise InputError(f"body bottom ({bottom}) must be below its top ({top})", field="body")
    return bottom, top


@dataclass(frozen=True)
class Cylinder(_Analytic):
    """Circular cylinder of ``radius`` (m) about the z axis, from ``bottom`` to ``top`` (m).

    Distances are to the lateral surface (caps ignored), exact.
    """

    radius: float
    bottom: float = 0.0
    top: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive(self.radius, "radius"))
        _span(self.bottom, self.top)

    def query(self, points: ArrayLike):
        p = _points(points)
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
        return _circumferential(_points(surface_points), 1.0 / self.radius)

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
class EllipticCylinder(_Analytic):
    """Elliptic cylinder x^2/a^2 + y^2/b^2 = 1 (semi-axes a along x, b along y, m) along z."""

    a: float
    b: float
    bottom: float = 0.0
    top: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", _positive(self.a, "a"))
        object.__setattr__(self, "b", _positive(self.b, "b"))
        _span(self.bottom, self.top)

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
        p = _points(points)
        q = self.closest_xy(p[:, :2])
        inside = (p[:, 0] / self.a) ** 2 + (p[:, 1] / self.b) ** 2 < 1.0
        distance = np.hypot(*(p[:, :2] - q).T) * np.where(inside, -1.0, 1.0)
        gradient = np.stack([q[:, 0] / self.a**2, q[:, 1] / self.b**2, np.zeros(len(p))], axis=1)
        normal = gradient / np.linalg.norm(gradient, axis=1)[:, None]
        return distance, np.column_stack([q, p[:, 2]]), normal

    def hessian(self, surface_points: ArrayLike) -> NDArray[np.float64]:
        """Hessian of the signed distance at surface points ((P, 3, 3), m-1): kappa t t^T."""
        p = _points(surface_points)
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
class Cone(_Analytic):
    """Truncated cone about z: radius ``radius_bottom`` at ``bottom``, ``radius_top`` at ``top``.

    Distances are to the lateral surface (its infinite extension; caps ignored), exact.
    """

    radius_bottom: float
    radius_top: float
    bottom: float = 0.0
    top: float = 1.0

    def __post_init__(self) -> None:
        _positive(self.radius_bottom, "radius_bottom")
        _positive(self.radius_top, "radius_top")
        _span(self.bottom, self.top)

    def radius(self, z: float | NDArray) -> float | NDArray:
        t = (np.asarray(z) - self.bottom) / (self.top - self.bottom)
        return self.radius_bottom + t * (self.radius_top - self.radius_bottom)

    def query(self, points: ArrayLike):
        p = _points(points)
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
        p = _points(surface_points)
        dr, dz = self.radius_top - self.radius_bottom, self.top - self.bottom
        n_r = dz / np.hypot(dr, dz)
        return _circumferential(p, n_r / np.hypot(p[:, 0], p[:, 1]))

    def _perimeter(self, z: float) -> float:
        return float(2 * np.pi * self.radius(z))


def to_z_up(vertices: NDArray[np.float64], units: str, up: str) -> NDArray[np.float64]:
    """Convert (V, 3) vertices in ``units`` with ``up`` axis to metres, z up (right-handed)."""
    if units not in UNITS:
        raise InputError(f"unknown units {units!r}; use one of m, cm, mm", field="units")
    if up not in UP_AXES:
        raise InputError(f"unknown up axis {up!r}; use one of x, y, z", field="up")
    v = np.asarray(vertices, dtype=np.float64) * UNITS[units]
    if up == "y":  # rotate +90 degrees about x: y -> z, z -> -y
        v = np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1)
    elif up == "x":  # rotate -90 degrees about y: x -> z, z -> -x
        v = np.stack([-v[:, 2], v[:, 1], v[:, 0]], axis=1)
    return v


@dataclass(frozen=True)
class MeshReport:
    """What the load checks found (and what ``repair`` did)."""

    n_vertices: int
    n_faces: int
    watertight: bool
    winding_consistent: bool
    degenerate_faces: int
    volume: float
    repairs: tuple[str, ...] = ()


@dataclass(eq=False)
class MeshBody:
    """A triangle-mesh body in metres, z up (see `MeshBody.load`).

    Attributes
    ----------
    vertices : (V, 3) float, m
    faces : (F, 3) int
        Outward oriented.
    source : str
        File the mesh came from ('' when built in memory).
    backend : {'igl', 'numpy'}
        Proximity implementation in use.
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.intp]
    source: str = ""
    backend: str = "auto"
    report: MeshReport | None = None
    _query: object = field(init=False, repr=False, default=None)
    _trimesh: object = field(init=False, repr=False, default=None)
    _topo: dict | None = field(init=False, repr=False, default=None)

    def __post_init__(self) -> None:
        self.vertices = np.ascontiguousarray(self.vertices, dtype=np.float64)
        self.faces = np.ascontiguousarray(self.faces, dtype=np.int64)
        if self.backend not in ("auto", "igl", "numpy"):
            raise InputError(
                f"unknown proximity backend {self.backend!r}; use auto, igl or numpy",
                field="backend",
            )
        if self.backend in ("auto", "igl"):
            try:
                import igl  # noqa: F401
            except ImportError:
                if self.backend == "igl":
                    raise InputError(
                        "the igl backend needs libigl: pip install libigl", field="backend"
                    ) from None
                self.backend = "numpy"
            else:
                self.backend = "igl"
        if self.backend == "numpy":
            from cloth.proximity import MeshProximity

            self._query = MeshProximity(self.vertices, self.faces).query

    @classmethod
    def load(
        cls,
        path: str | Path,
        units: str = "m",
        up: str = "z",
        repair: bool = False,
        backend: str = "auto",
    ) -> MeshBody:
        """Read and check a mesh file; convert it to metres, z up.

        A mesh that is not watertight, not consistently wound, inverted or has degenerate faces
        is refused with the defect and its count, unless ``repair`` is true: then trimesh's
        repairs are applied, logged and listed in `MeshBody.report`, and the checks rerun.
        """
        import trimesh

        path = Path(path)
        if units not in UNITS:
            raise InputError(f"unknown units {units!r}; use one of m, cm, mm", path, "units")
        if up not in UP_AXES:
            raise InputError(f"unknown up axis {up!r}; use one of x, y, z", path, "up")
        if not path.is_file():
            raise InputError("mesh file not found; check the path", path, "mesh")
        try:
            mesh = trimesh.load(path, force="mesh", process=True)
        except Exception as exc:  # trimesh raises many types for unreadable files
            raise InputError(
                f"not a mesh trimesh can read ({type(exc).__name__}: {exc}); export OBJ, STL, "
                "PLY or GLB",
                path,
                "mesh",
            ) from None
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
            raise InputError("the file holds no triangles; export a surface mesh", path, "mesh")
        repairs: list[str] = []
        if repair:
            repairs = _repair(mesh)
        report = _inspect(mesh, repairs)
        problems = []
        if report.degenerate_faces:
            problems.append(f"{report.degenerate_faces} degenerate faces")
        if not report.watertight:
            problems.append(f"not watertight ({_open_edges(mesh)} open edges)")
        if not report.winding_consistent:
            problems.append("inconsistently wound faces")
        if report.watertight and report.volume <= 0:
            problems.append("inside out (negative volume)")
        if problems:
            hint = "fix the mesh" if repair else "fix the mesh or set repair: true"
            raise InputError(f"{'; '.join(problems)}; {hint}", path, "mesh")
        vertices = to_z_up(np.asarray(mesh.vertices), units, up)
        body = cls(vertices, np.asarray(mesh.faces), str(path), backend, report)
        log.info(
            "mesh %s: %d vertices, %d faces, %s backend%s",
            path,
            report.n_vertices,
            report.n_faces,
            body.backend,
            f", repaired: {', '.join(repairs)}" if repairs else "",
        )
        return body

    @property
    def z_range(self) -> tuple[float, float]:
        return float(self.vertices[:, 2].min()), float(self.vertices[:, 2].max())

    def query(self, points: ArrayLike):
        p = _points(points)
        if self.backend == "igl":
            import igl

            distance, _, closest, pseudo = igl.signed_distance(
                p, self.vertices, self.faces, igl.SIGNED_DISTANCE_TYPE_PSEUDONORMAL
            )
            offset = p - closest
            magnitude = np.abs(distance)
            scale = max(float(np.ptp(self.vertices, axis=0).max()), 1.0)
            with np.errstate(invalid="ignore", divide="ignore"):
                gradient = offset / magnitude[:, None] * np.sign(distance)[:, None]
            normal = np.where((magnitude > 1e-12 * scale)[:, None], gradient, pseudo)
            return distance, closest, normal
        return self._query(p)  # type: ignore[operator]

    def _topology(self) -> dict:
        """Cached face normals, edge-to-faces and vertex-to-faces maps, and an AABB tree."""
        if self._topo is None:
            import igl

            corners = self.vertices[self.faces]
            normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            normal /= np.linalg.norm(normal, axis=1)[:, None]
            edges = np.stack(
                [self.faces[:, [0, 1]], self.faces[:, [1, 2]], self.faces[:, [2, 0]]], axis=1
            ).reshape(-1, 2)
            key = np.sort(edges, axis=1)
            key = key[:, 0] * len(self.vertices) + key[:, 1]
            order = np.argsort(key, kind="stable")
            pairs = order.reshape(-1, 2)  # watertight: every edge has exactly two faces
            edge_faces = np.empty((len(edges), 2), dtype=np.int64)
            edge_faces[pairs[:, 0]] = (pairs // 3)[:, [0, 1]]
            edge_faces[pairs[:, 1]] = (pairs // 3)[:, [0, 1]]
            vertex_faces = [[] for _ in range(len(self.vertices))]
            for f, (a, b, c) in enumerate(self.faces.tolist()):
                vertex_faces[a].append(f)
                vertex_faces[b].append(f)
                vertex_faces[c].append(f)
            tree = igl.AABB()
            tree.init(self.vertices, self.faces)
            self._topo = {
                "face_normal": normal,
                "edge_faces": edge_faces.reshape(-1, 3, 2),
                "vertex_faces": [np.asarray(v) for v in vertex_faces],
                "tree": tree,
            }
        return self._topo

    def sections(self, z: float) -> list[Segments]:
        _check_height(self, z)
        import trimesh
        from trimesh.intersections import mesh_plane

        if self._trimesh is None:
            self._trimesh = trimesh.Trimesh(self.vertices, self.faces, process=False)
        lines = mesh_plane(self._trimesh, [0.0, 0.0, 1.0], [0.0, 0.0, z])
        segments = np.asarray(lines)[:, :, :2] if len(lines) else np.zeros((0, 2, 2))
        if len(segments) == 0:
            raise InputError(
                f"the body has no cross-section at height {z:.6g} m; choose heights where the "
                "body is",
                self.source or None,
                "garment",
            )
        return _loops(segments)

    def girth(self, z: float) -> tuple[float, float]:
        loops = self.sections(z)
        return sum(loop_length(loop) for loop in loops), polygon_perimeter(hull_polygon(loops))


def _loops(segments: Segments) -> list[Segments]:
    """Split unordered section segments into connected loops (by shared endpoints)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    scale = max(float(np.abs(segments).max()), 1e-9)
    keys = np.round(segments.reshape(-1, 2) / (1e-9 * scale)).astype(np.int64)
    _, ids = np.unique(keys, axis=0, return_inverse=True)
    ids = ids.reshape(-1, 2)
    n = int(ids.max()) + 1
    graph = coo_matrix((np.ones(len(ids)), (ids[:, 0], ids[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    seg_label = label[ids[:, 0]]
    return [segments[seg_label == value] for value in np.unique(seg_label)]


def loop_around(loops: list[Segments], point: ArrayLike) -> list[Segments]:
    """The loops that enclose ``point`` ((2,), m) by ray casting; an error when none does."""
    px, py = np.asarray(point, dtype=np.float64)
    chosen = []
    for loop in loops:
        (x1, y1), (x2, y2) = loop[:, 0].T, loop[:, 1].T
        crosses = (y1 > py) != (y2 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = x1 + (py - y1) * (x2 - x1) / (y2 - y1)
        if np.count_nonzero(crosses & (xi > px)) % 2 == 1:
            chosen.append(loop)
    if not chosen:
        raise InputError(
            f"no cross-section loop encloses the point ({px:g}, {py:g}) m; pick a point inside "
            "the part the garment goes around",
            field="garment.loop_point",
        )
    return chosen


def _inspect(mesh, repairs: list[str]) -> MeshReport:
    areas = mesh.area_faces
    scale = float(mesh.scale) if mesh.scale > 0 else 1.0
    degenerate = int(np.count_nonzero(areas <= 1e-12 * scale**2))
    watertight = bool(mesh.is_watertight)
    return MeshReport(
        n_vertices=len(mesh.vertices),
        n_faces=len(mesh.faces),
        watertight=watertight,
        winding_consistent=bool(mesh.is_winding_consistent),
        degenerate_faces=degenerate,
        volume=float(mesh.volume) if watertight else float("nan"),
        repairs=tuple(repairs),
    )


def _open_edges(mesh) -> int:
    import trimesh

    groups = trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)
    return len(groups)


def _repair(mesh) -> list[str]:
    """Apply trimesh's repairs in place; return what changed."""
    import trimesh

    done = []
    before = len(mesh.faces)
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.update_faces(mesh.unique_faces())
    mesh.remove_unreferenced_vertices()
    mesh.merge_vertices()
    if len(mesh.faces) != before:
        done.append(f"removed {before - len(mesh.faces)} degenerate or duplicate faces")
    if not mesh.is_watertight:
        open_before = _open_edges(mesh)
        trimesh.repair.fill_holes(mesh)
        done.append(f"filled holes ({open_before} open edges before, {_open_edges(mesh)} after)")
    if not mesh.is_winding_consistent:
        trimesh.repair.fix_winding(mesh)
        done.append("made winding consistent")
    if mesh.is_watertight and mesh.volume < 0:
        mesh.invert()
        done.append("inverted an inside-out mesh")
    for line in done:
        log.warning("repair: %s", line)
    return done


def body_from_config(block: dict, base_dir: str | Path = ".") -> tuple[Body, dict]:
    """Build the body of a validated case's ``body`` block.

    Returns the body and its reference for state files: the block, plus the resolved path and
    sha256 of any file it reads.
    """
    from cloth.config import resolve
    from cloth.labtables import sha256
    from cloth.smoothtorso import SmoothTorso
    from cloth.torso import DEFAULT_CHART, chart_size, torso_mesh

    ref: dict = {"block": block}
    if "mesh" in block:
        path = resolve(block["mesh"], base_dir)
        body: Body = MeshBody.load(
            path, units=block.get("units", "m"), up=block.get("up", "z"),
            repair=bool(block.get("repair", False)),
        )  # fmt: skip
        ref.update(kind="mesh", path=str(path), sha256=sha256(path))
    elif "torso" in block:
        spec = block["torso"]
        chart_path = resolve(spec["chart"], base_dir) if "chart" in spec else DEFAULT_CHART
        chart = chart_size(spec["size"], chart_path)
        if spec.get("surface", "smooth") == "smooth":
            body = SmoothTorso(chart)
        else:
            vertices, faces = torso_mesh(chart, spec.get("around", 128), spec.get("rings", 120))
            body = MeshBody(vertices, faces, source=f"torso {spec['size']} ({chart_path})")
        ref.update(kind="torso", path=str(chart_path), sha256=sha256(chart_path))
        ref["landmarks"] = {k: chart.height[k] for k in ("hip", "waist", "underbust", "bust")}
    elif "cylinder" in block:
        body = Cylinder(**block["cylinder"])
        ref["kind"] = "cylinder"
    elif "elliptic_cylinder" in block:
        body = EllipticCylinder(**block["elliptic_cylinder"])
        ref["kind"] = "elliptic_cylinder"
    elif "cone" in block:
        body = Cone(**block["cone"])
        ref["kind"] = "cone"
    else:
        raise InputError("no body given; use one of mesh, torso, cylinder, elliptic_cylinder, cone")
    return body, ref
