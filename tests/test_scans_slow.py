"""Scans at full size (``make test-slow``; minutes each, not in ``make test``).

The acceptance cases of mesh bodies that are too slow for every commit. Measured numbers are in
docs/validation.md and docs/solvers.md.
"""

from __future__ import annotations

import numpy as np
import pytest

from cloth.bodies.torso import LANDMARKS, chart_size, torso_mesh
from tests.conftest import assert_quadratic_tail, write_obj
from tests.test_scans import girth_pressures, row_means

pytestmark = pytest.mark.slow

#: Measured (denoised, then refined): hip, waist and underbust within 1 % of the clean mesh's,
#: the bust line -6.6 %: the filter flattens the coarse mesh's bust by 2.9 % on its own
#: (docs/validation.md). Over the rows within half the mesh's ring spacing (9.4 mm) of the line
#: it is still -6.6 %: at 96 x 48 (rows 9.6 mm apart) that window holds the one row.
NOISY_COARSE_BUST = (
    "the coarse mesh with 1 mm of noise: bust line -6.6 %, also over half a ring spacing "
    "(docs/validation.md)"
)


def window_means(run, heights: dict[str, float], half: dict[str, float]) -> dict[str, float]:
    """Each line's mean pressure (Pa) over the grid rows within ``half`` (m) of its height, at
    the equilibrium of ``run`` (`girth_pressures`'s result and state)."""
    rows_z, means = row_means(*run[:2])
    return {
        name: float(means[np.abs(rows_z - h) <= half[name]].mean()) for name, h in heights.items()
    }


def ring_half_spacing(vertices: np.ndarray, heights: dict[str, float]) -> dict[str, float]:
    """Half the ring spacing (m) of a ring mesh at each height: the mean of the gaps below and
    above the ring nearest it, halved."""
    rings = np.unique(np.round(vertices[:, 2], 9))
    out = {}
    for name, h in heights.items():
        at = int(np.argmin(np.abs(rings - h)))
        out[name] = 0.5 * float(np.diff(rings[max(at - 1, 0) : at + 2]).mean())
    return out


@pytest.fixture(scope="module")
def smooth_torso_384():
    return girth_pressures({"torso": {"size": "M"}}, (384, 192))


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


def test_torso_mesh_at_384_x_192_converges_and_presses_like_the_smooth_torso(
    tmp_path, smooth_torso_384
):
    """73,728 nodes on the torso's 128 x 120 mesh (rings 4.7 mm apart): converged to 1e-8,
    quadratically at the end; girth-line means within 3 % of the smooth torso's at the same
    grid (the bust line, which moves ~40 % per cm of height, within 5 %), row by row."""
    result, _, mesh = mesh_case(tmp_path, 128, 120, (384, 192))
    assert result.converged and result.history.residual[-1] <= 1e-8
    assert_quadratic_tail(result.history.residual)
    for name, value in smooth_torso_384[2].items():
        assert mesh[name] == pytest.approx(value, rel=0.05 if name == "bust" else 0.03), name


def test_a_coarse_mesh_is_judged_at_its_own_resolution(tmp_path, smooth_torso_384):
    """The 32 x 30 mesh (rings 18-20 mm apart) at 384 x 192 (rows 2.3 mm apart): its rings
    sample the body no finer than they are apart, so each line is compared as the mean over the
    rows within half a ring spacing of it, on both bodies: within 3 % (bust 5 %). Measured:
    hip +0.2 %, waist -0.1 %, underbust +1.9 %, bust -2.2 % (row by row, the underbust was
    +4.5 %). The same rule fails the 128 x 120 mesh (hip -3.7 %, bust -11.9 %): its 2.4 mm
    window holds the smooth torso's bust spike on one or two rows, so that mesh is compared row
    by row (above)."""
    run = mesh_case(tmp_path, 32, 30, (384, 192))
    assert run[0].converged and run[0].history.residual[-1] <= 1e-8
    chart = chart_size("M")
    heights = {name: chart.height[name] for name in LANDMARKS}
    half = ring_half_spacing(torso_mesh(chart, 32, 30)[0], heights)
    assert all(0.008 < h < 0.011 for h in half.values())
    mesh = window_means(run, heights, half)
    smooth = window_means(smooth_torso_384, heights, half)
    for name, value in smooth.items():
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
