"""Richardson's estimate of a reported value's distance from the converged garment: exact on a
known power law, right on a cylinder whose continuum answer is Laplace's p = T / r, and silent
(no error number) where the levels do not show an order."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cloth.case.case import validate_case
from cloth.files.body import body_from_config
from cloth.files.material import load_fabric
from cloth.garment.predeform import predeform
from cloth.results.fields import node_fields
from cloth.results.richardson import estimate_levels, grid_spacing, richardson
from cloth.solvers import Settings, relax

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("order", [1.0, 2.0, 3.0])
def test_a_power_law_gives_its_order_and_its_limit(order):
    f = [10.0 + 3.0 * h**order for h in (0.25, 0.5, 1.0)]  # fine, middle, coarse
    estimate = richardson(*f)
    assert estimate.observed and estimate.order == pytest.approx(order, abs=1e-12)
    assert estimate.extrapolated == pytest.approx(10.0, abs=1e-12)
    assert estimate.error == pytest.approx(10.0 - f[0], abs=1e-12)
    safety = 1.25 if order == 2.0 else 3.0  # the scheme's order confirmed, or not
    # never below the last change f1 - f2 (order 2: 1.25 x a third of it would be less)
    stated = max(safety * abs(10.0 - f[0]), abs(f[0] - f[1]))
    assert estimate.uncertainty == pytest.approx(stated, rel=1e-12)
    assert estimate.relative_error == pytest.approx(stated / f[0])
    assert estimate.uncertainty == pytest.approx(
        {1.0: 3 * 0.75, 2.0: 9 / 16, 3.0: 21 / 64}[order], rel=1e-12
    )


@pytest.mark.parametrize("order", [0.8, 1.5, 2.0, 3.5])
def test_unequal_ratios_give_the_order_and_the_limit_of_a_power_law(order):
    """Grids halved with rounding (48 x 24 -> 24 x 12 -> 12 x 6) are not exactly twice as coarse:
    the spacings of `grid_spacing` give ratios 2.045 and 2.098, and a value f* + C h^p on them
    gives back p and f* exactly."""
    grids = [(48, 24), (24, 12), (12, 6)]
    h = [grid_spacing(n, m) for n, m in grids]
    assert h[1] / h[0] == pytest.approx(math.sqrt(2 * 23 / 11))
    values = [5.0 - 7.0 * hk**order for hk in h]
    estimate = estimate_levels(values, grids)
    assert estimate.observed and estimate.order == pytest.approx(order, abs=1e-9)
    assert estimate.extrapolated == pytest.approx(5.0, abs=1e-9)
    assert estimate_levels(values[:2], grids[:2]).reason == "too few levels"


def _cylinder_pressure(n: int, radius: float, reduction: float) -> float:
    """Mean pressure (Pa) of the interior rows of a tube of n nodes around on a cylinder."""
    case = validate_case(
        {
            "material": "powernet",
            "body": {"cylinder": {"radius": radius}},
            "garment": {"bottom": 0.1, "top": 0.4, "reduction": reduction, "grid": [n, 4]},
        }
    )
    body, record = body_from_config(case.body.block)
    state = predeform(case, load_fabric("powernet", ROOT), body, record)
    final = relax(state, body, Settings(method="newton")).final
    fields = node_fields(
        state.grid,
        final.x,
        final.springs,
        state.fabric.thickness,
        final.forces,
        final.unbalanced,
        final.on_body,
        final.normal,
        state.constraint,
    )
    return float(fields.pressure.reshape(4, n)[1:-1].mean())


def test_on_a_cylinder_the_estimate_is_the_true_error_and_the_order_is_two():
    """The tube's nodes lie on the circle, a polygon of n sides whose strain differs from the
    continuum's by O(1/n^2): the scheme is second order. Three levels (24, 48, 96 around)
    observe it, and the estimated error of the 96-node value is its true error, T / r - p."""
    radius, reduction = 0.1, 0.2
    fabric = load_fabric("powernet", ROOT)
    strain = 1.0 / (1.0 - reduction) - 1.0
    exact = float(fabric.weft(np.array([strain]))[0]) * fabric.thickness / radius
    fine, middle, coarse = (_cylinder_pressure(n, radius, reduction) for n in (96, 48, 24))
    estimate = richardson(fine, middle, coarse)
    assert estimate.observed and estimate.order == pytest.approx(2.0, abs=0.05)
    assert estimate.error == pytest.approx(exact - fine, rel=0.05)
    assert estimate.extrapolated == pytest.approx(exact, rel=1e-4)
    assert abs(exact - fine) <= estimate.uncertainty  # the stated error brackets the true one


@pytest.mark.parametrize(
    ("levels", "reason"),
    [
        ((100.0, math.nan, 110.0), "finite"),
        ((100.0, 100.0, 100.0), "same value"),  # nothing to tell an error from
    ],
)
def test_levels_with_a_missing_value_or_all_equal_give_no_error_number(levels, reason):
    estimate = richardson(*levels)
    assert not estimate.observed and reason in estimate.reason
    assert math.isnan(estimate.error) and math.isnan(estimate.extrapolated)
    assert math.isnan(estimate.uncertainty) and math.isnan(estimate.relative_error)


@pytest.mark.parametrize(
    ("levels", "spread"),
    [
        ((2379.0, 2370.0, 2376.0), 9.0),  # the waist's old nearest-row sequence: it turns
        ((2379.0, 2370.0, 2370.0), 9.0),  # the coarse pair equal: nothing shrinks
        ((100.0, 110.0, 121.0), 21.0),  # order 0.14: the levels hardly converge
        ((100.0, 110.0, 100.0), 10.0),  # back and forth
        ((100.0, 94.0, 105.0), 11.0),  # the finest difference more than half the coarser
        ((1304.74, 1303.97, 1304.00), 0.77),  # the graded torso's underbust at 192 x 96
    ],
)
def test_levels_that_neither_show_an_order_nor_shrink_state_three_times_their_range(levels, spread):
    """Eca and Hoekstra's data-range rule: 3 x max |fi - fj|, flag 7, nothing extrapolated."""
    estimate = richardson(*levels)
    assert estimate.observed and estimate.code == 7 and "3 x their range" in estimate.reason
    assert estimate.uncertainty == pytest.approx(3 * spread, rel=1e-9)
    assert math.isnan(estimate.extrapolated) and math.isnan(estimate.error)


