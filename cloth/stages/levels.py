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
So where the case's solver has continuation and its grid would be coarsened (`ladder`), the
levels take continuation's place (`relax_ladder`): the coarsest is relaxed as a user asking
for it would be (from its own pre-deformation, with its own continuation), each finer one
starts from the equilibrium below it (`cloth.solvers.continuation.carry_contact`, as
continuation starts a grid), and the case's grid from the finest level's. Each is relaxed to
the case's tolerance, so its equilibrium is the one a user asking for that grid gets (to the
tolerance; `tests/test_levels.py` compares them), and the fine grid's own coarse levels are
not solved again.
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
from cloth.results.landmarks import Landmark, band_half_widths, landmark_heights, landmarks
from cloth.results.richardson import estimate_levels
from cloth.solvers import Diverged, continuation, relax
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
    reading, widths = state.case.reading, band_half_widths(state)
    return tuple(landmarks(heights, final.x, fields, state.grid, reading, widths))


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


@dataclass(frozen=True)
class Solved:
    """One level relaxed: its initial ``state``, its ``result`` (None where it diverged) and
    the ``seconds`` its pre-deformation and relaxation took."""

    state: State
    result: Result | None
    seconds: float

    def level(self, heights: dict[str, float], body: Body) -> Level:
        """This level's girth lines at the fine grid's ``heights`` (m); none where it diverged."""
        grid = (self.state.grid.n, self.state.grid.m)
        if self.result is None:
            return Level(grid, (), False, self.seconds)
        marks = girth_marks(self.state, self.result.final, heights, body)
        return Level(grid, marks, self.result.converged, self.seconds)


def solve_level(
    state: State,
    body: Body,
    settings: Settings,
    grid: tuple[int, int],
    pattern: BodyCut | TableCut | None = None,
    below: Solved | None = None,
) -> Solved:
    """``state``'s case on ``grid``: pre-deformed and relaxed (no progress bar); started from
    the equilibrium of the level ``below`` where it is given and converged (`relax_ladder`), else
    from its own pre-deformation. ``pattern``: the garment's (`cloth.stages.cuts.state_cut`),
    where the case gives one."""
    start = time.perf_counter()
    coarse = predeform(
        state.case,
        state.fabric,
        body,
        state.body,
        grid=grid,
        pattern=pattern,
        fabrics=state.fabrics,
    )
    settings = replace(settings, progress=False)
    try:
        if below is not None and below.result is not None:
            result = relax_above(coarse, below.state, below.result, body, settings)
        else:
            result = relax(coarse, body, settings)
    except Diverged as failure:
        log.warning("levels: the %d x %d level diverged (%s): no error estimate", *grid, failure)
        return Solved(coarse, None, time.perf_counter() - start)
    seconds = time.perf_counter() - start
    log.info(
        "levels: %d x %d relaxed in %d iterations (residual %.2e), %.2f s",
        *grid,
        result.iterations,
        result.final.residual,
        seconds,
    )
    return Solved(coarse, result, seconds)


def relax_above(
    state: State, below: State, result: Result, body: Body, settings: Settings
) -> Result:
    """``state`` relaxed from the coarser equilibrium ``result`` of ``below``, carried up as
    continuation starts a grid (`cloth.solvers.continuation.carry_contact`), in place of its
    own continuation."""
    final = result.final
    x = continuation.carry_contact(final.x, final.on_body, below.grid, state, body)
    return relax(state.with_positions(x), body, replace(settings, continuation=False))


def ladder(state: State, settings: Settings) -> bool:
    """Whether ``state``'s relaxation would start from coarser grids of its own
    (`cloth.solvers.continuation`): its solver has continuation and its grid is coarsened.
    Then its error levels take their place (`relax_ladder`)."""
    return (
        settings.continuation
        and continuation.uniform_rows(state)
        and bool(continuation.levels(state.grid, settings.coarsest))
    )


def relax_ladder(
    state: State, body: Body, settings: Settings, count: int
) -> tuple[Result, list[Solved]]:
    """``state`` relaxed, with its ``count`` coarser levels (finest first) as its continuation
    (module docstring; where `ladder` holds): the coarsest relaxed first, each finer grid,
    ``state``'s last, started from the one below. Raises `Diverged` where ``state``'s grid
    diverges."""
    below: Solved | None = None
    solved = []
    pattern = state_cut(state)
    for grid in reversed(level_grids(state, count)):
        below = solve_level(state, body, settings, grid, pattern, below)
        solved.append(below)
    if below is None or below.result is None:
        return relax(state, body, settings), solved[::-1]
    return relax_above(state, below.state, below.result, body, settings), solved[::-1]


def relax_levels(
    state: State, body: Body, settings: Settings, heights: dict[str, float], count: int
) -> list[Level]:
    """The ``count`` coarser levels of ``state``'s grid (`coarser_grids` at the case's
    ``garment.level_ratio``), finest first."""
    pattern = state_cut(state)
    return [
        solve_level(state, body, settings, grid, pattern).level(heights, body)
        for grid in level_grids(state, count)
    ]


def level_grids(state: State, count: int) -> list[tuple[int, int]]:
    """The grids of ``state``'s ``count`` coarser levels (`coarser_grids` at the case's
    ``garment.level_ratio``), finest first; none (with a warning) where fewer than two fit
    (one level shows no order)."""
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
    return grids if len(grids) >= 2 else []


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
    pass ``cap`` nodes. Where `ladder` holds, each grid starts from the equilibrium below it,
    in place of its own continuation. A grid that diverges ends the refinement on the one
    before (`Diverged` from the first)."""
    runs: list[tuple[State, Result]] = []
    pattern = state_cut(start)
    state, met, worst, which = start, "node cap", math.inf, "fewer than three grids"
    while True:
        try:
            if runs and ladder(state, settings):  # the grid below as its continuation
                result = relax_above(state, *runs[-1], body, settings)
            else:
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
        state = predeform(
            start.case,
            start.fabric,
            body,
            start.body,
            grid=(n, m),
            pattern=pattern,
            fabrics=start.fabrics,
        )
    state, result = runs[-1]
    heights = landmark_heights(state.with_positions(result.final.x))
    return Refined(state, result, _levels(runs, heights, body), met, worst)


def _levels(runs: list[tuple[State, Result]], heights: dict[str, float], body: Body) -> list[Level]:
    """The levels below the last of ``runs`` (finest first), summarised at its ``heights``."""
    return [
        Level((s.grid.n, s.grid.m), girth_marks(s, r.final, heights, body), r.converged, r.seconds)
        for s, r in reversed(runs[:-1])
    ]
