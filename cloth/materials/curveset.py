"""Many piecewise-linear curves evaluated at once, one per spring (a garment of several fabrics).

A `CurveSet` holds C curves (`cloth.materials.curves.StressStrainCurve`) and, for each of S
springs, the index of its curve; it answers what one curve answers (stress, tangent, energy
density, tension-only) for the (S,) strains of all springs in one vectorised pass, so a garment
of several fabrics costs about what one of a single fabric does, however many composite curves
its junctions make (`cloth.materials.composite`).

The segment of each strain is found by one `numpy.searchsorted` over every curve's knots laid
end to end, each curve's shifted by its index times `SPAN` (strains are clipped to within
`SPAN` / 2 of zero for the search alone; the values use the strain itself, on the segment's
line, so a strain past the last knot follows the last slope as a single curve's does).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.materials.curves import StressStrainCurve

#: The shift between curves' knots in the joint search (1); strains are clipped to
#: [-SPAN / 4, SPAN / 2) for the search.
SPAN = 4096.0


class CurveSet:
    """Curves ``curves`` and the curve ``index`` ((S,) int) of each of S springs.

    Parameters
    ----------
    curves : sequence of StressStrainCurve
    index : (S,) int
        The curve of each spring.
    """

    def __init__(self, curves: Sequence[StressStrainCurve], index: ArrayLike) -> None:
        self.curves = tuple(curves)
        self.index = np.asarray(index, dtype=np.intp)
        if self.index.size and (self.index.min() < 0 or self.index.max() >= len(self.curves)):
            raise ValueError("a spring's curve index is out of range")
        counts = np.array([c.n_knots for c in self.curves])
        start = np.concatenate(([0], np.cumsum(counts)))[:-1]
        keys = np.concatenate(
            [c.knot_strain + k * SPAN for k, c in enumerate(self.curves)]
        )  # increasing: knots of curve k lie in [k SPAN, k SPAN + SPAN / 2)
        self._keys = keys
        self._last = np.repeat(start + counts - 2, counts)
        self._x = np.concatenate([c.knot_strain for c in self.curves])
        self._y = np.concatenate([c.knot_stress for c in self.curves])
        slopes = [np.append(c.slopes, c.slopes[-1]) for c in self.curves]
        self._slope = np.concatenate(slopes)
        energy = []
        for c in self.curves:
            steps = np.diff(c.knot_strain)
            mid = 0.5 * (c.knot_stress[1:] + c.knot_stress[:-1]) * steps
            energy.append(np.concatenate(([0.0], np.cumsum(mid))))
        self._energy = np.concatenate(energy)
        self._compression = np.array([c.compression_modulus for c in self.curves])[self.index]
        self._offset = self.index * SPAN
        self._start = start[self.index]

    @property
    def tension_only(self) -> bool:
        """Whether every curve carries no compression (`StressStrainCurve.tension_only`)."""
        return all(c.tension_only for c in self.curves)

    def _segment(self, eps: NDArray[np.float64]) -> NDArray[np.intp]:
        """The flat knot position that starts each strain's segment."""
        key = np.clip(eps, -0.25 * SPAN, 0.5 * SPAN * (1 - 1e-9)) + self._offset
        k = np.searchsorted(self._keys, key, side="right") - 1
        k = np.maximum(k, self._start)
        return np.minimum(k, self._last[self._start])

    def stress_tangent(self, eps: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Stress (Pa) and tangent (Pa) of every spring at strains ``eps`` ((S,), 1)."""
        eps = np.asarray(eps, dtype=np.float64)
        k = self._segment(eps)
        tangent = self._slope[k]
        sigma = self._y[k] + tangent * (eps - self._x[k])
        compressed = eps < 0.0
        sigma = np.where(compressed, self._compression * eps, sigma)
        tangent = np.where(compressed, self._compression, tangent)
        return sigma, tangent

    def stress(self, eps: ArrayLike) -> NDArray[np.float64]:
        """Stress (Pa) of every spring at strains ``eps`` ((S,), 1)."""
        return self.stress_tangent(eps)[0]

    def energy_density(self, eps: ArrayLike) -> NDArray[np.float64]:
        """Energy density int_0^eps sigma (J m-3) of every spring at strains ``eps`` ((S,))."""
        eps = np.asarray(eps, dtype=np.float64)
        k = self._segment(eps)
        d = eps - self._x[k]
        psi = self._energy[k] + self._y[k] * d + 0.5 * self._slope[k] * d * d
        return np.where(eps < 0.0, 0.5 * self._compression * eps * eps, psi)


__all__ = ["SPAN", "CurveSet"]