@pytest.mark.parametrize(
    ("levels", "stated"),
    [
        ((2343.0, 2345.0, 2314.0), 3 * 2.0),  # the waist band: wobbles by 2 Pa after 31 Pa
        ((2379.0, 2379.0, 2370.0), 3 * 9.0 / 16),  # two equal fine levels: floored at 3 |far| / 2^4
        ((100.0, 100.001, 110.0), 3 * 9.999 / 16),  # order 13: converged, faster than any order
    ],
)
def test_levels_that_converge_without_an_order_state_three_times_the_finest_difference(
    levels, stated
):
    """Roache's two-grid index with the safety factor 3 where the finest difference is at most
    half the coarser one, floored at what order 4 would leave; nothing extrapolated, flag 6."""
    estimate = richardson(*levels)
    assert estimate.observed and estimate.code == 6 and "finest difference" in estimate.reason
    assert estimate.uncertainty == pytest.approx(stated, rel=1e-12)
    assert math.isnan(estimate.order) and math.isnan(estimate.extrapolated)
    assert estimate.relative_error == pytest.approx(stated / levels[0], rel=1e-12)


def _power_law(order: float) -> tuple[float, float, float]:
    """f = 10 + 3 h^order on h = 0.25, 0.5, 1 (fine, middle, coarse)."""
    return tuple(10.0 + 3.0 * h**order for h in (0.25, 0.5, 1.0))


@pytest.mark.parametrize(
    ("order", "code"),
    [
        (0.49, 7),  # below the asymptotic range; its finest difference shrinks too little
        (0.51, 0),
        (3.99, 0),
        (4.01, 6),  # above it: converged faster than any order, stated from the difference
    ],
)
def test_the_asymptotic_range_is_0_5_to_4_on_both_sides(order, code):
    """An observed order is accepted in 0.5-4 only; just outside, the levels get no order."""
    estimate = richardson(*_power_law(order))
    assert estimate.code == code
    if code == 0:
        assert estimate.order == pytest.approx(order, abs=1e-9)
    else:
        assert math.isnan(estimate.extrapolated)


