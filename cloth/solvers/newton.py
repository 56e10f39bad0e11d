"""Static equilibrium by Newton's method on the total energy, with frictionless contact.

Each iteration solves, in the directions every node may move (the projector P of
`cloth.solvers.common.constraint_basis`),

    (P (K - sum_i lambda_i H_i) P + (I - P) + mu I) dx = P R

* K: the exact stiffness (the Hessian of the energy) when the linear solver takes indefinite
  systems (`cloth.solvers.linear.INDEFINITE`), or takes them by GMRES preconditioned by its
  Cholesky factor of the projected matrix (`cloth.solvers.linear.PRECONDITIONED`), and the
  step it gives is a descent direction; otherwise each spring's Hessian projected to positive
  semi-definite. Compressed springs make
  the exact K indefinite (a compressed spring softens the fabric across it). Dropping that
  softening costs quadratic convergence where the warp bunches up: torso S at 25 % reduction,
  48 x 24, oscillated between residuals 2e-4 and 4e-4 for 400 iterations with the projected K
  and converges in 6 with the exact one;
* contact: an active set (`cloth.solvers.activeset`). A node on or inside the body whose
  spring force pushes into it is held, and so is one within ``GAP`` (1 % of the shortest rest
  length) pushed hard enough to stay pushed once on it (`held_nodes`): its normal direction is
  removed from P (the Baraff-Witkin constraint filter I - n n^T) and its step gets the
  linearised constraint correction -d n that puts it on the surface (so nodes do not hover and
  chatter in and out of the set); a node the springs pull away from the body is released,
  unless its Newton move then goes into the body (`entering`: it stays held and the move is
  redone, at most ``KEEP_PASSES`` times). The reaction is lambda_i >= 0
  (`cloth.solvers.common.body_push`: -R_i . n_i, or from the horizontal balance alone at a
  sliding edge node, whose support carries the vertical force) and H_i the Hessian of the
  body's signed distance (its curvature) at the contact point: the term -lambda H makes the
  step exact for sliding on a curved body, so convergence is quadratic (closed-form bodies,
  the smooth torso). On a mesh every active face plane is a constraint (`_mesh_step`: a node
  on an edge pushed by both faces slides along the edge), linearised exactly, so the
  iteration is exact once the active set settles;
* mu = 1e-10 x the largest diagonal entry regularises slack fabric and rigid motions (a tube
  may turn freely around an axisymmetric body), where K is singular;
* I - P keeps the constrained directions at zero.

The step is followed by a backtracking (Armijo) line search on the energy; trial positions
inside the body, and the held nodes wherever they are, are projected onto its surface (the
linearised correction leaves a held node off a curved surface by O(kappa step^2), and a
shortened step shortens the correction too). Near convergence, where energy differences drown
in rounding, a step is also accepted when it lowers the residual.
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from cloth.bodies import MeshBody
from cloth.contact import polyhedral as contact
from cloth.garment.grid import FIXED, SLIDING
from cloth.garment.mechanics import stiffness
from cloth.solvers.activeset import Stiffness, entering, held_nodes
from cloth.solvers.krylov import FORCING, KRYLOV_LOOSEST, KRYLOV_RTOL
from cloth.solvers.linear import (
    ANALYSED,
    INDEFINITE,
    PRECONDITIONED,
    REUSABLE,
    Factorise,
    Reuse,
    solve,
)
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.stepper import Step

ARMIJO = 1e-4
MAX_HALVINGS = 30
REGULARISATION = 1e-10
#: Direction passes: a released node whose step enters the body is held, and the step redone.
KEEP_PASSES = 4
#: Levenberg-Marquardt shifts, x the largest diagonal entry: the first, the growth, the last.
SHIFT_START = 1e-9
SHIFT_GROWTH = 100.0
SHIFT_LIMIT = 1e-1
#: Below this relative residual a refused exact step with negative curvature marks a saddle
#: (an unstable equilibrium): the shifted exact matrix follows its unstable mode down.
SADDLE_RESIDUAL = 1e-4


def _block_diagonal(blocks: NDArray[np.float64]) -> sp.csr_matrix:
    count = len(blocks)
    indptr = np.arange(0, 9 * count + 1, 3)
    cols = (3 * np.arange(count)[:, None, None] + np.arange(3)[None, None, :]).repeat(3, axis=1)
    return sp.csr_matrix((blocks.ravel(), cols.ravel(), indptr), shape=(3 * count, 3 * count))


def stiffness_at(problem: Problem, ev: Evaluation) -> Stiffness:
    """``k(project)``: the stiffness at ``ev`` ((3N, 3N) CSR, N/m), exact or with each spring's
    Hessian projected to positive semi-definite, each assembled at most once; with the skin
    models' Hessians (`skin_blocks`) added."""

    def assemble(project: bool) -> sp.csr_matrix:
        k = stiffness(ev.x, problem.grid, project=project, state=ev.springs).tocsr()
        blocks = skin_blocks(problem, ev, project)
        return k if blocks is None else (k + _block_diagonal(blocks)).tocsr()

    return functools.cache(assemble)


