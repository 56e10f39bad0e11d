"""A graded pattern's profile: a reduction given at landmarks or heights, interpolated between.

``garment.reduction`` (and ``garment.lengthwise_reduction``) is a number, the same reduction on
every row, or a profile: a mapping from knots to reductions, each knot a girth line's name
(``waist``: the body's landmark, or one of the case's ``landmarks``) or a height in metres
(``1.05``)::

    reduction: {hip: 0.15, waist: 0.22, underbust: 0.20, bust: 0.15}

Between the knots the reduction is the monotone piecewise cubic (PCHIP, Fritsch and Carlson
1980; `scipy.interpolate.PchipInterpolator`) through them: C1, no overshoot, so between two
knots it stays between their values. Beyond the lowest and the highest knot it is held at their
values. One knot is a uniform reduction.

PCHIP's slopes depend on the values (a knot where the profile turns gets slope 0), so the row
reductions are smooth functions of the knot values except where two neighbouring differences
are both zero (a flat stretch): there `row_sensitivity` takes the mean of the one-sided
derivatives. The design loop (`cloth.design`) starts from knot values that differ.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError

#: Step (in reduction) of the central differences of `row_sensitivity`.
SENSITIVITY_STEP = 1e-6


def _height(key: str) -> float | None:
    try:
        return float(key)
    except ValueError:
        return None


@dataclass(frozen=True)
class Profile:
    """Knots (names or height texts) and their values (1), in the order given."""

    keys: tuple[str, ...]
    values: tuple[float, ...]

    @classmethod
    def of(cls, value: float | Mapping[str, float]) -> Profile:
        """The profile of a case's ``reduction``: a number (one knot, ``uniform``) or a mapping."""
        if isinstance(value, Mapping):
            return cls(tuple(str(k) for k in value), tuple(float(v) for v in value.values()))
        return cls(("uniform",), (float(value),))

    @property
    def uniform(self) -> bool:
        return self.keys == ("uniform",)

    def with_values(self, values: NDArray[np.float64]) -> Profile:
        """The same knots with new values ((K,), 1)."""
        return Profile(self.keys, tuple(float(v) for v in values))

    def to_block(self) -> float | dict[str, float]:
        """The case's ``reduction`` value this profile is."""
        return self.values[0] if self.uniform else dict(zip(self.keys, self.values, strict=True))

    def heights(self, landmarks: Mapping[str, float], field: str = "garment.reduction") -> NDArray:
        """(K,) float, m: each knot's height: a height text read as a number, a name looked up
        in ``landmarks`` (name -> m). `InputError` naming ``field`` for an unknown name or two
        knots at one height."""
        if self.uniform:
            return np.zeros(1)
        out = []
        for key in self.keys:
            height = _height(key)
            if height is None:
                if key not in landmarks:
                    known = ", ".join(sorted(landmarks)) or "none; give heights in m"
                    raise InputError(
                        f"knot {key!r} is neither a height in m nor a girth line of the body "
                        f"(its girth lines: {known})",
                        field=field,
                    )
                height = float(landmarks[key])
            out.append(height)
        heights = np.asarray(out)
        if len(np.unique(heights)) != len(heights):
            raise InputError("two knots are at one height; give each height once", field=field)
        return heights

    def evaluate(
        self,
        z: NDArray[np.float64],
        landmarks: Mapping[str, float],
        values: NDArray | None = None,
        field: str = "garment.reduction",
    ) -> NDArray[np.float64]:
        """(m,) float, 1: the reduction at heights ``z`` ((m,), m), with the knots' ``values``
        ((K,)) in place of the profile's own where given (module docstring); `InputError`
        naming ``field`` where a knot is not found (`heights`)."""
        v = np.asarray(self.values if values is None else values, dtype=float)
        z = np.asarray(z, dtype=float)
        h = self.heights(landmarks, field)
        if len(v) == 1:
            return np.full(z.shape, float(v[0]))
        order = np.argsort(h)
        h, v = h[order], v[order]
        # imported here: scipy.interpolate takes ~0.5 s, which `cloth case write` need not pay
        from scipy.interpolate import PchipInterpolator

        return PchipInterpolator(h, v, extrapolate=False)(np.clip(z, h[0], h[-1]))

    def row_sensitivity(
        self, z: NDArray[np.float64], landmarks: Mapping[str, float]
    ) -> NDArray[np.float64]:
        """(m, K) float, 1: d(reduction at z_j) / d(value of knot k), by central differences of
        `evaluate` (step `SENSITIVITY_STEP`; exact to rounding where the interpolant is smooth
        in the values)."""
        v = np.asarray(self.values, dtype=float)
        out = np.empty((len(np.asarray(z)), len(v)))
        for k in range(len(v)):
            step = np.zeros_like(v)
            step[k] = SENSITIVITY_STEP
            up = self.evaluate(z, landmarks, v + step)
            down = self.evaluate(z, landmarks, v - step)
            out[:, k] = (up - down) / (2 * SENSITIVITY_STEP)
        return out


def lengthwise_spans(
    profile: Profile, heights: NDArray[np.float64], landmarks: Mapping[str, float]
) -> NDArray[np.float64]:
    """(m-1,) float, m: the warp rest length between rows at ``heights`` ((m,), m): the height
    step times (1 - the lengthwise reduction at its middle)."""
    middle = 0.5 * (heights[1:] + heights[:-1])
    return np.diff(heights) * (
        1.0 - profile.evaluate(middle, landmarks, field="garment.lengthwise_reduction")
    )
