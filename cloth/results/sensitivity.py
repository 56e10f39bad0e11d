"""Sensitivities of the girth-line mean pressures to the pattern, by the adjoint of the equilibrium.

The controls theta are the knot values of the case's reduction profile (`cloth.case.profile`;
one for a uniform reduction). A girth line's mean pressure is read on the body
(`cloth.results.bands`):

    J = N / D,   N = sum_i w_i lambda_i,   D = sum_i w_i a_i,

with lambda_i = -R_i . m_i the body's reaction on node i where it is held (0 elsewhere;
`cloth.solvers.common.body_push`: m_i = n_i, or n_h / |n_h|^2 at a sliding edge node), a_i its
deformed tributary area and w_i the band's weight (the kernel averaged over node i's span of
height). At an equilibrium P R(x, theta) = 0, the moves its constraints allow (the projector
P, the body's contact set held fixed, as the Newton step holds it), a change of the pattern
moves the garment by dx = M^-1 P dR/dtheta dtheta, M the exact constrained Newton matrix
(`cloth.solvers.stability.exact_matrix`: the stiffness less the contact's curvature term, in
the allowed directions). So

    dJ/dtheta = partial J/partial theta + mu^T P partial R/partial theta,   M mu = dJ/dx,

one solve per girth line with M's factor, whatever the number of knots:

* dJ/dx = (dN/dx - J dD/dx) / D: lambda's through the stiffness K v (v_i = w_i m_i / D, one
  product with the sparse K) and through the normal's turn on the curved body (the Hessian H
  of the signed distance); the areas' through the cells' cross products; the weights' through
  the heights of the nodes' spans (`cloth.results.bands.BandWeights.chain`), with
  (lambda_i - J a_i) / D;
* partial R / partial theta: each spring's force sigma(eps) A along it changes with its rest
  length L0 (by -sigma'(eps) A l / L0^2) and its area A (by sigma); L0 and A of every spring
  come from the pattern (`cloth.garment.predeform.recut`) by central differences in the row
  reductions (exact to rounding: they are smooth in them), the row reductions from the knots by
  `cloth.case.profile.Profile.row_sensitivity`;
* partial J / partial theta at fixed x = -v . partial R/partial theta.

Edges: a fixed edge row's nodes are not moved (P removes them); a sliding edge row's height is
held (P removes the vertical), its reaction taken from the horizontal balance. Smooth bodies
without skin models only (`cloth.solvers.stability.counts`): faceted contact switches faces
under the garment and the skin models' lagged quantities are not differentiated.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from cloth.bodies import Body
from cloth.case.reading import Reading
from cloth.garment.grid import SLIDING, Grid, node_area
from cloth.garment.mechanics import operators
from cloth.garment.predeform import recut
from cloth.garment.state import State
from cloth.results.bands import band_weights
from cloth.results.landmarks import band_half_widths, girth_line
from cloth.solvers.activeset import held_nodes
from cloth.solvers.linear import lu_factor
from cloth.solvers.newton import newton_matrix, stiffness_at
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.stability import counts

log = logging.getLogger(__name__)

#: Step of the central differences of the rest lengths and areas in the row reductions.
RECUT_STEP = 1e-6
#: Refinement steps of the adjoint solve with an older factor, and the residual that stops them.
REFINEMENTS = 8
REFINED = 1e-13


@dataclass(frozen=True)
class Sensitivity:
    """Girth-line means and their derivatives in the profile's knot values.

    lines : (L,) str; knots : (K,) str
    means : (L,) float, Pa
    jacobian : (L, K) float, Pa per unit reduction: d(mean pressure) / d(knot value)
    """

    lines: tuple[str, ...]
    knots: tuple[str, ...]
    means: NDArray[np.float64]
    jacobian: NDArray[np.float64]


@dataclass(frozen=True)
class LineGradient:
    """One girth line's mean J (Pa), v ((N, 3): the weights of -R in J at fixed x) and dJ/dx
    ((N, 3), Pa m-1)."""

    value: float
    weights: NDArray[np.float64]
    gradient: NDArray[np.float64]


def reaction_direction(normal: NDArray[np.float64], constraint: NDArray[np.int8]) -> NDArray:
    """(N, 3): m_i with lambda_i = -R_i . m_i (`cloth.solvers.common.body_push`)."""
    m = normal.copy()
    sliding = np.flatnonzero(constraint == SLIDING)
    horizontal = normal[sliding].copy()
    horizontal[:, 2] = 0.0
    squared = np.einsum("ij,ij->i", horizontal, horizontal)
    steep = squared > 1e-12
    m[sliding[steep]] = horizontal[steep] / squared[steep, None]
    return m


def _direction_turn(normal, constraint, hessian_blocks) -> NDArray[np.float64]:
    """(N, 3, 3): dm_i/dx_i, the reaction direction's turn as the node slides on the body."""
    turn = hessian_blocks.copy()
    sliding = np.flatnonzero(constraint == SLIDING)
    for row in sliding:
        n = normal[row]
        h = np.array([n[0], n[1], 0.0])
        s = float(h @ h)
        if s <= 1e-12:
            continue
        m = h / s
        e = np.diag([1.0, 1.0, 0.0])
        turn[row] = ((e - 2.0 * np.outer(m, h)) / s) @ hessian_blocks[row]
    return turn


