"""Frictionless contact with a polyhedral (mesh) body.

On a polyhedron the body's reaction at a contact point lies in the normal cone of the faces
there: one face's normal on a face interior, any non-negative combination of the two faces'
normals on an edge, of the incident faces' normals on a vertex. This module gives

* `remainder`: the part of a force the body cannot balance (the residual of the relaxation);
* `frames`: Newton's active face planes per held node (the faces with a positive multiplier).

The edge zigzag. A node whose equilibrium is on an edge, moved along one face's plane,
overshoots into the next face and is sent back along that plane; on the torso at 96 x 48 Newton
spent about 100 iterations near a residual of 0.2 that way before the active set settled.
Stopping a node on the edge it would cross back over cut 96 x 48 to 69 iterations, but stalled
other cases (48 x 24 at 20 % reduction: residual 1e-3 after 150 iterations, against 23 without),
so it is not used; see docs/solvers.md.

Points are (P, 3) in m, forces (P, 3) in N, normals unit vectors; faces are row indices into
``body.faces``. Feature codes are those of `cloth.bodies.proximity` (FACE, EDGE_*, VERTEX_*).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.proximity import EDGE_AB, EDGE_BC, EDGE_CA, FACE, VERTEX_A, VERTEX_B, VERTEX_C

if TYPE_CHECKING:
    from cloth.bodies import MeshBody

#: A contact point within this fraction (barycentric) of its face's size from an edge (vertex)
#: is on it.
FEATURE_TOLERANCE = 1e-4
#: At most this many face planes are active at one node (three independent planes fix a point).
MAX_ACTIVE = 3


def barycentric(tri: NDArray[np.float64], point: NDArray[np.float64]) -> NDArray[np.float64]:
    """Barycentric coordinates ((..., 3)) of points ((..., 3), m) projected onto the planes of
    triangles ((..., 3, 3), corners, m); all >= 0 inside the triangle's prism."""
    a, b, c = tri[..., 0, :], tri[..., 1, :], tri[..., 2, :]
    v0, v1, v2 = b - a, c - a, point - a
    d00, d01, d11 = (np.einsum("...i,...i->...", u, w) for u, w in ((v0, v0), (v0, v1), (v1, v1)))
    d20, d21 = np.einsum("...i,...i->...", v2, v0), np.einsum("...i,...i->...", v2, v1)
    den = d00 * d11 - d01 * d01
    beta = (d11 * d20 - d01 * d21) / den
    gamma = (d00 * d21 - d01 * d20) / den
    return np.stack([1.0 - beta - gamma, beta, gamma], axis=-1)


def feature(tri: NDArray[np.float64], point: NDArray[np.float64]) -> NDArray[np.int8]:
    """Face, edge or vertex code of points ((P, 3)) on triangles ((P, 3, 3)), with tolerance."""
    small = barycentric(tri, point) < FEATURE_TOLERANCE
    code = np.full(len(point), FACE, dtype=np.int8)
    code[small[:, 2]] = EDGE_AB
    code[small[:, 0]] = EDGE_BC
    code[small[:, 1]] = EDGE_CA
    code[small[:, 1] & small[:, 2]] = VERTEX_A
    code[small[:, 0] & small[:, 2]] = VERTEX_B
    code[small[:, 0] & small[:, 1]] = VERTEX_C
    return code


def locate(
    body: MeshBody, points: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int8]]:
    """Closest face ((P,) int), closest point ((P, 3), m) and its feature code ((P,))."""
    topo = body.topology()
    _, face, closest = topo["tree"].squared_distance(body.vertices, body.faces, points)
    face = np.asarray(face, dtype=np.int64).reshape(-1)
    closest = np.asarray(closest, dtype=np.float64).reshape(-1, 3)
    return face, closest, feature(body.vertices[body.faces[face]], closest)


def cone_pair(force: NDArray[np.float64], normals: NDArray[np.float64]) -> NDArray[np.float64]:
    """Multipliers lambda >= 0 ((P, 2)) minimising |F + lambda_1 n_1 + lambda_2 n_2| for two
    generators per row (normals (P, 2, 3)): closed form over the four active sets."""
    count = len(force)
    best = np.zeros((count, 2))
    best_norm = np.einsum("ij,ij->i", force, force)
    for k in (0, 1):  # one generator
        lam = np.maximum(-np.einsum("ij,ij->i", force, normals[:, k]), 0.0)
        rem = force + lam[:, None] * normals[:, k]
        norm = np.einsum("ij,ij->i", rem, rem)
        better = norm < best_norm
        best[better] = 0.0
        best[better, k] = lam[better]
        best_norm[better] = norm[better]
    n1, n2 = normals[:, 0], normals[:, 1]
    g12 = np.einsum("ij,ij->i", n1, n2)
    b1, b2 = -np.einsum("ij,ij->i", force, n1), -np.einsum("ij,ij->i", force, n2)
    det = 1.0 - g12**2  # the generators are unit vectors (or zero: then det = 1, lambda = 0)
    ok = det > 1e-12
    with np.errstate(divide="ignore", invalid="ignore"):
        l1 = (b1 - b2 * g12) / det
        l2 = (b2 - b1 * g12) / det
    ok &= (l1 >= 0) & (l2 >= 0)
    l1, l2 = np.where(ok, l1, 0.0), np.where(ok, l2, 0.0)  # parallel normals: no pair solution
    rem = force + l1[:, None] * n1 + l2[:, None] * n2
    better = ok & (np.einsum("ij,ij->i", rem, rem) < best_norm)
    best[better] = np.stack([l1, l2], axis=1)[better]
    return best


