"""A size recut from what its own equilibria read (issue 71): the step of ``cloth sizes``
after a confirmation that misses a band.

A size's confirmations (`cloth.stages.sizes`) are full equilibria of its extreme wearers in its
pattern. Where one reads outside a band, the fast model (`cloth.results.tubemodel`) was wrong
about this size by more than the search's margin. The recut trusts the equilibria:

1. **The correction.** At each target line the wearers' equilibrium pressures are fitted
   against the fast model's at the size's cut, ``read = shift + scale x fast``
   (`cloth.results.tubemodel.Correction`; a shift alone where the slope would not be
   positive), so the corrected model reads each confirmed extreme as it was read (exactly
   with two wearers) and keeps the fast model's order of the wearers.
2. **The cut.** At each line the rest circumference that puts the corrected lowest and highest
   of the size's wearers (its members who fit, as the confirmations were chosen) equally far
   inside the band: the confirmed extremes centred. Kept where every line is then at least
   `RECUT_MARGIN` inside.
3. **The range.** Where the corrected spread is wider than the band less twice the margin
   at some line, the size's range is narrowed: of the windows of its wearers along one of
   its sizing measures (people of one girth together), the one of the most weight whose
   centred cut holds every line with the margin. Its range is then the window's girths; the
   people outside it are in no size.
4. **No recut** where no window of one or more wearers holds: the band is narrower than what
   the equilibria read on wearers of one girth.

The size is then confirmed again (`cloth.stages.sizes`), within the command's ``--rounds``.

Units: girths and circumferences in m, pressures in Pa, weights as the population's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from cloth.results.pressure import MMHG
from cloth.results.sizechart import Band, People, Size
from cloth.results.tubemodel import Correction, LineModel

#: How far inside each band the recut keeps its corrected extremes, Pa (a fifth of the search's
#: least margin: these are the equilibria's own values, not the fast model's).
RECUT_MARGIN = 0.1 * MMHG
#: Bisection steps of a centred cut.
STEPS = 60


@dataclass(frozen=True)
class Recut:
    """What the recut found: the recut ``size`` (None where none holds) and ``why`` (what
    changed, or why no recut holds), one sentence."""

    size: Size | None
    why: str


def corrections(
    size: Size,
    reads: Sequence[tuple[int, Mapping[str, float]]],
    people: People,
    models: Mapping[str, LineModel],
    lines: Sequence[str],
) -> dict[str, Correction]:
    """Step 1 (module docstring): each line's correction from ``reads`` (person index, line
    -> her equilibrium's mean pressure, Pa) of the size's wearers at its present cut."""
    out = {}
    index = np.array([person for person, _ in reads], dtype=np.intp)
    for line in lines:
        fast = models[line].pressure(
            people.girth[line][index], size.rest[line], people.offset[line][index]
        )
        read = np.array([values.get(line, np.nan) for _, values in reads], dtype=float)
        out[line] = Correction.fit(fast, read)
    return out


def centred(
    model: LineModel,
    correction: Correction,
    band: Band,
    girth: NDArray[np.float64],
    offset: NDArray[np.float64],
) -> tuple[float, float]:
    """The rest circumference (m) that puts the corrected lowest and highest pressure of the
    people of ``girth`` (m) and shape term ``offset`` (Pa) equally far inside ``band``, and
    that distance (Pa; negative where they spread wider than the band). Bisection: a larger
    circumference lowers every pressure."""

    def ends(rest: float) -> tuple[float, float]:
        p = correction(model.pressure(girth, rest, offset))
        return float(np.min(p)), float(np.max(p))

    small, large = 0.05 * float(np.min(girth)), 2.0 * float(np.max(girth))
    for _ in range(STEPS):
        middle = 0.5 * (small + large)
        low, high = ends(middle)
        if (low - band.low) - (band.high - high) > 0:
            small = middle
        else:
            large = middle
    rest = 0.5 * (small + large)
    low, high = ends(rest)
    return rest, min(low - band.low, band.high - high)


def _cut(
    members: NDArray[np.intp],
    people: People,
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    fixes: Mapping[str, Correction],
) -> tuple[dict[str, float], float]:
    """Each line's centred rest (m) over ``members`` and the least slack over the lines
    (Pa)."""
    rest, slack = {}, np.inf
    for line, band in bands.items():
        rest[line], room = centred(
            models[line],
            fixes[line],
            band,
            people.girth[line][members],
            people.offset[line][members],
        )
        slack = min(slack, room)
    return rest, float(slack)


def _window(
    wearers: NDArray[np.intp],
    values: NDArray[np.float64],
    people: People,
    holds,
) -> NDArray[np.intp]:
    """The wearers in the window along ``values`` (their girths at one sizing measure) of the
    most weight that ``holds`` (a test of a set of wearers, monotone: a window inside one
    that holds holds); none where no single girth holds. People of one girth stay together."""
    order = np.argsort(values, kind="stable")
    v, who = values[order], wearers[order]
    starts = np.flatnonzero(np.concatenate([[True], np.diff(v) > 0]))
    ends = np.concatenate([starts[1:], [len(v)]])
    weight = np.concatenate([[0.0], np.cumsum(people.weight[who])])
    best, best_weight = np.zeros(0, dtype=np.intp), -1.0
    j = 0  # the groups [i, j) hold
    for i in range(len(starts)):
        j = max(j, i)
        while j < len(starts) and holds(who[starts[i] : ends[j]]):
            j += 1
        if j > i:
            w = weight[ends[j - 1]] - weight[starts[i]]
            if w > best_weight:
                best, best_weight = who[starts[i] : ends[j - 1]], w
    return best


def recut(
    size: Size,
    reads: Sequence[tuple[int, Mapping[str, float]]],
    people: People,
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    margin: float = RECUT_MARGIN,
) -> Recut:
    """The size recut from its confirmations ``reads`` (person index, line -> Pa) (module
    docstring), its wearers ``people`` (the population's girths and shape terms by line),
    the fast ``models`` and the ``bands``, each line's corrected extremes at least ``margin``
    (Pa) inside."""
    fixes = corrections(size, reads, people, models, list(bands))
    wearers = size.members[size.fits] if size.fits.any() else size.members
    if len(wearers) == 0:
        return Recut(None, "it has no wearer")

    def holds(chosen: NDArray[np.intp]) -> bool:
        return _cut(chosen, people, models, bands, fixes)[1] >= margin

    ranges = dict(size.ranges)
    kept = wearers
    how = "cut centred on its confirmed extremes"
    if not holds(wearers):
        best = np.zeros(0, dtype=np.intp)
        for measure in size.ranges:
            window = _window(wearers, people.girth[measure][wearers], people, holds)
            if people.weight[window].sum() > people.weight[best].sum() or not len(best):
                best, narrowed = window, measure
        if not len(best):
            line, band = _widest(wearers, people, models, bands, fixes)
            return Recut(
                None,
                f"its equilibria at {line} spread wider than the band "
                f"{band.low / MMHG:.4g}-{band.high / MMHG:.4g} mmHg less "
                f"{margin / MMHG:.2g} mmHg each side on wearers of one girth",
            )
        kept = best
        girths = people.girth[narrowed][kept]
        ranges[narrowed] = (float(np.min(girths)), float(np.max(girths)))
        low, high = size.ranges[narrowed]
        how = (
            f"range of {narrowed} narrowed from {100 * low:.2f}-{100 * high:.2f} to "
            f"{100 * ranges[narrowed][0]:.2f}-{100 * ranges[narrowed][1]:.2f} cm and its cut "
            "centred"
        )
    rest, _ = _cut(kept, people, models, bands, fixes)
    moved = ", ".join(
        f"{line} {100 * size.rest[line]:.2f} -> {100 * rest[line]:.2f} cm" for line in bands
    )
    how = f"{how} (rest circumference {moved})"
    members = size.members
    for measure, (low, high) in ranges.items():
        value = people.girth[measure][members]
        members = members[(value >= low) & (value <= high)]
    new = replace(size, rest=rest, members=members, corrections=fixes, recuts=size.recuts + 1)
    fits = np.ones(len(members), dtype=bool)
    for line, band in bands.items():
        p = new.pressure(models, line, people.girth[line][members], people.offset[line][members])
        tol = 1e-9 * max(abs(band.high), 1.0)
        fits &= (p >= band.low - tol) & (p <= band.high + tol)
    return Recut(replace(new, ranges=ranges, fits=fits), how)


def _widest(
    wearers: NDArray[np.intp],
    people: People,
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    fixes: Mapping[str, Correction],
) -> tuple[str, Band]:
    """The line whose centred cut leaves the least room on ``wearers``, and its band."""
    rooms = {}
    for line, band in bands.items():
        _, rooms[line] = centred(
            models[line],
            fixes[line],
            band,
            people.girth[line][wearers],
            people.offset[line][wearers],
        )
    line = min(rooms, key=rooms.get)
    return line, bands[line]


__all__ = ["RECUT_MARGIN", "Recut", "centred", "corrections", "recut"]
