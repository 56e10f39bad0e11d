"""A size chart designed for a measured population (issue 62): the fewest sizes that hold a
pressure band on the asked share of the people.

A size is a range of one sizing measure (the primary, e.g. the ankle's girth B) and, for a
variant, of a second one (e.g. the calf's C), and one pattern: a rest circumference at every
target line, worn unchanged by everyone in the ranges. A person fits her size when the fast
model (`cloth.results.tubemodel`) puts every target line inside its band, the band's limits
included. Each sizing measure is the girth of a target line (the ankle's line is B): that line
sets how wide a size can be.

**How wide** (`span`). With one rest circumference ``c0`` a line's pressure rises with the
girth (for any fabric whose tension grows faster than its strain's share of the girth, every
lab curve through zero), so a size ``[a, b]`` holds the band ``[low, high]`` when ``P(a) >=
low`` and ``P(b) <= high``. From ``a`` the widest size cuts ``c0`` so that ``P(a) = low`` and
ends at the ``b`` where ``P(b) = high``. For a fabric linear through zero (``T = E e``) on a
cylinder, ``1/b = 1/a - (high - low) / (2 pi E)``: `tests/test_sizes.py` works charts out by
hand from it.

**How many** (`cover`). Sizes follow one another with no gap (the next starts where one ends),
from a first size that starts at a person's measure: moving the start up to the next person
loses no one and moves every end up. For K = 1, 2, ... every start is tried and the first K
whose best start covers the asked share (by weight) is the chart; of the starts that do, the
one leaving the most even shares below and above. The people outside every size are the
made-to-measure share. With a secondary measure, each primary size is split the same way into
variants over its own people, and each level covers the square root of the asked share, so the
chart covers the share.

**The pattern** (`centred_rest`, `stabbing_rest`). At a sizing line the rest circumference puts
the range's ends equally far inside the band (each ``margin`` inside when the size is as wide as
it can be). At a target line that is no sizing measure (a riding line: the calf when sizing by
the ankle alone), it is the one that holds the most of the size's people (by weight) inside the
band, the middle of the best such interval.

Units: girths and circumferences in m, pressure in Pa, weights as the population's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.wearers import weighted_quantile
from cloth.results.tubemodel import Correction, LineModel

#: Bisection steps of a size's end (relative precision about 2^-60 of the bracket).
STEPS = 60
#: A size's end is looked for up to this many times its start.
WIDEST = 3.0
#: The central shares of the people's shape terms a size may be held over, past the asked
#: share (`design_chart`).
SHAPE_SHARES = (0.9, 0.8, 0.7, 0.6, 0.5)


@dataclass(frozen=True)
class Band:
    """A target line's pressure band, Pa, limits included."""

    line: str
    low: float
    high: float

    def shrunk(self, margin: float) -> Band:
        """The band ``margin`` (Pa) inside each limit (the search's, so that the fast model's
        error keeps the confirmed pressures inside)."""
        return Band(self.line, self.low + margin, self.high - margin)


@dataclass(frozen=True)
class Size:
    """One size: ``name``, ``ranges`` (measure -> (low, high) m, limits included), ``rest``
    (line -> rest circumference, m), ``members`` (the people in its ranges: indices into the
    population) and ``fits`` (bool per member: every line inside its band)."""

    name: str
    ranges: dict[str, tuple[float, float]]
    rest: dict[str, float]
    members: NDArray[np.intp]
    fits: NDArray[np.bool_]
    #: line -> the fast model's correction from the size's own equilibria, where it was
    #: recut (`cloth.results.recut`); none as searched
    corrections: Mapping[str, Correction] = field(default_factory=dict)
    #: how many times the size was recut from its confirmations (0: as searched)
    recuts: int = 0

    def pressure(
        self,
        models: Mapping[str, LineModel],
        line: str,
        girth: NDArray[np.float64],
        offset: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """The mean pressure (Pa) at ``line`` of this size's row there on people of
        ``girth`` (m) and shape term ``offset`` (Pa): the fast model's, corrected where the
        size was recut."""
        fast = models[line].pressure(girth, self.rest[line], offset)
        return self.corrections.get(line, Correction())(fast)


@dataclass(frozen=True)
class Chart:
    """A designed chart: its ``sizes``, the sizing ``measures`` (primary first), the
    ``coverage`` (share of the complete people, by weight, who fit their size), the asked
    share ``asked``, ``people`` (indices of the complete people the chart was designed for)
    and the central ``shape_share`` of their shape terms the sizes are held over."""

    sizes: tuple[Size, ...]
    measures: tuple[str, ...]
    coverage: float
    asked: float
    people: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, dtype=np.intp))
    #: the central share of the people's shape terms the sizes are held over
    shape_share: float = 1.0

    @property
    def met(self) -> bool:
        return self.coverage >= self.asked - 1e-12


