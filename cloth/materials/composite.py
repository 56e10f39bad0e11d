"""Curves of fabrics combined: in parallel (side by side, one strain) and in series (end to end,
one force), exact for piecewise-linear curves (DESIGN.md section 14).

A spring of a garment of several fabrics may stand for more than one: a warp spring crossing a
band's edge is part body fabric, part band (in series along it); a weft spring under a layer is
the garment's fabric and the layer's side by side (in parallel); a weft spring across a seam is
one panel, the seam strip and the next panel in series. Each part i is a fabric's curve
sigma_i times a factor k_i (its thickness and layers over the spring's reference thickness), so
that k_i sigma_i is a tension per reference thickness:

* **parallel**, parts of tributary share w_i (summing to 1) at one strain e:
  sigma(e) = sum_i w_i k_i sigma_i(e). The knots are the union of the parts' knots; beyond the
  last, every part follows its last slope, so the sum does too.
* **series**, parts of rest-length share f_i (summing to 1) carrying one stress s:
  e(s) = sum_i f_i e_i(s / k_i), e_i the inverse of part i's curve. Each inverse is piecewise
  linear in s with its breaks at the part's knot stresses, so e(s) is too, and the composite's
  knots are e(s) at the union of those stresses. A flat stretch of a part (a toe) is a jump of
  its inverse: the composite is flat there as well (both ends of the jump are knots).

Below zero strain fabric buckles: in parallel the compression moduli add (weighted); in series
they add as compliances, and a part that carries no compression (a tension field) makes the
whole carry none. The energy density of the composite is its own curve's integral, so a spring
network built from composites keeps a true total energy.

Units: strain 1, stress Pa (per the spring's reference thickness), weights and factors 1.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.materials.curves import StressStrainCurve

#: Parts with a share below this (1) are left out of a composite (rounding at a region's edge).
SHARE_FLOOR = 1e-12


def scaled(curve: StressStrainCurve, factor: float) -> StressStrainCurve:
    """``curve`` with its stresses and compression modulus times ``factor`` (> 0)."""
    if factor == 1.0:
        return curve
    return StressStrainCurve(
        curve.knot_strain, curve.knot_stress * factor, curve.compression_modulus * factor
    )


def parallel(parts: Sequence[tuple[float, StressStrainCurve]]) -> StressStrainCurve:
    """The curve of parts side by side at one strain: sum of ``weight`` x curve over
    ``parts`` ((weight (1, > 0), curve) pairs; module docstring)."""
    parts = [(float(w), c) for w, c in parts if w > SHARE_FLOOR]
    if not parts:
        raise ValueError("a parallel composite needs at least one part")
    if len(parts) == 1 and parts[0][0] == 1.0:
        return parts[0][1]
    knots = np.unique(np.concatenate([c.knot_strain for _, c in parts]))
    knots = np.append(knots, knots[-1] + 1.0)  # past every part's last knot: the last slopes
    stress = sum(w * c.stress_tangent(knots)[0] for w, c in parts)
    modulus = sum(w * c.compression_modulus for w, c in parts)
    return StressStrainCurve(knots, stress, modulus)


def _inverse(curve: StressStrainCurve, s: NDArray[np.float64], right: bool) -> NDArray:
    """The smallest (``right`` False) or largest (True) strain >= 0 at which ``curve`` carries
    stresses ``s`` ((K,), Pa, >= 0)."""
    x, y = curve.knot_strain, curve.knot_stress
    last = float(curve.slopes[-1])
    out = np.empty_like(s)
    beyond = (s >= y[-1]) if right else (s > y[-1])
    out[beyond] = x[-1] + (s[beyond] - y[-1]) / last
    inside = ~beyond
    k = np.searchsorted(y, s[inside], side="right" if right else "left")
    k = np.clip(k, 1, len(y) - 1)
    dy = y[k] - y[k - 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(dy > 0, (s[inside] - y[k - 1]) / dy, 1.0 if not right else 0.0)
    out[inside] = x[k - 1] + np.clip(t, 0.0, 1.0) * (x[k] - x[k - 1])
    if not right:
        out[s <= 0] = 0.0
    return out


def series(parts: Sequence[tuple[float, StressStrainCurve]]) -> StressStrainCurve:
    """The curve of parts end to end carrying one stress: ``parts`` are (rest-length share
    (1, > 0), curve) pairs (module docstring). `InputError` where a part's curve ends flat (it
    would stretch without bound at that stress)."""
    parts = [(float(f), c) for f, c in parts if f > SHARE_FLOOR]
    if not parts:
        raise ValueError("a series composite needs at least one part")
    total = sum(f for f, _ in parts)
    parts = [(f / total, c) for f, c in parts]
    if len(parts) == 1:
        return parts[0][1]
    for _, curve in parts:
        if not curve.slopes[-1] > 0:
            raise InputError(
                "a curve that ends flat cannot be joined in series (it would stretch without "
                "bound at its last stress); give a table whose stress rises at its end",
                field="material",
            )
    levels = np.unique(np.concatenate([c.knot_stress for _, c in parts]))
    top = float(levels[-1])
    levels = np.append(levels, top + max(top, 1.0))  # past every part's last knot
    low = sum(f * _inverse(c, levels, right=False) for f, c in parts)
    high = sum(f * _inverse(c, levels, right=True) for f, c in parts)
    strain = np.column_stack([low, high]).ravel()
    stress = np.repeat(levels, 2)
    keep = np.concatenate(([True], np.diff(strain) > 1e-15 * np.maximum(1.0, strain[1:])))
    strain, stress = strain[keep], stress[keep]
    moduli = [c.compression_modulus for _, c in parts]
    modulus = 0.0
    if all(m > 0 for m in moduli):
        modulus = 1.0 / sum(f / m for (f, _), m in zip(parts, moduli, strict=True))
    return StressStrainCurve(strain, stress, modulus)


__all__ = ["SHARE_FLOOR", "parallel", "scaled", "series"]
