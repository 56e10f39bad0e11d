"""Reduce dense, noisy lab points to a monotone piecewise-linear curve of K knots.

The curve is written as sigma(eps) = sum_i sigma_i h_i(eps) over hat functions h_i at knots
0 = e_0 < e_1 < ... < e_{K-1} = max strain, with sigma_0 = 0 and sigma_i = sum_{l<=i} delta_l,
delta_l >= 0: a bounded linear least-squares problem (``scipy.optimize.lsq_linear``) whose
solution is the best monotone non-decreasing curve through the origin for those knots.

Knot strains are placed greedily: starting from the two ends, each step inserts the candidate
strain (``n_candidates`` evenly spaced) that lowers the RMS error most; then sweeps move each
interior knot to the candidate that lowers the error most until no move helps. Deterministic,
insensitive to single noisy points, and it puts knots where a J-shaped fabric curve bends.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import lsq_linear

from cloth.errors import InputError


@dataclass(frozen=True)
class FitReport:
    """Fit error of a curve against the points it was fitted to.

    Attributes
    ----------
    max_error, rms_error : float, Pa
        Largest and root-mean-square absolute difference between curve and points.
    max_error_percent, rms_error_percent : float, %
        The same relative to the largest measured stress.
    n_points : int
        Number of points fitted.
    """

    max_error: float
    rms_error: float
    max_error_percent: float
    rms_error_percent: float
    n_points: int

    @classmethod
    def of(cls, residual: NDArray[np.float64], scale: float) -> FitReport:
        max_err = float(np.max(np.abs(residual))) if residual.size else 0.0
        rms = float(np.sqrt(np.mean(residual**2))) if residual.size else 0.0
        scale = scale if scale > 0 else 1.0
        return cls(max_err, rms, 100 * max_err / scale, 100 * rms / scale, int(residual.size))


def _hat_basis(x: NDArray[np.float64], knots: NDArray[np.float64]) -> NDArray[np.float64]:
    """(N, K) matrix of piecewise-linear hat functions at ``knots`` evaluated at ``x``."""
    k = np.clip(np.searchsorted(knots, x, side="right") - 1, 0, knots.size - 2)
    t = (x - knots[k]) / (knots[k + 1] - knots[k])
    basis = np.zeros((x.size, knots.size))
    rows = np.arange(x.size)
    basis[rows, k] = 1.0 - t
    basis[rows, k + 1] = t
    return basis


def _fit_values(
    x: NDArray[np.float64], y: NDArray[np.float64], knots: NDArray[np.float64]
) -> tuple[NDArray[np.float64], float]:
    """Monotone knot stresses (sigma_0 = 0) for given knot strains, and the RMS error."""
    basis = _hat_basis(x, knots)[:, 1:]
    design = np.cumsum(basis[:, ::-1], axis=1)[:, ::-1]  # sigma_i = sum_{l<=i} delta_l
    scale = max(float(np.max(np.abs(y))), 1.0)
    solution = lsq_linear(design, y / scale, bounds=(0.0, np.inf), method="bvls")
    values = np.concatenate(([0.0], np.cumsum(solution.x) * scale))
    residual = basis @ values[1:] - y
    return values, float(np.sqrt(np.mean(residual**2)))


def fit_monotone(
    strain: ArrayLike,
    stress: ArrayLike,
    n_knots: int = 8,
    n_candidates: int = 48,
) -> tuple[NDArray[np.float64], NDArray[np.float64], FitReport]:
    """Fit a monotone piecewise-linear curve through the origin.

    Parameters
    ----------
    strain : (N,) float, 1
        Measured strains, >= 0, any order.
    stress : (N,) float, Pa
        Measured stresses.
    n_knots : int
        Number of knots K of the result, including the origin (>= 2).
    n_candidates : int
        Evenly spaced candidate strains for the greedy knot placement.

    Returns
    -------
    knot_strain : (K,) float, 1
    knot_stress : (K,) float, Pa
    report : FitReport
        Error of the curve against the given points.
    """
    x = np.asarray(strain, dtype=np.float64)
    y = np.asarray(stress, dtype=np.float64)
    if n_knots < 2:
        raise InputError(f"the number of knots must be >= 2, got {n_knots}", field="knots")
    top = float(np.max(x)) if x.size else 0.0
    if x.size < 2 or top <= 0.0:
        raise InputError(
            f"need at least 2 points with positive strain to fit a curve, got {x.size}",
            field="strain",
        )
    knots = np.array([0.0, top])
    candidates = np.linspace(0.0, top, n_candidates + 2)[1:-1]
    values, _ = _fit_values(x, y, knots)
    while knots.size < n_knots:
        free = candidates[~np.isin(candidates, knots)]
        if free.size == 0:
            break
        trials = [np.sort(np.append(knots, c)) for c in free]
        errors = [_fit_values(x, y, t)[1] for t in trials]
        knots = trials[int(np.argmin(errors))]
        values, _ = _fit_values(x, y, knots)
    knots, values = _refine(x, y, knots, candidates)
    residual = _hat_basis(x, knots) @ values - y
    return knots, values, FitReport.of(residual, float(np.max(np.abs(y))))


def _refine(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    knots: NDArray[np.float64],
    candidates: NDArray[np.float64],
    sweeps: int = 4,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Move each interior knot to the candidate that lowers the RMS error most, until no move
    helps (greedy insertion alone fixes early knots too soon)."""
    values, best = _fit_values(x, y, knots)
    for _ in range(sweeps):
        improved = False
        for index in range(1, knots.size - 1):
            others = np.delete(knots, index)
            for c in candidates[~np.isin(candidates, knots)]:
                trial = np.sort(np.append(others, c))
                trial_values, error = _fit_values(x, y, trial)
                if error < best * (1 - 1e-12):
                    knots, values, best, improved = trial, trial_values, error, True
                    others = np.delete(knots, np.searchsorted(knots, c))
        if not improved:
            break
    return knots, values


