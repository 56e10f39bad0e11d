"""Coarse-to-fine continuation reaches the equilibrium plain Newton reaches, in fewer fine steps."""

from __future__ import annotations

import numpy as np
import pytest

from cloth.files.body import body_from_config
from cloth.garment.grid import WARP, WEFT
from cloth.solvers import Settings, relax
from cloth.solvers.continuation import coarse_state, levels
from cloth.stages.case import initial_state
from tests.conftest import assert_quadratic_tail

TORSO = {"torso": {"size": "M"}}
ELLIPSE = {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}


def state_on(body: dict, grid: list[int], bottom: float, top: float):
    garment = {"bottom": bottom, "top": top, "reduction": 0.15, "grid": grid, "edges": "sliding"}
    return initial_state({"material": "powernet", "body": body, "garment": garment})


def test_a_coarse_level_is_the_same_pattern():
    """Each coarse row keeps its fine row's rest circumference and height: its weft springs'
    rest lengths sum to the fine row's, its warp springs span the fine rows between."""
    state = state_on(TORSO, [96, 48], 0.80, 1.25)
    assert [(n, rows.size) for n, rows in levels(state.grid, 1500)] == [(48, 24)]
    around, rows = levels(state.grid, 1500)[0]
    coarse = coarse_state(state, around, rows)
    fine, grid = state.grid, coarse.grid
    fine_rows = fine.rest_length[fine.family_slices[WEFT]].reshape(fine.m, fine.n).sum(axis=1)
    coarse_rows = grid.rest_length[grid.family_slices[WEFT]].reshape(grid.m, grid.n).sum(axis=1)
    np.testing.assert_allclose(coarse_rows, fine_rows[rows], rtol=1e-14)
    fine_height = fine.rest_length[fine.family_slices[WARP]].reshape(fine.m - 1, fine.n)[:, 0]
    coarse_height = grid.rest_length[grid.family_slices[WARP]].reshape(grid.m - 1, grid.n)[:, 0]
    np.testing.assert_allclose(coarse_height.sum(), fine_height.sum(), rtol=1e-14)
    assert rows[0] == 0 and rows[-1] == fine.m - 1  # the edge rows and their constraints
    np.testing.assert_array_equal(coarse.constraint[: grid.n], state.constraint[0])


@pytest.mark.parametrize(
    ("body", "grid", "bottom", "top", "coarsest"),
    [(TORSO, [96, 48], 0.80, 1.25, 1500), (ELLIPSE, [128, 24], 0.1, 0.4, 800)],
    ids=["torso", "ellipse"],
)
def test_continuation_reaches_the_same_equilibrium(body, grid, bottom, top, coarsest):
    """To relative residual 1e-10, with and without continuation: positions within 1e-9 m,
    the last steps quadratic, and fewer Newton iterations on the fine grid (torso 96 x 48:
    measured 13 plain, 8 after one coarse level)."""
    state = state_on(body, grid, bottom, top)
    solid, _ = body_from_config(state.case.body.block)
    results = {}
    for continued in (False, True):
        settings = Settings(
            tolerance=1e-10,
            max_iterations=60,
            progress=False,
            log_every=0,
            continuation=continued,
            coarsest=coarsest,
        )
        results[continued] = relax(state, solid, settings)
        assert results[continued].converged
        assert_quadratic_tail(results[continued].history.residual)
    gap = np.abs(results[True].final.x - results[False].final.x).max()
    assert gap < 1e-9
    assert results[True].iterations < results[False].iterations


def test_a_coarse_level_that_diverges_leaves_the_fine_start_as_it_was(monkeypatch):
    """A coarse level that fails is no reason to fail the run: the fine grid then starts from
    its own positions, as without continuation."""
    from cloth.solvers.common import Diverged, History
    from cloth.solvers.continuation import start_from_coarse

    state = state_on(TORSO, [96, 48], 0.80, 1.25)

    def diverge(level, body, settings):
        raise Diverged("the energy grew", level.x, History())

    settings = Settings(progress=False, continuation=True, coarsest=1500)
    assert start_from_coarse(state, body_from_config(TORSO)[0], settings, diverge) is state


@pytest.mark.parametrize(
    ("body", "grid", "bottom", "top", "fewer"),
    [(TORSO, [96, 48], 0.80, 1.25, True), (ELLIPSE, [128, 24], 0.1, 0.4, False)],
    ids=["torso", "ellipse"],
)
def test_reusing_factorisations_reaches_the_same_equilibrium(
    body, grid, bottom, top, fewer, monkeypatch
):
    """Newton with SuperLU's factor kept and GMRES on the next systems (``reuse``): the same
    positions within 1e-9 m at 1e-10, the last steps quadratic, and on the torso fewer
    factorisations (96 x 48: measured 18 plain, 8 reusing) with some systems solved by a kept
    factor. The ellipse converges in 4 steps, each too far from the last for its factor."""
    from cloth.solvers import newton

    steppers = []
    made = newton.Newton.__init__

    def keep(self, *args, **kwargs):
        made(self, *args, **kwargs)
        steppers.append(self)

    monkeypatch.setattr(newton.Newton, "__init__", keep)
    state = state_on(body, grid, bottom, top)
    solid, _ = body_from_config(state.case.body.block)
    results = {}
    for reuse in (False, True):
        settings = Settings(
            tolerance=1e-10,
            max_iterations=60,
            progress=False,
            log_every=0,
            linear_solver="superlu",
            reuse=reuse,
        )
        results[reuse] = relax(state, solid, settings)
        assert results[reuse].converged
        assert_quadratic_tail(results[reuse].history.residual)
    assert np.abs(results[True].final.x - results[False].final.x).max() < 1e-9
    krylov = steppers[-1].reuse.krylov
    assert krylov.count(0) == results[True].factorisations <= results[False].factorisations
    if fewer:
        assert results[True].factorisations < results[False].factorisations and max(krylov) > 0