def span(
    model: LineModel,
    band: Band,
    start: NDArray[np.float64],
    offset: tuple[float, float] = (0.0, 0.0),
) -> NDArray[np.float64]:
    """The widest size's end (m) from each ``start`` (m) at a sizing line (module docstring):
    the girth where the rest circumference that gives ``band.low`` at the start to a person
    of the lowest shape term ``offset`` (Pa) gives ``band.high`` to one of the highest;
    `WIDEST` x the start where it never does."""
    a = np.asarray(start, dtype=float)
    rest = model.rest_for(a, band.low, offset[0])
    low, high = a.copy(), WIDEST * a
    reached = model.pressure(high, rest, offset[1]) >= band.high
    for _ in range(STEPS):
        middle = 0.5 * (low + high)
        above = model.pressure(middle, rest, offset[1]) >= band.high
        high = np.where(above, middle, high)
        low = np.where(above, low, middle)
    return np.where(reached, 0.5 * (low + high), WIDEST * a)


def chain(
    model: LineModel,
    band: Band,
    start: NDArray[np.float64],
    count: int,
    offset: tuple[float, float] = (0.0, 0.0),
) -> NDArray[np.float64]:
    """(S, count + 1) edges, m, of ``count`` sizes following one another from each of the S
    ``start`` values (`span`)."""
    edges = [np.asarray(start, dtype=float)]
    for _ in range(count):
        edges.append(span(model, band, edges[-1], offset))
    return np.stack(edges, axis=1)


def cover(
    values: NDArray[np.float64],
    weight: NDArray[np.float64],
    model: LineModel,
    band: Band,
    share: float,
    most: int,
    offset: tuple[float, float] = (0.0, 0.0),
) -> NDArray[np.float64]:
    """The edges (K + 1,) m of the fewest sizes (at most ``most``) that cover ``share`` of the
    weight of ``values`` (module docstring, "How many"), each held over the shape terms'
    ``offset`` range (Pa); where ``most`` cannot, the ``most`` sizes that cover the largest
    share."""
    order = np.argsort(values, kind="stable")
    v, w = values[order], weight[order]
    starts = np.unique(v)
    total = w.sum()
    cumulative = np.concatenate([[0.0], np.cumsum(w)])
    below = cumulative[np.searchsorted(v, starts, side="left")]
    edges = chain(model, band, starts, most, offset)
    best: NDArray[np.float64] | None = None
    for count in range(1, most + 1):
        end = edges[:, count]
        covered = cumulative[np.searchsorted(v, end, side="right")] - below
        reach = covered.max()
        if reach >= share * total - 1e-12 * total or count == most:
            good = covered >= min(reach, share * total) - 1e-12 * total
            above = total - below - covered
            pick = np.flatnonzero(good)[np.argmin(np.abs(below - above)[good])]
            best = edges[pick, : count + 1]
            break
    assert best is not None  # most >= 1
    return best


def centred_rest(
    model: LineModel,
    band: Band,
    low: float,
    high: float,
    offset: tuple[float, float] = (0.0, 0.0),
) -> float:
    """The rest circumference (m) that puts the girth ``low`` (m) of the lowest shape term
    ``offset`` and ``high`` of the highest (Pa) equally far inside ``band`` (module
    docstring, "The pattern"): bisection on the slack's difference, which falls as the
    circumference grows."""

    def imbalance(rest: float) -> float:
        below = float(model.pressure(low, rest, offset[0])) - band.low
        above = band.high - float(model.pressure(high, rest, offset[1]))
        return below - above

    small = float(model.rest_for(high, band.high, offset[1])) * 0.5
    large = float(model.rest_for(low, band.low, offset[0])) * 1.5
    large = min(large, low * 0.999999)
    for _ in range(STEPS):
        middle = 0.5 * (small + large)
        if imbalance(middle) > 0:
            small = middle
        else:
            large = middle
    return 0.5 * (small + large)


def stabbing_rest(
    model: LineModel,
    band: Band,
    girth: NDArray[np.float64],
    weight: NDArray[np.float64],
    offset: NDArray[np.float64],
) -> float:
    """The rest circumference (m) inside the most people's intervals (by weight; module
    docstring): each person (``girth`` m, her shape term ``offset`` Pa) holds the band for
    rests in [rest_for(g, high), rest_for(g, low)]; the middle of the best-covered stretch."""
    lo = model.rest_for(girth, band.high, offset)
    hi = model.rest_for(girth, band.low, offset)
    points = np.concatenate([lo, hi])
    kinds = np.concatenate([np.zeros(len(lo)), np.ones(len(hi))])  # opens before closes
    change = np.concatenate([weight, -weight])
    order = np.lexsort((kinds, points))
    level = np.cumsum(change[order])
    k = int(np.argmax(level))
    start = points[order][k]
    end = points[order][k + 1] if k + 1 < len(points) else start
    return float(0.5 * (start + end))


