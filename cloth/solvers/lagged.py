"""The skin models' lagged quantities, and the outer iteration that settles them.

Tissue (`cloth.tissue`) and friction (`cloth.friction`) each depend on a quantity Newton holds
fixed while it solves: the nodes' tributary areas (the tissue's stiffness k = E A / h) and the
normal forces and normals (friction's bound mu lambda and its tangent planes). `relax` solves
with them frozen, takes them afresh from the solution (`relag`), and solves again, until the
largest relative change is at most ``LAG_TOLERANCE`` (at most ``MAX_LAGS`` solves). Without
either model there is nothing to lag and a relaxation is one solve, as before.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from cloth.errors import InputError
from cloth.friction import SLIP_FRACTION, Friction
from cloth.pressure import node_area
from cloth.tissue import Layer, tissue_from_case

if TYPE_CHECKING:
    from cloth.solvers.problem import Evaluation, Problem
    from cloth.statefile import State

#: Outer iterations stop when no lagged quantity changes by more than this (relative).
LAG_TOLERANCE = 1e-6
#: At most this many solves with lagged quantities.
MAX_LAGS = 30


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


def skin_models(state: State) -> tuple[Layer | None, Friction | None]:
    """The tissue layer under each node and the friction the state's case asks for (None where
    it asks for none), not yet lagged (`start` takes them at the first evaluation)."""
    grid, x = state.grid, state.x
    tissue = tissue_from_case(state.case)
    layer = None
    if tissue is not None:
        thickness, modulus = tissue.layers(x[:, 2])
        layer = Layer(thickness, modulus, node_area(x, grid))
    mu, eps = friction_settings(state.case, float(grid.rest_length.min()))
    friction = None
    if mu > 0:
        zeros = np.zeros(grid.n_nodes)
        friction = Friction(mu, eps, x.copy(), zeros, np.zeros_like(x))
    return layer, friction


def _normal_forces(ev: Evaluation) -> np.ndarray:
    return np.where(ev.on_body, np.maximum(ev.push, 0.0), 0.0)


def start(problem: Problem, ev: Evaluation) -> Problem:
    """The problem lagged at the relaxation's start ``ev``: friction measured from its
    positions, with its normal forces and normals; the tissue at its areas."""
    if not problem.lagged:
        return problem
    friction = problem.friction
    if friction is not None:
        friction = Friction(friction.mu, friction.eps, ev.x.copy(), _normal_forces(ev), ev.normal)
    tissue = problem.tissue
    if tissue is not None:
        tissue, _ = tissue.at_area(node_area(ev.x, problem.grid))
    return replace(problem, tissue=tissue, friction=friction)


def relag(problem: Problem, ev: Evaluation) -> tuple[Problem, float]:
    """The problem with its lagged quantities taken at ``ev``, and their largest relative
    change (0 when nothing is lagged)."""
    change = 0.0
    tissue, friction = problem.tissue, problem.friction
    if tissue is not None:
        tissue, moved = tissue.at_area(node_area(ev.x, problem.grid))
        change = max(change, moved)
    if friction is not None:
        friction, moved = friction.lagged(_normal_forces(ev), ev.normal)
        change = max(change, moved)
    return replace(problem, tissue=tissue, friction=friction), change
