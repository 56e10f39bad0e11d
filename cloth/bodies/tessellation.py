"""How a triangle mesh tessellates the surface it samples: its creases, and its noise.

* `crease_spacing`: how far apart the creases are that a smooth surface fitted to the mesh must
  round off (it sets the default smoothing, `cloth.bodies.surface`, and whether the mesh is
  refined first, `cloth.bodies.refine`).
* `roughness`: the flatness of the facets, median |n . L| (L the umbrella Laplacian of a vertex:
  how far the mean of its neighbours lies off its tangent plane, ~ w^2 kappa / 4 for facets w
  wide), against the scatter of the vertices about a smooth surface, median |n . L - its
  neighbours' mean| (~ the noise: measured 1.06-1.36 mm at 1 mm of vertex noise, 0.30-0.37 mm
  at 0.3 mm, 0.55 mm on the clean 32 x 30 torso mesh).

Shapes and units: vertices (V, 3) m, faces (F, 3) int; lengths m.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: An edge bent by this much (rad) or more is a feature of the body, not a tessellation crease.
FEATURE_ANGLE = 0.5


def crease_spacing(vertices: NDArray[np.float64], faces: NDArray[np.intp]) -> float:
    """Median width (m) of the facets across their shared edges, weighted by the edge's length
    times its bending angle: how far apart the creases a smooth surface must round off are
    (a regular mesh: about its edge length; the long side faces of a cylinder: their width).
    Edges bent by `FEATURE_ANGLE` or more (a cylinder's rims) are features, not creases of a
    tessellated smooth surface, and do not count."""
    import trimesh

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    pairs, edges = mesh.face_adjacency, mesh.face_adjacency_edges
    if len(pairs) == 0:
        return float(np.median(mesh.edges_unique_length))
    length = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    area = mesh.area_faces
    with np.errstate(divide="ignore", invalid="ignore"):
        width = (area[pairs[:, 0]] + area[pairs[:, 1]]) / np.where(length > 0, length, np.inf)
    angle = mesh.face_adjacency_angles
    weight = np.where(angle < FEATURE_ANGLE, angle * length, 0.0)  # sharper: a feature
    good = np.isfinite(width) & (width > 0) & (weight > 0)
    if not np.any(good):
        return float(np.median(mesh.edges_unique_length))
    order = np.argsort(width[good])
    cumulative = np.cumsum(weight[good][order])
    return float(width[good][order][np.searchsorted(cumulative, 0.5 * cumulative[-1])])


def vertex_adjacency(edges: NDArray[np.intp], count: int):
    """The symmetric vertex adjacency (CSR, ones) of ``count`` vertices joined by ``edges``
    ((E, 2), each edge once), and each vertex's number of neighbours ((count,) float)."""
    import scipy.sparse as sp

    adjacency = sp.coo_matrix(
        (np.ones(2 * len(edges)), (edges.ravel(), edges[:, ::-1].ravel())), shape=(count, count)
    ).tocsr()
    return adjacency, np.asarray(adjacency.sum(axis=1)).ravel()


def roughness(vertices: NDArray[np.float64], faces: NDArray[np.intp]) -> tuple[float, float]:
    """(scatter, flatness), m: the median scatter of the vertices about a smooth surface and
    the median flatness error of the facets (module docstring)."""
    import trimesh

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    adjacency, neighbours = vertex_adjacency(mesh.edges_unique, len(vertices))
    used = neighbours > 0
    degree = np.maximum(neighbours, 1.0)
    umbrella = adjacency @ vertices / degree[:, None] - vertices
    offset = np.einsum("ij,ij->i", umbrella, mesh.vertex_normals)
    scatter = np.abs(offset - adjacency @ offset / degree)
    return float(np.median(scatter[used])), float(np.median(np.abs(offset[used])))