def inside(
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    girths: Mapping[str, NDArray[np.float64]],
    rest: Mapping[str, float],
    offset: Mapping[str, NDArray[np.float64]],
) -> NDArray[np.bool_]:
    """(P,) whether every line's pressure on the people with ``girths`` and shape terms
    ``offset`` (line -> (P,) m, Pa) under ``rest`` is inside its band, limits included (to a
    relative 1e-9, so a person exactly at a band's edge is inside)."""
    ok = None
    for line, band in bands.items():
        p = models[line].pressure(girths[line], rest[line], offset[line])
        tol = 1e-9 * max(abs(band.high), 1.0)
        here = (p >= band.low - tol) & (p <= band.high + tol)
        ok = here if ok is None else ok & here
    assert ok is not None
    return ok


def extreme_wearers(
    size: Size, people: People, models: Mapping[str, LineModel], lines: Sequence[str]
) -> dict[str, int]:
    """A size's extreme wearers: of its members who fit (all its members where none does),
    at each of ``lines`` the one of the lowest and the one of the highest pressure by the full
    fast model (`Size.pressure`: her girth and her shape term), named ``{line}_min`` and
    ``{line}_max``; a person already named is not named again. Name -> person index."""
    members = size.members[size.fits] if size.fits.any() else size.members
    out: dict[str, int] = {}
    if len(members) == 0:
        return out
    for line in lines:
        p = size.pressure(models, line, people.girth[line][members], people.offset[line][members])
        for end, k in (("min", int(np.argmin(p))), ("max", int(np.argmax(p)))):
            person = int(members[k])
            if person not in out.values():
                out[f"{line}_{end}"] = person
    return out


def _sizes_over(edges: NDArray[np.float64], values: NDArray[np.float64]) -> list[NDArray[np.intp]]:
    """Indices of ``values`` in each of the sizes between ``edges``; one on a shared edge in
    the lower size."""
    out = []
    for k in range(len(edges) - 1):
        low = edges[k] if k == 0 else np.nextafter(edges[k], np.inf)
        out.append(np.flatnonzero((values >= low) & (values <= edges[k + 1])))
    return out


def central(
    values: NDArray[np.float64], weight: NDArray[np.float64], share: float
) -> tuple[float, float]:
    """The central ``share`` of ``values`` by ``weight``: its (1 - share) / 2 and
    (1 + share) / 2 weighted quantiles (`cloth.bodies.wearers.weighted_quantile`, Hazen's);
    (0, 0) for no value."""
    if len(values) == 0:
        return (0.0, 0.0)
    tail = 0.5 * (1.0 - share)
    return (weighted_quantile(values, weight, tail), weighted_quantile(values, weight, 1 - tail))


def offset_range(
    values: NDArray[np.float64], weight: NDArray[np.float64], share: float
) -> tuple[float, float]:
    """The central ``share`` of the shape terms ``values`` (Pa) by weight: (low, high)."""
    return central(values, weight, share)


@dataclass(frozen=True)
class People:
    """Who a chart is designed for: per target line her ``girth`` and her shape term
    ``offset`` ((P,) m and Pa, `cloth.results.tubemodel.Calibration.offset`; NaN where not
    measured), and her ``weight`` (P,)."""

    girth: Mapping[str, NDArray[np.float64]]
    offset: Mapping[str, NDArray[np.float64]]
    weight: NDArray[np.float64]

    def complete(self) -> NDArray[np.intp]:
        """The people with every line's girth and shape term, of weight > 0."""
        keep = self.weight > 0
        for table in (self.girth, self.offset):
            for values in table.values():
                keep &= np.isfinite(values)
        return np.flatnonzero(keep)


