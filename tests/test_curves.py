"""StressStrainCurve: exact values, exact energy, validation, and properties of any curve."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from cloth.errors import InputError
from cloth.materials.curves import COMPRESSION_RATIO, Fabric, StressStrainCurve

CURVE = StressStrainCurve([0.0, 0.2, 0.5, 1.0], [0.0, 1.0e5, 2.0e5, 8.0e5])


def test_values_between_and_beyond_knots():
    eps = np.array([0.1, 0.2, 0.35, 0.75, 1.0, 1.5])
    expected = [0.5e5, 1.0e5, 1.5e5, 5.0e5, 8.0e5, 8.0e5 + 0.5 * 12.0e5]
    np.testing.assert_allclose(CURVE.stress(eps), expected, rtol=1e-15)
    np.testing.assert_allclose(CURVE.tangent([0.1, 0.3, 0.9, 2.0]), [5e5, 1e5 / 0.3, 12e5, 12e5])


def test_compression_follows_small_documented_modulus():
    modulus = COMPRESSION_RATIO * 5.0e5
    assert CURVE.compression_modulus == pytest.approx(modulus)
    np.testing.assert_allclose(CURVE.stress([-0.1, -0.3]), [-0.1 * modulus, -0.3 * modulus])
    np.testing.assert_allclose(CURVE.energy_density(-0.2), 0.5 * modulus * 0.04)
    stiff = StressStrainCurve([0.0, 1.0], [0.0, 1.0], compression_modulus=7.0)
    assert float(stiff.stress(-1.0)) == -7.0


@pytest.mark.parametrize("eps", [-0.3, 0.0, 0.05, 0.2, 0.33, 0.5, 0.99, 1.0, 1.7])
def test_energy_is_the_exact_integral_of_stress(eps):
    breaks = [0.2, 0.5, 1.0]
    integral, _ = quad(lambda e: float(CURVE.stress(e)), 0.0, eps, points=breaks, epsabs=0)
    assert float(CURVE.energy_density(eps)) == pytest.approx(integral, rel=1e-12, abs=1e-9)


@pytest.mark.parametrize(
    ("strain", "stress", "field"),
    [
        ([0.0], [0.0], "knots"),
        ([0.0, 0.5, 0.5], [0.0, 1.0, 2.0], "strain"),
        ([0.0, 0.5, 0.3], [0.0, 1.0, 2.0], "strain"),
        ([0.0, np.nan], [0.0, 1.0], "knots"),
        ([0.1, 0.5], [0.0, 1.0], "knots"),
        ([0.0, 0.5], [1.0, 2.0], "knots"),
    ],
)
def test_invalid_knots_are_refused(strain, stress, field):
    with pytest.raises(InputError) as info:
        StressStrainCurve(strain, stress)
    assert info.value.field == field


def test_fabric_needs_positive_thickness():
    with pytest.raises(InputError, match="thickness"):
        Fabric("x", CURVE, CURVE, thickness=0.0)
    with pytest.raises(InputError, match="direction"):
        Fabric("x", CURVE, CURVE, thickness=1e-3).curve("diagonal")


@st.composite
def curves(draw):
    k = draw(st.integers(2, 8))
    steps = draw(st.lists(st.floats(0.01, 0.5), min_size=k - 1, max_size=k - 1))
    rises = draw(st.lists(st.floats(0.0, 1e6), min_size=k - 1, max_size=k - 1))  # never falls
    strain = np.concatenate(([0.0], np.cumsum(steps)))
    stress = np.concatenate(([0.0], np.cumsum(rises)))
    return StressStrainCurve(strain, stress)


@settings(max_examples=60, deadline=None)
@given(curves())
def test_continuous_at_every_knot(curve):
    h = 1e-9
    for e, s in zip(curve.knot_strain, curve.knot_stress, strict=True):
        left, mid, right = curve.stress([e - h, e, e + h])
        assert mid == pytest.approx(s, abs=1e-6)
        assert abs(right - left) <= 2 * h * max(np.max(np.abs(curve.slopes)), 1.0) + 1e-6


@settings(max_examples=60, deadline=None)
@given(curves(), st.floats(-0.5, 3.0))
def test_energy_derivative_is_stress(curve, eps):
    h = 1e-6
    slope = (curve.energy_density(eps + h) - curve.energy_density(eps - h)) / (2 * h)
    scale = max(abs(float(curve.stress(eps))), 1.0)
    # exact for piecewise-quadratic psi away from knots; at most a slope jump x h near a knot
    assert abs(slope - curve.stress(eps)) <= 1e-6 * scale + h * np.max(np.abs(curve.slopes))


@settings(max_examples=60, deadline=None)
@given(curves(), st.floats(0.0, 2.0), st.floats(0.0, 2.0), st.floats(0.0, 1.0))
def test_energy_convex_where_stress_increases(curve, e1, e2, t):
    assume_monotone = np.all(curve.slopes >= 0)
    if not assume_monotone:
        # restrict to a stretch of increasing stress: the segment containing e1
        k = int(np.clip(np.searchsorted(curve.knot_strain, e1, side="right") - 1, 0, None))
        if k >= curve.slopes.size or curve.slopes[k] < 0:
            return
        lo = curve.knot_strain[k]
        hi = curve.knot_strain[k + 1] if k + 1 < curve.n_knots - 1 else np.inf
        e2 = float(np.clip(e2, lo, hi))
    mid = t * e1 + (1 - t) * e2
    lhs = float(curve.energy_density(mid))
    rhs = t * float(curve.energy_density(e1)) + (1 - t) * float(curve.energy_density(e2))
    assert lhs <= rhs + 1e-9 * max(abs(rhs), 1.0)


def test_a_falling_curve_is_refused():
    """Knots (0, 0), (0.5, 1e5), (0.6, 9e4) Pa would give sigma(2.0) = -5e4 Pa: a stretched
    spring that pushes (accepted before: linear extrapolation with the last slope)."""
    with pytest.raises(InputError, match="the stress falls from knot 1 to knot 2"):
        StressStrainCurve([0.0, 0.5, 0.6], [0.0, 1e5, 9e4])
