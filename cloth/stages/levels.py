"""Grid levels: the case's garment relaxed again on coarser grids, for the error estimate.

A case of n x m nodes is relaxed on its own grid and on ``garment.levels`` coarser ones (2 by
default), each halving n and m (rounded up: 48 x 24 -> 24 x 12 -> 12 x 6), down to at least
`MIN_AROUND` nodes around and `MIN_ROWS` rows. A level is the case itself with the coarser
grid, pre-deformed on the same body and fabric and relaxed with the same settings: exactly what
a user would get by asking for that grid. Each level's girth lines are summarised at the same
heights as the fine grid's (`cloth.results.landmarks`), and `cloth.results.richardson` turns the
three finest values into the reported value's order, extrapolation and error
(`cloth.files.levels` writes them).

Continuation's own levels are not these: they keep a subset of the fine grid's rows, unevenly
spaced where m - 1 is odd (a pattern a user could not ask for), and are relaxed only to 1e-6.
A level costs about a quarter of the grid above it, so two levels add about a third.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace

from cloth.bodies import Body
from cloth.case import Case, Settings
from cloth.garment.predeform import predeform
from cloth.garment.state import State
from cloth.results.fields import node_fields
from cloth.results.landmarks import Landmark, landmarks
from cloth.solvers import Diverged, relax
from cloth.solvers.problem import Evaluation

log = logging.getLogger(__name__)

#: Coarser levels relaxed for a case's error estimate (three grids in all).
LEVELS = 2
#: Smallest level: nodes around and rows.
MIN_AROUND, MIN_ROWS = 8, 3


@dataclass(frozen=True)
class Level:
    """One grid's girth-line summaries: its ``grid`` (n, m), the `Landmark` of each line (at the
    fine grid's heights; empty where the level diverged), whether it ``converged``, and the
    ``seconds`` it took."""

    grid: tuple[int, int]
    marks: tuple[Landmark, ...]
    converged: bool
    seconds: float


def coarser_grids(grid: tuple[int, int], count: int) -> list[tuple[int, int]]:
    """Up to ``count`` grids below ``grid`` (n, m), finest first, each halving n and m (rounded
    up), none below `MIN_AROUND` x `MIN_ROWS`."""
    n, m = grid
    out: list[tuple[int, int]] = []
    for _ in range(count):
        n, m = -(-n // 2), -(-m // 2)
        if n < MIN_AROUND or m < MIN_ROWS:
            break
        out.append((n, m))
    return out


def with_grid(case: Case, grid: tuple[int, int]) -> Case:
    """``case`` with the garment's grid replaced (its mapping too, so that it writes back)."""
    data = case.to_dict()
    data["garment"]["grid"] = [int(grid[0]), int(grid[1])]
    return Case.from_dict(data)


def girth_marks(state: State, final: Evaluation, heights: dict[str, float]) -> tuple[Landmark, ...]:
    """The girth-line summaries of ``state``'s grid at the equilibrium ``final``."""
    fields = node_fields(
        state.grid, final.x, final.springs, state.fabric.thickness, final.forces,
        final.unbalanced, final.on_body, final.normal, state.constraint,
    )  # fmt: skip
    return tuple(landmarks(heights, final.x, fields, state.grid))


def relax_level(
    state: State, body: Body, settings: Settings, grid: tuple[int, int], heights: dict[str, float]
) -> Level:
    """``state``'s case on ``grid``: pre-deformed, relaxed (no progress bar) and summarised at
    ``heights`` (m); a level that diverges has no marks (its estimate says so)."""
    start = time.perf_counter()
    coarse = predeform(with_grid(state.case, grid), state.fabric, body, state.body)
    try:
        result = relax(coarse, body, replace(settings, progress=False))
    except Diverged as failure:
        log.warning("levels: the %d x %d level diverged (%s): no error estimate", *grid, failure)
        return Level(grid, (), False, time.perf_counter() - start)
    seconds = time.perf_counter() - start
    log.info(
        "levels: %d x %d relaxed in %d iterations (residual %.2e), %.2f s", *grid,
        result.iterations, result.final.residual, seconds,
    )  # fmt: skip
    return Level(grid, girth_marks(coarse, result.final, heights), result.converged, seconds)


def relax_levels(
    state: State, body: Body, settings: Settings, heights: dict[str, float], count: int
) -> list[Level]:
    """The ``count`` coarser levels of ``state``'s grid (`coarser_grids`), finest first."""
    grids = coarser_grids((state.grid.n, state.grid.m), count)
    if count and len(grids) < count:
        log.warning(
            "levels: a %d x %d grid has %d coarser level%s of at least %d x %d, not %d: no error "
            "estimate", state.grid.n, state.grid.m, len(grids), "" if len(grids) == 1 else "s",
            MIN_AROUND, MIN_ROWS, count,
        )  # fmt: skip
    if len(grids) < 2:  # one level shows no order
        return []
    return [relax_level(state, body, settings, grid, heights) for grid in grids]
