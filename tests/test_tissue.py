"""Soft tissue (a Winkler layer under the skin) against its scalar solution on a cylinder."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from cloth.case import Tissue
from cloth.case.case import validate_case
from cloth.errors import InputError
from cloth.files.body import body_from_config
from cloth.garment.grid import WEFT, node_area
from cloth.results.pressure import contact_reaction
from cloth.solvers import Settings, relax
from cloth.solvers.newton import stiffness_at
from cloth.solvers.problem import Problem
from cloth.stages.case import initial_state

RADIUS, DEPTH, MODULUS, REDUCTION = 0.1, 0.02, 20e3, 0.2


def tube(tissue=None, n=128, m=4, reduction=REDUCTION):
    body = {"cylinder": {"radius": RADIUS, "bottom": 0.0, "top": 0.5}}
    if tissue is not None:
        body["tissue"] = tissue
    case = {
        "material": "powernet",
        "body": body,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": reduction,
            "grid": [n, m],
            "edges": "sliding",
        },
    }
    return initial_state(case)


def solve(state, tolerance=1e-10):
    body, _ = body_from_config(state.case.body.block)
    return relax(state, body, Settings(tolerance=tolerance, max_iterations=80, progress=False))


def pressure(state, result):
    ev = result.final
    reaction = contact_reaction(ev.forces, ev.unbalanced, ev.on_body)
    return np.linalg.norm(reaction, axis=1) / node_area(ev.x, state.grid)


def scalar_solution(state, modulus=MODULUS):
    """u = p h / E, r = R - u, T = sigma(2 pi r / C0 - 1) t, p = T / r, solved for u."""
    grid = state.grid
    c0 = float(grid.rest_length[grid.family_slices[WEFT]][0]) * grid.n
    thickness = state.fabric.thickness

    def pressure_of(u):
        r = RADIUS - u
        return float(state.fabric.weft.stress(np.array([2 * np.pi * r / c0 - 1]))[0]) * (
            thickness / r
        )

    u = brentq(lambda u: u - pressure_of(u) * DEPTH / modulus, 0.0, DEPTH)
    return RADIUS - u, pressure_of(u)


def test_a_tube_on_soft_tissue_sinks_to_the_scalar_solution():
    state = tube({"thickness": DEPTH, "modulus": MODULUS})
    result = solve(state)
    assert result.converged and result.lags >= 1
    r_expected, p_expected = scalar_solution(state)
    radius = np.hypot(result.final.x[:, 0], result.final.x[:, 1])
    p = pressure(state, result)
    assert np.all(result.final.on_body)
    np.testing.assert_allclose(radius, r_expected, rtol=5e-3)
    np.testing.assert_allclose(p, p_expected, rtol=5e-3)
    # the layer's law holds node by node: u = p h / E with the deformed areas
    np.testing.assert_allclose(result.final.indentation, p * DEPTH / MODULUS, rtol=1e-6)
    # and the indentation is what makes the answer differ from the rigid body's, by percents
    rigid = pressure(state, solve(tube()))
    assert p.mean() < 0.97 * rigid.mean()


@pytest.mark.slow  # two relaxations (10 s; make test-slow)
def test_a_stiff_layer_reproduces_the_rigid_answer():
    rigid = tube()
    p_rigid = pressure(rigid, solve(rigid))
    stiff = tube({"thickness": DEPTH, "modulus": 1e12})
    p_stiff = pressure(stiff, solve(stiff))
    np.testing.assert_allclose(p_stiff, p_rigid, rtol=1e-6)


def test_the_layer_stiffness_is_the_energy_hessian():
    """The Newton matrix's tissue part against central differences of the loads."""
    state = tube({"thickness": DEPTH, "modulus": MODULUS}, n=16, m=3)
    body, _ = body_from_config(state.case.body.block)
    problem = Problem.of(state, body)
    rng = np.random.default_rng(3)
    x = state.x.copy()
    x[:, :2] *= 0.97  # every node indents the layer
    x += 1e-4 * rng.standard_normal(x.shape)
    ev = problem.evaluate(x)
    k = stiffness_at(problem, ev)(False)
    step = 1e-7
    for node in (0, 5, 20):
        for axis in range(3):
            plus, minus = x.copy(), x.copy()
            plus[node, axis] += step
            minus[node, axis] -= step
            column = -(problem.evaluate(plus).loads - problem.evaluate(minus).loads) / (2 * step)
            np.testing.assert_allclose(
                k[:, 3 * node + axis].toarray().ravel(),
                column.ravel(),
                rtol=1e-5,
                atol=1e-6 * np.abs(column).max(),
            )


@pytest.mark.parametrize(
    ("tissue", "field"),
    [
        ({"thickness": -0.01, "modulus": 2e4}, "body.tissue.thickness"),
        ({"thickness": 0.01, "modulus": float("nan")}, "body.tissue.modulus"),
        ({"thickness": 0.01, "modulus": 0.0}, "body.tissue.modulus"),
        (
            {
                "thickness": 0.01,
                "modulus": 2e4,
                "bands": [
                    {"bottom": 0.1, "top": 0.3, "thickness": 0.01, "modulus": 1e4},
                    {"bottom": 0.2, "top": 0.4, "thickness": 0.01, "modulus": 1e4},
                ],
            },
            "body.tissue.bands[1]",
        ),
        (
            {
                "thickness": 0.01,
                "modulus": 2e4,
                "bands": [{"bottom": 0.3, "top": 0.6, "thickness": 0.01, "modulus": 1e4}],
            },
            "body.tissue.bands[0]",
        ),
    ],
)
def test_bad_tissue_is_refused_naming_the_field(tissue, field):
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1}, "tissue": tissue},
        "garment": {"bottom": 0.1, "top": 0.4, "grid": [8, 4], "reduction": 0.1},
    }
    with pytest.raises(InputError) as error:
        validate_case(case, "case.yaml")
    assert error.value.field == field and "case.yaml" in str(error.value)


def test_bands_give_their_layer_to_the_nodes_within_them():
    block = {
        "thickness": 0.01,
        "modulus": 2e4,
        "bands": [{"bottom": 0.2, "top": 0.3, "thickness": 0.03, "modulus": 5e3}],
    }
    thickness, modulus = Tissue.from_block(block, 0.1, 0.4).layers(np.array([0.15, 0.25, 0.35]))
    np.testing.assert_array_equal(thickness, [0.01, 0.03, 0.01])
    np.testing.assert_array_equal(modulus, [2e4, 5e3, 2e4])
