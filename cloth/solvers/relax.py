"""Run a relaxation: dispatch on the method, record history, report progress, detect failure."""

from __future__ import annotations

import logging
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import Body
from cloth.case import Settings
from cloth.garment.state import State
from cloth.solvers import lagged, saddle
from cloth.solvers.common import Diverged, History
from cloth.solvers.continuation import start_from_coarse
from cloth.solvers.explicit import MAX_STEP, Explicit, shortest_rest
from cloth.solvers.linear import blas_threads, choose, factorisations, lu_fallbacks
from cloth.solvers.newton import Newton
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.stability import counts, factor_inertia
from cloth.solvers.stepper import Callback, LogLine, ProgressBar, Step, Stepper

log = logging.getLogger(__name__)

#: Share of a typical spring force on the turning gauge above which the log warns.
TURNING_WARNING = 1e-2
#: Energy growth (relative to the largest seen) that the explicit method treats as divergence.
GROWTH = 10.0


@dataclass(frozen=True)
class Result:
    """Outcome of `relax`: final evaluation, history and solver facts (``factorisations``:
    linear systems factorised by the run; ``peak_memory``: the process's peak resident memory
    at its end, bytes; ``lags``: solves with the skin models' lagged quantities, 0 without them;
    ``lu_fallbacks``: systems cholespy found not positive definite, factorised by SuperLU;
    ``friction``: with friction, the skin's friction force ``force`` ((N, 3), N) and each
    node's ``state`` ((N,) int8: 0 off the skin, 1 sticking, 2 slipping))."""

    final: Evaluation
    history: History
    converged: bool
    iterations: int
    method: str
    linear_solver: str
    seconds: float
    factorisations: int = 0
    peak_memory: float = 0.0
    lags: int = 0
    lu_fallbacks: int = 0
    friction: dict[str, NDArray] = field(default_factory=dict)
    unstable_modes: int | None = None
    #: SuperLU's factor of the exact Newton matrix at (or one quadratic step before) the
    #: equilibrium, where the run holds a valid one (`cloth.solvers.saddle.kept_factor`): the
    #: sensitivities solve with it (`cloth.results.sensitivity`). None otherwise.
    factor: object = field(default=None, repr=False, compare=False)

    @classmethod
    def diverged(cls, error: Diverged, final: Evaluation, settings: Settings) -> Result:
        """A run that diverged (`Diverged`): ``final``, its last finite positions evaluated,
        not converged, after the iterations its history holds."""
        return cls(
            final,
            error.history,
            False,
            len(error.history) - 1,
            settings.method,
            settings.linear_solver,
            0.0,
        )


def _record(history: History, problem: Problem, ev: Evaluation, step: float, method: int) -> None:
    history.record(
        ev.residual, ev.energy, ev.penetration, problem.contacts(ev), step, method, ev.turning
    )


class Recorder:
    """The callback that keeps the history: each step's residual, energy, penetration,
    contacts, move, method and turning force (the first of `relax`'s callbacks)."""

    def __init__(self, history: History, problem: Problem) -> None:
        self.history, self.problem = history, problem

    def __call__(self, iteration: int, stepper: Stepper, step: Step, history: History) -> None:
        _record(self.history, self.problem, step.evaluation, step.move, stepper.code)


def _check(ev: Evaluation, last_good: NDArray, history: History, peak: float) -> None:
    if not (np.isfinite(ev.energy) and np.all(np.isfinite(ev.x)) and np.isfinite(ev.residual)):
        raise Diverged("the iteration produced NaN or inf positions or energy", last_good, history)
    if ev.energy > GROWTH * max(peak, 1e-300) and ev.energy > 0:
        raise Diverged(
            f"the energy grew from {peak:.4g} J to {ev.energy:.4g} J", last_good, history
        )


def _phases(problem: Problem, settings: Settings, solver: str) -> list[tuple[Stepper, int]]:
    """The steppers of ``settings.method`` and the iterations each may take."""
    phases: list[tuple[Stepper, int]] = []
    if settings.method in ("explicit", "explicit+newton"):
        count = settings.max_iterations if settings.method == "explicit" else settings.warm_start
        phases.append((Explicit(MAX_STEP * shortest_rest(problem)), count))
    if settings.method in ("newton", "explicit+newton"):
        phases.append((Newton(solver, settings.reuse), settings.max_iterations))
    return phases


def relax(
    state: State, body: Body, settings: Settings, callbacks: Sequence[Callback] = ()
) -> Result:
    """Relax ``state`` on ``body`` to equilibrium (or the iteration limit): the settings'
    steppers in phases (explicit, Newton, or explicit then Newton), each step recorded in the
    history and handed to the progress bar, the log line and ``callbacks``.

    Raises `Diverged` (with the last finite positions and the history) on NaN or energy growth.
    """
    solver = "none"
    if settings.method != "explicit":
        solver = choose(settings.linear_solver, positive_definite(state))
    with blas_threads(settings.blas_threads, solver):
        return _relax(state, body, settings, solver, callbacks)


