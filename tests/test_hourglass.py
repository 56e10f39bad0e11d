"""The grid solver's girth lines against an independent axisymmetric reference (issue 40, item
8): a tube on a body of revolution with a waist (an hourglass: the parametric leg given point by
point with round sections), frictionless, in the default tension field, with and without a
lengthwise reduction. The reference (`tests.axisymmetric`) minimises its own rings and meridian
segments with scipy; it covers what no closed form does: the fabric gathering at the waist where
the warp is slack (no lengthwise reduction), and the taut warp (0.10)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cloth.bodies.leg import POINTS, _profiles, leg_of
from cloth.files.material import load_fabric
from tests.axisymmetric import band_mean, solve
from tests.conftest import load_result

ROOT = Path(__file__).resolve().parents[1]
#: Round sections narrowing from 60 cm to 48 cm at 0.40 m and widening again.
HOURGLASS = {
    "circumference_cm": dict(zip(POINTS, [60, 57, 52, 48, 52, 57, 60], strict=True)),
    "height_cm": dict(zip(POINTS, [10, 20, 30, 40, 50, 60, 70], strict=True)),
    "depth_ratio": dict.fromkeys(POINTS, 1.0),
}
LINES = {"low": 0.25, "waist": 0.40, "high": 0.55}
BOTTOM, TOP, REDUCTION = 0.15, 0.65, 0.2


def _reference(lengthwise: float) -> dict[str, float]:
    girth = _profiles(leg_of(HOURGLASS))[0]
    slope = girth.derivative(1)

    def radius(z):
        return girth(z) / (2 * np.pi)

    def radius_slope(z):
        return slope(z) / (2 * np.pi)

    fabric = load_fabric("powernet", ROOT)
    rings = solve(radius, radius_slope, fabric, BOTTOM, TOP, REDUCTION, lengthwise, 200)
    return {name: band_mean(rings, h) for name, h in LINES.items()}


@pytest.mark.parametrize(
    ("lengthwise", "tolerance"),
    [
        (0.10, {"low": 5e-3, "waist": 5e-3, "high": 5e-3}),
        (0.0, {"low": 5e-3, "waist": 1e-2, "high": 5e-3}),
    ],
    ids=["taut-warp", "slack-warp"],
)
def test_band_values_on_an_hourglass_agree_with_the_axisymmetric_reference(
    tmp_path, lengthwise, tolerance
):
    """At 64 x 80 every band value is within 0.5 % of the reference (measured 0.22-0.26 %),
    except the waist where the slack warp lets the rows gather: 1 % there (measured 0.86 %;
    5.9 % at 32 x 40, so second order or better). Each stated error contains the reference. The
    reference itself moves by 4e-4 at the gathered waist from 200 to 400 rings, 1e-5 elsewhere."""
    reference = _reference(lengthwise)
    case = {
        "material": "powernet",
        "body": {"leg": HOURGLASS},
        "landmarks": LINES,
        "garment": {
            "bottom": BOTTOM,
            "top": TOP,
            "reduction": REDUCTION,
            "lengthwise_reduction": lengthwise,
            "grid": [64, 80],
        },
    }
    ds = load_result(tmp_path, case)
    assert ds.attrs["converged"] == 1
    for name, expected in reference.items():
        value = float(ds["pressure_mean"].sel(landmark=name))
        error = float(ds["pressure_mean_error"].sel(landmark=name))
        assert value == pytest.approx(expected, rel=tolerance[name]), name
        assert abs(value - expected) <= error, name
    # the slack warp gathers the fabric at the waist, and the result says so
    gathered = int(ds["landmark_slack_warp"].sel(landmark="waist"))
    assert gathered == (1 if lengthwise == 0 else 0)
