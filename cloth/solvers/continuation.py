"""Coarse-to-fine continuation: start a fine grid's Newton from a coarser grid's equilibrium.

Newton's cost is its factorisations, one per iteration, and most of its iterations on a fine
grid are spent getting from the wrapped pattern to near the equilibrium, where a coarser grid
of the same pattern would get as well. So the grid is coarsened (about halving n and m) until
it has at most ``Settings.coarsest`` nodes; the coarsest is relaxed from the pattern, and each
finer level starts from the level below's equilibrium, interpolated, and projected out of the
body: only its last, quadratic, Newton steps remain.

A coarse level is the same pattern: a tube of ceil(n/2) nodes around (at least 3), and
ceil(m/2) of the fine grid's rows (the first and the last always among them, so the edge rows
and their constraints carry over), each with its own rest circumference and height, so its
springs' rest lengths are the fine pattern's, summed. The coarse levels are relaxed to
`COARSE_TOLERANCE` (their equilibrium differs from the fine one's by the discretisation anyway).
Interpolation is bilinear in the pattern's coordinates (the fraction of the way around, and
the rest height v): a new node lands on the chord between coarse nodes, inside a convex body by
the chord's sagitta, and the projection out of the body puts it back on it; the seam column 0 is the
same material line on every level, and so is the turning gauge's node 0.

Contact carries over: a new node whose coarse neighbours (all four of the bilinear stencil) were
held by the body is put on the body too (`carry_contact`), where it would otherwise start
hovering above a concave stretch on the chord (the cleavage, the small of the back) and Newton
would spend its first iterations finding the contact set again. Measured on the torso case of
docs/performance.md: fine-grid Newton iterations 10 -> 6 at 192 x 96 and 12 -> 5 at 384 x 192.

Fixed nodes keep their positions and sliding nodes their heights (Newton does not move them
there, so interpolated ones would make another garment's equilibrium).

Only closed grids (tubes) with constraints uniform along each row are coarsened; otherwise the
fine grid starts from its own positions, as without continuation.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import Body
from cloth.case import Settings
from cloth.garment.grid import FIXED, SLIDING, WEFT, Grid, build_grid
from cloth.garment.pieces import garment_grid
from cloth.garment.state import State, grid_fabric
from cloth.solvers.common import Diverged
from cloth.solvers.problem import Problem

log = logging.getLogger(__name__)

#: relax(state, body, settings) -> a result with ``final.x``, ``final.residual``, ``iterations``
Relax = Callable[[State, Body, Settings], Any]

#: Relative residual the coarse levels are relaxed to.
COARSE_TOLERANCE = 1e-6
#: Smallest coarse grid: nodes around and rows.
MIN_AROUND, MIN_ROWS = 8, 3


def levels(grid: Grid, coarsest: int) -> list[tuple[int, NDArray[np.intp]]]:
    """The coarse levels below ``grid``, finest first: (nodes around, indices of the level
    above's rows that it keeps), halving until at most ``coarsest`` nodes (empty if ``grid``
    has no more than that, or is too small to halve)."""
    found = []
    n, m = grid.n, grid.m
    while n * m > coarsest:
        n_c, m_c = max(-(-n // 2), 3), -(-m // 2)
        if n_c < MIN_AROUND or m_c < MIN_ROWS:
            break
        keep = np.unique(np.round(np.linspace(0, m - 1, m_c)).astype(np.intp))
        found.append((n_c, keep))
        n, m = n_c, keep.size
    return found


def coarse_state(state: State, around: int, rows: NDArray[np.intp]) -> State:
    """``state``'s pattern on ``around`` nodes around and the fine rows ``rows`` (module
    docstring), its positions interpolated from ``state``'s."""
    grid = state.grid
    n = grid.n
    weft = grid.rest_length[grid.family_slices[WEFT]].reshape(grid.m, n)
    width = weft[:, 0] * n  # each row's rest circumference, m
    v = grid.rest_uv[np.arange(grid.m) * n, 1]
    coarse = build_grid(
        around,
        rows.size,
        width[rows],
        v[rows],
        grid_fabric(state.fabric, state.around),
        closed=True,
        **state.moduli,
    )
    attrs = dict(state.attrs)
    for key in ("cut_height", "row_band"):  # the kept rows' own
        values = state.row_values(key)
        if values is not None:
            attrs[key] = values[rows].tolist()
    if state.layout is not None:  # a garment of several fabrics: its pieces on this level too
        zone = state.row_values("row_band")
        zone = np.full(rows.size, -1) if zone is None else zone[rows].astype(int)
        coarse = garment_grid(
            coarse,
            state.layout,
            state.fabric,
            state.fabrics,
            state.row_values("cut_height")[rows],
            zone,
        )
    constraint = np.repeat(state.constraint.reshape(grid.m, n)[rows, 0], around)
    x = interpolate(state.x, grid, coarse)
    contact = np.zeros(coarse.n_nodes, dtype=np.int8)
    return replace(state, grid=coarse, x=x, constraint=constraint, on_body=contact, attrs=attrs)