def skin_blocks(problem: Problem, ev: Evaluation, project: bool) -> NDArray[np.float64] | None:
    """The tissue layer's and the friction potential's Hessians per node ((N, 3, 3), N/m), or
    None without them; ``project`` drops the tissue's indefinite curvature term."""
    if not problem.lagged:
        return None
    blocks = np.zeros((problem.grid.n_nodes, 3, 3))
    if problem.tissue is not None:
        hessian = getattr(problem.body, "hessian", None)
        inside = ev.distance < 0.0
        curvature = None
        if hessian is not None and np.any(inside):
            # grad^2 d at depth d under the skin: H (I + d H)^-1, H the skin's at the closest
            # point (the principal curvatures kappa become kappa / (1 + kappa d))
            surface = hessian(ev.closest[inside])
            depth = ev.distance[inside][:, None, None]
            curvature = np.zeros_like(blocks)
            curvature[inside] = surface @ np.linalg.inv(np.eye(3) + depth * surface)
        blocks += problem.tissue.hessian_blocks(ev.distance, ev.normal, curvature, project)
    if problem.friction is not None:
        blocks += problem.friction.hessian_blocks(ev.x)
    return blocks


def newton_matrix(
    problem: Problem,
    ev: Evaluation,
    held: NDArray[np.bool_],
    projector_blocks: NDArray,
    k: sp.csr_matrix,
    curvature: bool = True,
) -> sp.csr_matrix:
    """The constrained, curvature-corrected, regularised Newton matrix at ``ev`` from the
    stiffness ``k`` ((3N, 3N), N/m); without the contact curvature term -lambda H where not
    ``curvature`` (then positive definite for a PSD ``k``: a Cholesky preconditioner)."""
    hessian = getattr(problem.body, "hessian", None)
    if curvature and hessian is not None and np.any(held):
        held = np.flatnonzero(held)
        reaction = ev.push[held]
        blocks = np.zeros((problem.grid.n_nodes, 3, 3))
        blocks[held] = reaction[:, None, None] * hessian(ev.closest[held])
        k = k - _block_diagonal(blocks)
    projector = _block_diagonal(projector_blocks)
    identity = sp.identity(k.shape[0], format="csr")
    mu = REGULARISATION * float(np.abs(k.diagonal()).max() or 1.0)
    return (projector @ k @ projector + (identity - projector) + mu * identity).tocsr()