@pytest.mark.parametrize(
    ("order", "safety"), [(1.79, 3.0), (1.81, 1.25), (2.19, 1.25), (2.21, 3.0)]
)
def test_the_scheme_s_order_is_confirmed_within_ten_percent_of_two(order, safety):
    """Safety factor 1.25 where the observed order is within 10 % of the scheme's 2, else 3
    (Roache), never below the last change."""
    f = _power_law(order)
    estimate = richardson(*f)
    assert estimate.code == 0
    stated = max(safety * abs(10.0 - f[0]), abs(f[0] - f[1]))
    assert estimate.uncertainty == pytest.approx(stated, rel=1e-9)


@pytest.mark.parametrize(("share", "code"), [(0.49, 6), (0.5, 6), (0.51, 7)])
def test_wobbling_levels_count_where_the_finest_difference_is_at_most_half_the_coarser(share, code):
    """Levels that change direction state 3 x the finest difference where it is at most half
    the coarser difference (what a first-order scheme leaves when h halves), else 3 x their
    range."""
    far = 16.0
    levels = (100.0 - share * far, 100.0, 100.0 - far)  # near = -share x far: the other sign
    estimate = richardson(*levels)
    assert estimate.code == code
    if code == 6:
        assert estimate.uncertainty == pytest.approx(3 * max(share * far, far / 16), rel=1e-12)
    else:
        assert estimate.uncertainty == pytest.approx(3 * far, rel=1e-12)  # f2 - f3: the range


@pytest.mark.parametrize(("levels", "code"), [(3, 0), (2, 1)])
def test_an_estimate_needs_three_levels(levels, code):
    values = list(_power_law(2.0))[:levels]
    grids = [(48, 24), (24, 12), (12, 6)][:levels]
    assert estimate_levels(values, grids).code == code


def test_an_estimate_keeps_its_value_and_says_why_it_has_no_order():
    """A missing estimate still reports its value, with the reason; one stated from the range
    keeps the order observed outside the asymptotic range; an observed one has no reason and
    flag 0; one stated from the finest difference has no error or extrapolation."""
    low = _power_law(0.3)
    estimate = richardson(*low)
    assert estimate.reported == low[0] and estimate.code == 7 and estimate.observed
    assert estimate.order == pytest.approx(0.3, abs=1e-9)
    assert estimate.uncertainty == pytest.approx(3 * (low[2] - low[0]), rel=1e-12)
    for levels, code in (((100.0, math.nan, 110.0), 2), ((100.0, 100.0, 100.0), 3)):
        missing = richardson(*levels)
        assert missing.code == code and missing.reported == 100.0 and missing.observed is False
    wobbling = richardson(100.0, 104.0, 84.0)  # near -4, far +20: the finest difference
    assert wobbling.code == 6 and wobbling.uncertainty == pytest.approx(3 * 4.0)
    assert wobbling.reported == 100.0 and math.isnan(wobbling.error)
    observed = richardson(*_power_law(2.0))
    assert observed.reason == "" and observed.code == 0 and observed.observed is True


def test_the_grid_spacing_is_the_side_of_a_square_cell_of_the_same_area():
    assert grid_spacing(48, 24, around=0.8, height=0.3) == pytest.approx(
        math.sqrt(0.8 / 48 * 0.3 / 23), rel=1e-15
    )
    assert grid_spacing(10, 2) == pytest.approx(math.sqrt(1 / 10), rel=1e-15)  # one row step
    assert grid_spacing(10, 1) == pytest.approx(math.sqrt(1 / 10), rel=1e-15)  # no step: one
    values, grids = list(_power_law(2.0)), [(48, 24), (24, 12)]
    assert estimate_levels(values, grids).code == 1  # three values, two grids
    assert estimate_levels(values[:2], [*grids, (12, 6)]).code == 1


def test_the_sign_and_size_rules_at_exact_differences():
    """A finest difference of exactly 1 is a difference (order log2 10 from 1 and 10); a wobble
    that does not shrink keeps its value and states 3 x its range; a wobble exactly half the
    coarser difference counts as shrinking."""
    assert richardson(101.0, 100.0, 90.0).code == 0
    stuck = richardson(100.0, 110.0, 100.0)
    assert stuck.code == 7 and stuck.reported == 100.0 and stuck.uncertainty == 30.0
    half = richardson(100.0, 100.5, 99.5)  # near -0.5, far 1.0
    assert half.code == 6 and half.uncertainty == pytest.approx(1.5)