def curve_error(
    knot_strain: ArrayLike, knot_stress: ArrayLike, strain: ArrayLike, stress: ArrayLike
) -> FitReport:
    """Error of the piecewise-linear curve through the given knots against points (strain >= 0)."""
    knots = np.asarray(knot_strain, dtype=np.float64)
    values = np.asarray(knot_stress, dtype=np.float64)
    x = np.asarray(strain, dtype=np.float64)
    y = np.asarray(stress, dtype=np.float64)
    residual = _hat_basis(x, knots) @ values - y if x.size else np.zeros(0)
    return FitReport.of(residual, float(np.max(np.abs(y))) if y.size else 1.0)


#: The toe of a branch, as fractions of its peak stress: the points between, above the noise of
#: the force at zero and below the stiffening, give the line whose zero is the branch's
#: zero-force strain (`zero_force_strain`).
TOE = (0.005, 0.05)


def zero_force_strain(strain: ArrayLike, stress: ArrayLike) -> float:
    """The strain (1) at which a branch of a lab curve reaches zero stress, between samples.

    The zero of the least-squares line through the branch's toe: its points below its peak's
    strain whose stress is within `TOE` of the peak. Noise near zero force decides which samples
    read zero, so the largest strain that reads zero is off by up to a sample spacing (0.0067 for
    120 points to 80 %); the toe's line is not. With fewer than three toe points (a clean table
    of a few points), the largest strain at zero stress below the peak; 0 where none reaches
    zero.

    strain, stress : (P,) the branch's points, 1 and Pa (any order).
    """
    strain, stress = np.asarray(strain, float), np.asarray(stress, float)
    if strain.size == 0 or not np.any(stress > 0.0):
        return 0.0
    below = strain <= strain[np.argmax(stress)]
    low, high = TOE[0] * stress.max(), TOE[1] * stress.max()
    toe = below & (stress >= low) & (stress <= high)
    if np.count_nonzero(toe) >= 3:
        slope, intercept = np.polyfit(strain[toe], stress[toe], 1)
        if slope > 0.0:
            return float(max(-intercept / slope, 0.0))
    zero = strain[below & (stress <= 0.0)]
    return float(max(zero.max(), 0.0)) if zero.size else 0.0
