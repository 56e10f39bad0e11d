"""The skin models a case asks for: the tissue layer under each node and the friction.

`skin_models` builds them from a state's case (``body.tissue``, ``contact``), checked, before
any is lagged (`cloth.solvers.lagged.start` takes them at the relaxation's first evaluation).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cloth.contact.friction import SLIP_FRACTION, Friction
from cloth.contact.tissue import Layer, tissue_from_case
from cloth.errors import InputError
from cloth.garment.grid import Grid, node_area


def friction_settings(case: dict, shortest_rest: float) -> tuple[float, float]:
    """The case's friction coefficient (1) and slip length (m, default `SLIP_FRACTION` x the
    shortest rest spring), checked (`InputError`)."""
    block = case.get("contact") or {}
    mu = block.get("friction", 0.0)
    try:
        mu = float(mu)
    except (TypeError, ValueError):
        mu = float("nan")
    if not (np.isfinite(mu) and mu >= 0):
        raise InputError(
            f"friction must be a coefficient >= 0 (cotton on skin: 0.3-0.9), got "
            f"{block.get('friction')!r}",
            field="contact.friction",
        )
    eps = block.get("slip_length", SLIP_FRACTION * shortest_rest)
    if not (np.isfinite(float(eps)) and float(eps) > 0):
        raise InputError(
            f"slip_length must be a positive length in m, got {eps!r}", field="contact.slip_length"
        )
    return mu, float(eps)


def skin_models(
    case: dict, grid: Grid, x: NDArray[np.float64]
) -> tuple[Layer | None, Friction | None]:
    """The tissue layer under each node and the friction ``case`` asks for, for a garment on
    ``grid`` wrapped at ``x`` ((N, 3), m); None where it asks for none. Not yet lagged
    (`cloth.solvers.lagged.start` takes them at the relaxation's first evaluation)."""
    tissue = tissue_from_case(case)
    layer = None
    if tissue is not None:
        thickness, modulus = tissue.layers(x[:, 2])
        layer = Layer(thickness, modulus, node_area(x, grid))
    mu, eps = friction_settings(case, float(grid.rest_length.min()))
    friction = None
    if mu > 0:
        zeros = np.zeros(grid.n_nodes)
        friction = Friction(mu, eps, x.copy(), zeros, np.zeros_like(x))
    return layer, friction


def check_solver(case: dict, method: str, continuation: bool, source=None) -> None:
    """Tissue and friction are solved by Newton only, and friction never from a coarse grid's
    answer (it depends on the path: the relaxation from the wrap); else `InputError`."""
    tissue = (case.get("body") or {}).get("tissue") is not None
    friction = float((case.get("contact") or {}).get("friction", 0.0) or 0.0) != 0.0
    if (tissue or friction) and method != "newton":
        raise InputError(
            f"tissue and friction are solved by method newton only, got {method}; "
            "set solver.method: newton",
            source, "solver.method",
        )  # fmt: skip
    if friction and continuation:
        raise InputError(
            "friction depends on the path from the wrapped state, which continuation replaces; "
            "set solver.continuation: false",
            source, "solver.continuation",
        )  # fmt: skip