class Newton:
    """Sparse Newton with contact and line search as a `cloth.solvers.stepper.Stepper`, on
    the linear ``solver`` (`cloth.solvers.linear.choose`)."""

    name = "newton"
    code = 1

    def __init__(self, solver: str, reuse: bool = False) -> None:
        self.solver = solver
        # CHOLMOD and pardiso keep their symbolic analysis between iterations even without reuse
        keep = solver in REUSABLE and (reuse or solver in ANALYSED)
        self.reuse = Reuse(solver, gmres=reuse) if keep else None
        #: SuperLU's unpivoted factor of the last step's exact Newton matrix, where that step
        #: solved with one (None otherwise): its pivots give the inertia at the iterate the step
        #: started from (`cloth.solvers.stability.factor_inertia`), which relax reports at
        #: convergence instead of factorising again
        self.factor = None
        self.factored_at: Evaluation | None = None  # the iterate ``factor``'s matrix is at

    def step(self, problem: Problem, ev: Evaluation) -> Step:
        if self.reuse is not None:  # inexact Newton: a solve as exact as the residual asks
            self.reuse.rtol = max(KRYLOV_RTOL, min(KRYLOV_LOOSEST, FORCING * ev.residual))
        kept: list = []
        self.factor = None  # let the last step's factor go before this step's is built (memory)
        new, move, ok = newton_step(problem, ev, self.solver, self.reuse, kept)
        self.factor = kept[-1] if kept else None
        self.factored_at = ev
        return Step(new, move, ok)


def newton_step(
    problem: Problem,
    ev: Evaluation,
    solver: str,
    reuse: Reuse | None = None,
    kept: list | None = None,
) -> tuple[Evaluation, float, bool]:
    """One Newton iteration with line search: (new evaluation, largest move in m, accepted);
    ``kept`` gets SuperLU's factor of the exact matrix where the move came from one."""
    k = stiffness_at(problem, ev)
    held = held_nodes(problem, ev, k)
    if isinstance(problem.body, MeshBody) and np.any(held):
        return _mesh_step(problem, ev, held, k, solver, reuse)
    # the exact Hessian first (compressed springs soften the fabric across them) where the
    # backend takes it (indefinite, or through its factor of the projected one), then the
    # projected one
    tries = (False, True) if solver in INDEFINITE + PRECONDITIONED else (True,)
    for _ in range(KEEP_PASSES):
        projector, _ = problem.basis(ev.x, ev.normal, held)
        if kept is not None:
            kept.clear()
        dx, slope = _direction(problem, ev, held, projector, k, solver, tries, reuse, kept)
        enter = entering(problem, ev, held, dx)
        if not np.any(enter):
            break
        held = held | enter
    # linearised contact: held nodes step onto the surface (along z-free normal when sliding)
    normal = ev.normal[held].copy()
    sliding = problem.constraint[held] == SLIDING
    normal[sliding, 2] = 0.0
    along = np.einsum("ij,ij->i", normal, ev.normal[held])
    usable = along > 1e-6
    dx[np.flatnonzero(held)[usable]] -= (ev.distance[held][usable] / along[usable])[
        :, None
    ] * normal[usable]
    # held nodes are put on the surface at every trial: the linearised correction is exact only
    # to second order on a curved body, and a shortened step scales it down too
    return _line_search(problem, ev, dx, slope, held)