def _vertex_multipliers(force: NDArray[np.float64], gens: NDArray[np.float64]) -> NDArray:
    from scipy.optimize import nnls

    lam, _ = nnls(gens.T, -force)
    return lam


def _level(normals: NDArray[np.float64], flat: NDArray[np.bool_]) -> NDArray[np.float64]:
    """Normals ((P, K, 3)) with z removed and renormalised on the ``flat`` rows (sliding edge
    nodes, whose vertical reaction comes from the edge support); zero where nothing is left."""
    if not np.any(flat):
        return normals
    n = normals.copy()
    n[flat, ..., 2] = 0.0
    length = np.linalg.norm(n[flat], axis=-1, keepdims=True)
    n[flat] = np.where(length > 1e-12, n[flat] / np.maximum(length, 1e-300), 0.0)
    return n


def _active(
    body: MeshBody,
    face: NDArray[np.int64],
    code: NDArray[np.int8],
    force: NDArray[np.float64],
    flat: NDArray[np.bool_],
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Per point, the faces of its normal cone with a positive multiplier ((P, 3), -1 unused)
    and those multipliers ((P, 3), N), largest first; the cone of the ``flat`` rows is taken
    in the horizontal plane."""
    topo = body.topology()
    normal = topo["face_normal"]
    count = len(force)
    faces = np.full((count, MAX_ACTIVE), -1, dtype=np.int64)
    lams = np.zeros((count, MAX_ACTIVE))
    on_face = np.flatnonzero(code == FACE)
    n = _level(normal[face[on_face]][:, None, :], flat[on_face])[:, 0]
    lam = np.maximum(-np.einsum("ij,ij->i", force[on_face], n), 0.0)
    faces[on_face, 0] = np.where(lam > 0, face[on_face], -1)
    lams[on_face, 0] = lam
    on_edge = np.flatnonzero((code >= EDGE_AB) & (code < VERTEX_A))
    if on_edge.size:
        pair = topo["edge_faces"][face[on_edge], code[on_edge] - EDGE_AB]  # (E, 2)
        lam = cone_pair(force[on_edge], _level(normal[pair], flat[on_edge]))
        order = np.argsort(-lam, axis=1)
        pair, lam = np.take_along_axis(pair, order, 1), np.take_along_axis(lam, order, 1)
        faces[on_edge, :2] = np.where(lam > 0, pair, -1)
        lams[on_edge, :2] = lam
    for index in np.flatnonzero(code >= VERTEX_A):  # few: nodes rarely rest on a vertex
        vertex = body.faces[face[index], code[index] - VERTEX_A]
        ring = topo["vertex_faces"][vertex]
        lam = _vertex_multipliers(force[index], _level(normal[ring][None], flat[[index]])[0])
        order = np.argsort(-lam)[:MAX_ACTIVE]
        order = order[lam[order] > 0]
        faces[index, : order.size] = ring[order]
        lams[index, : order.size] = lam[order]
    return faces, lams


def remainder(
    body: MeshBody,
    points: NDArray[np.float64],
    force: NDArray[np.float64],
    horizontal: NDArray[np.bool_] | None = None,
) -> NDArray[np.float64]:
    """The part of the force ((P, 3), N) that the body cannot balance at points on it.

    Rows flagged in ``horizontal`` (sliding edge nodes) are treated in the horizontal plane:
    force and normals lose their z before the cone projection.
    """
    flat = np.zeros(len(points), bool) if horizontal is None else np.asarray(horizontal, bool)
    force = force.copy()
    force[flat, 2] = 0.0
    face, _, code = locate(body, points)
    faces, lams = _active(body, face, code, force, flat)
    normal = body.topology()["face_normal"]
    gens = _level(np.where(faces[..., None] >= 0, normal[faces], 0.0), flat)
    return force + np.einsum("pk,pkd->pd", lams, gens)


def frames(
    body: MeshBody,
    points: NDArray[np.float64],
    force: NDArray[np.float64],
    horizontal: NDArray[np.bool_],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Newton's active contact constraints at points held by the body.

    Returns the unit normals ((P, 3, 3), unused rows zero) of the faces whose reaction is active
    (multiplier > 0 in the normal-cone projection of the force: one on a face, one or two on an
    edge, up to three on a vertex), each one's plane offset ((P, 3), m), n_a . (x - v_a) with v_a
    a corner of face a, which a step must cancel to keep the point on that face's plane, and the
    faces themselves ((P, 3), -1 unused).
    """
    flat = np.asarray(horizontal, bool)
    f = force.copy()
    f[flat, 2] = 0.0
    face, _, code = locate(body, points)
    faces, _ = _active(body, face, code, f, flat)
    used = faces >= 0
    normals = np.where(used[..., None], body.topology()["face_normal"][faces], 0.0)
    corner = body.vertices[body.faces[np.maximum(faces, 0), 0]]
    offsets = np.where(used, np.einsum("pad,pad->pa", normals, points[:, None, :] - corner), 0.0)
    return normals, offsets, faces
