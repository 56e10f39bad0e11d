"""The fabric a size chart needs (issue 62, item 4): per size, the working strain window and
the corridor of weft tension against strain that holds a line's band over the size's range.

The chart asked for has ``most`` sizes over the central ``share`` of the people's primary
measure, each size ``[a, b]`` as wide in ratio (``b / a`` the same for every size: Laplace's
pressure scales with the girth's inverse). A row of rest circumference ``c0`` worn on the girth
``g = c0 (1 + e)`` puts ``P = hoop 2 pi T(e) / g + shape term`` on it
(`cloth.results.tubemodel`), so the band
``[low, high]`` holds over the size when the weft term stays in ``[low', high']``, the band
less the shape term (at the ends of the shape terms the search holds the size over), that
is when the fabric's tension stays in the corridor

    low' c0 (1 + e) / (2 pi hoop) <= T(e) <= high' c0 (1 + e) / (2 pi hoop),
    e in [a/c0 - 1, b/c0 - 1].

A fabric linear through zero (``T = E e``) fits the corridor at some cut when
``E <= (high' - low') / (2 pi hoop (1/a - 1/b))`` (`linear_modulus`, N m-1): the stiffest such
fabric, cut so that ``P(a) = low``, touches the corridor's floor at ``a`` and its roof at ``b``.
The window and the corridor are stated at that cut: the least stretch at which a linear fabric
can hold the size (a softer fabric works at more stretch, a fabric that stiffens with strain at
less).

**The case's fabric** is cut where it holds the size best (`fabric_rest`: the rest
circumference that puts the size's ends equally far inside the band, `cloth.results.sizechart.
centred_rest`, or equally far outside where no cut holds it). At that cut its window is
``[a/c0 - 1, b/c0 - 1]`` and the corridor is the one above with that ``c0``: the fabric holds
the size exactly where its curve is above the corridor's floor at the window's start and below
its roof at the window's end (the pressure rises with the girth), which is ``fabric_holds``;
sizes.png draws each size's corridor at that cut with the fabric's curve
(`cloth.stages.sizetables`), so the figure and the table say the same thing.

Units: girths and circumferences in m, tension in N m-1, pressure in Pa, strain 1.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.results.sizechart import Band, central, centred_rest
from cloth.results.tubemodel import LineModel


@dataclass(frozen=True)
class Need:
    """One size of the chart asked for: its girth range (m), the stiffest linear fabric that
    holds it (``linear_modulus``, N m-1, T / e; 0 where none can), the rest circumference at
    which that fabric does (m), the strain window there (1), the corridor's floor at the
    window's start and roof at its end (N m-1), and whether the fabric given holds the size at
    some cut."""

    low: float
    high: float
    linear_modulus: float
    rest: float
    strain_min: float
    strain_max: float
    tension_floor: float
    tension_roof: float
    fabric_holds: bool
    #: the weft term's band (Pa): the line's band less the warp term at each end
    weft_band: tuple[float, float] = (0.0, 0.0)
    hoop: float = 1.0
    #: where the case's fabric is cut for the size (m; module docstring)
    fabric_rest: float = float("nan")
    #: the case's fabric's weft tension at its window's start and end there (N m-1)
    fabric_tension: tuple[float, float] = (float("nan"), float("nan"))

    def corridor(
        self, strain: NDArray[np.float64], rest: float | None = None
    ) -> NDArray[np.float64]:
        """(2, S) the corridor's floor and roof (N m-1) at ``strain`` (S,) for the cut
        ``rest`` (m; default the stiffest linear fabric's)."""
        c0 = self.rest if rest is None else rest
        scale = c0 * (1.0 + np.asarray(strain, dtype=float)) / (2.0 * np.pi * self.hoop)
        return np.stack([self.weft_band[0] * scale, self.weft_band[1] * scale])

    @property
    def fabric_window(self) -> tuple[float, float]:
        """The case's fabric's strain window at its cut (1)."""
        return self.low / self.fabric_rest - 1.0, self.high / self.fabric_rest - 1.0


def linear_modulus(
    weft_low: float, weft_high: float, low: float, high: float, hoop: float
) -> float:
    """The stiffest fabric linear through zero (T / e, N m-1) whose weft term stays within
    ``weft_low`` to ``weft_high`` (Pa) over the girths ``low`` to ``high`` (m); 0 where the
    band leaves the weft term no room (module docstring)."""
    room = weft_high - weft_low
    return max(room, 0.0) / (2.0 * np.pi * hoop * (1.0 / low - 1.0 / high))


def requirement(
    values: NDArray[np.float64],
    weight: NDArray[np.float64],
    model: LineModel,
    band: Band,
    share: float,
    most: int,
    offset: tuple[float, float] = (0.0, 0.0),
) -> list[Need]:
    """The chart asked for and the fabric each of its sizes needs (module docstring):
    ``values`` (P,) the primary measure's girths (m) with ``weight`` (P,), ``model`` the fast
    model at its line (its calibration's hoop; its tension whether the given fabric
    holds), held over the shape terms' ``offset`` range (Pa) as the search is."""
    first, last = central(values, weight, share)
    edges = first * (last / first) ** (np.arange(most + 1) / most)
    hoop = model.calibration.hoop
    weft_low = band.low - offset[0]
    weft_high = band.high - offset[1]
    needs = []
    for a, b in itertools.pairwise(edges):
        modulus = linear_modulus(weft_low, weft_high, a, b, hoop)
        rest = (
            1.0 / (1.0 / a + weft_low / (2.0 * np.pi * hoop * modulus))
            if modulus > 0
            else float("nan")
        )
        cut = centred_rest(model, band, float(a), float(b), offset)
        tension = model.tension(np.array([a / cut - 1.0, b / cut - 1.0]))
        floor = weft_low * a / (2.0 * np.pi * hoop)
        roof = weft_high * b / (2.0 * np.pi * hoop)
        holds = bool(tension[0] >= floor * (1 - 1e-9) and tension[1] <= roof * (1 + 1e-9))
        needs.append(
            Need(
                low=float(a),
                high=float(b),
                linear_modulus=float(modulus),
                rest=float(rest),
                strain_min=float(a / rest - 1.0),
                strain_max=float(b / rest - 1.0),
                tension_floor=float(floor),
                tension_roof=float(roof),
                fabric_holds=holds,
                weft_band=(float(weft_low), float(weft_high)),
                hoop=float(hoop),
                fabric_rest=float(cut),
                fabric_tension=(float(tension[0]), float(tension[1])),
            )
        )
    return needs


__all__ = ["Need", "linear_modulus", "requirement"]
