"""Grid levels: the case's garment relaxed again on coarser grids, for the error estimate.

A case of n x m nodes (with ``garment.error_estimate``, the default) is relaxed on its own grid
and on `LEVELS` (2) coarser ones, the k-th with n and m divided by ``garment.level_ratio`` r to
the k (rounded up; r = 2: 48 x 24 -> 24 x 12 -> 12 x 6), down to at least `MIN_AROUND` nodes
around and `MIN_ROWS` rows. A ratio nearer 1 keeps the coarsest level nearer the finest, in the
range where the error falls as h^2, at more time: the levels cost about r^-2 + r^-4 of the grid
(0.31 at 2, 0.75 at 1.41); docs/validation.md measures both on the edge lines and the
stocking. A level is the case itself with the coarser grid, pre-deformed on the same body and
fabric and relaxed with the same settings: exactly what a user would get by asking for that
grid. Each level's girth lines are summarised at the same heights as the fine grid's
(`cloth.results.landmarks`), and `cloth.results.richardson` turns the three finest values into
the reported value's order, extrapolation and error (`cloth.files.levels` writes them).

Continuation's own levels are not these: they keep a subset of the fine grid's rows, unevenly
spaced where m - 1 is odd (a pattern a user could not ask for), and are relaxed only to 1e-6.
At r = 2 a level costs about a quarter of the grid above it, so two levels add about a third.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, replace

from cloth.bodies import Body
from cloth.case import Settings
from cloth.garment.cut import BodyCut, TableCut
from cloth.garment.predeform import predeform
from cloth.garment.state import State
from cloth.results.fields import Fields, node_fields
from cloth.results.landmarks import Landmark, landmark_heights, landmarks
from cloth.results.richardson import estimate_levels
from cloth.solvers import Diverged, relax
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.relax import Result
from cloth.stages.cuts import state_cut

log = logging.getLogger(__name__)

#: Coarser levels relaxed for a case's error estimate (three grids in all).
LEVELS = 2
#: Smallest level: nodes around and rows.
MIN_AROUND, MIN_ROWS = 8, 3
#: ``garment.level_ratio`` where the case gives none: n and m halved from level to level.
DEFAULT_RATIO = 2.0


@dataclass(frozen=True)
class Level:
    """One grid's girth-line summaries: its ``grid`` (n, m), the `Landmark` of each line (at the
    fine grid's heights; empty where the level diverged), whether it ``converged``, and the
    ``seconds`` it took."""

    grid: tuple[int, int]
    marks: tuple[Landmark, ...]
    converged: bool
    seconds: float


def coarser_grids(
    grid: tuple[int, int], count: int, ratio: float = DEFAULT_RATIO
) -> list[tuple[int, int]]:
    """Up to ``count`` grids below ``grid`` (n, m), finest first, the k-th with n and m divided
    by ``ratio`` (> 1) to the k, rounded up (``ratio`` 2: halving); none below `MIN_AROUND` x
    `MIN_ROWS`, and none that is not smaller than the one above in both n and m."""
    if not ratio > 1.0:
        raise ValueError(f"level ratio must exceed 1, got {ratio}")
    out: list[tuple[int, int]] = []
    above = grid
    for k in range(1, count + 1):
        scale = ratio**k
        # rounded to 1e-9 first: 289 / 1.7^2 is 100.00000000000001 in floats, a level of 100
        n, m = (math.ceil(round(v / scale, 9)) for v in grid)
        if n < MIN_AROUND or m < MIN_ROWS or n >= above[0] or m >= above[1]:
            break
        out.append((n, m))
        above = (n, m)
    return out


def reported(state: State, final: Evaluation, body: Body) -> Evaluation:
    """The evaluation result.nc reports at the equilibrium ``final`` (`cloth.stages.results`):
    where the case has friction, the problem rebuilt at the equilibrium, so each held node's
    reaction is the body's normal push alone. The relaxation's own final evaluation counts the
    friction force that holds a node in the reaction too, and its magnitude sqrt(lambda^2 +
    f_t^2) is up to sqrt(1 + mu^2) of the pressure (4.4 % at mu 0.3)."""
    if not state.skin.friction:
        return final
    return Problem.of(state.with_positions(final.x), body).evaluate(final.x)


def girth_marks(
    state: State, final: Evaluation, heights: dict[str, float], body: Body
) -> tuple[Landmark, ...]:
    """The girth-line summaries of ``state``'s grid at the equilibrium ``final`` on ``body``,
    as result.nc reports them (`reported`)."""
    final, fields = reported_fields(state, final, body)
    return tuple(landmarks(heights, final.x, fields, state.grid, state.case.reading))


def reported_fields(state: State, final: Evaluation, body: Body) -> tuple[Evaluation, Fields]:
    """The evaluation result.nc reports at the equilibrium ``final`` (`reported`) and its node
    fields (`cloth.results.fields.node_fields`)."""
    final = reported(state, final, body)
    fields = node_fields(
        state.grid,
        final.x,
        final.springs,
        state.fabric.thickness,
        final.forces,
        final.unbalanced,
        final.on_body,
        final.normal,
        state.constraint,
    )
    return final, fields


def relax_level(
    state: State,
    body: Body,
    settings: Settings,
    grid: tuple[int, int],
    heights: dict[str, float],
    pattern: BodyCut | TableCut | None = None,
) -> Level:
    """``state``'s case on ``grid``: pre-deformed, relaxed (no progress bar) and summarised at
    ``heights`` (m); a level that diverges has no marks (its estimate says so). ``pattern``:
    the garment's (`cloth.stages.cuts.state_cut`), where the case gives one."""
    start = time.perf_counter()
    coarse = predeform(state.case, state.fabric, body, state.body, grid=grid, pattern=pattern)
    try:
        result = relax(coarse, body, replace(settings, progress=False))
    except Diverged as failure:
        log.warning("levels: the %d x %d level diverged (%s): no error estimate", *grid, failure)
        return Level(grid, (), False, time.perf_counter() - start)
    seconds = time.perf_counter() - start
    log.info(
        "levels: %d x %d relaxed in %d iterations (residual %.2e), %.2f s",
        *grid,
        result.iterations,
        result.final.residual,
        seconds,
    )
    return Level(grid, girth_marks(coarse, result.final, heights, body), result.converged, seconds)


