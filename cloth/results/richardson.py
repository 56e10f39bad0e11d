"""How far a reported value is from the converged garment: Richardson's estimate from one value
on three grids, each twice as fine as the one before.

With f1, f2, f3 the value on the fine, middle and coarse grid (refinement ratio r = 2 in n and
m), the observed order is

    p = ln((f3 - f2) / (f2 - f1)) / ln r,

the extrapolated (converged) value f* = f1 + (f1 - f2) / (r^p - 1), and the estimated error of
the reported value f1 is f* - f1 (Pa for a pressure; relative: divided by |f*|).

The order is observed only where the three values converge monotonically (the two differences
have one sign) and p lies within `ORDERS`: the scheme's order is 2 on smooth fields (Laplace's
law on a polygon of n sides: p = T/r (1 - pi^2 / (6 n^2) + ...)), and contact fronts and edge
rows lower it towards 1; outside that range the levels are not in the asymptotic range and no
error is given (`Estimate.observed` is False, `Estimate.reason` says why). Two equal levels (no
change) give order "not observed" too, rather than a made-up zero error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Observed orders accepted as asymptotic (docs/outputs.md).
ORDERS = (0.5, 4.0)
#: Refinement ratio between levels (n and m halved).
RATIO = 2.0


@dataclass(frozen=True)
class Estimate:
    """The estimate of one value (module docstring): ``order`` (1), ``extrapolated`` (the
    value's unit) and ``error`` (extrapolated - reported) where ``observed``, else NaN and a
    ``reason``."""

    reported: float
    order: float
    extrapolated: float
    error: float
    observed: bool
    reason: str = ""

    @property
    def relative_error(self) -> float:
        """|error| / |extrapolated| (1), NaN where not observed."""
        if not self.observed or self.extrapolated == 0.0:
            return math.nan
        return abs(self.error) / abs(self.extrapolated)


def richardson(fine: float, middle: float, coarse: float, ratio: float = RATIO) -> Estimate:
    """The Richardson estimate of ``fine`` from its values on the two coarser levels."""
    nan = math.nan
    values = (fine, middle, coarse)
    if not all(math.isfinite(v) for v in values):
        return Estimate(fine, nan, nan, nan, False, "a level has no finite value")
    near, far = fine - middle, middle - coarse
    if near == 0.0 or far == 0.0:
        return Estimate(fine, nan, nan, nan, False, "two levels give the same value")
    if (near > 0.0) != (far > 0.0):
        return Estimate(fine, nan, nan, nan, False, "the levels do not converge monotonically")
    order = math.log(far / near) / math.log(ratio)
    if not ORDERS[0] <= order <= ORDERS[1]:
        return Estimate(
            fine, order, nan, nan, False,
            f"observed order {order:.2g} outside {ORDERS[0]:g}-{ORDERS[1]:g}: the levels are "
            "not in the asymptotic range",
        )  # fmt: skip
    error = near / (ratio**order - 1.0)
    return Estimate(fine, order, fine + error, error, True)
