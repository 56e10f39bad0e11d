"""Triangle-mesh bodies: load any mesh trimesh reads, convert units and axes, check, repair.

`MeshBody` wraps any mesh trimesh reads (OBJ, STL, PLY, GLB, ...), converted once at load to metres
and z up, checked for finite vertices, watertightness, manifold edges, consistent winding and
degenerate faces, with an explicit ``repair`` option. Its proximity queries are exact (closest point
on triangles): libigl's AABB tree with pseudonormal signs when installed (a core dependency, ~2 us
per point), else the numpy/scipy implementation in `cloth.bodies.proximity` (~30 us per point); see
docs/bodies.md for measurements. Contact with the facets themselves is the ``surface: mesh`` option;
by default a mesh body is contacted through the smooth surface fitted to it
(`cloth.bodies.surface`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.bodies.base import (
    Segments,
    as_points,
    check_height,
    hull_polygon,
    loop_length,
    polygon_perimeter,
)
from cloth.bodies.proximity import MeshProximity
from cloth.bodies.sections import closed, loops
from cloth.errors import InputError

log = logging.getLogger(__name__)

UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
UP_AXES = ("x", "y", "z")
#: The smooth surface closes holes whose perimeter is at most this share of the mesh's size
#: (its bounding-box diagonal) by the winding number; a larger one is refused.
HOLE_LIMIT = 0.25


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
    loop_point : (2,) float, m, or None
        A point inside the part of the body a garment wraps where its rows meet several section
        loops (an avatar's trunk or leg; `cloth.bodies.sections.follow`); None: the largest.
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.intp]
    source: str = ""
    backend: str = "auto"
    report: MeshReport | None = None
    loop_point: tuple[float, float] | None = None
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
            self._query = MeshProximity(self.vertices, self.faces).query

    @classmethod
    def load(
        cls,
        path: str | Path,
        units: str = "m",
        up: str = "z",
        repair: bool = False,
        backend: str = "auto",
        allow_holes: bool = False,
    ) -> MeshBody:
        """Read and check a mesh file; convert it to metres, z up.

        A mesh with vertices that are not finite numbers or with non-manifold edges (shared by
        more than two faces) is refused. One that is not watertight, not consistently wound,
        inverted or has degenerate faces is refused with the defect and its count, unless
        ``repair`` is true: then trimesh's repairs are applied, logged and listed in
        `MeshBody.report`, and the checks rerun. With ``allow_holes`` (the smooth surface, whose
        inside comes from the winding number) open edges and degenerate faces are only logged.
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
            mesh = trimesh.load(path, force="mesh", process=False)
        except Exception as exc:  # trimesh raises many types for unreadable files
            raise InputError(
                f"not a mesh trimesh can read ({type(exc).__name__}: {exc}); export OBJ, STL, "
                "PLY or GLB",
                path,
                "mesh",
            ) from None
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
            raise InputError("the file holds no triangles; export a surface mesh", path, "mesh")
        finite = np.isfinite(np.asarray(mesh.vertices)).all(axis=1)
        if not np.all(finite):
            raise InputError(
                f"{np.count_nonzero(~finite)} vertices are not finite numbers (NaN or inf); fix "
                "the export",
                path,
                "mesh",
            )
        try:
            return cls._checked(mesh, path, units, up, repair, backend, allow_holes)
        except InputError:
            raise
        except Exception as exc:  # a malformed file trimesh read but cannot index (many types)
            raise InputError(
                f"the vertices and faces do not form a mesh ({type(exc).__name__}: "
                f"{str(exc)[:80]}); fix the export",
                path,
                "mesh",
            ) from None

    @classmethod
    def _checked(
        cls, mesh, path, units: str, up: str, repair: bool, backend: str, allow_holes: bool
    ) -> MeshBody:
        """The body of a loaded mesh, checked (`load`)."""
        mesh.process()  # merge duplicate vertices (as trimesh.load(process=True) does)
        _, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
        if np.any(counts > 2):
            raise InputError(
                f"{np.count_nonzero(counts > 2)} non-manifold edges (shared by more than two "
                "faces); the body must be one closed surface, fix the mesh",
                path,
                "mesh",
            )
        repairs: list[str] = []
        if repair:
            repairs = _repair(mesh)
        report = _inspect(mesh, repairs)
        problems, tolerated = [], []
        if report.degenerate_faces:
            (tolerated if allow_holes else problems).append(
                f"{report.degenerate_faces} degenerate faces"
            )
        if not report.watertight:
            holes = f"not watertight ({_open_edges(mesh)} open edges)"
            largest = _largest_hole(mesh)
            if allow_holes and largest <= HOLE_LIMIT * float(mesh.scale):
                tolerated.append(holes)
            else:
                if allow_holes:
                    holes += (
                        f", a hole {largest:.3g} units around, more than {HOLE_LIMIT:.0%} of the "
                        "mesh's size: too large for the winding number to close"
                    )
                problems.append(holes)
        if not report.winding_consistent:
            problems.append("inconsistently wound faces")
        if report.watertight and report.volume <= 0:
            problems.append("inside out (negative volume)")
        if problems:
            hint = "fix the mesh" if repair else "fix the mesh or set repair: true"
            raise InputError(f"{'; '.join(problems)}; {hint}", path, "mesh")
        for line in tolerated:
            log.warning(
                "%s: %s; the smooth surface takes its inside from the winding number", path, line
            )
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
        p = as_points(points)
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

    def topology(self) -> dict:
        """Cached face normals, edge-to-faces and vertex-to-faces maps, and an AABB tree (what
        faceted contact, `cloth.contact.polyhedral`, reads of the mesh)."""
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
        check_height(self, z)
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
        chains = loops(segments)
        closed_loops = [chain for chain in chains if closed(chain)]
        if not closed_loops:
            raise InputError(
                f"the body has no closed cross-section at height {z:.6g} m (the mesh is open "
                "there); choose heights where the body is closed, or repair the mesh",
                self.source or None,
                "garment",
            )
        return closed_loops

    def girth(self, z: float) -> tuple[float, float]:
        loops = self.sections(z)
        return sum(loop_length(loop) for loop in loops), polygon_perimeter(hull_polygon(loops))


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


def _largest_hole(mesh) -> float:
    """Perimeter of the largest hole (loop of open edges), in the mesh's units."""
    outline = mesh.outline()
    return max((entity.length(outline.vertices) for entity in outline.entities), default=0.0)


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