def relax_levels(
    state: State, body: Body, settings: Settings, heights: dict[str, float], count: int
) -> list[Level]:
    """The ``count`` coarser levels of ``state``'s grid (`coarser_grids` at the case's
    ``garment.level_ratio``), finest first."""
    ratio = state.case.garment.level_ratio
    grids = coarser_grids((state.grid.n, state.grid.m), count, ratio)
    if count and len(grids) < count:
        log.warning(
            "levels: a %d x %d grid has %d coarser level%s (level ratio %g) of at least %d x %d, "
            "not %d: no error estimate",
            state.grid.n,
            state.grid.m,
            len(grids),
            "" if len(grids) == 1 else "s",
            ratio,
            MIN_AROUND,
            MIN_ROWS,
            count,
        )
    if len(grids) < 2:  # one level shows no order
        return []
    pattern = state_cut(state)
    return [relax_level(state, body, settings, grid, heights, pattern) for grid in grids]


@dataclass(frozen=True)
class Refined:
    """What ``grid: auto`` found (`refine`): the finest grid's initial ``state`` and its
    relaxation ``result``, the ``levels`` below it (finest first), what ended the refinement
    (``met``: "accuracy" or "node cap") and the largest stated relative error of a girth-line
    mean on the finest grid (``worst``; inf where a line had none)."""

    state: State
    result: Result
    levels: list[Level]
    met: str
    worst: float


def worst_error(
    grid: tuple[int, int], marks: tuple[Landmark, ...], levels: list[Level]
) -> tuple[float, str]:
    """The largest stated error of a girth-line mean pressure of ``marks`` (on ``grid``),
    relative to the value (1), from the ``levels`` below it, and which line and why: (inf, the
    line and the reason) where a line has no estimate."""
    worst, which = (0.0, "") if marks else (math.inf, "no girth line on the garment")
    for mark in marks:
        values = [mark.mean] + [
            next((m.mean for m in lv.marks if m.name == mark.name), math.nan) for lv in levels
        ]
        estimate = estimate_levels(values, [grid, *(lv.grid for lv in levels)])
        if not estimate.observed:
            return math.inf, f"{mark.name}: no estimate ({estimate.reason})"
        if estimate.relative_error > worst:
            worst, which = estimate.relative_error, mark.name
    return worst, which


def refine(start: State, body: Body, settings: Settings, accuracy: float, cap: int) -> Refined:
    """``grid: auto``: relax ``start`` (the case on `cloth.garment.predeform.start_grid`), then
    the case on grids with n and m doubled, until the stated error of every girth-line mean
    (from the grid and the two below it) is at most ``accuracy`` (1), or the next grid would
    pass ``cap`` nodes. A grid that diverges ends the refinement on the one before (`Diverged`
    from the first)."""
    runs: list[tuple[State, Result]] = []
    pattern = state_cut(start)
    state, met, worst, which = start, "node cap", math.inf, "fewer than three grids"
    while True:
        try:
            result = relax(state, body, settings)
        except Diverged as failure:
            if not runs:
                raise
            log.warning(
                "grid auto: the %d x %d grid diverged (%s); the result is the grid before",
                state.grid.n,
                state.grid.m,
                failure,
            )
            break
        runs = [*runs[-2:], (state, result)]
        heights = landmark_heights(state.with_positions(result.final.x))
        levels = _levels(runs, heights, body)
        if len(levels) == 2:
            grid = (state.grid.n, state.grid.m)
            worst, which = worst_error(
                grid, girth_marks(state, result.final, heights, body), levels
            )
            log.info(
                "grid auto: %d x %d, largest stated error of a girth-line mean %.3g %% "
                "(%s; asked %.3g %%)",
                *grid,
                100 * worst,
                which,
                100 * accuracy,
            )
            if worst <= accuracy:
                met = "accuracy"
                log.info("grid auto: %d x %d meets the accuracy asked", *grid)
                break
        n, m = 2 * state.grid.n, 2 * state.grid.m
        if n * m > cap:
            log.warning(
                "grid auto: the next grid (%d x %d) would pass max_nodes %d; stopping at %d x %d "
                "with a largest stated error of %.3g %% (%s; asked %.3g %%)",
                n,
                m,
                cap,
                state.grid.n,
                state.grid.m,
                100 * worst,
                which,
                100 * accuracy,
            )
            break
        state = predeform(start.case, start.fabric, body, start.body, grid=(n, m), pattern=pattern)
    state, result = runs[-1]
    heights = landmark_heights(state.with_positions(result.final.x))
    return Refined(state, result, _levels(runs, heights, body), met, worst)


def _levels(runs: list[tuple[State, Result]], heights: dict[str, float], body: Body) -> list[Level]:
    """The levels below the last of ``runs`` (finest first), summarised at its ``heights``."""
    return [
        Level((s.grid.n, s.grid.m), girth_marks(s, r.final, heights, body), r.converged, r.seconds)
        for s, r in reversed(runs[:-1])
    ]
