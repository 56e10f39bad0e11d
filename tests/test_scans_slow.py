"""Scans at full size (``make test-slow``; minutes each, not in ``make test``).

The acceptance cases of mesh bodies that are too slow for every commit. Measured numbers are in
docs/validation.md and docs/solvers.md.
"""

from __future__ import annotations

import numpy as np
import pytest

from cloth.bodies.torso import chart_size, torso_mesh
from tests.conftest import assert_quadratic_tail, write_obj
from tests.test_scans import girth_pressures

pytestmark = pytest.mark.slow

#: Measured: converged to 1e-8 (32 iterations), but the underbust line +4.5 % of the smooth
#: torso's at 384 x 192 (+2.5 % at 96 x 48; hip +2.1 %, waist -1.9 %, bust -1.0 %): the fine
#: grid samples what is left of the 20-30 mm facets.
COARSE_384 = "the coarse mesh at 384 x 192: underbust line +4.5 % (3 % asked)"
#: Measured (denoised, then refined): hip, waist and underbust within 1 % of the clean mesh's,
#: the bust line -6.6 %: the filter flattens the coarse mesh's bust by 2.9 % on its own
#: (docs/validation.md).
NOISY_COARSE_BUST = "the coarse mesh with 1 mm of noise: bust line -6.6 % (docs/validation.md)"


@pytest.fixture(scope="module")
def smooth_torso_384():
    return girth_pressures({"torso": {"size": "M"}}, (384, 192))[2]


def mesh_case(tmp_path, around, rings, grid, noise=0.0, holes=0):
    vertices, faces = torso_mesh(chart_size("M"), around, rings)
    rng = np.random.default_rng(3)
    if noise:
        vertices = vertices + rng.normal(scale=noise, size=vertices.shape)
    if holes:  # punch holes of two faces (a quad) each, apart, in the band the garment covers
        centre = vertices[faces].mean(axis=1)
        band = np.flatnonzero((centre[:, 2] > 0.9) & (centre[:, 2] < 1.2))
        drop, used = [], set()
        for quad in rng.permutation(band[::2]):
            corners = set(faces[quad : quad + 2].ravel().tolist())
            if not corners & used:  # holes sharing a vertex make one larger hole
                drop.append(quad)
                used |= corners
            if len(drop) == holes:
                break
        drop = np.array(drop)
        faces = np.delete(faces, np.concatenate([drop, drop + 1]), axis=0)
    path = write_obj(tmp_path / "torso.obj", vertices, faces)
    return girth_pressures({"mesh": str(path)}, grid)


@pytest.mark.parametrize(
    ("around", "rings"),
    [
        (128, 120),
        pytest.param(32, 30, marks=pytest.mark.xfail(strict=True, reason=COARSE_384)),
    ],
    ids=["default", "coarse"],
)
def test_torso_mesh_at_384_x_192_converges_and_presses_like_the_smooth_torso(
    tmp_path, smooth_torso_384, around, rings
):
    """73,728 nodes on the torso's mesh, default and coarse: converged to 1e-8, quadratically
    at the end; girth-line means within 3 % of the smooth torso's at the same grid (the bust
    line, which moves ~40 % per cm of height, within 5 %)."""
    result, _, mesh = mesh_case(tmp_path, around, rings, (384, 192))
    assert result.converged and result.history.residual[-1] <= 1e-8
    assert_quadratic_tail(result.history.residual)
    for name, value in smooth_torso_384.items():
        assert mesh[name] == pytest.approx(value, rel=0.05 if name == "bust" else 0.03), name


@pytest.mark.parametrize(
    ("around", "rings", "noise", "holes"),
    [
        (128, 120, 1e-3, 0),
        pytest.param(
            32, 30, 1e-3, 0, marks=pytest.mark.xfail(strict=True, reason=NOISY_COARSE_BUST)
        ),
        (128, 120, 0.0, 3),
        (32, 30, 0.0, 3),
    ],
    ids=["noise-fine", "noise-coarse", "holes-fine", "holes-coarse"],
)
def test_noisy_or_holed_mesh_presses_like_the_clean_one(tmp_path, around, rings, noise, holes):
    """1 mm of Gaussian vertex noise, or three small holes in the band: converged, girth-line
    means within 5 % of the clean mesh's."""
    _, _, clean = mesh_case(tmp_path, around, rings, (96, 48))
    result, _, rough = mesh_case(tmp_path, around, rings, (96, 48), noise, holes)
    assert result.converged
    for name, value in clean.items():
        assert rough[name] == pytest.approx(value, rel=0.05), name
