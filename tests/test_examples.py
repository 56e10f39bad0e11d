"""The documented examples run as tests (as scikit-fem's do): each asserts its own physics, and
the numbers it leaves behind are checked here against a closed form computed apart from it."""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"


def test_cylinder_example_obeys_laplace():
    """docs/examples/cylinder.py: p = T / r on every interior node; and T itself is the lab
    curve's stress at the arc strain (1 - reduction)^-1 - 1 times the thickness, to the
    polygon's chord error (pi / n)^2 / 6 = 1.8e-4 at n = 96."""
    run = runpy.run_path(str(EXAMPLES / "cylinder.py"), run_name="example")
    pressure, tension, radius = run["pressure"], run["tension"], run["RADIUS"]
    assert pressure.shape == (4, 96) and np.all(pressure > 0)
    np.testing.assert_allclose(pressure, tension / radius, rtol=1e-3)
    fabric = run["state"].fabric
    arc = float(fabric.weft.stress(1 / (1 - 0.2) - 1)) * fabric.thickness  # N/m
    np.testing.assert_allclose(tension, arc, rtol=2e-3)
