"""Leaving saddles: a converged Newton run that ended on a saddle is moved downhill along its
unstable modes and converged again, until it rests on a minimum (docs/model.md, "Compressed
fabric").

Newton converges to any stationary point of the energy; where compressed fabric softens across
its springs (the compression modulus's A sigma / l < 0) the equilibria it finds on fine grids
can be saddles, and two solver paths then end on different ones (torso, 448 x 224, 0.80-1.25 m:
the waist 12 % apart). At a converged state `equilibrium_factor` gives SuperLU's unpivoted
factor of the exact Newton matrix there (the run's own last one where it is valid, else a fresh
one); its negative pivots count the unstable modes (`cloth.solvers.stability.factor_inertia`)
and give a direction of negative curvature through all of them at once
(`cloth.solvers.stability.negative_direction`). `downhill` moves along it, in the allowed
directions, by at most a quarter of the shortest rest spring at a node, whichever sign lowers
the energy more; relax then runs Newton again from there (`cloth.solvers.relax`).
"""

from __future__ import annotations

import logging

import numpy as np

from cloth.solvers.activeset import held_nodes
from cloth.solvers.explicit import shortest_rest
from cloth.solvers.linear import lu_factor
from cloth.solvers.newton import SADDLE_RESIDUAL, Newton, stiffness_at
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.stability import exact_matrix, negative_direction

log = logging.getLogger(__name__)

#: Saddles left per run at most.
MAX_ESCAPES = 8
#: Largest move of a node along the unstable modes, x its shortest rest spring.
ESCAPE_MOVE = 0.25
#: Halvings of that move tried, each sign.
ESCAPE_HALVINGS = 12


def kept_factor(problem: Problem, newton: Newton | None, ev: Evaluation):
    """The run's last factor of the exact Newton matrix (`Newton.factor`) where its inertia is
    the equilibrium ``ev``'s: the step it solved started in Newton's quadratic range (relative
    residual below `SADDLE_RESIDUAL`, a step of about the tolerance's square root away) with the
    same contact set. None otherwise (CHOLMOD, the projected matrix, GMRES on an older factor,
    a step from farther away or with another contact set)."""
    if newton is None or newton.factor is None or newton.factored_at is None:
        return None
    start = newton.factored_at
    if start.residual > SADDLE_RESIDUAL:
        return None
    held = held_nodes(problem, ev, stiffness_at(problem, ev))
    if not np.array_equal(held, held_nodes(problem, start, stiffness_at(problem, start))):
        return None
    return newton.factor


def equilibrium_factor(problem: Problem, ev: Evaluation, newton: Newton | None):
    """SuperLU's unpivoted factor of the exact constrained Newton matrix at ``ev``: the run's
    own (`kept_factor`) or a fresh one (one factorisation, counted)."""
    kept = kept_factor(problem, newton, ev)
    return kept if kept is not None else lu_factor(exact_matrix(problem, ev))


def downhill(problem: Problem, ev: Evaluation, factor) -> Evaluation | None:
    """The state a move along the unstable modes of ``factor`` (at ``ev``) reaches with lower
    energy (module docstring); None where there is no such move or no decrease."""
    direction = negative_direction(factor, 3 * problem.grid.n_nodes)
    if direction is None or not np.all(np.isfinite(direction)):
        return None
    k = stiffness_at(problem, ev)
    held = held_nodes(problem, ev, k)
    projector, _ = problem.basis(ev.x, ev.normal, held)
    move = np.einsum("nij,nj->ni", projector, direction.reshape(-1, 3))
    size = np.linalg.norm(move, axis=1)
    limit = ESCAPE_MOVE * shortest_rest(problem)
    finite = np.isfinite(limit) & (size > 0)
    if not np.any(finite):
        return None
    move *= float(np.min(limit[finite] / size[finite]))
    rounding = 64 * np.finfo(float).eps * max(abs(ev.energy), 1e-300)
    best = None
    for sign in (1.0, -1.0):
        alpha = 1.0
        for _ in range(ESCAPE_HALVINGS):
            trial = problem.evaluate(*problem.settle(ev.x + sign * alpha * move, held))
            if np.isfinite(trial.energy) and trial.energy < ev.energy - rounding:
                if best is None or trial.energy < best.energy:
                    best = trial
                break
            alpha *= 0.5
    if best is not None:
        log.info(
            "saddle: moved along its unstable modes, energy %.6g J lowered by %.3g J",
            ev.energy,
            ev.energy - best.energy,
        )
    return best
