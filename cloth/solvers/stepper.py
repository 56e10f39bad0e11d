"""The shape every relaxation method shares: a stepper takes the problem and the current
evaluation and returns a `Step`; `cloth.solvers.relax.relax` runs steppers in phases and hands
each step to its callbacks (the history's recorder, the progress bar, the log line, and any of
the caller's), as PyElastica's time steppers and callbacks do.

Steppers: `cloth.solvers.explicit.Explicit` (the paper's eq. 2) and
`cloth.solvers.newton.Newton` (sparse Newton with contact and line search).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Protocol

from cloth.case import Settings
from cloth.solvers.common import History
from cloth.solvers.problem import Evaluation, Problem

log = logging.getLogger("cloth.solvers.relax")


@dataclass(frozen=True)
class Step:
    """One iteration: the new evaluation, the largest node move (m), and whether the method
    could go on (False: Newton's line search found no decrease)."""

    evaluation: Evaluation
    move: float
    ok: bool = True


class Stepper(Protocol):
    """A relaxation method: ``name`` (its phase), ``code`` (the history's ``iteration_method``
    flag) and one iteration, `step`."""

    name: str
    code: int

    def step(self, problem: Problem, ev: Evaluation) -> Step: ...


class Callback(Protocol):
    """Called after every iteration with its number (from 1), the stepper, the step and the
    history so far (the step already recorded)."""

    def __call__(self, iteration: int, stepper: Stepper, step: Step, history: History) -> None: ...


class LogLine:
    """A log line every ``every`` iterations (0: none): residual, energy, contacts, depth."""

    def __init__(self, every: int) -> None:
        self.every = every

    def __call__(self, iteration: int, stepper: Stepper, step: Step, history: History) -> None:
        if self.every and iteration % self.every == 0:
            ev = step.evaluation
            log.info(
                "%s iteration %d: residual %.3e, energy %.6g J, %d nodes on the body, "
                "penetration %.2e m",
                stepper.name,
                iteration,
                ev.residual,
                ev.energy,
                history.contacts[-1],
                ev.penetration,
            )


class ProgressBar:
    """A tqdm bar over at most ``total`` iterations with the residual (``settings.progress``:
    True, False, or None for a terminal only); a context manager."""

    def __init__(self, total: int, settings: Settings) -> None:
        from tqdm import tqdm

        show = settings.progress
        self.bar = tqdm(
            total=total,
            disable=show is False if show is not None else None,
            desc="relax",
            unit="it",
            miniters=1,
            leave=False,
        )

    def __call__(self, iteration: int, stepper: Stepper, step: Step, history: History) -> None:
        self.bar.update(1)
        self.bar.set_postfix(residual=f"{step.evaluation.residual:.2e}", refresh=False)

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc) -> None:
        self.bar.close()
