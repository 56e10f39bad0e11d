"""Putting nodes on the body hands its query on: what `Problem.settle` returns is the body's
query at the settled positions, so an evaluation need not query again."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from cloth.bodies import MeshBody
from cloth.bodies.implicit import _kkt_step
from cloth.bodies.torso import chart_size, torso_mesh
from cloth.files.body import body_from_config
from cloth.garment.grid import SLIDING
from cloth.solvers.problem import Problem
from cloth.stages.case import initial_state

BODIES = {
    "smooth torso": {"torso": {"size": "M"}},
    "cylinder": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 1.5}},
    "cone": {"cone": {"radius_bottom": 0.14, "radius_top": 0.08, "bottom": 0.6, "top": 1.5}},
}


def _state(block: dict):
    garment = {"bottom": 0.95, "top": 1.10, "reduction": 0.15, "grid": [32, 8], "edges": "sliding"}
    return initial_state({"material": "powernet", "body": block, "garment": garment})


def _bodies():
    for name, block in BODIES.items():
        state = _state(block)
        yield pytest.param(state, body_from_config(state.case.body.block)[0], id=name)
    state = _state(BODIES["smooth torso"])
    yield pytest.param(state, MeshBody(*torso_mesh(chart_size("M"), 64, 60)), id="torso mesh")


@pytest.mark.parametrize(("state", "body"), list(_bodies()))
def test_settled_query_is_the_query_at_the_settled_positions(state, body):
    """Nodes pushed in and out by up to 3 mm, every third held: the query `settle` returns
    matches a fresh query of its positions (distances and closest points to 1e-12 m, normals
    to 1e-9), moved nodes are on the surface and at their heights when sliding, and the
    positions are `project_out`'s."""
    problem = Problem(state.grid, body, state.constraint)
    rng = np.random.default_rng(7)
    x = state.x + rng.uniform(-3e-3, 3e-3, state.x.shape)
    hold = np.arange(len(x)) % 3 == 0
    settled, (distance, closest, normal) = problem.settle(x, hold)
    fresh = body.query(settled)
    np.testing.assert_allclose(distance, fresh[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(closest, fresh[1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(normal, fresh[2], rtol=0, atol=1e-9)
    moved = hold | (body.query(x)[0] < 0.0)
    assert moved.sum() > len(x) // 3  # some nodes were inside as well as the held ones
    assert np.abs(fresh[0][moved]).max() < 1e-9
    sliding = state.constraint == SLIDING
    np.testing.assert_array_equal(settled[sliding, 2], x[sliding, 2])
    np.testing.assert_array_equal(settled, problem.project_out(x, hold))
    np.testing.assert_array_equal(settled[~moved], x[~moved])


def test_kkt_step_solves_the_bordered_system():
    """The closed-form step of the closest-point Newton solves [[A, g], [g^T, 0]] like LAPACK,
    and a singular system (g = 0) gives NaN, not a number."""
    rng = np.random.default_rng(3)
    count = 500
    h = rng.normal(size=(count, 3, 3))
    a = np.eye(3) + 0.2 * (h + h.transpose(0, 2, 1))
    g, r, c = rng.normal(size=(count, 3)), rng.normal(size=(count, 3)), rng.normal(size=count)
    bordered = np.zeros((count, 4, 4))
    bordered[:, :3, :3], bordered[:, :3, 3], bordered[:, 3, :3] = a, g, g
    expected = np.linalg.solve(bordered, np.column_stack([r, c])[..., None])[..., 0]
    np.testing.assert_allclose(_kkt_step(a, g, r, c), expected, rtol=1e-9, atol=1e-9)
    g[0] = 0.0
    step = _kkt_step(a, g, r, c)
    assert np.all(np.isnan(step[0])) and np.all(np.isfinite(step[1:]))


def test_kkt_step_of_an_overflowing_system_is_nan_and_silent():
    """A trial point far off a fitted surface gives a Hessian of 1e160: its step is NaN (the
    fallback's), the others' are unchanged, and numpy prints no overflow warning."""
    rng = np.random.default_rng(4)
    a = np.broadcast_to(np.eye(3), (3, 3, 3)).copy()
    g, r, c = rng.normal(size=(3, 3)), rng.normal(size=(3, 3)), rng.normal(size=3)
    expected = _kkt_step(a, g, r, c)
    a[1] *= 1e160
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        step = _kkt_step(a, g, r, c)
    assert np.all(np.isnan(step[1]))
    np.testing.assert_array_equal(step[[0, 2]], expected[[0, 2]])
