"""Rows graded toward the garment's edges (`cloth.garment.rows`): the same m rows, closer at
both edges, one smooth map for every m (so the error estimate's coarser levels sample it too)."""

from __future__ import annotations

import numpy as np
import pytest

from cloth.garment.rows import MAX_GRADING, edge_ratio, row_heights


def test_ungraded_rows_are_numpys_equally_spaced_rows_bit_for_bit():
    np.testing.assert_array_equal(row_heights(0.86, 1.22, 97), np.linspace(0.86, 1.22, 97))


@pytest.mark.parametrize("grading", [0.1, 0.5, MAX_GRADING])
def test_graded_rows_keep_the_edges_and_are_closest_there(grading):
    z = row_heights(0.09, 0.77, 401, grading)
    assert z[0] == 0.09 and z[-1] == 0.77
    gaps = np.diff(z)
    assert (gaps > 0).all()
    # the spacing is (top - bottom) / (m - 1) x (1 - g cos(2 pi xi)), measured at the middle of
    # each gap: the edge gap over the middle one is (1 - g) / (1 + g) to O(1 / m^2)
    xi = (np.arange(400) + 0.5) / 400
    np.testing.assert_allclose(gaps * 400 / 0.68, 1 - grading * np.cos(2 * np.pi * xi), atol=1e-4)
    assert gaps[0] / gaps[200] == pytest.approx(edge_ratio(grading), rel=1e-3)


def test_a_coarser_grid_samples_the_same_map():
    """Every other row of 2k - 1 rows is the grid of k rows: the levels' map is the grid's."""
    fine, coarse = row_heights(0.1, 0.4, 49, 0.5), row_heights(0.1, 0.4, 25, 0.5)
    np.testing.assert_allclose(fine[::2], coarse, rtol=0, atol=1e-15)


@pytest.mark.parametrize("grading", [-0.1, 0.95])
def test_a_grading_outside_its_range_is_refused(grading):
    with pytest.raises(ValueError, match="row grading"):
        row_heights(0.0, 1.0, 10, grading)