def _area_gradient(x: NDArray[np.float64], grid: Grid, weight: NDArray) -> NDArray[np.float64]:
    """(N, 3): the gradient of sum_i weight_i a_i (`cloth.garment.grid.node_area`)."""
    pts = x.reshape(grid.m, grid.n, 3)
    w = weight.reshape(grid.m, grid.n)
    cols = np.arange(grid.n if grid.closed else grid.n - 1)
    nxt_cols = (cols + 1) % grid.n
    here, nxt = pts[:, cols], pts[:, nxt_cols]
    d1 = nxt[1:] - here[:-1]
    d2 = here[1:] - nxt[:-1]
    c = np.cross(d1, d2)
    norm = np.linalg.norm(c, axis=2, keepdims=True)
    unit = np.divide(c, norm, out=np.zeros_like(c), where=norm > 0)
    share = 0.25 * (w[:-1][:, cols] + w[:-1][:, nxt_cols] + w[1:][:, cols] + w[1:][:, nxt_cols])
    g1 = 0.5 * share[..., None] * np.cross(d2, unit)  # dA/dd1
    g2 = 0.5 * share[..., None] * np.cross(unit, d1)  # dA/dd2
    out = np.zeros((grid.m, grid.n, 3))
    rows = np.arange(grid.m - 1)[:, None]
    np.add.at(out, (rows + 1, nxt_cols[None, :]), g1)
    np.add.at(out, (rows, cols[None, :]), -g1)
    np.add.at(out, (rows + 1, cols[None, :]), g2)
    np.add.at(out, (rows, nxt_cols[None, :]), -g2)
    return out.reshape(-1, 3)


def line_gradient(
    problem: Problem,
    ev: Evaluation,
    k: sp.csr_matrix,
    height: float,
    turn: NDArray,
    area: NDArray,
    m: NDArray,
    reading: Reading,
) -> LineGradient | None:
    """The girth line at ``height`` (m): its band mean and dJ/dx (module docstring); None where
    the line is beyond the garment. ``k``: the exact stiffness ((3N, 3N), N m-1); the same for
    every line: ``turn`` ((N, 3, 3) m-1, `_direction_turn`), ``area`` ((N,) m2,
    `cloth.garment.grid.node_area`), ``m`` ((N, 3), `reaction_direction`) and ``reading``
    (the band, `cloth.case.reading.Reading`)."""
    grid = problem.grid
    rows_z = ev.x.reshape(grid.m, grid.n, 3)[..., 2].mean(axis=1)
    if girth_line(rows_z, height) is None:
        return None
    held = ev.on_body
    push = np.where(held, -np.einsum("ij,ij->i", ev.loads, m), 0.0)  # the contact force f_i
    band = band_weights(ev.x[:, 2], (grid.m, grid.n), height, reading)
    weight = band.value
    total = float(weight @ area)  # D, the band's area
    if total <= 0:
        return None
    value = float(weight @ push) / total  # J = N / D
    c = np.where(held, weight / total, 0.0)
    v = c[:, None] * m
    gradient = (k @ v.ravel()).reshape(-1, 3)
    gradient -= c[:, None] * np.einsum("nji,nj->ni", turn, ev.loads)
    gradient += _area_gradient(ev.x, grid, -value * weight / total)
    gradient[:, 2] += band.chain((push - value * area) / total)  # the weights move with z
    return LineGradient(value, v, gradient)


