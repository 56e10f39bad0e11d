"""Every girth-line value says how far it is from the converged garment: a case relaxes two
coarser grids too, and its result.nc and summary.csv carry the Richardson estimate of each value
(`cloth.stages.levels`, `cloth.files.levels`). Checked against a finer grid on a cone, and
silent (no error number) where the levels show no order."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from cloth.bodies.torso import chart_size, torso_mesh
from cloth.case.case import validate_case
from cloth.errors import InputError
from cloth.files.levels import read_levels
from cloth.files.material import load_fabric
from cloth.io import write_netcdf
from cloth.results.resolution import mesh_spacing, row_spacing
from cloth.stages.levels import coarser_grids
from cloth.stages.results import write_result
from tests.conftest import capped_cylinder, load_result, run_result

ROOT = Path(__file__).resolve().parents[1]
CONE = {"cone": {"radius_bottom": 0.13, "radius_top": 0.09, "bottom": 0.0, "top": 0.5}}
LINES = {"low": 0.17, "mid": 0.25}


def _cone_case(grid: list[int], solver: dict | None = None, **garment) -> dict:
    """A tube on a cone, its warp stretched (lengthwise reduction 0.1) so that no fabric is
    compressed: one stable equilibrium, every row its own radius and pressure; ``garment``
    keys on top of the garment block, ``solver`` as the solver block."""
    case = {
        "material": "powernet",
        "body": CONE,
        "landmarks": LINES,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": 0.15,
            "lengthwise_reduction": 0.1,
            "grid": grid,
            **garment,
        },
    }
    return case if solver is None else {**case, "solver": solver}


def _cone(folder: Path, grid: list[int], estimate: bool = True, stop: str = "aggregate") -> Path:
    """`_cone_case` run to ``stop`` in ``folder``, with or without its error ``estimate``."""
    return run_result(folder, _cone_case(grid, error_estimate=estimate), stop)


@pytest.fixture(scope="module")
def cones(tmp_path_factory) -> dict[str, xr.Dataset]:
    base = tmp_path_factory.mktemp("cones")
    out = {}
    for name, grid in (("coarse", [96, 24]), ("fine", [192, 48])):
        with xr.open_dataset(_cone(base / name, grid) / "result.nc") as ds:
            out[name] = ds.load()
    out["summary"] = base / "coarse" / "out" / "summary.csv"
    return out


def test_grids_halve_rounding_up_and_stop_at_the_smallest():
    assert coarser_grids((48, 24), 2) == [(24, 12), (12, 6)]
    assert coarser_grids((97, 25), 2) == [(49, 13), (25, 7)]
    assert coarser_grids((16, 6), 2) == [(8, 3)]  # 4 x 2 would be below 8 x 3


def test_a_level_ratio_divides_the_grid_by_its_powers():
    """garment.level_ratio r: level k is the grid / r^k, rounded up (289 / 1.7^2 is 100, not
    101, though the float gives 100.00000000000001), and stops where a level would not be
    smaller than the one above."""
    assert coarser_grids((96, 48), 2, 2**0.5) == [(68, 34), (48, 24)]
    assert coarser_grids((289, 289), 2, 1.7) == [(170, 170), (100, 100)]
    assert coarser_grids((288, 144), 2, 1.5) == [(192, 96), (128, 64)]
    assert coarser_grids((12, 4), 2, 1.2) == []  # 10 x 4: the rows stay 4, no level
    with pytest.raises(ValueError, match="exceed 1"):
        coarser_grids((48, 24), 2, 1.0)


def test_on_a_cone_the_stated_error_brackets_the_distance_to_a_finer_grid(cones):
    """The cone's 96 x 24 band values (levels 48 x 12 and 24 x 6) with their stated errors
    contain the converged value as the 192 x 48 grid extrapolates it; an order is observed on
    both grids, near the scheme's second (measured 1.7-2.5: the band's quadrature over the rows
    adds its own error to Laplace's polygon)."""
    coarse, fine = cones["coarse"], cones["fine"]
    for ds in (coarse, fine):
        assert (ds["pressure_mean_estimate"].values == 0).all()
        np.testing.assert_allclose(ds["pressure_mean_order"].values, 2.0, atol=0.6)
    distance = np.abs(fine["pressure_mean_extrapolated"].values - coarse["pressure_mean"].values)
    assert (distance <= coarse["pressure_mean_error"].values).all()
    # the estimate is informative: the finer grid's stated error is smaller, and not zero
    assert (0 < fine["pressure_mean_error"].values).all()
    assert (fine["pressure_mean_error"].values < coarse["pressure_mean_error"].values).all()


