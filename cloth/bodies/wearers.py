"""The wearers of a size (issue 52, item 2): a few bodies that span everyone the size fits.

A size is worn by a range of bodies. Its wearers are the girth and stature targets of a few
avatars (`cloth.bodies.avatar.fit_targets`), one `Wearer` each:

* **From a population** (`population_wearers`; a file of measured people,
  `cloth.files.population`). The size holds the people whose every measure that the chart gives
  as a range (`cloth.bodies.ranges`) and the file has lies in that range (the torso chart's hip;
  its bust where a file has it). Its wearers take the measures the chart and the file share
  (girths by name, and the stature) at the people's survey-weighted quantiles: ``centre`` all
  at the median, then for each shared measure ``{measure}_p5`` and ``{measure}_p95`` at its 5th
  and 95th percentile with the others at their median: 1 + 2k wearers for k shared measures.
  What they span is reported as the share of the size's people (by weight) inside the box of
  every measure's p5-p95 (`Wearers.coverage`).
* **From the chart's ranges** (`range_wearers`; no population): ``centre`` at the size's
  values, and every combination of the minimum and maximum of the girths given as ranges
  (``B_min_C_max``, ...): 1 + 2^k wearers. Past `MAX_CORNERS` corners (k > 3) a scrambled
  Sobol sample of `MAX_CORNERS` points of the box (`scipy.stats.qmc`, seed 0) replaces them.
* **The body model's shape** (both): the centre wearer's girths and stature at each extreme of
  its `SHAPES`, muscle and proportions held at 0 and at 1 instead of fitted
  (``centre_muscle_min``, ...; `shape_wearers`): 4 more, where the model reaches them.

A population's wearer's girths that neither the file nor the size's ranges set (the torso's
underbust: the survey does not measure it, the chart gives it as one value) are left to the
body model, its most average body with her other measures (`ChartTargets.free`): the chart's
value need not go with a waist at the survey's 95th percentile, and the model cannot always
join them. A range wearer's other girths are the size's own. The wearer's girth lines sit at
the chart's heights times her stature over the chart's, so a shorter wearer's hip is lower.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from cloth.bodies.avatar import ChartTargets
from cloth.errors import InputError

#: The name, among a size's wearers' runs, of the size's own body (the body a garment is cut
#: for: the chart's torso or leg, an avatar), which `cloth wearers` runs beside them.
SIZE = "size"
#: Quantiles (0-1) of a population's wearers at the ends of each measure.
LOW, HIGH = 0.05, 0.95
#: Most corners of the chart's ranges; past it a space-filling sample of this many points.
MAX_CORNERS = 8
#: The body model's shape parameters whose extremes (0 and 1) are a further axis at the centre
#: wearer's girths.
SHAPES = ("muscle", "proportions")


@dataclass(frozen=True)
class Wearer:
    """One wearer: her ``name`` (``centre``, ``waist_p95``, ``B_min_C_max``, ...), her
    ``targets`` (girths and stature, m), and how she was chosen (``quantiles``: measure ->
    quantile 0-1 for a population's, empty for the chart's)."""

    name: str
    targets: ChartTargets
    quantiles: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Wearers:
    """A size's wearers and what they stand for: ``people`` in the size (rows of the file) and
    their survey ``weight``, the share of it the wearers' range covers (``coverage``, 0-1), the
    ``measures`` their choice varied; ``source`` ``population`` or ``ranges``."""

    wearers: tuple[Wearer, ...]
    source: str
    measures: tuple[str, ...]
    people: int = 0
    weight: float = 0.0
    coverage: float = 1.0


def weighted_quantile(values: NDArray[np.float64], weights: NDArray[np.float64], q: float) -> float:
    """The ``q`` quantile (0-1) of ``values`` with ``weights``: the weighted empirical
    distribution, linear between the midpoints of each value's weight (Hazen's rule)."""
    order = np.argsort(values, kind="stable")
    v, w = values[order], weights[order]
    cumulative = np.cumsum(w) - 0.5 * w
    return float(np.interp(q * w.sum(), cumulative, v))


def wearer_targets(
    centre: ChartTargets,
    girths: Mapping[str, float],
    stature: float | None,
    name: str,
    free: tuple[str, ...] = (),
) -> ChartTargets:
    """``centre`` (the size's targets) with ``girths`` (m) and ``stature`` (m; None: the
    size's), its girth-line heights scaled by the stature, the girths ``free`` left to the
    body model."""
    scale = 1.0 if stature is None else stature / centre.stature
    return replace(
        centre,
        free=tuple(free),
        size=f"{centre.size}/{name}",
        girth={**centre.girth, **{k: float(v) for k, v in girths.items()}},
        height={k: v * scale for k, v in centre.height.items()},
        stature=centre.stature if stature is None else float(stature),
        span=(centre.span[0] * scale, centre.span[1] * scale),
    )


def shape_wearers(centre: Wearer) -> list[Wearer]:
    """The centre wearer at each extreme of the body model's `SHAPES`, her girths and stature
    unchanged: ``centre_muscle_min``, ``centre_muscle_max``, ... (module docstring)."""
    out = []
    for shape in SHAPES:
        for end, value in (("min", 0.0), ("max", 1.0)):
            name = f"{centre.name}_{shape}_{end}"
            size = f"{centre.targets.size.split('/')[0]}/{name}"
            targets = replace(centre.targets, size=size, pinned={shape: value})
            out.append(Wearer(name, targets, centre.quantiles))
    return out


def population_wearers(
    centre: ChartTargets,
    ranges: Mapping[str, tuple[float, float]],
    measures: Mapping[str, NDArray[np.float64]],
    weight: NDArray[np.float64],
    source: str = "population",
) -> Wearers:
    """The wearers of the size ``centre`` with girth ``ranges`` (m) among the people of
    ``measures`` (name -> (P,) m, ``stature`` the height) and survey ``weight`` (P,)
    (module docstring); `InputError` naming ``source`` where the file shares no range with the
    chart, or no one is in the size."""
    selecting = [name for name in ranges if name in measures]
    if not selecting:
        raise InputError(
            f"the population has none of the measures the size gives as ranges "
            f"({', '.join(ranges) or 'none'}), so it cannot tell who is in size "
            f"{centre.size}; add a column {next(iter(ranges), 'hip')}_cm",
            source,
            f"{next(iter(ranges), 'hip')}_cm",
        )
    shared = [name for name in (*centre.girth, "stature") if name in measures]
    keep = weight > 0
    for name in shared:
        keep &= np.isfinite(measures[name])
    for name in selecting:
        low, high = ranges[name]
        keep &= (measures[name] >= low) & (measures[name] <= high)
    if not keep.any():
        bounds = ", ".join(
            f"{n} {ranges[n][0] * 100:g}-{ranges[n][1] * 100:g} cm" for n in selecting
        )
        raise InputError(
            f"no person is in size {centre.size} ({bounds}); check the file's units and the "
            "chart's ranges",
            source,
            f"{selecting[0]}_cm",
        )
    values = {name: measures[name][keep] for name in shared}
    w = weight[keep]
    median = {name: weighted_quantile(values[name], w, 0.5) for name in shared}
    ends = {
        name: (weighted_quantile(values[name], w, LOW), weighted_quantile(values[name], w, HIGH))
        for name in shared
    }

    free = tuple(n for n in centre.girth if n not in measures and n not in ranges)

    def make(name: str, at: dict[str, float], quantiles: dict[str, float]) -> Wearer:
        girths = {k: v for k, v in at.items() if k != "stature"}
        targets = wearer_targets(centre, girths, at.get("stature"), name, free)
        return Wearer(name, targets, quantiles)

    out = [make("centre", median, dict.fromkeys(shared, 0.5))]
    for name in shared:
        for q, value in zip((LOW, HIGH), ends[name], strict=True):
            at = {**median, name: value}
            out.append(
                make(f"{name}_p{round(100 * q)}", at, {**dict.fromkeys(shared, 0.5), name: q})
            )
    out += shape_wearers(out[0])
    inside = np.ones(len(w), dtype=bool)
    for name in shared:
        inside &= (values[name] >= ends[name][0]) & (values[name] <= ends[name][1])
    return Wearers(
        tuple(out),
        "population",
        tuple(shared),
        people=int(keep.sum()),
        weight=float(w.sum()),
        coverage=float(w[inside].sum() / w.sum()),
    )


def range_wearers(centre: ChartTargets, ranges: Mapping[str, tuple[float, float]]) -> Wearers:
    """The wearers of the size ``centre`` from its girth ``ranges`` (m) alone (module
    docstring); the centre alone where the size gives no range."""
    names = [name for name in centre.girth if name in ranges]
    out = [Wearer("centre", centre)]
    if len(names) <= 3:
        for ends in itertools.product((0, 1), repeat=len(names)):
            label = "_".join(
                f"{n}_{'max' if e else 'min'}" for n, e in zip(names, ends, strict=True)
            )
            girths = {n: ranges[n][e] for n, e in zip(names, ends, strict=True)}
            out.append(Wearer(label, wearer_targets(centre, girths, None, label)))
    else:
        from scipy.stats import qmc  # late: scipy.stats is slow to import, and rarely needed

        sample = qmc.Sobol(len(names), scramble=True, seed=0).random(MAX_CORNERS)
        for k, point in enumerate(sample):
            label = f"sample_{k + 1}"
            girths = {
                n: ranges[n][0] + t * (ranges[n][1] - ranges[n][0])
                for n, t in zip(names, point, strict=True)
            }
            out.append(Wearer(label, wearer_targets(centre, girths, None, label)))
    out += shape_wearers(out[0])
    return Wearers(tuple(out), "ranges", tuple(names))


__all__ = [
    "HIGH",
    "LOW",
    "MAX_CORNERS",
    "SIZE",
    "Wearer",
    "Wearers",
    "population_wearers",
    "range_wearers",
    "wearer_targets",
    "weighted_quantile",
]