def _direction(
    problem: Problem,
    ev: Evaluation,
    held: NDArray[np.bool_],
    projector: NDArray[np.float64],
    k: Stiffness,
    solver: str,
    tries: tuple[bool, ...],
    reuse: Reuse | None = None,
    kept: list | None = None,
) -> tuple[NDArray[np.float64], float]:
    """The Newton move ((N, 3), m) in the allowed directions (``projector``, (N, 3, 3)) and its
    slope (P R) . dx (J): with the stiffness ``k(project)`` for each of ``tries`` in turn until
    one is a descent direction (a singular matrix is skipped); else with the last matrix
    shifted by s I (Levenberg-Marquardt, `_shifted`); else a scaled gradient step. ``held``
    nodes get the body's curvature term.

    Near an equilibrium (relative residual below `SADDLE_RESIDUAL`) an exact step refused with
    negative curvature along it means the state is a saddle: the exact matrix has a negative
    eigenvalue, a mode the fabric lowers its energy along (measured at 204,800 nodes on the
    torso: Rayleigh quotients of -4e-4 to -3e-3 N/m). The projected Hessian drops the
    compressed springs' softening that makes that mode and crawled along it (residual 1e-7 for
    iterations on end, the energy falling by 5e-13 J each); the exact matrix shifted past the
    negative eigenvalue follows the mode down, so it is tried first there."""
    free = np.einsum("nij,nj->ni", projector, ev.loads)
    rhs = free.ravel()
    curvature = 0.0  # the most negative curvature seen along a refused step, N/m
    matrix = shifted = None
    factorise = None  # what a PRECONDITIONED backend factorises for the exact matrix
    for project in tries:
        matrix = newton_matrix(problem, ev, held, projector, k(project))
        if not project and solver in PRECONDITIONED:  # positive definite; assembled if needed
            factorise = functools.cache(
                lambda: newton_matrix(problem, ev, held, projector, k(True), curvature=False)
            )
        exact = None if project or kept is None else []
        dx, slope = _solve_step(matrix, rhs, projector, solver, reuse, factorise, exact)
        if slope > 0:
            if exact:
                kept.append(exact[0])
            return dx, slope
        if np.all(np.isfinite(dx)) and np.any(dx):
            step = dx.ravel()
            curvature = min(curvature, float(step @ (matrix @ step)) / float(step @ step))
        if not project and curvature < 0 and ev.residual < SADDLE_RESIDUAL:
            found = _shifted(matrix, rhs, projector, solver, reuse, curvature, factorise)
            shifted = matrix
            if found is not None:
                return found
    # a direction of negative curvature (the body's curvature term outweighs the fabric's
    # stiffness along it): shift the matrix until the move is a descent direction
    # (Levenberg-Marquardt); the line search then moves down that direction
    if matrix is not None and matrix is not shifted:  # not the saddle's shifts again
        found = _shifted(matrix, rhs, projector, solver, reuse, curvature, factorise)
        if found is not None:
            return found
    # a scaled gradient step, kept in the allowed directions
    diagonal = np.maximum(k(True).diagonal().reshape(-1, 3), 1e-300)
    dx = np.einsum("nij,nj->ni", projector, free / diagonal)
    return dx, float(rhs @ dx.ravel())


def _shifted(
    matrix: sp.csr_matrix,
    rhs: NDArray[np.float64],
    projector: NDArray[np.float64],
    solver: str,
    reuse: Reuse | None,
    curvature: float,
    factorise: Factorise | None = None,
) -> tuple[NDArray[np.float64], float] | None:
    """The move with ``matrix`` shifted by s I (Levenberg-Marquardt) and its slope, the first
    that descends: s from twice the most negative ``curvature`` (N/m) met along a refused move,
    growing ``SHIFT_GROWTH``-fold up to ``SHIFT_LIMIT`` x its largest diagonal entry; None if
    none does. ``factorise`` (the projected matrix, for a `PRECONDITIONED` backend) is shifted
    alike."""
    scale = float(np.abs(matrix.diagonal()).max() or 1.0)
    shift = max(-2.0 * curvature, SHIFT_START * scale)
    identity = sp.identity(matrix.shape[0], format="csr")
    while shift <= SHIFT_LIMIT * scale:
        moved = None if factorise is None else _shifted_assembly(factorise, shift * identity)
        dx, slope = _solve_step(matrix + shift * identity, rhs, projector, solver, reuse, moved)
        if slope > 0:
            return dx, slope
        shift *= SHIFT_GROWTH
    return None


def _shifted_assembly(factorise: Factorise, shift: sp.csr_matrix) -> Factorise:
    """``factorise`` (a matrix or its assembly) plus ``shift``, assembled when needed."""
    return lambda: (factorise() if callable(factorise) else factorise) + shift