def test_the_result_lists_its_levels_with_units_and_the_summary_says_the_error(cones):
    ds = cones["coarse"]
    assert ds["level_n"].values.tolist() == [96, 48, 24]
    assert ds["level_m"].values.tolist() == [24, 12, 6]
    np.testing.assert_array_equal(ds["level_pressure_mean"].values[0], ds["pressure_mean"].values)
    assert ds["pressure_mean_error"].attrs["units"] == "Pa"
    assert ds["tension_mean_error"].attrs["units"] == "N m-1"
    assert ds["pressure_mean_order"].attrs["units"] == "1"
    assert "flag_meanings" in ds["pressure_mean_estimate"].attrs
    with open(cones["summary"], newline="") as handle:
        rows = list(csv.DictReader(handle))
    for row, error, value in zip(
        rows, ds["pressure_mean_error"].values, ds["pressure_mean"].values, strict=True
    ):
        assert float(row["pressure_mean_error_Pa"]) == pytest.approx(error, rel=1e-5)
        assert float(row["pressure_mean_error_percent"]) == pytest.approx(
            100 * error / value, rel=1e-5
        )
        assert row["error_note"] == ""


def test_levels_that_neither_converge_nor_shrink_state_three_times_their_range(tmp_path):
    """relaxed.nc's middle level moved beyond the fine value: the summary says so, and the
    error is 3 x the range of the three levels' values (flag 7, data_range)."""
    out = _cone(tmp_path, [48, 12], stop="relax")
    with xr.open_dataset(out / "relaxed.nc") as ds:
        relaxed = ds.load()
    with xr.open_dataset(_cone(tmp_path / "plain", [48, 12]) / "result.nc") as ds:
        fine = ds["pressure_mean"].values
    zigzag = relaxed["level_pressure_mean"].values.copy()
    zigzag[0] = fine + 2 * (fine - zigzag[1])  # middle beyond fine, coarse on the other side
    write_netcdf(
        relaxed.assign(level_pressure_mean=(("level", "landmark"), zigzag)), out / "zigzag.nc"
    )
    result = write_result(out / "zigzag.nc", out / "result.nc", out / "summary.csv")
    assert (result["pressure_mean_estimate"].values == 7).all()  # data_range
    spread = np.ptp(np.vstack([fine, zigzag]), axis=0)
    np.testing.assert_allclose(result["pressure_mean_error"].values, 3 * spread, rtol=1e-12)
    with open(out / "summary.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    for row, stated in zip(rows, 3 * spread, strict=True):
        assert row["error_note"].endswith("the error is 3 x their range")
        assert float(row["pressure_mean_error_Pa"]) == pytest.approx(stated, rel=1e-5)


def test_without_levels_the_result_says_the_error_was_not_estimated(tmp_path):
    out = _cone(tmp_path, [48, 12], estimate=False)
    with xr.open_dataset(out / "relaxed.nc") as ds:
        assert read_levels(ds, list(LINES)) == ([], [], {})
    with xr.open_dataset(out / "result.nc") as ds:
        assert (ds["pressure_mean_estimate"].values == 1).all()  # too_few_levels
        assert np.isnan(ds["pressure_mean_error"].values).all()
        assert ds["level_n"].values.tolist() == [48]


def _cylinder_auto(folder: Path, accuracy: float, max_nodes: int) -> xr.Dataset:
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1}},
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": 0.2,
            "grid": "auto",
            "accuracy": accuracy,
            "max_nodes": max_nodes,
        },
    }
    return load_result(folder, case)


def test_an_automatic_grid_refines_until_its_stated_error_meets_the_accuracy(tmp_path):
    """On a cylinder, Laplace's p = T / r is the converged value. ``grid: auto`` doubles n and m
    from 12 around until the stated error of the mean is within 0.2 %: that error then holds
    (the true one is inside it), and the grid one step coarser could not have met it (its
    stated error is never below its last change, `cloth.results.richardson`)."""
    ds = _cylinder_auto(tmp_path, 0.002, 100_000)
    fabric = load_fabric("powernet", ROOT)
    tension = float(fabric.weft(np.array([1.0 / 0.8 - 1.0]))[0]) * fabric.thickness
    exact = tension / 0.1
    value, error = float(ds["pressure_mean"][0]), float(ds["pressure_mean_error"][0])
    assert ds.attrs["grid_met"] == "accuracy"
    assert error / value <= 0.002
    assert abs(exact - value) <= error
    n = int(ds.attrs["n"])
    assert n == 12 * 2 ** round(math.log2(n / 12)) and n >= 48  # doubled from the start
    assert ds["level_n"].values.tolist() == [n, n // 2, n // 4]
    # the step before could not meet it: its stated error is at least its own last change
    coarser = ds["level_pressure_mean"].values[1:, 0]
    assert abs(coarser[0] - coarser[1]) / coarser[0] > 0.002


def test_an_automatic_grid_stops_at_its_node_cap_and_says_so(tmp_path, caplog):
    ds = _cylinder_auto(tmp_path, 1e-6, 2000)
    assert ds.attrs["grid_met"] == "node cap"
    assert int(ds.attrs["n"]) * int(ds.attrs["m"]) <= 2000
    assert "would pass max_nodes 2000" in caplog.text


@pytest.mark.parametrize(
    ("garment", "field", "words"),
    [
        ({"grid": "aut"}, "garment.grid", "or auto"),
        ({"grid": [48, 24], "accuracy": 0.01}, "garment.accuracy", "give grid: auto"),
        ({"grid": [48, 24], "max_nodes": 5000}, "garment.max_nodes", "give grid: auto"),
        ({"grid": "auto", "accuracy": 0.0}, "garment.accuracy", "0"),
        ({"grid": [48, 24], "level_ratio": 1.0}, "garment.level_ratio", "minimum of 1.1"),
        ({"grid": [48, 24], "level_ratio": "two"}, "garment.level_ratio", "not of type"),
        ({"grid": [48, 24], "row_grading": 0.95}, "garment.row_grading", "maximum of 0.9"),
        ({"grid": [48, 24], "row_grading": True}, "garment.row_grading", "not of type"),
    ],
)
def test_an_automatic_grid_asked_wrongly_gets_one_line_naming_the_field(garment, field, words):
    case = {
        "material": "powernet",
        "body": CONE,
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.15, **garment},
    }
    with pytest.raises(InputError) as caught:
        validate_case(case, "case.yaml")
    assert caught.value.field == field and words in caught.value.detail
    assert "\n" not in str(caught.value)