def design_chart(
    people: People,
    measures: tuple[str, ...],
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    share: float,
    most: int,
    variants: int = 3,
    margin: float | Mapping[str, float] = 0.0,
) -> Chart:
    """The chart (module docstring) for ``people``, sized by ``measures`` (one or two target
    lines, primary first), each line's fast model and band; ``share`` (0-1) of them to cover
    with at most ``most`` sizes (and ``variants`` per size by the secondary), the search
    ``margin`` (Pa; or line -> Pa) inside each band.

    A size is held over a central share of the people's shape terms at its sizing line
    (`offset_range`): the asked share first, then narrower ones (`SHAPE_SHARES`), since where
    the shape terms spread over more than the band a size of any width would lose people at
    both ends. With variants, charts of more sizes than the primary range needs are tried too:
    the same range in more, narrower sizes of equal ratio, whose people spread less over the
    secondary measure. Of these charts, the
    fewest sizes that cover ``share`` of the people (the most covered among equals); where
    none does, the one that covers most."""
    index = people.complete()
    level = share ** (1.0 / len(measures))
    margins = margin if isinstance(margin, Mapping) else dict.fromkeys(bands, margin)
    search = {line: band.shrunk(margins[line]) for line, band in bands.items()}
    w = people.weight[index]
    best: Chart | None = None
    for shape_share in sorted({level, *(s for s in SHAPE_SHARES if s < level)}, reverse=True):
        bends = {line: offset_range(people.offset[line][index], w, shape_share) for line in bands}
        for least in range(1, most + 1):  # more sizes than the range needs: narrower variants
            counts = (least, most)
            chart = _chart(
                people, index, measures, models, bands, search, level, counts, variants, bends
            )
            chart = Chart(chart.sizes, measures, chart.coverage, share, index, shape_share)
            if best is None or _better(chart, best):
                best = chart
            if chart.met or len(measures) == 1:
                break
    assert best is not None
    return best


def _better(chart: Chart, best: Chart) -> bool:
    """Whether ``chart`` beats ``best`` (`design_chart`'s order)."""
    if chart.met != best.met:
        return chart.met
    if chart.met and len(chart.sizes) != len(best.sizes):
        return len(chart.sizes) < len(best.sizes)
    return chart.coverage > best.coverage + 1e-12


def _chart(
    people: People,
    index: NDArray[np.intp],
    measures: tuple[str, ...],
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    search: Mapping[str, Band],
    level: float,
    counts: tuple[int, int],
    variants: int,
    bends: Mapping[str, tuple[float, float]],
) -> Chart:
    """One chart of `design_chart`, of at most ``counts[1]`` sizes held over the shape terms
    ``bends``, split into ``counts[0]`` equal ratios where that is more."""
    primary = measures[0]
    values = people.girth[primary][index]
    w = people.weight[index]
    least, most = counts
    edges = cover(values, w, models[primary], search[primary], level, most, bends[primary])
    if least > len(edges) - 1:  # more, narrower sizes over the same range, in equal ratios
        edges = edges[0] * (edges[-1] / edges[0]) ** (np.arange(least + 1) / least)
    sizes = []
    for k, members in enumerate(_sizes_over(edges, values)):
        name = f"S{k + 1}"
        ranges = {primary: (float(edges[k]), float(edges[k + 1]))}
        if len(measures) == 1:
            sizes.append(_size(name, ranges, index[members], people, models, bands, bends))
            continue
        if len(members) == 0:
            continue
        second = measures[1]
        chosen = index[members]
        inner = people.girth[second][chosen]
        cut = cover(
            inner, w[members], models[second], search[second], level, variants, bends[second]
        )
        for j, sub in enumerate(_sizes_over(cut, inner)):
            variant_ranges = {**ranges, second: (float(cut[j]), float(cut[j + 1]))}
            label = f"{name}{chr(ord('a') + j)}"
            sizes.append(_size(label, variant_ranges, chosen[sub], people, models, bands, bends))
    sizes = [s for s in sizes if s.ranges[primary][1] > s.ranges[primary][0]]
    fitted = sum(float(people.weight[s.members[s.fits]].sum()) for s in sizes)
    total = float(w.sum())
    coverage = fitted / total if total > 0 else 0.0
    return Chart(tuple(sizes), measures, coverage, level, index)


def _size(
    name: str,
    ranges: dict[str, tuple[float, float]],
    members: NDArray[np.intp],
    people: People,
    models: Mapping[str, LineModel],
    bands: Mapping[str, Band],
    bends: Mapping[str, tuple[float, float]],
) -> Size:
    """A size with its ranges and members: each line's rest circumference (module docstring,
    "The pattern"; a sizing line's centred over the people's central shape terms ``bends``)
    and who fits."""
    rest = {}
    w = people.weight[members]
    for line, band in bands.items():
        bend = people.offset[line][members]
        if line in ranges:
            rest[line] = centred_rest(models[line], band, *ranges[line], bends[line])
        elif len(members):
            rest[line] = stabbing_rest(models[line], band, people.girth[line][members], w, bend)
        else:
            rest[line] = float("nan")
    at = {line: people.girth[line][members] for line in bands}
    bends = {line: people.offset[line][members] for line in bands}
    fits = inside(models, bands, at, rest, bends) if len(members) else np.zeros(0, dtype=bool)
    return Size(name, ranges, rest, members, fits)


__all__ = [
    "Band",
    "Chart",
    "People",
    "Size",
    "central",
    "centred_rest",
    "chain",
    "cover",
    "design_chart",
    "extreme_wearers",
    "inside",
    "offset_range",
    "span",
    "stabbing_rest",
]