def _relax(
    state: State, body: Body, settings: Settings, solver: str, callbacks: Sequence[Callback]
) -> Result:
    start = time.perf_counter()
    factorised, fallbacks = factorisations(), lu_fallbacks()
    state.skin.check_solver(settings.method, settings.continuation)
    if settings.continuation:
        state = start_from_coarse(state, body, settings, relax)
    problem = Problem.of(state, body)
    history = History()
    ev = problem.evaluate(*problem.settle(state.x))
    if problem.lagged:
        problem = lagged.start(problem, ev)
        ev = problem.evaluate(ev.x)
    _record(history, problem, ev, 0.0, 0)
    peak = max(ev.energy, 1e-300)
    phases = _phases(problem, settings, solver)
    iterations, lags, change = 0, 0, 0.0
    modes, escapes, kept = None, 0, None
    with ProgressBar(sum(count for _, count in phases), settings) as bar:
        listeners = [Recorder(history, problem), bar, LogLine(settings.log_every), *callbacks]
        while True:
            for stepper, count in phases:
                for _ in range(count):
                    if ev.residual <= settings.tolerance:
                        break
                    step = stepper.step(problem, ev)
                    _check(step.evaluation, ev.x, history, peak)
                    ev = step.evaluation
                    peak = max(peak, ev.energy)
                    iterations += 1
                    for listener in listeners:
                        listener(iterations, stepper, step, history)
                    if not step.ok:
                        log.warning(
                            "%s: the line search found no decrease at residual %.3e; stopping",
                            stepper.name,
                            ev.residual,
                        )
                        break
            if not problem.lagged:
                newton = _newton(phases)
                if ev.residual > settings.tolerance or newton is None or not counts(problem):
                    break
                if not settings.leave_saddles:  # counted from the run's own factor, if valid
                    kept = saddle.kept_factor(problem, newton, ev)
                    modes = None if kept is None else _inertia(kept)
                    break
                factor = kept = saddle.equilibrium_factor(problem, ev, newton)
                modes = _inertia(factor)
                if not modes or escapes >= saddle.MAX_ESCAPES:
                    break
                moved = saddle.downhill(problem, ev, factor)
                if moved is None:
                    break
                escapes += 1
                log.warning(
                    "%s: the equilibrium is a saddle (%d unstable modes); moving along them "
                    "and converging again (%d of at most %d)",
                    newton.name,
                    modes,
                    escapes,
                    saddle.MAX_ESCAPES,
                )
                ev, newton.factor = moved, None
                phases = [(newton, settings.max_iterations)]
                continue
            # the skin models' lagged quantities from this solution, and solve again
            problem, change = lagged.relag(problem, ev)
            ev = problem.evaluate(ev.x)
            peak = max(peak, ev.energy)
            lags += 1
            log.info("lagged skin models: change %.3e after solve %d", change, lags)
            settled = change <= lagged.LAG_TOLERANCE and ev.residual <= settings.tolerance
            if settled or lags >= lagged.MAX_LAGS:
                break
    if problem.lagged and change > lagged.LAG_TOLERANCE:
        log.warning(
            "the skin models' lagged normal forces and areas still changed by %.2e after %d "
            "solves (tolerance %.0e)",
            change,
            lags,
            lagged.LAG_TOLERANCE,
        )
    converged = ev.residual <= settings.tolerance and change <= lagged.LAG_TOLERANCE
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
            problem.gauge,
            ev.turning,
            share,
            "; frictionless, the garment would turn: the body's shape has a handedness"
            if turns
            else "",
        )
    count, fallbacks = factorisations() - factorised, lu_fallbacks() - fallbacks
    peak = peak_memory()
    log.info(
        "%d linear factorisations (%s%s); peak memory %.0f MiB",
        count,
        solver,
        f", {fallbacks} not positive definite, by superlu" if fallbacks else "",
        peak / 2**20,
    )
    modes = modes if converged else None
    if escapes:
        (log.info if modes == 0 else log.warning)(
            "left %d saddle%s: the equilibrium has %s unstable modes",
            escapes,
            "" if escapes == 1 else "s",
            modes,
        )
    return Result(
        ev,
        history,
        converged,
        iterations,
        settings.method,
        solver,
        seconds,
        count,
        peak,
        lags,
        fallbacks,
        _friction_fields(problem, ev),
        modes,
        kept if converged else None,
    )


def positive_definite(state: State) -> bool:
    """Whether Newton's matrix for ``state`` is positive definite by construction: the spring
    energy is convex (`cloth.garment.grid.Grid.convex`: every curve tension-only) and no skin
    model adds its terms (the tissue's curvature, friction's). The contact curvature term can
    still make a step's matrix indefinite; the SPD backends then fall back to LU for it
    (`cloth.solvers.linear.spd_factor`)."""
    return state.grid.convex and not state.skin.present


def _newton(phases: list) -> Newton | None:
    return next((stepper for stepper, _ in phases if isinstance(stepper, Newton)), None)


def _inertia(factor) -> int | None:
    """The unstable modes `factor_inertia` counts from ``factor``; None where it pivoted."""
    try:
        return factor_inertia(factor)
    except ValueError:
        return None


def _friction_fields(problem: Problem, ev: Evaluation) -> dict[str, NDArray]:
    """The friction force and the stick/slip state at ``ev`` (empty without friction)."""
    if problem.friction is None or ev.friction is None:
        return {}
    state = np.where(problem.friction.normal_force > 0, 1, 0).astype(np.int8)
    state[problem.friction.sliding(ev.x)] = 2
    return {"force": ev.friction, "state": state}


def reset_peak_memory() -> None:
    """Start `peak_memory` afresh (Linux: writing 5 to /proc/self/clear_refs resets VmHWM), so
    that runs in one process each report their own peak (benchmarks)."""
    try:
        with open("/proc/self/clear_refs", "w") as refs:
            refs.write("5")
    except OSError:
        pass


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