def test_a_ring_meshs_vertical_sampling_is_its_ring_spacing():
    """The torso written as 32 x 30 rings (a ring at every girth line): at each line the mesh
    samples the body at the gap to the next ring below or above; a cylinder meshed with
    rings one segment apart, at that gap; a height outside the mesh at none. The garment's row
    spacing is the gap between the rows around the line."""
    chart = chart_size("M")
    vertices, faces = torso_mesh(chart, 32, 30)
    rings = np.unique(np.round(vertices[:, 2], 9))
    heights = np.array([chart.height[name] for name in ("hip", "waist", "underbust", "bust")])
    found = mesh_spacing(vertices, faces, heights)
    for height, step in zip(heights, found, strict=True):
        at = int(np.argmin(np.abs(rings - height)))
        gaps = np.diff(rings[at - 1 : at + 2])
        assert gaps.min() - 1e-12 <= step <= gaps.max() + 1e-12
    tube_v, tube_f = capped_cylinder(0.1, 0.5, 16)
    gap = float(np.diff(np.unique(tube_v[:-2, 2]))[0])
    assert mesh_spacing(tube_v, tube_f, np.array([0.25, 0.26]))[1] == pytest.approx(gap)
    assert np.isnan(mesh_spacing(tube_v, tube_f, np.array([0.9]))[0])
    rows = np.array([0.0, 0.1, 0.3, 0.6])
    np.testing.assert_allclose(
        row_spacing(rows, np.array([0.05, 0.1, 0.5, 0.6])), [0.1, 0.2, 0.3, 0.3]
    )


@pytest.mark.parametrize(
    ("rows", "levels"),
    [({}, [48, 24, 12]), ({"row_grading": 0.5, "level_ratio": 1.5}, [48, 32, 22])],
    ids=["equal-rows", "graded-rows"],
)
def test_a_rerun_is_bit_identical(tmp_path, rows, levels):
    """The same case run twice (with its levels, continuation from 100 nodes and factor reuse,
    so every path of the estimate runs; equally spaced rows and graded ones at another level
    ratio) writes the same numbers to the last bit."""
    case = _cone_case([48, 12], {"continuation": True, "coarsest": 100, "reuse": True}, **rows)
    first, second = (load_result(tmp_path / name, case) for name in ("one", "two"))
    assert first["level_n"].values.tolist() == levels
    for name, variable in first.data_vars.items():
        assert np.array_equal(variable.values, second[name].values, equal_nan=True) or (
            variable.dtype.kind not in "fc" and (variable.values == second[name].values).all()
        ), name


def test_levels_as_continuation_find_the_equilibria_each_grid_has_alone(tmp_path):
    """With continuation (from 100 nodes, so a 48 x 12 grid is coarsened) the error levels are
    the fine grid's continuation (`cloth.stages.levels.relax_ladder`): each level starts from the
    one below. Each must still be the equilibrium a user asking for its grid gets: the fine
    grid's and each level's girth-line values equal those of the grid relaxed on its own (its
    own continuation, no levels), to the solver's tolerance."""
    solver = {"continuation": True, "coarsest": 100}
    laddered = load_result(tmp_path / "ladder", _cone_case([48, 12], solver))
    assert laddered["level_n"].values.tolist() == [48, 24, 12]
    grids = zip(laddered["level_n"].values, laddered["level_m"].values, strict=True)
    for k, (n, m) in enumerate(grids):
        alone = _cone_case([int(n), int(m)], solver, error_estimate=False)
        single = load_result(tmp_path / f"alone{n}", alone)
        np.testing.assert_allclose(
            laddered["level_pressure_mean"].values[k],
            single["pressure_mean"].values,
            rtol=1e-6,
            err_msg=f"{n} x {m}",
        )
