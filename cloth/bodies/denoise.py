"""Vertex noise taken off a scan before its surface is fitted.

A scan's vertices scatter about the body by about a millimetre. Interpolated (`cloth.bodies.refine`)
that scatter stays at full height between vertices a few millimetres apart, and Laplace's law
turns its curvature into pressure; smoothed with a Gaussian wide enough to remove it
(`cloth.bodies.surface`), the body's own sharp features flatten (the torso's bust line: -12 %
at sigma = 15 mm). So a noisy mesh is first filtered along its normals by a filter that keeps
smooth shapes and removes what varies from vertex to vertex:

    minimise  sum_i d_i^2  +  mu sum_i ( L kappa(x + d n)_i )^2,     mu = STRENGTH s^4 / 4,

with d_i the move of vertex i along its normal n_i, L the umbrella operator (the mean of the
neighbours minus the vertex), kappa_i = 2 n_i . (L x)_i / <|e|^2>_i the vertex's curvature
estimate (1/m; <|e|^2>_i the mean squared length of its edges) and s the median edge length.
The penalty is on how the curvature varies, not on the curvature: a sphere, a cylinder and,
to first order, any quadric patch pass unchanged, and a pole of many thin triangles keeps its
place (an unnormalised umbrella moved the torso mesh's 32-valent pole by 28 mm). Linearised,
kappa(x + d n) = kappa + S L d with S = diag(2 / <|e|^2>), so d solves

    (I + mu P^T P) d = -mu P^T L kappa,    P = L S L,

a symmetric positive definite system that conjugate gradients solves without forming P^T P.
On a regular mesh (L ~ s^2/4 x the Laplacian) the filter keeps 1 / (1 + STRENGTH (pi s /
lambda)^8) of a wave of wavelength lambda: 87 % at 4 edges, 41 % at 3 edges, 3 % at 2.

Measured on the torso mesh at 96 x 48, 1 mm of Gaussian noise (docs/validation.md): 128 x 120,
girth-line means within 2.3 % of the clean mesh's (without the filter: -6.2 % at the
underbust); 32 x 30 (denoised, then refined), within 2.2 % at the hip, waist and underbust,
but -4 to -7 % at the bust line.

When: a mesh whose vertices scatter about a smooth surface by more than
`cloth.bodies.refine.NOISE_RATIO` of its facets' flatness (`cloth.bodies.tessellation.roughness`).

Shapes and units: vertices (V, 3) m, faces (F, 3) int.
"""

from __future__ import annotations

import logging

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.tessellation import roughness, vertex_adjacency

log = logging.getLogger(__name__)

#: mu as a multiple of s^4 / 4 (s the median edge length): 1 takes off waves of 2-3 edges.
STRENGTH = 1.0
#: Relative residual of the conjugate-gradient solve.
TOLERANCE = 1e-8


def is_noisy(vertices: NDArray[np.float64], faces: NDArray[np.intp], ratio: float) -> bool:
    """Whether the vertices scatter about a smooth surface by more than ``ratio`` of the
    facets' flatness (`roughness`)."""
    scatter, flatness = roughness(vertices, faces)
    noisy = scatter > ratio * flatness
    if noisy:
        log.info(
            "the mesh's vertices scatter %.3g mm about a smooth surface, against %.3g mm of "
            "facet flatness: noise",
            scatter * 1e3,
            flatness * 1e3,
        )
    return bool(noisy)


def as_fitted(
    vertices: NDArray[np.float64], faces: NDArray[np.intp], choice: bool | None, ratio: float
) -> tuple[NDArray[np.float64], float]:
    """The vertices a fit uses, and how far they moved (RMS, m): filtered (`denoise`) where
    ``choice`` is True, or None and the mesh `is_noisy` at ``ratio``; else as they are, 0."""
    if choice is None:
        choice = is_noisy(vertices, faces, ratio)
    if not choice:
        return vertices, 0.0
    return denoise(vertices, faces)


def denoise(
    vertices: NDArray[np.float64], faces: NDArray[np.intp], strength: float = STRENGTH
) -> tuple[NDArray[np.float64], float]:
    """The vertices moved along their normals by the filter of the module docstring, and the
    RMS move (m)."""
    import scipy.sparse as sp
    import trimesh
    from scipy.sparse.linalg import LinearOperator, cg

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    edges, lengths = mesh.edges_unique, mesh.edges_unique_length
    count = len(vertices)
    adjacency, degree = vertex_adjacency(edges, count)
    used = degree > 0
    degree = np.maximum(degree, 1.0)
    umbrella = (sp.diags(1.0 / degree) @ adjacency - sp.diags(used.astype(float))).tocsr()
    squared = np.bincount(edges.ravel(), np.repeat(lengths**2, 2), count) / degree
    scale = np.where(used, 2.0 / np.where(squared > 0, squared, np.inf), 0.0)
    normals = np.asarray(mesh.vertex_normals, dtype=np.float64)
    kappa = scale * np.einsum("ij,ij->i", umbrella @ vertices, normals)
    s = float(np.median(lengths))
    mu = strength * s**4 / 4

    def p(d: NDArray) -> NDArray:
        return umbrella @ (scale * (umbrella @ d))

    def p_t(r: NDArray) -> NDArray:
        return umbrella.T @ (scale * (umbrella.T @ r))

    system = LinearOperator((count, count), matvec=lambda d: d + mu * p_t(p(d)), dtype=float)
    rhs = -mu * p_t(umbrella @ kappa)
    move, info = cg(system, rhs, rtol=TOLERANCE, maxiter=1000)
    if info != 0:
        log.warning("denoising: conjugate gradients stopped after %d iterations", info)
    rms = float(np.sqrt(np.mean(move[used] ** 2)))
    log.info(
        "denoised the mesh along its normals: moved %.3g mm RMS, %.3g mm at most",
        rms * 1e3,
        np.abs(move).max() * 1e3,
    )
    return vertices + move[:, None] * normals, rms
