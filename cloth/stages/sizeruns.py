"""A size's confirmations in ``cloth sizes`` (issues 62 and 71): the equilibria its extreme
wearers read, the verdict, and the one line the command ends with where a size is not
confirmed.

A size is confirmed where every confirmation converged and reads inside every band, limits
included. `cloth.stages.sizes` recuts a size that is not (`cloth.results.recut`) and confirms it
again, within ``--rounds``; a size still not confirmed after them is written with ``confirmed``
0 and the command ends with `shortfall`'s line and exit status 2, as the robust design does.

Units: lengths in m, pressures in Pa (mmHg in the line).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.results.pressure import MMHG
from cloth.results.sizechart import Band, Size


@dataclass
class Run:
    """One equilibrium: who wore what (``girth``: line -> m, ``rest``: line -> m), where it
    ran, and what it read (line -> Pa; ``error`` the stated discretisation error, NaN where
    none), whether it converged."""

    name: str
    folder: Path
    girth: dict[str, float]
    rest: dict[str, float]
    features: dict[str, NDArray[np.float64]]
    pressure: dict[str, float] = field(default_factory=dict)
    error: dict[str, float] = field(default_factory=dict)
    converged: bool = False


@dataclass
class Confirmation:
    """A size's confirmations: its runs, by wearer; ``why`` what its last recut did, or why
    none held (empty where it was not recut)."""

    size: Size
    runs: list[Run]
    wearers: dict[str, int]  # wearer name -> person index
    why: str = ""

    def reads(self) -> list[tuple[int, dict[str, float]]]:
        """Each converged run's wearer (person index) and what she read (line -> Pa)."""
        return [(self.wearers[r.name], r.pressure) for r in self.runs if r.converged]


def _inside(value: float, band: Band) -> bool:
    return band.low - 1e-9 * band.high <= value <= band.high * (1 + 1e-9)


def confirmed(confirmation: Confirmation, bands: Mapping[str, Band]) -> bool:
    """Whether every run of a size converged and is inside every band (limits included)."""
    if not confirmation.runs:
        return False
    for run in confirmation.runs:
        if not run.converged:
            return False
        for line, band in bands.items():
            if not _inside(run.pressure.get(line, float("nan")), band):
                return False
    return True


def miss(confirmation: Confirmation, bands: Mapping[str, Band], ids: Sequence[str]) -> str:
    """What keeps a size from being confirmed, in words: its first run that did not converge
    or reads outside a band (the wearer's run, her id, the line, her value and the band)."""
    size = confirmation.size.name
    if not confirmation.runs:
        return f"size {size} has no wearer to confirm it on"
    for run in confirmation.runs:
        who = f"{run.name} (id {ids[confirmation.wearers[run.name]]})"
        if not run.converged:
            return f"size {size}: the equilibrium of wearer {who} did not converge ({run.folder})"
        for line, band in bands.items():
            value = run.pressure.get(line, float("nan"))
            if not _inside(value, band):
                return (
                    f"size {size}: wearer {who} reads {value / MMHG:.2f} mmHg at {line}, "
                    f"outside the band {band.low / MMHG:.4g}-{band.high / MMHG:.4g} mmHg"
                )
    return f"size {size} is confirmed"


#: how a confirmation's ``why`` begins where no recut of its size holds its wearers
NO_RECUT = "no recut holds it"


def shortfall(
    confirmations: Sequence[Confirmation],
    bands: Mapping[str, Band],
    ids: Sequence[str],
    rounds: int,
) -> str | None:
    """The command's last line where a size is not confirmed after ``rounds`` rounds (module
    docstring): the first such size's `miss`, why no recut held it, and what to change; None
    where every size is confirmed."""
    for confirmation in confirmations:
        if confirmed(confirmation, bands):
            continue
        recuts = confirmation.size.recuts
        after = f" after {recuts} recut{'s' if recuts != 1 else ''} in {rounds} rounds"
        why = f" ({confirmation.why})" if confirmation.why else ""
        fix = "a wider band or more --max-sizes"
        if not confirmation.why.startswith(NO_RECUT):  # a further round could recut it
            fix = f"more --rounds, {fix}"
        return (
            f"{miss(confirmation, bands, ids)}{after}{why}; its files are written with "
            f"confirmed 0: give {fix}"
        )
    return None


__all__ = ["NO_RECUT", "Confirmation", "Run", "confirmed", "miss", "shortfall"]
