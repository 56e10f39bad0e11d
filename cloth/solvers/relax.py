"""Run a relaxation: dispatch on the method, record history, report progress, detect failure."""

from __future__ import annotations

import logging
import sys
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from tqdm import tqdm

from cloth.bodies import Body
from cloth.solvers.common import Diverged, History, Settings
from cloth.solvers.continuation import start_from_coarse
from cloth.solvers.explicit import MAX_STEP, explicit_step, shortest_rest
from cloth.solvers.linear import choose, factorisations
from cloth.solvers.newton import newton_step
from cloth.solvers.problem import Evaluation, Problem
from cloth.statefile import State

log = logging.getLogger(__name__)

#: Share of a typical spring force on the turning gauge above which the log warns.
TURNING_WARNING = 1e-2
#: Energy growth (relative to the largest seen) that the explicit method treats as divergence.
GROWTH = 10.0


@dataclass(frozen=True)
class Result:
    """Outcome of `relax`: final evaluation, history and solver facts (``factorisations``:
    linear systems factorised by the run; ``peak_memory``: the process's peak resident memory
    at its end, bytes)."""

    final: Evaluation
    history: History
    converged: bool
    iterations: int
    method: str
    linear_solver: str
    seconds: float
    factorisations: int = 0
    peak_memory: float = 0.0


def _record(history: History, problem: Problem, ev: Evaluation, step: float, method: int) -> None:
    history.record(
        ev.residual, ev.energy, ev.penetration, problem.contacts(ev), step, method, ev.turning
    )


def _check(ev: Evaluation, last_good: NDArray, history: History, peak: float) -> None:
    if not (np.isfinite(ev.energy) and np.all(np.isfinite(ev.x)) and np.isfinite(ev.residual)):
        raise Diverged("the iteration produced NaN or inf positions or energy", last_good, history)
    if ev.energy > GROWTH * max(peak, 1e-300) and ev.energy > 0:
        raise Diverged(
            f"the energy grew from {peak:.4g} J to {ev.energy:.4g} J", last_good, history
        )


def relax(state: State, body: Body, settings: Settings) -> Result:
    """Relax ``state`` on ``body`` to equilibrium (or the iteration limit).

    Raises `Diverged` (with the last finite positions and the history) on NaN or energy growth.
    """
    start = time.perf_counter()
    factorised = factorisations()
    if settings.continuation:
        state = start_from_coarse(state, body, settings, relax)
    problem = Problem.of(state, body)
    solver = choose(settings.linear_solver) if settings.method != "explicit" else "none"
    history = History()
    ev = problem.evaluate(problem.project_out(state.x))
    _record(history, problem, ev, 0.0, 0)
    peak = max(ev.energy, 1e-300)
    phases: list[tuple[str, int]] = []
    if settings.method in ("explicit", "explicit+newton"):
        count = settings.max_iterations if settings.method == "explicit" else settings.warm_start
        phases.append(("explicit", count))
    if settings.method in ("newton", "explicit+newton"):
        phases.append(("newton", settings.max_iterations))
    cap = MAX_STEP * shortest_rest(problem)
    total = sum(count for _, count in phases)
    iterations = 0
    with tqdm(
        total=total, disable=settings.progress is False if settings.progress is not None else None,
        desc="relax", unit="it", miniters=1, leave=False,
    ) as bar:  # fmt: skip
        for phase, count in phases:
            for _ in range(count):
                if ev.residual <= settings.tolerance:
                    break
                if phase == "explicit":
                    x, move = explicit_step(problem, ev, cap)
                    new = problem.evaluate(x)
                    ok = True
                else:
                    new, move, ok = newton_step(problem, ev, solver)
                _check(new, ev.x, history, peak)
                peak = max(peak, new.energy)
                ev = new
                iterations += 1
                _record(history, problem, ev, move, 0 if phase == "explicit" else 1)
                bar.update(1)
                bar.set_postfix(residual=f"{ev.residual:.2e}", refresh=False)
                if settings.log_every and iterations % settings.log_every == 0:
                    log.info(
                        "%s iteration %d: residual %.3e, energy %.9g J, %d nodes on the body, "
                        "penetration %.2e m",
                        phase, iterations, ev.residual, ev.energy, history.contacts[-1],
                        ev.penetration,
                    )  # fmt: skip
                if not ok:
                    log.warning(
                        "newton: the line search found no decrease at residual %.3e; stopping",
                        ev.residual,
                    )
                    break
    converged = ev.residual <= settings.tolerance
    seconds = time.perf_counter() - start
    message = (
        f"{settings.method}: {'converged' if converged else 'NOT converged'} after {iterations} "
        f"iterations, relative residual {ev.residual:.3e} (tolerance {settings.tolerance:.1e}), "
        f"{seconds:.2f} s"
    )
    (log.info if converged else log.warning)(message)
    if problem.gauge is not None:
        share = abs(ev.turning) / ev.typical
        turns = converged and share > TURNING_WARNING  # unbalanced, it says nothing yet
        (log.warning if turns else log.info)(
            "turning gauge: node %d holds the garment against turning about the body with "
            "%.3g N (%.2g of a typical spring force)%s",
            problem.gauge, ev.turning, share,
            "; frictionless, the garment would turn: the body's shape has a handedness"
            if turns else "",
        )  # fmt: skip
    count = factorisations() - factorised
    peak = peak_memory()
    log.info("%d linear factorisations; peak memory %.0f MiB", count, peak / 2**20)
    return Result(ev, history, converged, iterations, settings.method, solver, seconds, count, peak)


def peak_memory() -> float:
    """The process's peak resident memory so far, bytes (0 where the platform does not say).

    Linux: VmHWM of /proc/self/status, this program's own peak. Not ru_maxrss: a process
    started by fork (or vfork) and exec keeps in ru_maxrss the peak of its parent before the
    exec (measured: a 250 MiB `cloth predeform` reported 2.6 GiB, started from a test runner of
    that size)."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) * 1024  # kB
    except OSError:
        pass
    try:
        import resource
    except ImportError:  # Windows has no resource module
        return 0.0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return float(peak if sys.platform == "darwin" else peak * 1024)  # macOS: bytes
