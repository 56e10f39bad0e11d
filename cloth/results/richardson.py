"""How far a reported value is from the converged garment: Richardson's estimate from one value
on three grids, each coarser than the one before.

With f1, f2, f3 the value on the fine, middle and coarse grid, and r21 = h2 / h1, r32 = h3 / h2
the refinement ratios of their spacings h (a grid of n nodes around and m rows has
h = sqrt(around / n x height / (m - 1)); halving n and m gives r of about 2), the values of a
scheme of order p follow f_k = f* + C h_k^p, so

    (f3 - f2) / (f2 - f1) = r21^p (r32^p - 1) / (r21^p - 1),

which increases with p and is solved for the observed order p (equal ratios r: r^p, so
p = ln((f3 - f2) / (f2 - f1)) / ln r). The extrapolated (converged) value is
f* = f1 + (f1 - f2) / (r21^p - 1) and the Richardson error of the reported value f1 is f* - f1.

The error stated beside a reported value (`Estimate.uncertainty`) is Roache's grid convergence
index, the Richardson error times a safety factor: `SAFETY_CONFIRMED` (1.25) where the observed
order is within 10 % of the scheme's order `SCHEME_ORDER` (2: Laplace's law on a polygon of n
sides, p = T / r (1 - pi^2 / (6 n^2) + ...); tests/test_richardson.py observes it on the
cylinder), else `SAFETY` (3): contact fronts and edge rows lower the observed order on a torso
towards 1, and three levels then only estimate the error's size (Roache 1998; Roy and
Oberkampf 2011 use the same rule). The stated error is never less than the finest difference
|f1 - f2|: a sequence converging at first order leaves an error as large as its last change,
and an order near 2 seen on levels not yet in the asymptotic range is luck (the torso's hip at
48 x 24, from levels 12 x 6 and 24 x 12: p 2.19, 1.25 x the Richardson error 10 Pa, the true
error 25 Pa; its last change 30 Pa). docs/validation.md measures it against a grid eight times
finer.

The order is observed only where the three values converge monotonically (the two differences
have one sign) and p lies within `ORDERS`. Converged values wobble, though: a girth line read
on the body settles by 96 x 48 and then moves by a few Pa either way (the torso's waist band
2314, 2345, 2343 Pa at 48 x 24, 96 x 48, 192 x 96), which shows no order. Where the levels show
no order (not monotone, two equal, or an order beyond `ORDERS`) but the finest difference is at
most 1 / `SHRINK` of the coarser one, the levels converge, and the stated error is Roache's
two-grid index with his safety factor for two grids, `SAFETY` x |f1 - f2|, floored at
`SAFETY` x |f2 - f3| / r21^4 (what the fastest accepted order would still leave, so that two
equal fine levels do not state a zero error); nothing is extrapolated (code 6,
``finest_difference``). Where the finest difference does not shrink either (the levels move by
a few tenths of a per cent either way: a line converged below what the grids resolve, or still
short of it), the stated error is `SAFETY` x the levels' range max |fi - fj| (Eca and Hoekstra's
rule for levels without an asymptotic order, J. Comput. Phys. 262, 2014; code 7,
``data_range``): it bounds a value that moves less than that range from grid to grid, and it is
as large as the levels disagree. Before this rule such lines stated no error: at 192 x 96 with
graded rows, the torso's underbust read 1304.74, 1303.97, 1304.00 Pa over its three levels and
stated nothing, where 3 x 0.77 Pa holds the 0.2 Pa it is off the 384 x 192 value
(docs/validation.md, "Graded rows"). Only levels with a value missing, or all three equal,
give no error (`Estimate.observed` is False, `Estimate.reason` says why).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from scipy.optimize import brentq

#: Observed orders accepted as asymptotic (docs/outputs.md).
ORDERS = (0.5, 4.0)
#: Refinement ratio between levels where none is given (n and m halved).
RATIO = 2.0
#: The scheme's order on smooth fields (module docstring).
SCHEME_ORDER = 2.0
#: Safety factors of the stated error: the observed order within 10 % of the scheme's, or not.
SAFETY_CONFIRMED, SAFETY = 1.25, 3.0
#: Levels without an order converge where the finest difference is at most 1 / SHRINK of the
#: coarser one (module docstring): the factor a first-order scheme shrinks by when h halves.
SHRINK = 2.0

#: Why an order was not observed, by code (result.nc's ``*_estimate`` flag; 0: observed).
REASONS = {
    1: "too few levels",
    2: "a level has no finite value",
    3: "two levels give the same value",
    4: "the levels do not converge monotonically",
    5: "the observed order is outside the asymptotic range",
}
#: The code of an error stated from the finest difference (module docstring).
FINEST_DIFFERENCE = 6
#: What summary.csv says of an error stated from the finest difference.
FINEST_NOTE = (
    "the levels converge without an order (they wobble): the error is 3 x the finest difference"
)
#: The code of an error stated from the levels' range (module docstring).
DATA_RANGE = 7
#: What summary.csv says of an error stated from the levels' range.
RANGE_NOTE = (
    "the levels show no order and do not converge (they move either way): the error is 3 x "
    "their range"
)
#: The notes of errors stated without an order, by code.
NOTES = {FINEST_DIFFERENCE: FINEST_NOTE, DATA_RANGE: RANGE_NOTE}
#: The flag meanings of `REASONS` and `NOTES`, with 0 first (CF ``flag_meanings``).
FLAG_MEANINGS = (
    "observed too_few_levels not_finite equal_levels not_monotone order_out_of_range "
    "finest_difference data_range"
)


@dataclass(frozen=True)
class Estimate:
    """The estimate of one value (module docstring): ``order`` (1), ``extrapolated`` (the
    value's unit), ``error`` (extrapolated - reported, the value's unit) and ``uncertainty``
    (the stated error: |error| x the safety factor) where ``observed``, else NaN, a ``reason``
    and its ``code`` (`REASONS`)."""

    reported: float
    order: float
    extrapolated: float
    error: float
    observed: bool
    reason: str = ""
    uncertainty: float = math.nan
    code: int = 0

    @property
    def relative_error(self) -> float:
        """The stated error relative to the reported value: uncertainty / |reported| (1), NaN
        where not observed."""
        if not self.observed or self.reported == 0.0:
            return math.nan
        return self.uncertainty / abs(self.reported)

    @classmethod
    def missing(cls, reported: float, code: int, detail: str = "") -> Estimate:
        """No estimate of ``reported``, for reason ``code`` (`REASONS`; ``detail`` appended)."""
        nan = math.nan
        reason = REASONS[code] + (f": {detail}" if detail else "")
        return cls(reported, nan, nan, nan, False, reason, nan, code)


def _ratio_of_differences(order: float, r21: float, r32: float) -> float:
    """(f3 - f2) / (f2 - f1) of a scheme of ``order`` with the ratios r21, r32."""
    a = r21**order
    return a * (r32**order - 1.0) / (a - 1.0)


def observed_order(near: float, far: float, r21: float, r32: float) -> float:
    """The order p at which (f3 - f2) / (f2 - f1) = ``far`` / ``near`` (module docstring);
    ``near`` and ``far`` of one sign. Searched in 1e-3..50 (its ends where beyond)."""
    target = far / near
    low, high = 1e-3, 50.0
    if target <= _ratio_of_differences(low, r21, r32):
        return low
    if target >= _ratio_of_differences(high, r21, r32):
        return high
    return float(
        brentq(lambda p: _ratio_of_differences(p, r21, r32) - target, low, high, xtol=1e-12)
    )


def richardson(
    fine: float,
    middle: float,
    coarse: float,
    ratio: float = RATIO,
    ratio_coarse: float | None = None,
) -> Estimate:
    """The Richardson estimate of ``fine`` from its values on the two coarser levels;
    ``ratio`` = h_middle / h_fine and ``ratio_coarse`` = h_coarse / h_middle (default:
    ``ratio``)."""
    r21, r32 = float(ratio), float(ratio if ratio_coarse is None else ratio_coarse)
    if not all(math.isfinite(v) for v in (fine, middle, coarse)):
        return Estimate.missing(fine, 2)
    near, far = fine - middle, middle - coarse
    if near == 0.0 or far == 0.0:
        return _converging(fine, near, far, r21, Estimate.missing(fine, 3))
    if (near > 0.0) != (far > 0.0):
        return _converging(fine, near, far, r21, Estimate.missing(fine, 4))
    order = observed_order(near, far, r21, r32)
    if not ORDERS[0] <= order <= ORDERS[1]:
        missing = Estimate.missing(fine, 5, f"{order:.2g}, not in {ORDERS[0]:g}-{ORDERS[1]:g}")
        return _converging(fine, near, far, r21, replace(missing, order=order))
    error = near / (r21**order - 1.0)
    confirmed = abs(order - SCHEME_ORDER) <= 0.1 * SCHEME_ORDER
    safety = SAFETY_CONFIRMED if confirmed else SAFETY
    stated = max(safety * abs(error), abs(near))  # never below the last change
    return Estimate(fine, order, fine + error, error, True, "", stated, 0)


def _converging(fine: float, near: float, far: float, r21: float, missing: Estimate) -> Estimate:
    """The two-grid estimate of levels that show no order but converge, or the data-range
    estimate where the finest difference does not shrink (module docstring); ``missing`` where
    the three levels are equal."""
    nan = math.nan
    if far == 0.0 or abs(near) * SHRINK > abs(far):
        spread = max(abs(near), abs(far), abs(near + far))  # max |fi - fj| of the three
        if spread == 0.0:
            return missing
        order = missing.order  # an order outside the asymptotic range is kept, for the record
        return Estimate(fine, order, nan, nan, True, RANGE_NOTE, SAFETY * spread, DATA_RANGE)
    stated = SAFETY * max(abs(near), abs(far) / r21 ** ORDERS[1])
    return Estimate(fine, nan, nan, nan, True, FINEST_NOTE, stated, FINEST_DIFFERENCE)


def grid_spacing(n: int, m: int, around: float = 1.0, height: float = 1.0) -> float:
    """The spacing h (m) of a grid of ``n`` nodes around a girth ``around`` (m) and ``m`` rows
    over ``height`` (m): sqrt(around / n x height / (m - 1)), the side of a square cell of the
    same area. Refinement ratios are quotients of it, so the lengths cancel."""
    return math.sqrt(around / n * height / max(m - 1, 1))


def estimate_levels(values: list[float], grids: list[tuple[int, int]]) -> Estimate:
    """The estimate of ``values[0]`` on ``grids[0]`` ((n, m)) from the values on the coarser
    ``grids`` after it (finest first; the first three are used): `Estimate.missing` with
    "too few levels" below three."""
    if len(values) < 3 or len(grids) < 3:
        return Estimate.missing(values[0] if values else math.nan, 1)
    h = [grid_spacing(n, m) for n, m in grids[:3]]
    return richardson(values[0], values[1], values[2], h[1] / h[0], h[2] / h[1])