def interpolate(x: NDArray[np.float64], source: Grid, target: Grid) -> NDArray[np.float64]:
    """Positions ((target N, 3), m) at ``target``'s nodes, bilinear in the pattern's
    coordinates (fraction around, rest height) from ``x`` ((source N, 3)) on ``source``."""
    n_s, n_t = source.n, target.n
    v_s = source.rest_uv[np.arange(source.m) * n_s, 1]
    v_t = target.rest_uv[np.arange(target.m) * n_t, 1]
    rows = x.reshape(source.m, n_s, 3)
    # around: target column i at fraction i / n_t, between source columns k and k + 1 (periodic)
    p = np.arange(n_t) * n_s / n_t
    k = np.floor(p).astype(np.intp)
    f = (p - k)[None, :, None]
    around = (1 - f) * rows[:, k % n_s] + f * rows[:, (k + 1) % n_s]  # (source m, n_t, 3)
    # along: target row at v, between source rows
    j = np.clip(np.searchsorted(v_s, v_t, side="right") - 1, 0, source.m - 2)
    g = ((v_t - v_s[j]) / (v_s[j + 1] - v_s[j]))[:, None, None]
    return ((1 - g) * around[j] + g * around[j + 1]).reshape(-1, 3)


def uniform_rows(state: State) -> bool:
    """Whether ``state`` can be coarsened: a tube whose constraints are uniform along rows."""
    grid = state.grid
    by_row = state.constraint.reshape(grid.m, grid.n)
    return bool(grid.closed) and bool(np.all(by_row == by_row[:, :1]))


def start_from_coarse(state: State, body: Body, settings: Settings, relax: Relax) -> State:
    """``state`` with its positions from the equilibrium of its coarse levels (module
    docstring); unchanged where it has none. ``settings``: the fine run's; ``relax``: how a
    level is relaxed (`cloth.solvers.relax.relax`, which calls this)."""

    found = levels(state.grid, settings.coarsest) if uniform_rows(state) else []
    if not found:
        return state
    coarse = replace(
        settings,
        continuation=False,
        tolerance=max(settings.tolerance, COARSE_TOLERANCE),
        progress=False,
    )
    ladder = [state]
    for around, rows in found:  # each level's rows index the level above's rows
        ladder.append(coarse_state(ladder[-1], around, rows))
    x, grid, held = None, None, None
    for level in reversed(ladder[1:]):
        start = time.perf_counter()
        if x is not None:
            level = level.with_positions(carry_contact(x, held, grid, level, body))
        try:
            result = relax(level, body, coarse)
        except Diverged as failure:
            log.warning(
                "continuation: the %d x %d level diverged (%s); the %d x %d grid starts from "
                "its own positions",
                level.grid.n,
                level.grid.m,
                failure,
                state.grid.n,
                state.grid.m,
            )
            return state
        log.info(
            "continuation: %d x %d relaxed in %d iterations (residual %.2e), %.2f s",
            level.grid.n,
            level.grid.m,
            result.iterations,
            result.final.residual,
            time.perf_counter() - start,
        )
        x, grid, held = result.final.x, level.grid, result.final.on_body
    return state.with_positions(carry_contact(x, held, grid, state, body))


def carry_contact(
    x: NDArray[np.float64], held: NDArray[np.bool_], source: Grid, target: State, body: Body
) -> NDArray[np.float64]:
    """``target``'s positions ((N, 3), m) from the coarser equilibrium ``x`` on ``source``
    (interpolated, `keep_constraints`), with every node whose coarse neighbours were all held
    (``held``, (source N,)) put on the body (`Problem.project_out`: a sliding node along its
    horizontal normal); with tissue, nothing is put on the skin."""
    placed = keep_constraints(interpolate(x, source, target.grid), target)
    if target.skin.tissue is not None:
        return placed  # the skin gives way: its nodes stay where the coarse answer sank them
    flags = interpolate(
        np.repeat(np.asarray(held, float)[:, None], 3, axis=1), source, target.grid
    )[:, 0]
    hold = (flags > 1.0 - 1e-9) & (target.constraint != FIXED)
    return Problem(target.grid, body, target.constraint).project_out(placed, hold)


def keep_constraints(x: NDArray[np.float64], state: State) -> NDArray[np.float64]:
    """``x`` with ``state``'s fixed nodes where they are and its sliding nodes at their own
    heights: Newton never moves those, so interpolated ones would be another garment's."""
    fixed, sliding = state.constraint == FIXED, state.constraint == SLIDING
    x = x.copy()
    x[fixed] = state.x[fixed]
    x[sliding, 2] = state.x[sliding, 2]
    return x
