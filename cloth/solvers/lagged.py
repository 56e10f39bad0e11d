"""The skin models' lagged quantities, and the outer iteration that settles them.

Tissue (`cloth.contact.tissue`) and friction (`cloth.contact.friction`) each depend on a quantity
Newton holds fixed while it solves: the nodes' tributary areas (the tissue's stiffness k = E A / h)
and the normal forces and normals (friction's bound mu lambda and its tangent planes). `relax`
solves with them frozen, takes them afresh from the solution (`relag`), and solves again, until the
largest relative change is at most ``LAG_TOLERANCE`` (at most ``MAX_LAGS`` solves). Without either
model there is nothing to lag and a relaxation is one solve, as before. The models a case asks for
are built by `cloth.contact.skin.skin_models`.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from cloth.garment.grid import node_area

if TYPE_CHECKING:
    from cloth.solvers.problem import Evaluation, Problem

#: Outer iterations stop when no lagged quantity changes by more than this (relative).
LAG_TOLERANCE = 1e-6
#: At most this many solves with lagged quantities.
MAX_LAGS = 30


def _normal_forces(ev: Evaluation) -> np.ndarray:
    return np.where(ev.on_body, np.maximum(ev.push, 0.0), 0.0)


def start(problem: Problem, ev: Evaluation) -> Problem:
    """The problem lagged at the relaxation's start ``ev``: friction measured from its
    positions, with its normal forces and normals; the tissue at its areas."""
    if problem.friction is not None:
        problem = replace(problem, friction=replace(problem.friction, origin=ev.x.copy()))
    return relag(problem, ev)[0]


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
