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


def test_stocking_tissue_example_softens_the_calf_and_not_the_shin():
    """docs/examples/stocking_tissue.py: under the soft, thick calf band (25 mm, 8 kPa) the
    fabric sinks in, its hoop strain and so its pressure fall (measured: to about half the rigid
    leg's); under the thin, stiff band over the lower shin (4 mm, 60 kPa) the pressure stays
    within 10 % of the rigid leg's away from the band's edges, where the layer steps."""
    run = runpy.run_path(str(EXAMPLES / "stocking_tissue.py"), run_name="example")
    z, rigid, tissue = run["heights"], run["rigid"], run["tissue"]
    thin, soft = run["bands"]
    inside = lambda band, margin: (z > band["bottom"] + margin) & (z < band["top"] - margin)  # noqa: E731
    calf, shin = inside(soft, 0.03), inside(thin, 0.03)
    assert calf.sum() >= 5 and shin.sum() >= 2
    assert np.mean(tissue[calf]) < 0.7 * np.mean(rigid[calf])
    np.testing.assert_allclose(tissue[shin], rigid[shin], rtol=0.1)
