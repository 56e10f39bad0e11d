"""Curved refinement of a coarse mesh before its surface is fitted (Phong tessellation).

A coarse mesh's vertices lie on the body, its flat facets cut inside it by the sagitta
h^2 kappa / 8, and its curvature sits on the creases. Smoothing the facets (`cloth.bodies.surface`)
spreads that curvature but keeps the error of the flat facets: on the torso's 32 x 30 mesh
(facets about 30 mm wide) girth-line pressures came out 3-13 % off the smooth torso's.

Refinement: every triangle is split ``levels`` times into four (midpoints, shared edges shared),
and each new point, at barycentric (b_1, b_2, b_3) on its triangle, moves to

    p* = (1 - ALPHA) p + ALPHA sum_i b_i pi_i(p),   pi_i(p) = p - ((p - p_i) . n_i) n_i,

the Phong tessellation (Boubekeur & Alexa, 2008): p is the flat point, pi_i its projection on the
tangent plane of vertex i, n_i the area-weighted vertex normals. On an edge only the edge's two
vertices count, so neighbouring triangles agree and the mesh stays closed. ALPHA = 1/2 puts the
midpoint of a chord of a circle on the circle to second order (measured on a 32-segment cylinder:
radius error -3.5 um against the flat facets' -0.48 mm; 3/4, the value for rendering, bulges
out by 0.24 mm). A vertex on a feature edge (bent by `FEATURE_ANGLE` or more: a cylinder's rim)
keeps its facets flat around it: its tangent plane is undefined.

When. Phong patches assume the vertices lie on a smooth surface; a noisy scan's do not, and its
noise, not its facets, sets the smoothing it needs: a mesh is refined only while the scatter of
its vertices about a smooth surface is under `NOISE_RATIO` of its facets' flatness
(`cloth.bodies.tessellation.roughness`; the clean torso meshes: 0.30-0.33; with 1 mm of noise:
0.75-1.3).

Shapes and units: vertices (V, 3) m, faces (F, 3) int.
"""

from __future__ import annotations

import logging

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.tessellation import FEATURE_ANGLE, crease_spacing, roughness

log = logging.getLogger(__name__)

#: Weight of the curved (Phong) point against the flat one.
ALPHA = 0.5
#: Facets are refined until their creases are at most this far apart, m.
TARGET_SPACING = 8e-3
#: At most this many levels (each splits a triangle into four).
MAX_LEVELS = 3
#: A mesh refined to more faces than this is left as it is (a log line says so).
MAX_FACES = 2_000_000
#: A mesh whose vertices scatter more than this share of its facets' flatness is not refined.
NOISE_RATIO = 0.5


def refine_levels(crease_spacing: float, faces: int, scatter: float, flatness: float) -> int:
    """How many times to split a mesh whose creases are ``crease_spacing`` (m) apart: until
    they are at most `TARGET_SPACING` apart, at most `MAX_LEVELS`; 0 where its vertices
    scatter (``scatter``, ``flatness``: `roughness`) or the refined mesh would exceed
    `MAX_FACES`."""
    if crease_spacing <= TARGET_SPACING:
        return 0
    if scatter > NOISE_RATIO * flatness:
        log.info(
            "the mesh's vertices scatter %.3g mm about a smooth surface, against %.3g mm of "
            "facet flatness: noise, so it is smoothed, not refined",
            scatter * 1e3,
            flatness * 1e3,
        )
        return 0
    levels = min(MAX_LEVELS, int(np.ceil(np.log2(crease_spacing / TARGET_SPACING))))
    if faces * 4**levels > MAX_FACES:
        log.info(
            "the mesh's facets are %.3g mm wide but refining %d faces %d times would make "
            "more than %d; fitted unrefined",
            crease_spacing * 1e3,
            faces,
            levels,
            MAX_FACES,
        )
        return 0
    return levels


def auto_levels(
    vertices: NDArray[np.float64], faces: NDArray[np.intp], creases: float | None = None
) -> int:
    """`refine_levels` of a mesh, from its crease spacing (``creases``, m, when the caller has
    it) and, only where its facets are wide enough to refine, its `roughness`."""
    creases = crease_spacing(vertices, faces) if creases is None else creases
    if creases <= TARGET_SPACING:
        return 0
    return refine_levels(creases, len(faces), *roughness(vertices, faces))


def phong_refine(
    vertices: NDArray[np.float64],
    faces: NDArray[np.intp],
    levels: int,
    feature_angle: float = FEATURE_ANGLE,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The mesh split ``levels`` times with its new points on Phong patches (module docstring)."""
    import trimesh

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    normals = np.array(mesh.vertex_normals, dtype=np.float64)
    sharp = mesh.face_adjacency_edges[mesh.face_adjacency_angles >= feature_angle]
    normals[np.unique(sharp)] = 0.0  # flat around a feature
    points, triangles = vertices, faces
    owner = np.arange(len(faces))
    for _ in range(levels):
        points, triangles = trimesh.remesh.subdivide(points, triangles)
        owner = np.repeat(owner, 4)  # trimesh puts a face's four children together
    # barycentric coordinates of every refined vertex on (one of) its original triangle(s)
    vertex_owner = np.empty(len(points), dtype=np.intp)
    vertex_owner[triangles.ravel()] = np.repeat(owner, 3)
    corners = vertices[faces[vertex_owner]]  # (P, 3, 3)
    bary = _barycentric(points, corners)
    flat = np.einsum("pk,pki->pi", bary, corners)
    curved = np.zeros_like(flat)
    for k in range(3):
        n = normals[faces[vertex_owner, k]]
        along = np.einsum("pi,pi->p", flat - corners[:, k], n)
        curved += bary[:, k : k + 1] * (flat - along[:, None] * n)
    return (1.0 - ALPHA) * flat + ALPHA * curved, np.asarray(triangles, dtype=np.int64)


def _barycentric(points: NDArray[np.float64], corners: NDArray[np.float64]) -> NDArray:
    """(P, 3) barycentric coordinates of ``points`` ((P, 3)) in the triangles ``corners``
    ((P, 3, 3)), clipped to the triangle and summing to one."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    e1, e2, d = b - a, c - a, points - a
    d11 = np.einsum("pi,pi->p", e1, e1)
    d12 = np.einsum("pi,pi->p", e1, e2)
    d22 = np.einsum("pi,pi->p", e2, e2)
    r1 = np.einsum("pi,pi->p", d, e1)
    r2 = np.einsum("pi,pi->p", d, e2)
    det = d11 * d22 - d12**2
    safe = np.where(det > 0, det, 1.0)
    v = np.where(det > 0, (d22 * r1 - d12 * r2) / safe, 0.0)
    w = np.where(det > 0, (d11 * r2 - d12 * r1) / safe, 0.0)
    bary = np.clip(np.column_stack([1.0 - v - w, v, w]), 0.0, 1.0)
    return bary / bary.sum(axis=1, keepdims=True)
