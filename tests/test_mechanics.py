"""Energy, forces and stiffness agree with each other by finite differences."""

from __future__ import annotations

import numpy as np
import pytest

from cloth.garment.grid import build_grid
from cloth.garment.mechanics import energy, forces, spring_state, stiffness
from tests.conftest import make_fabric


def random_configuration(fabric, kind, seed, closed=False):
    rng = np.random.default_rng(seed)
    n, m = 7, 5
    grid = build_grid(
        n,
        m,
        0.3,
        np.linspace(0, 0.2, m),
        fabric,
        closed=closed,
        shear_modulus=2.0e4,
        bend_modulus=1.0e3,
    )
    u, v = grid.rest_uv.T
    scale = {"stretched": (1.5, 1.3), "compressed": (0.7, 0.8), "mixed": (1.4, 0.85)}[kind]
    x = np.stack([scale[0] * u, scale[1] * v, np.zeros_like(u)], axis=1)
    x += rng.normal(scale=0.004, size=x.shape)  # out of plane too: a 3D configuration
    return grid, x


CASES = [
    (kind, seed, closed)
    for kind in ("stretched", "compressed", "mixed")
    for seed in (1, 2)
    for closed in (False, True)
]


@pytest.mark.parametrize(("kind", "seed", "closed"), CASES)
def test_forces_are_minus_energy_gradient(fabric, kind, seed, closed):
    grid, x = random_configuration(fabric, kind, seed, closed)
    r = forces(x, grid)
    rng = np.random.default_rng(seed + 10)
    for _ in range(4):
        v = rng.normal(size=x.shape)
        h = 1e-7
        fd = (energy(x + h * v, grid) - energy(x - h * v, grid)) / (2 * h)
        exact = -np.sum(r * v)
        assert fd == pytest.approx(exact, rel=1e-6)


@pytest.mark.parametrize(("kind", "seed", "closed"), CASES)
def test_stiffness_is_energy_hessian(fabric, kind, seed, closed):
    grid, x = random_configuration(fabric, kind, seed, closed)
    k = stiffness(x, grid)
    assert abs(k - k.T).max() <= 1e-9 * abs(k).max()
    rng = np.random.default_rng(seed + 20)
    for _ in range(4):
        v = rng.normal(size=x.shape)
        h = 1e-7
        fd = -(forces(x + h * v, grid) - forces(x - h * v, grid)) / (2 * h)
        exact = (k @ v.ravel()).reshape(x.shape)
        assert np.linalg.norm(fd - exact) <= 1e-6 * np.linalg.norm(exact)


def test_projected_stiffness_is_positive_semidefinite():
    """With a compression modulus (1 %, the default) compressed springs soften across and the
    exact stiffness is indefinite; the projected one is not. A pure tension field (compression
    modulus 0) makes the exact one positive semi-definite itself (each spring's energy convex
    in the positions)."""
    tension = build_grid(7, 5, 0.3, np.linspace(0, 0.2, 5), make_fabric(compression=0.0))
    fabric = make_fabric(compression=0.01)
    grid = build_grid(7, 5, 0.3, np.linspace(0, 0.2, 5), fabric)  # the paper's springs only
    u, v = grid.rest_uv.T
    x = np.stack([1.3 * u, 0.8 * v, np.zeros_like(u)], axis=1)
    x += np.random.default_rng(3).normal(scale=0.004, size=x.shape)
    full = stiffness(x, grid).toarray()
    projected = stiffness(x, grid, project=True).toarray()
    assert np.linalg.eigvalsh(full).min() < -1e-6 * np.abs(full).max()  # compression: indefinite
    assert np.linalg.eigvalsh(projected).min() >= -1e-9 * np.abs(projected).max()
    exact = stiffness(x, tension).toarray()
    assert np.linalg.eigvalsh(exact).min() >= -1e-9 * np.abs(exact).max()
    assert np.any(spring_state(x, tension).strain < 0)  # compressed springs, carrying nothing


def test_projection_changes_nothing_in_pure_tension(fabric):
    grid, x = random_configuration(fabric, "stretched", 4)
    state = spring_state(x, grid)
    assert np.all(state.strain > 0)
    diff = stiffness(x, grid) - stiffness(x, grid, project=True)
    assert abs(diff).max() == 0.0


def test_shapes_are_checked(fabric):
    grid, x = random_configuration(fabric, "mixed", 5)
    with pytest.raises(ValueError, match="shape"):
        forces(x[:-1], grid)
