"""The fast model of a size chart's search: Laplace's law on a tube, calibrated by equilibria.

A tube of fabric whose row at a girth line has the rest circumference ``c0`` (m), worn on a
body whose girth there is ``g`` (m), is stretched along the weft by ``e = g / c0 - 1`` and
carries the weft tension ``T(e) = thickness x sigma_weft(e)`` (N m-1). On a closed convex
section of perimeter ``g`` the mean curvature is ``2 pi / g``, so by Laplace the mean pressure
on the line is

    P = k 2 pi T(e) / g   (Pa),

exact on a cylinder (docs/validation.md). On a leg or a torso the warp carries tension too, and
the pattern, cut for the size's body, meets a wearer of another shape: on the stocking
(config/stocking.yaml's garment at 96 x 288, the power net, cut for the chart's leg and placed by
B) 25 equilibria of ANSUR II women read 0.9-13.6 mmHg below Laplace's weft term at B, by their
shape as much as by their ankle (their weft tension is Laplace's; the difference is the warp's
over the leg's profile). The fast model adds a shape term (`Calibration`) linear in the
wearer's shape features (her stature and her girths' ratios to the line's, each relative to the
pattern's body; `cloth.stages.sizes`):

    P = hoop x 2 pi T(e) / g + beta_0 + sum_j beta_j f_j   (Pa),

fitted by least squares to full equilibria's band means, ridge-regularised towards Laplace
(hoop 1, no shape term). On those 25 equilibria it leaves 0.83 mmHg rms (2.4 at most), where
Laplace times a fitted factor leaves 3.99 (9.2 at most).

Inverting it (`rest_for`): the rest circumference that gives the pressure ``P`` on the girth
``g`` is ``g / (1 + e)`` with ``T(e) = (P - shape term) g / (2 pi hoop)``; the tension is
piecewise linear and non-decreasing, so its inverse is exact (`Tension.strain_at`).

Units: girths and circumferences in m, pressure in Pa, tension in N m-1, strain 1.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.errors import InputError
from cloth.materials.curves import Fabric

#: The calibration's pull towards Laplace's law (hoop 1, no shape term), in equilibria: as
#: much as this many more points that each say so (weak against ten, firm against two).
RIDGE = 1.0


@dataclass(frozen=True)
class Tension:
    """The weft tension of a fabric against its strain: T(e) = thickness x sigma_weft(e),
    N m-1 (``knots``: (K,) strain, 1; ``tension``: (K,) N m-1; linear beyond the last knot with
    the last slope, as the curve)."""

    strain: NDArray[np.float64]
    tension: NDArray[np.float64]

    @classmethod
    def of(cls, fabric: Fabric) -> Tension:
        """The weft tension of ``fabric``."""
        curve = fabric.weft
        return cls(
            np.asarray(curve.knot_strain, dtype=float),
            fabric.thickness * np.asarray(curve.knot_stress, dtype=float),
        )

    def __call__(self, strain: ArrayLike) -> NDArray[np.float64]:
        """T(e), N m-1, for strains (any shape, 1); 0 at and below zero strain (a tension
        field)."""
        e = np.asarray(strain, dtype=float)
        slope = (self.tension[-1] - self.tension[-2]) / (self.strain[-1] - self.strain[-2])
        inside = np.interp(e, self.strain, self.tension)
        beyond = self.tension[-1] + slope * (e - self.strain[-1])
        return np.where(e <= 0, 0.0, np.where(e > self.strain[-1], beyond, inside))

    def strain_at(self, tension: ArrayLike) -> NDArray[np.float64]:
        """The strain (1) whose tension is ``tension`` (N m-1, >= 0): the inverse of a
        non-decreasing piecewise-linear curve. Above a flat stretch (a slack toe, a plateau)
        the rise starts at the stretch's end; exactly at a flat stretch's tension, its
        smallest strain."""
        t = np.asarray(tension, dtype=float)
        step = np.diff(self.tension)
        ends = np.concatenate([step > 0, [True]])  # the last knot at each tension
        starts = np.concatenate([[True], step > 0])  # the first
        strain, values = self.strain[ends], self.tension[ends]
        inside = np.where(
            np.isin(t, self.tension[starts]),
            np.interp(t, self.tension[starts], self.strain[starts]),
            np.interp(t, values, strain),
        )
        slope = (self.tension[-1] - self.tension[-2]) / (self.strain[-1] - self.strain[-2])
        above = t > values[-1]
        if np.any(above) and not slope > 0:
            raise InputError(
                "the fabric's weft tension does not rise at its last knot, so no strain gives "
                "a higher pressure; give a lab table whose curve rises",
                field="material",
            )
        beyond = self.strain[-1] + (t - values[-1]) / slope if slope > 0 else self.strain[-1]
        return np.where(above, beyond, inside)


@dataclass(frozen=True)
class Calibration:
    """The fast model's correction (module docstring): ``hoop`` (1), the weft term's share,
    and ``shape`` (F + 1,) Pa, the constant and one coefficient per shape feature."""

    hoop: float = 1.0
    shape: NDArray[np.float64] = field(default_factory=lambda: np.zeros(1))

    @classmethod
    def exact(cls, features: int = 0) -> Calibration:
        """Laplace on a cylinder: the weft term alone."""
        return cls(1.0, np.zeros(features + 1))

    @classmethod
    def fit(cls, weft: ArrayLike, features: ArrayLike, pressure: ArrayLike) -> Calibration:
        """Least squares of the equilibria's ``pressure`` (N,) Pa against their weft term
        ``weft`` (N,) Pa and shape ``features`` (N, F; standardised, about 1 across the
        people), ridge-regularised (`RIDGE`) so that a few points give the nearest to
        Laplace's, not a wild fit; exact where none."""
        w = np.asarray(weft, dtype=float)
        f = np.asarray(features, dtype=float)
        f = f.reshape(len(w), -1) if f.ndim != 2 else f
        p = np.asarray(pressure, dtype=float)
        keep = np.isfinite(w) & np.isfinite(p) & np.all(np.isfinite(f), axis=1)
        w, f, p = w[keep], f[keep], p[keep]
        count = f.shape[1]
        if len(p) == 0:
            return cls.exact(count)
        scale = max(float(np.median(np.abs(p))), 1.0)
        matrix = np.column_stack([w, np.ones(len(p)), f])
        # the prior: hoop 1 and no shape term, each as RIDGE points would say it: the hoop's
        # effect over the weft terms' spread, a standard feature's effect (the constant is
        # free)
        spread = max(float(np.std(w)), 0.01 * scale)
        prior = np.concatenate([[1.0], np.zeros(count + 1)])
        weight = np.sqrt(RIDGE) * np.concatenate([[spread], [0.0], np.ones(count)])
        stacked = np.vstack([matrix, np.diag(weight)])
        target = np.concatenate([p, weight * prior])
        solution, *_ = np.linalg.lstsq(stacked, target, rcond=None)
        return cls(float(solution[0]), solution[1:])

    def offset(self, features: ArrayLike) -> NDArray[np.float64]:
        """The shape term (Pa) of people with ``features`` (P, F)."""
        f = np.asarray(features, dtype=float)
        f = f.reshape(-1, len(self.shape) - 1) if f.size else np.zeros((f.shape[0], 0))
        return self.shape[0] + f @ self.shape[1:]