def _solve_step(
    matrix: sp.csr_matrix,
    rhs: NDArray[np.float64],
    projector: NDArray[np.float64],
    solver: str,
    reuse: Reuse | None = None,
    factorise: Factorise | None = None,
    factor: list | None = None,
) -> tuple[NDArray[np.float64], float]:
    """The move ``matrix^-1 rhs`` in the allowed directions ((N, 3), m) and its slope (J); the
    slope is NaN where the matrix is singular. ``factorise``: `cloth.solvers.linear.solve`'s.
    ``factor`` (a list) gets SuperLU's factor of ``matrix`` itself where the solve made one."""
    try:
        dx = solve(matrix, rhs, solver, reuse, factorise, factor, projector).reshape(-1, 3)
    except RuntimeError:  # SuperLU: "factor is exactly singular"
        return np.zeros((len(rhs) // 3, 3)), float("nan")
    dx = np.einsum("nij,nj->ni", projector, dx)
    slope = float(rhs @ dx.ravel())
    return dx, slope if np.isfinite(slope) else float("nan")


def _line_search(
    problem: Problem, ev: Evaluation, dx: NDArray, slope: float, hold: NDArray | None = None
):
    alpha = 1.0
    rounding = 64 * np.finfo(float).eps * max(abs(ev.energy), 1e-300)
    for _ in range(MAX_HALVINGS):
        trial = problem.evaluate(*problem.settle(ev.x + alpha * dx, hold))
        # a trial that folds two nodes onto one point has NaN spring directions: refused
        if (
            np.isfinite(trial.energy)
            and np.isfinite(trial.residual)
            and (
                trial.energy <= ev.energy - ARMIJO * alpha * slope
                or (trial.energy <= ev.energy + rounding and trial.residual < ev.residual)
            )
        ):
            move = float(np.max(np.linalg.norm(trial.x - ev.x, axis=1)))
            return trial, move, True
        alpha *= 0.5
    return ev, 0.0, False


def _plane_constraints(
    basis: NDArray[np.float64], target: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """For constraint directions ((K, C, 3), rows may be zero or dependent) and required
    components ((K, C), m): the projector onto the free directions ((K, 3, 3)) and the smallest
    move meeting the requirements in the least-squares sense ((K, 3), m)."""
    u, s, vt = np.linalg.svd(basis, full_matrices=False)  # (K, C, 3), (K, 3), (K, 3, 3)
    keep = s > 1e-9
    projector = np.eye(3) - np.einsum("kr,kri,krj->kij", keep, vt, vt)
    inverse = np.where(keep, 1.0 / np.where(keep, s, 1.0), 0.0)
    coefficient = np.einsum("kcr,kc->kr", u, target) * inverse
    return projector, np.einsum("kr,kri->ki", coefficient, vt)


def _mesh_step(
    problem: Problem,
    ev: Evaluation,
    held: NDArray[np.bool_],
    k: Stiffness,
    solver: str,
    reuse: Reuse | None = None,
):
    """Newton on a polyhedral body: every active face plane is a constraint (a node on an
    edge with both faces pushing slides along the edge), linearised exactly (planes)."""
    rows = np.flatnonzero(held)
    sliding = problem.constraint == SLIDING
    normals, offsets, _ = contact.frames(problem.body, ev.x[rows], ev.loads[rows], sliding[rows])
    count = problem.grid.n_nodes
    basis = np.zeros((count, 4, 3))  # constraint directions per node
    target = np.zeros((count, 4))  # required n . dx
    basis[sliding, 0] = (0.0, 0.0, 1.0)
    basis[rows, 1:] = normals
    target[rows, 1:] = -offsets
    projector = np.broadcast_to(np.eye(3), (count, 3, 3)).copy()
    correction = np.zeros((count, 3))
    constrained = np.flatnonzero(sliding | held)
    projector[constrained], correction[constrained] = _plane_constraints(
        basis[constrained], target[constrained]
    )
    projector[problem.constraint == FIXED] = 0.0
    correction[problem.constraint == FIXED] = 0.0
    problem.hold_turning(ev.x, projector)
    dx, slope = _direction(problem, ev, np.zeros(count, bool), projector, k, solver, (True,), reuse)
    return _line_search(problem, ev, dx + correction, slope)
