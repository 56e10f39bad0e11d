"""Exact, vectorised closest-point and signed-distance queries on a triangle mesh.

Method (numpy + scipy only):

1. Every face is covered by sample points: its centroid, or for a large face (radius above the
   median, e.g. a flat cap) the centroids of its level-s subdivision, so that every point of a
   face lies within rho (the median face radius) of one of its samples. A KD-tree over all
   samples gives each query point the faces of its ``k`` nearest samples as candidates.
2. The exact closest point on each candidate triangle (Ericson's region classification,
   vectorised) gives the best distance d*.
3. Completeness: a face none of whose samples is among the k nearest has all its samples at
   least d_k (the k-th sample distance) away, hence lies at least d_k - rho away. Where
   d* <= d_k - rho the answer is exact; the other points are re-queried with 4k, 16k, ...
   samples, and finally with every face owning a sample within d* + rho.
4. The sign comes from the angle-weighted pseudonormal of the closest feature (face, edge or
   vertex; Baerentzen & Aanaes 2005), which is exact for closed, consistently oriented meshes.

The outward unit normal returned is the gradient of the signed distance, (p - q)/d x sign, where
the point is off the surface, and the feature's pseudonormal on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

# closest-feature codes of `closest_on_triangles`
FACE, EDGE_AB, EDGE_BC, EDGE_CA, VERTEX_A, VERTEX_B, VERTEX_C = range(7)


def _dot(u: NDArray, v: NDArray) -> NDArray:
    return np.einsum("...i,...i->...", u, v)


def closest_on_triangles(
    p: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """Closest point on triangle (a, b, c) to p, elementwise.

    Parameters
    ----------
    p, a, b, c : (..., 3) float, m
        Query points and triangle corners (broadcast together).

    Returns
    -------
    q : (..., 3) float, m
        Closest points.
    feature : (...,) int8
        Which feature q lies on: FACE, EDGE_AB, EDGE_BC, EDGE_CA, VERTEX_A/B/C.
    """
    p, a, b, c = np.broadcast_arrays(p, a, b, c)
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = _dot(ab, ap), _dot(ac, ap)
    bp = p - b
    d3, d4 = _dot(ab, bp), _dot(ac, bp)
    cp = p - c
    d5, d6 = _dot(ab, cp), _dot(ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = 1.0 / (va + vb + vc)
        v_face = vb * denom
        w_face = vc * denom
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    q = a + v_face[..., None] * ab + w_face[..., None] * ac
    feature = np.full(p.shape[:-1], FACE, dtype=np.int8)
    # regions in the reverse order of precedence, so the later assignments win
    on_bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
    q = np.where(on_bc[..., None], b + t_bc[..., None] * (c - b), q)
    feature[on_bc] = EDGE_BC
    on_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    q = np.where(on_ac[..., None], a + t_ac[..., None] * ac, q)
    feature[on_ac] = EDGE_CA
    on_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    q = np.where(on_ab[..., None], a + t_ab[..., None] * ab, q)
    feature[on_ab] = EDGE_AB
    at_c = (d6 >= 0) & (d5 <= d6)
    q = np.where(at_c[..., None], c, q)
    feature[at_c] = VERTEX_C
    at_b = (d3 >= 0) & (d4 <= d3)
    q = np.where(at_b[..., None], b, q)
    feature[at_b] = VERTEX_B
    at_a = (d1 <= 0) & (d2 <= 0)
    q = np.where(at_a[..., None], a, q)
    feature[at_a] = VERTEX_A
    return q, feature


@dataclass(eq=False)
class MeshProximity:
    """Closest-point queries on a closed, consistently oriented triangle mesh.

    Parameters
    ----------
    vertices : (V, 3) float, m
    faces : (F, 3) int
        Counter-clockwise seen from outside (outward normals).
    k : int
        Candidate faces per point in the first pass.
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.intp]
    k: int = 12
    chunk: int = 16384
    _tree: cKDTree = field(init=False, repr=False)

    def __post_init__(self) -> None:
        v = np.ascontiguousarray(self.vertices, dtype=np.float64)
        f = np.ascontiguousarray(self.faces, dtype=np.intp)
        self.vertices, self.faces = v, f
        corners = v[f]  # (F, 3, 3)
        self._corners = corners
        centroid = corners.mean(axis=1)
        radius = np.linalg.norm(corners - centroid[:, None], axis=2).max(axis=1)
        target = float(np.median(radius))
        level = np.maximum(1, np.ceil(radius / target)).astype(int)
        samples, owner = [], []
        for s in np.unique(level):
            group = np.flatnonzero(level == s)
            # centroids of the s*s sub-triangles of a level-s subdivision: every point of a
            # sub-triangle is within (face radius / s) of its centroid
            i, j = np.meshgrid(np.arange(s), np.arange(s), indexing="ij")
            up = (i + j <= s - 1).ravel()
            down = (i + j <= s - 2).ravel()
            ij = (
                np.concatenate(
                    [
                        np.stack([i.ravel()[up], j.ravel()[up]], axis=1) + 1 / 3,
                        np.stack([i.ravel()[down], j.ravel()[down]], axis=1) + 2 / 3,
                    ]
                )
                / s
            )
            bary = np.column_stack([1 - ij.sum(axis=1), ij])  # (s*s, 3)
            points = np.einsum("gc,fcd->fgd", bary, corners[group])
            samples.append(points.reshape(-1, 3))
            owner.append(np.repeat(group, len(bary)))
        self._owner = np.concatenate(owner)
        self._radius = float(np.max(radius / level))
        self._tree = cKDTree(np.concatenate(samples))
        self.k = int(min(self.k, len(self._owner)))
        normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        face_normal = normal / np.linalg.norm(normal, axis=1)[:, None]
        self._face_normal = face_normal
        # angle-weighted vertex pseudonormals
        vertex_normal = np.zeros_like(v)
        for corner in range(3):
            e1 = corners[:, (corner + 1) % 3] - corners[:, corner]
            e2 = corners[:, (corner + 2) % 3] - corners[:, corner]
            cos = _dot(e1, e2) / (np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1))
            angle = np.arccos(np.clip(cos, -1.0, 1.0))
            np.add.at(vertex_normal, f[:, corner], angle[:, None] * face_normal)
        self._vertex_normal = vertex_normal / np.linalg.norm(vertex_normal, axis=1)[:, None]
        # edge pseudonormals: the sum of the two adjacent faces' normals, per (face, edge)
        edges = np.stack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]], axis=1).reshape(-1, 2)
        key = np.sort(edges, axis=1)
        key = key[:, 0].astype(np.int64) * len(v) + key[:, 1]
        _, inverse = np.unique(key, return_inverse=True)
        summed = np.zeros((inverse.max() + 1, 3))
        np.add.at(summed, inverse, np.repeat(face_normal, 3, axis=0))
        edge_normal = summed[inverse]
        self._edge_normal = (edge_normal / np.linalg.norm(edge_normal, axis=1)[:, None]).reshape(
            -1, 3, 3
        )

    def _pseudonormal(self, face: NDArray, feature: NDArray) -> NDArray[np.float64]:
        normal = self._face_normal[face].copy()
        for code, edge in ((EDGE_AB, 0), (EDGE_BC, 1), (EDGE_CA, 2)):
            mask = feature == code
            normal[mask] = self._edge_normal[face[mask], edge]
        for code, corner in ((VERTEX_A, 0), (VERTEX_B, 1), (VERTEX_C, 2)):
            mask = feature == code
            normal[mask] = self._vertex_normal[self.faces[face[mask], corner]]
        return normal

    def _best(self, p: NDArray, candidates: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Closest point over candidate faces ((P, C) int) for points p ((P, 3))."""
        tri = self._corners[candidates]  # (P, C, 3, 3)
        q, feature = closest_on_triangles(
            p[:, None, :], tri[..., 0, :], tri[..., 1, :], tri[..., 2, :]
        )
        d2 = _dot(q - p[:, None, :], q - p[:, None, :])
        pick = np.argmin(d2, axis=1)
        rows = np.arange(len(p))
        return q[rows, pick], feature[rows, pick], candidates[rows, pick], np.sqrt(d2[rows, pick])

    def query(
        self, points: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Signed distance (positive outside), closest point and outward unit normal.

        Parameters
        ----------
        points : (P, 3) float, m

        Returns
        -------
        distance : (P,) float, m
        closest : (P, 3) float, m
        normal : (P, 3) float, 1
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        if len(p) > self.chunk:  # bound the (P, k, 3, 3) temporaries
            parts = [self.query(p[s : s + self.chunk]) for s in range(0, len(p), self.chunk)]
            return tuple(np.concatenate(arrays) for arrays in zip(*parts, strict=True))  # type: ignore[return-value]
        sample_distance, nearest = self._tree.query(p, k=self.k)
        if self.k == 1:
            sample_distance, nearest = sample_distance[:, None], nearest[:, None]
        closest, feature, face, distance = self._best(p, self._owner[nearest])
        unresolved = np.flatnonzero(distance > sample_distance[:, -1] - self._radius)
        k = self.k
        while unresolved.size and k < min(1024, len(self._owner)):  # widen the search first
            k = min(4 * k, len(self._owner))
            cd, near = self._tree.query(p[unresolved], k=k)
            c, fe, fa, d = self._best(p[unresolved], self._owner[near])
            closest[unresolved], feature[unresolved], face[unresolved] = c, fe, fa
            distance[unresolved] = d
            unresolved = unresolved[d > cd[:, -1] - self._radius]
        for index in unresolved:  # exact fallback: every face that could be closer
            near = self._tree.query_ball_point(p[index], distance[index] + self._radius)
            if near:
                faces = np.unique(self._owner[near])
                c, fe, fa, d = self._best(p[index : index + 1], faces[None, :])
                closest[index], feature[index], face[index], distance[index] = (
                    c[0],
                    fe[0],
                    fa[0],
                    d[0],
                )
        pseudo = self._pseudonormal(face, feature)
        offset = p - closest
        sign = np.where(_dot(offset, pseudo) < 0.0, -1.0, 1.0)
        scale = max(float(np.ptp(self.vertices, axis=0).max()), 1.0)
        off_surface = distance > 1e-12 * scale
        normal = pseudo
        with np.errstate(invalid="ignore", divide="ignore"):
            gradient = offset / distance[:, None] * sign[:, None]
        normal = np.where(off_surface[:, None], gradient, pseudo)
        return sign * distance, closest, normal