def laplace(tension: Tension, girth: ArrayLike, rest: ArrayLike) -> NDArray[np.float64]:
    """Laplace's weft term (Pa) of a row of rest circumference ``rest`` (m) on the girth
    ``girth`` (m): 2 pi T(g / c0 - 1) / g; broadcast."""
    g = np.asarray(girth, dtype=float)
    return 2.0 * np.pi * tension(g / np.asarray(rest, dtype=float) - 1.0) / g


@dataclass(frozen=True)
class LineModel:
    """The fast model at one girth line: the fabric's ``tension`` and the line's
    ``calibration`` (module docstring)."""

    tension: Tension
    calibration: Calibration

    def pressure(
        self, girth: ArrayLike, rest: ArrayLike, offset: ArrayLike = 0.0
    ) -> NDArray[np.float64]:
        """Mean pressure, Pa, on ``girth`` (m) of a row of rest circumference ``rest`` (m),
        on a person whose shape term is ``offset`` (Pa; `Calibration.offset`)."""
        weft = self.calibration.hoop * laplace(self.tension, girth, rest)
        return weft + np.asarray(offset, dtype=float)

    def rest_for(
        self, girth: ArrayLike, pressure: ArrayLike, offset: ArrayLike = 0.0
    ) -> NDArray[np.float64]:
        """The rest circumference (m) that puts ``pressure`` (Pa) on ``girth`` (m) of a person
        whose shape term is ``offset`` (Pa); the girth itself (no stretch) where the shape
        term alone gives it."""
        g = np.asarray(girth, dtype=float)
        weft = np.asarray(pressure, dtype=float) - np.asarray(offset, dtype=float)
        needed = np.maximum(weft, 0.0) * g / (2.0 * np.pi * self.calibration.hoop)
        return g / (1.0 + self.tension.strain_at(needed))


@dataclass(frozen=True)
class Correction:
    """A size's correction of the fast model from its own equilibria (`cloth.results.recut`):
    the pressure a wearer reads is ``shift + scale x`` the fast model's (``shift`` Pa,
    ``scale`` 1 and > 0, so the order of the wearers is the fast model's)."""

    shift: float = 0.0
    scale: float = 1.0

    def __call__(self, pressure: ArrayLike) -> NDArray[np.float64]:
        """The corrected pressure (Pa) of fast-model pressures ``pressure`` (Pa, any shape)."""
        return self.shift + self.scale * np.asarray(pressure, dtype=float)

    @classmethod
    def fit(cls, fast: ArrayLike, read: ArrayLike) -> Correction:
        """Least squares of the equilibria's ``read`` (N,) Pa on the fast model's ``fast``
        (N,) Pa where they spread and the slope is positive; else the mean difference (a
        shift alone); none where no pair is finite."""
        f = np.asarray(fast, dtype=float)
        r = np.asarray(read, dtype=float)
        keep = np.isfinite(f) & np.isfinite(r)
        f, r = f[keep], r[keep]
        if len(f) == 0:
            return cls()
        if len(f) > 1 and np.ptp(f) > 1e-9 * max(float(np.max(np.abs(f))), 1.0):
            scale, shift = np.polyfit(f, r, 1)
            if np.isfinite(scale) and scale > 0:
                return cls(float(shift), float(scale))
        return cls(float(np.mean(r - f)), 1.0)


__all__ = ["Calibration", "Correction", "LineModel", "Tension", "laplace"]