def force_derivatives(
    state: State, ev: Evaluation, row_derivative: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(K, N, 3) N per unit: partial R / partial theta_k at fixed x, from ``row_derivative``
    ((m, K): d r_j / d theta_k) and the recut pattern (module docstring)."""
    grid = state.grid
    row_reduction = state.row_values("row_reduction")
    springs = ev.springs
    incidence_t = operators(grid).incidence_t
    out = np.empty((row_derivative.shape[1], grid.n_nodes, 3))
    for k in range(row_derivative.shape[1]):
        step = RECUT_STEP * row_derivative[:, k]
        up = recut(state, row_reduction + step)
        down = recut(state, row_reduction - step)
        d_rest = (up.rest_length - down.rest_length) / (2 * RECUT_STEP)
        d_area = (up.area - down.area) / (2 * RECUT_STEP)
        d_force = (
            -springs.tangent * grid.area * springs.length / grid.rest_length**2 * d_rest
            + springs.stress * d_area
        )
        out[k] = -(incidence_t @ (d_force[:, None] * springs.direction))
    return out


def sensitivities(
    state: State,
    body: Body,
    ev: Evaluation,
    heights: dict[str, float],
    factor=None,
    bands: Sequence[int] = (),
    knots: bool = True,
) -> Sensitivity:
    """The girth lines' means at the equilibrium ``ev`` of ``state`` on ``body`` and their
    derivatives in the profile's knot values (module docstring). ``factor``: a factor of the
    exact Newton matrix at or near ``ev`` (the run's own, `cloth.solvers.saddle.kept_factor`),
    refined against the matrix at ``ev`` (no factorisation); else one is made.

    A garment's bands (`cloth.case.pieces`) are cut with their own reductions, which the
    profile does not move; ``bands``: the bands (indices) whose reductions are controls too,
    after the knots (``knots`` False: the bands' alone). A band line is read over its own
    width (`cloth.results.landmarks.band_half_widths`), as result.nc reads it."""
    problem = Problem.of(state, body)
    if not counts(problem):
        raise ValueError(
            "sensitivities take a smooth body without tissue or friction (faceted contact and "
            "the skin models are not differentiated)"
        )
    k = stiffness_at(problem, ev)
    held = held_nodes(problem, ev, k)
    projector, _ = problem.basis(ev.x, ev.normal, held)
    matrix = newton_matrix(problem, ev, held, projector, k(False))
    hessian_blocks = np.zeros((state.grid.n_nodes, 3, 3))
    on = np.flatnonzero(ev.on_body)
    if on.size:
        hessian_blocks[on] = body.hessian(ev.closest[on])
    profile = state.case.garment.reduction_profile
    marks = {**state.body.get("landmarks", {}), **state.case.landmarks}
    rows = profile.row_sensitivity(state.row_values("cut_height"), marks)
    names_of = list(profile.keys)
    band = state.row_values("row_band")
    if band is not None:
        rows = np.where(band[:, None] >= 0, 0.0, rows)  # the profile leaves bands be
    if not knots:
        rows, names_of = rows[:, :0], []
    if bands:
        rows = np.column_stack([rows, *[(band == k).astype(float) for k in bands]])
        names_of += [f"band_{state.case.garment.pieces.bands[k].name}" for k in bands]
    d_forces = force_derivatives(state, ev, rows)  # (K, N, 3)
    projected = np.einsum("nij,knj->kni", projector, d_forces).reshape(len(d_forces), -1)
    if factor is None:
        factor = lu_factor(matrix)
    turn = _direction_turn(ev.normal, problem.constraint, hessian_blocks)  # once, not per line
    area = node_area(ev.x, state.grid)
    direction = reaction_direction(ev.normal, problem.constraint)
    names, means, jac = [], [], []
    widths = band_half_widths(state)
    for name, height in sorted(heights.items(), key=lambda item: item[1]):
        reading = state.case.reading
        if name in widths:
            reading = replace(reading, half_width=widths[name])
        line = line_gradient(problem, ev, k(False), height, turn, area, direction, reading)
        if line is None:
            continue
        mu = _refined_solve(matrix, factor, line.gradient.ravel())
        direct = -np.einsum("ni,kni->k", line.weights, d_forces)
        names.append(name)
        means.append(line.value)
        jac.append(direct + projected @ mu)
    return Sensitivity(tuple(names), tuple(names_of), np.asarray(means), np.asarray(jac))


def _refined_solve(matrix: sp.csr_matrix, factor, rhs: NDArray[np.float64]) -> NDArray:
    """``matrix`` x = ``rhs`` with ``factor`` of it (or of a matrix near it), refined."""
    x = factor.solve(rhs)
    scale = float(np.linalg.norm(rhs)) or 1.0
    for _ in range(REFINEMENTS):
        residual = rhs - matrix @ x
        if np.linalg.norm(residual) <= REFINED * scale:
            break
        x = x + factor.solve(residual)
    return x
