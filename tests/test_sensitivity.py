"""The adjoint sensitivities of the girth-line means to the reduction profile (issue 30, item 2),
against central finite differences over full equilibria: 1e-5 relative on the cylinder, the
cone and the torso (96 x 48), with sliding and with fixed edges."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cloth.files.body import body_from_record
from cloth.results.landmarks import landmark_heights
from cloth.results.sensitivity import sensitivities
from cloth.solvers.linear import factorisations
from cloth.solvers.relax import relax
from cloth.stages.case import initial_state
from cloth.stages.design import finite_difference_jacobian, line_means

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
LINES = {"low": 0.18, "waist": 0.25, "high": 0.33}
KNOTS = {"0.15": 0.10, "waist": 0.22, "0.35": 0.15}
BODIES = {
    "cylinder": {"cylinder": {"radius": 0.1}},
    "cone": {"cone": {"radius_bottom": 0.12, "radius_top": 0.08, "bottom": 0.0, "top": 0.5}},
}
#: The equilibria's tolerance: tight, so that the differences measure the derivative.
TIGHT = {"tolerance": 1.0e-12, "max_iterations": 200}
#: Plain Newton (no continuation, no reuse): its last factor is of the exact matrix.
PLAIN = {**TIGHT, "continuation": False, "reuse": False}


def _case(body: str, edges: str) -> dict:
    if body == "torso":
        return {
            "material": "powernet",
            "body": {"torso": {"size": "M"}},
            "solver": PLAIN,
            "garment": {
                "bottom": 0.86,
                "top": 1.22,
                "grid": [96, 48],
                "edges": edges,
                "lengthwise_reduction": 0.05,
                "reduction": {"hip": 0.15, "waist": 0.22, "underbust": 0.2, "bust": 0.16},
            },
        }
    return {
        "material": "powernet",
        "body": BODIES[body],
        "landmarks": LINES,
        "solver": TIGHT,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "grid": [24, 11],
            "lengthwise_reduction": 0.1,
            "edges": edges,
            "reduction": KNOTS,
        },
    }


def _equilibrium(body: str, edges: str):
    state = initial_state(_case(body, edges), ROOT)
    shape = body_from_record(state.body)
    settings = replace(state.case.solver, progress=False)
    result = relax(state, shape, settings)
    assert result.converged
    return state.with_positions(result.final.x), shape, settings, result


@pytest.mark.parametrize("edges", ["sliding", "fixed"])
@pytest.mark.parametrize(
    "body", ["cylinder", "cone", pytest.param("torso", marks=pytest.mark.slow)]
)
def test_adjoint_equals_central_differences(body, edges):
    """Every line's row of the Jacobian within 1e-5 of its largest entry (measured: 1e-10 on
    the cylinder and cone, 1e-8 and 6e-7 on the torso); the means are the landmarks' band
    values. The torso's warp is stretched (lengthwise reduction 0.05): with none, every warp
    spring sits at zero strain, on the tension field's kink, where the derivative is one-sided
    and central differences average the two sides (measured 3e-5 there). The cylinder and cone
    run the default path (continuation and reuse: the adjoint
    factorises once); the torso plain Newton, whose last factor of the exact matrix relax keeps
    (SuperLU's LU, or on the tension field cholespy's Cholesky factor), so the adjoint
    factorises nothing (CHOLMOD and pardiso keep none, and it factorises once)."""
    state, shape, settings, result = _equilibrium(body, edges)
    heights = landmark_heights(state)
    if body == "torso" and result.linear_solver in ("superlu", "cholespy"):  # plain Newton
        assert result.factor is not None  # Newton kept its last factor: nothing is factorised
    before = factorisations()
    sens = sensitivities(state, shape, result.final, heights, result.factor)
    assert factorisations() - before == (0 if result.factor is not None else 1)
    np.testing.assert_allclose(sens.means, line_means(state, result, heights, shape), rtol=1e-12)
    fd = finite_difference_jacobian(state, shape, settings, heights, 1e-5)
    assert sens.jacobian.shape == fd.shape == (len(heights), len(state.case.garment.reduction))
    scale = np.abs(fd).max(axis=1, keepdims=True)
    assert np.all(np.abs(sens.jacobian - fd) <= 1e-5 * scale), (sens.jacobian, fd)
    # an inner line presses harder the more its own knot reduces the pattern (the torso's hip
    # and bust are its edge rows, which press nothing when the edges are fixed)
    inner = [1] if body != "torso" else [1, 2]
    assert np.all(np.diag(sens.jacobian)[inner] > 0)
