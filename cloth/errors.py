"""The one exception users see: bad input, reported as a single line.

Every check of user input (lab tables, configs, meshes, state files) raises `InputError` naming
the file, the field and the fix. The CLI prints its message on one line and exits with status 2;
library callers can catch it like any `ValueError`.
"""

from __future__ import annotations

from pathlib import Path

EXIT_INPUT = 2
#: Exit status of a relaxation that diverged (its last finite state is written beside).
EXIT_DIVERGED = 3


class InputError(ValueError):
    """Bad user input.

    Parameters
    ----------
    message : str
        What is wrong and how to fix it, one sentence.
    source : str or Path, optional
        The file (or config key) the bad input came from.
    field : str, optional
        The column, row, key or variable that is wrong.
    """

    def __init__(self, message: str, source: str | Path | None = None, field: str | None = None):
        self.source = None if source is None else str(source)
        self.field = field
        self.detail = message
        where = ": ".join(part for part in (self.source, field) if part)
        super().__init__(f"{where}: {message}" if where else message)


def require_positive(value: float, name: str, quantity: str) -> float:
    """``value`` as a float if finite and > 0, else an `InputError` naming ``name`` and the
    expected ``quantity`` (e.g. "length in m")."""
    value = float(value)
    if not (value > 0 and value != float("inf")):
        raise InputError(f"{name} must be a positive {quantity}, got {value}", field=name)
    return value


class StageFailed(RuntimeError):
    """A stage that could not finish for a reason other than its input (a relaxation that
    diverged); the CLI prints the message on one line and exits with ``status``."""

    def __init__(self, message: str, status: int) -> None:
        self.status = status
        super().__init__(message)
