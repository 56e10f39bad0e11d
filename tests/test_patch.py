"""Exact patch tests: with the paper's springs only, a uniformly stretched flat patch carries the
lab curve exactly, interior nodes are in equilibrium, and the edge reactions are sigma x t x width.
"""

from __future__ import annotations

import numpy as np
import pytest

from cloth.garment.grid import WARP, WEFT, build_grid, rectangle
from cloth.garment.mechanics import forces, spring_state

WIDTH, HEIGHT = 0.30, 0.20


def stretched(grid, lx, ly):
    u, v = grid.rest_uv.T
    return np.stack([lx * u, ly * v, np.zeros_like(u)], axis=1)


@pytest.mark.parametrize(("lx", "ly"), [(1.4, 1.0), (1.0, 1.25), (1.35, 1.6), (1.9, 1.05)])
def test_uniform_stretch_reproduces_lab_curve(fabric, lx, ly):
    grid = rectangle(9, 6, WIDTH, HEIGHT, fabric)
    x = stretched(grid, lx, ly)
    state = spring_state(x, grid)
    weft, warp = grid.family_slices[WEFT], grid.family_slices[WARP]
    np.testing.assert_allclose(state.strain[weft], lx - 1.0, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(state.strain[warp], ly - 1.0, rtol=1e-12, atol=1e-15)
    expect_weft = float(fabric.weft.stress(lx - 1.0))
    expect_warp = float(fabric.warp.stress(ly - 1.0))
    # absolute tolerance: a strain rounded at 1e-16 times a modulus of ~1e6 Pa
    np.testing.assert_allclose(state.stress[weft], expect_weft, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(state.stress[warp], expect_warp, rtol=1e-12, atol=1e-9)

    r = forces(x, grid).reshape(grid.m, grid.n, 3)
    scale = max(np.max(np.abs(grid.area * state.stress)), 1.0)
    interior = r[1:-1, 1:-1]
    assert np.max(np.abs(interior)) <= 1e-12 * scale

    # reactions of the cut edges: exactly sigma x thickness x the edge's rest length
    right = r[:, -1, 0].sum()
    top = r[-1, :, 1].sum()
    t = fabric.thickness
    assert right == pytest.approx(-expect_weft * t * HEIGHT, rel=1e-12, abs=1e-12 * scale)
    assert top == pytest.approx(-expect_warp * t * WIDTH, rel=1e-12, abs=1e-12 * scale)
    # and the whole patch is in equilibrium
    np.testing.assert_allclose(r.sum(axis=(0, 1)), 0.0, atol=1e-12 * scale)


def test_tube_rows_are_rings_of_equal_tension(fabric):
    n, m, radius = 24, 5, 0.1
    circumference = 0.8 * 2 * np.pi * radius  # cut 20 % smaller than the ring it is put on
    grid = build_grid(n, m, circumference, np.linspace(0, 0.1, m), fabric, closed=True)
    theta = 2 * np.pi * np.arange(n) / n
    ring = np.stack([radius * np.cos(theta), radius * np.sin(theta)], axis=1)
    x = np.concatenate([np.column_stack([ring, np.full(n, z)]) for z in np.linspace(0, 0.1, m)])
    state = spring_state(x, grid)
    weft = grid.family_slices[WEFT]
    chord = 2 * radius * np.sin(np.pi / n)
    np.testing.assert_allclose(state.strain[weft], chord / (circumference / n) - 1, rtol=1e-12)
    # a ring of equal tension pushes every node straight in: R is radial
    r = forces(x, grid).reshape(m, n, 3)
    radial = np.einsum("jik,ik->ji", r[..., :2], ring / radius)
    unit = ring / radius
    tangential = unit[:, 0] * r[..., 1] - unit[:, 1] * r[..., 0]
    assert np.max(np.abs(tangential)) <= 1e-12 * np.max(np.abs(radial))
    assert np.all(radial < 0)


def test_spring_numbering_follows_the_paper(fabric):
    grid = rectangle(4, 3, 0.3, 0.2, fabric)
    weft = grid.ends[grid.family_slices[WEFT]]
    warp = grid.ends[grid.family_slices[WARP]]
    np.testing.assert_array_equal(weft[:4], [[0, 1], [1, 2], [2, 3], [4, 5]])
    np.testing.assert_array_equal(warp[:5], [[0, 4], [1, 5], [2, 6], [3, 7], [4, 8]])
    assert grid.n_springs == 3 * 3 + 2 * 4
    assert grid.node(2, 1) == 6
    # tributary areas: half at free edges
    t = fabric.thickness
    dy, dx = 0.1, 0.1
    np.testing.assert_allclose(
        grid.area[grid.family_slices[WEFT]][[0, 3, 6]], t * np.array([dy / 2, dy, dy / 2])
    )
    np.testing.assert_allclose(
        grid.area[grid.family_slices[WARP]][:4], t * np.array([dx / 2, dx, dx, dx / 2])
    )
