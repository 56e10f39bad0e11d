"""The sweep's files from known numbers (`cloth.pipeline.sweep`): result files written with
chosen girth-line values, stacked by `collect`, read into sweep.csv's rows, answered by
`design`, confirmed by `confirm` and drawn by `plot_design`; every expectation by hand."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from cloth.errors import InputError
from cloth.pipeline.designplots import plot_design
from cloth.pipeline.sweep import (
    collect,
    confirm,
    confirm_name,
    design,
    design_header,
    read_design,
    sweep_rows,
    write_rows,
)
from tests.conftest import MMHG_BY_DEFINITION as MMHG

LINES = ["waist", "hip"]


def _result(path, mean, error=None, converged=1, lines=LINES):
    """A result.nc reduced to its girth-line values: the mean ``mean`` (per line, Pa), the max
    1.1 x and the min 0.9 x it, the tension mean / 10, and the errors ``error`` (Pa)."""
    mean = np.asarray(mean, dtype=float)
    data = {
        "pressure_mean": ("landmark", mean),
        "pressure_max": ("landmark", 1.1 * mean),
        "pressure_min": ("landmark", 0.9 * mean),
        "tension_mean": ("landmark", mean / 10),
    }
    if error is not None:
        error = np.asarray(error, dtype=float)
        data.update(
            pressure_mean_error=("landmark", error),
            pressure_max_error=("landmark", 2 * error),
            pressure_min_error=("landmark", 3 * error),
            tension_mean_error=("landmark", error / 10),
        )
    ds = xr.Dataset(data, coords={"landmark": lines})
    ds.attrs.update(cloth_kind="result", converged=converged)
    ds.to_netcdf(path)
    return path


@pytest.fixture
def swept(tmp_path):
    """Two reductions x new and worn on one fabric and body: the index and the result files.
    The waist reads 1000 Pa x (1 + 10 (r - 0.1)) new, 0.8 x that worn; the hip half of it."""
    index, paths = [], []
    for r in (0.1, 0.2):
        for worn in (0, 1):
            waist = 1000.0 * (1 + 10 * (r - 0.1)) * (0.8 if worn else 1.0)
            name = f"m__b__r{round(1000 * r):03d}" + ("__worn" if worn else "")
            index.append({"case": name, "material": "m", "body": "b", "reduction": r, "worn": worn})
            paths.append(
                _result(
                    tmp_path / f"{name}.nc",
                    [waist, waist / 2],
                    [10.0 * (1 + worn), 5.0],
                    converged=0 if (r, worn) == (0.2, 1) else 1,
                )
            )
    return index, paths


def test_collect_stacks_each_case_at_its_coordinates_with_units(swept):
    index, paths = swept
    ds = collect(index, paths)
    assert dict(ds.sizes) == {"material": 1, "body": 1, "reduction": 2, "worn": 2, "landmark": 2}
    assert ds["reduction"].values.tolist() == [0.1, 0.2]
    assert ds["landmark"].values.tolist() == LINES
    at = {"material": "m", "body": "b"}
    waist = ds["pressure_mean"].sel(at | {"landmark": "waist"})
    np.testing.assert_allclose(waist.sel(worn=0).values, [1000.0, 2000.0])
    np.testing.assert_allclose(waist.sel(worn=1).values, [800.0, 1600.0])
    hip = ds.sel(at | {"landmark": "hip", "reduction": 0.2, "worn": 0})
    assert float(hip["pressure_max"]) == pytest.approx(1100.0)
    assert float(hip["pressure_min"]) == pytest.approx(900.0)
    assert float(hip["tension_mean"]) == pytest.approx(100.0)
    assert float(hip["pressure_mean_error"]) == 5.0
    assert float(hip["pressure_max_error"]) == 10.0 and float(hip["pressure_min_error"]) == 15.0
    assert float(hip["tension_mean_error"]) == 0.5
    assert float(ds["pressure_mean_error"].sel(at | {"landmark": "waist", "worn": 1})[0]) == 20.0
    np.testing.assert_array_equal(ds["converged"].sel(at).values, [[1, 1], [1, 0]])
    for name in ("pressure_mean", "pressure_max", "pressure_min", "pressure_mean_error"):
        assert ds[name].attrs["units"] == "Pa"
    assert ds["tension_mean"].attrs["units"] == "N m-1"
    assert ds["tension_mean_error"].attrs["units"] == "N m-1"
    assert ds["reduction"].attrs["units"] == "1" and ds["worn"].dtype == np.int8
    assert ds["converged"].attrs["flag_meanings"] == "no yes"
    assert ds.attrs["cloth_kind"] == "sweep" and json.loads(ds.attrs["cases"]) == index
    with pytest.raises(InputError) as caught:
        collect(index, paths[:-1])
    assert caught.value.field == "results"
    assert "give one result.nc per sweep case (4), got 3" in str(caught.value)


def test_sweep_nc_is_cf_every_variable_described_and_the_flags_typed(swept):
    index, paths = swept
    ds = collect(index, paths)
    for name in ds.data_vars:
        assert ds[name].attrs["long_name"] and "units" in ds[name].attrs, name
    assert ds["pressure_mean_error"].attrs["long_name"].startswith("estimated discretisation")
    assert ds["converged"].dtype == np.int8
    np.testing.assert_array_equal(ds["converged"].attrs["flag_values"], [0, 1])
    assert ds["converged"].attrs["flag_values"].dtype == np.int8
    assert ds["worn"].attrs["flag_values"].dtype == np.int8
    names = {
        "material": "fabric",
        "body": "body",
        "reduction": "pattern reduction",
        "landmark": "girth line",
        "converged": "relaxation converged",
    }
    for name, long_name in names.items():
        assert ds[name].attrs["long_name"] == long_name
    assert ds["converged"].attrs["units"] == "1"
    assert ds.attrs["title"] == "cloth sweep"
    assert ds.attrs["cases"] == json.dumps(index, sort_keys=True)


def test_a_lengthwise_variant_keeps_its_values_as_numbers(tmp_path):
    """A variant key other than worn is a float coordinate (0.05, not truncated to 0)."""
    index = [
        {
            "case": f"c{k}",
            "material": "m",
            "body": "b",
            "reduction": 0.1,
            "lengthwise_reduction": lw,
        }
        for k, lw in enumerate((0.0, 0.05))
    ]
    paths = [_result(tmp_path / f"c{k}.nc", [1000.0 + k], lines=["w"]) for k in range(2)]
    ds = collect(index, paths)
    assert ds["lengthwise_reduction"].values.tolist() == [0.0, 0.05]
    assert ds["lengthwise_reduction"].dtype == np.float64


def _without_mean(path: Path, line: str) -> Path:
    """A result file of one girth line ``line`` without its ``pressure_mean``."""
    xr.Dataset(
        {"pressure_max": ("landmark", [1.0])},
        coords={"landmark": [line]},
        attrs={"cloth_kind": "result"},
    ).to_netcdf(path)
    return path


def test_a_result_without_its_mean_or_convergence_flag(tmp_path):
    """A result.nc without ``pressure_mean`` is refused naming it; one without the
    ``converged`` attribute counts as not converged."""
    index = [
        {"case": "a", "material": "m", "body": "b", "reduction": 0.1},
        {"case": "c", "material": "m", "body": "b", "reduction": 0.2},
    ]
    bare = _without_mean(tmp_path / "bare.nc", "waist")
    good = _result(tmp_path / "good.nc", [1000.0], lines=["waist"])
    with pytest.raises(InputError, match="pressure_mean"):
        collect(index, [good, bare])
    unflagged = tmp_path / "unflagged.nc"
    with xr.open_dataset(good) as ds:
        plain = ds.load()
    del plain.attrs["converged"]
    plain.to_netcdf(unflagged)
    ds = collect(index, [good, unflagged])
    assert ds["converged"].values.ravel().tolist() == [1, 0]


def test_a_case_missing_a_line_leaves_it_nan_and_other_lines_are_stacked(tmp_path):
    index = [
        {"case": "a", "material": "m", "body": "b", "reduction": 0.1},
        {"case": "c", "material": "m", "body": "b", "reduction": 0.2},
    ]
    paths = [
        _result(tmp_path / "a.nc", [1000.0], lines=["waist"]),
        _result(tmp_path / "c.nc", [3000.0, 500.0], lines=["bust", "waist"]),
    ]
    ds = collect(index, paths)
    assert ds["landmark"].values.tolist() == ["waist", "bust"]
    assert np.isnan(float(ds["pressure_mean"].sel(reduction=0.1, landmark="bust")[0, 0]))
    assert float(ds["pressure_mean"].sel(reduction=0.2, landmark="waist")[0, 0]) == 500.0
    assert np.isnan(ds["pressure_mean_error"].values).all()  # the results state no error
    rows = sweep_rows(ds)
    assert [(r["reduction"], r["landmark"]) for r in rows] == [
        (0.1, "waist"),
        (0.2, "waist"),
        (0.2, "bust"),
    ]  # the missing line has no row
    assert all(math.isnan(r["pressure_mean_error_mmHg"]) for r in rows)


def test_sweep_rows_give_each_new_case_its_worn_value_beside_in_mmhg(swept, tmp_path):
    index, paths = swept
    rows = sweep_rows(collect(index, paths))
    assert len(rows) == 4  # two reductions x two lines, the worn beside each
    waist = next(r for r in rows if r["reduction"] == 0.2 and r["landmark"] == "waist")
    assert waist["pressure_mean_Pa"] == pytest.approx(2000.0)
    assert waist["pressure_mean_mmHg"] == pytest.approx(2000.0 / MMHG)
    assert waist["pressure_mean_error_mmHg"] == pytest.approx(10.0 / MMHG)
    assert waist["pressure_max_mmHg"] == pytest.approx(2200.0 / MMHG)
    assert waist["tension_mean_N_per_m"] == pytest.approx(200.0)
    assert waist["pressure_mean_mmHg_worn"] == pytest.approx(1600.0 / MMHG)
    assert waist["worn_change_percent"] == pytest.approx(-20.0)
    assert waist["converged"] == 1 and "worn" not in waist
    header = list(rows[0])
    write_rows(rows, tmp_path / "sweep.csv", header)
    with open(tmp_path / "sweep.csv", newline="") as handle:
        written = list(csv.DictReader(handle))
    assert written[0].keys() == rows[0].keys()
    assert float(written[1]["pressure_mean_mmHg"]) == pytest.approx(
        rows[1]["pressure_mean_mmHg"], rel=1e-5
    )
    assert written[1]["pressure_mean_mmHg"] == f"{rows[1]['pressure_mean_mmHg']:.6g}"


def test_design_interpolates_each_variant_and_its_interval_by_hand(swept):
    index, paths = swept
    ds = collect(index, paths)
    goal = 1500.0  # Pa at the waist
    rows = design(ds, [{"landmark": "waist", "pressure_kPa": goal / 1e3}])
    assert [r["worn"] for r in rows] == [0, 1]
    new, worn = rows
    # new: 1000 + 10000 (r - 0.1) Pa: r = 0.15 half-way, errors 10 Pa both ends, slope 1e4 Pa
    assert new["status"] == "ok" and new["reduction"] == pytest.approx(0.15)
    assert new["slope_Pa"] == pytest.approx(1e4)
    assert new["reduction_error"] == pytest.approx(10.0 / 1e4)
    assert new["reduction_low"] == pytest.approx(0.15 - 1e-3)
    assert new["reduction_high"] == pytest.approx(0.15 + 1e-3)
    assert new["target_Pa"] == goal and new["target_mmHg"] == pytest.approx(goal / MMHG)
    # worn: 800 + 8000 (r - 0.1): r = 0.1875, errors 20 Pa, slope 8000 Pa
    assert worn["reduction"] == pytest.approx(0.1875)
    assert worn["slope_Pa"] == pytest.approx(8000.0)
    assert worn["reduction_error"] == pytest.approx(20.0 / 8000.0)
    assert design_header(rows)[:4] == ["material", "body", "worn", "landmark"]
    assert confirm_name(new) == "design__m__b__waist" and confirm_name(worn).endswith("__worn")
    low = design(ds, [{"landmark": "hip", "pressure_mmHg": 100.0}])
    assert {r["status"] for r in low} == {"out_of_range"}
    assert "no reduction in 0.1-0.2 reaches 100 mmHg at the hip" in low[0]["message"]
    assert math.isnan(low[0]["reduction"])
    with pytest.raises(InputError, match="unknown landmark 'knee'; the sweep has waist, hip"):
        design(ds, [{"landmark": "knee", "pressure_mmHg": 20}])


def test_design_without_two_finite_cases_says_so(tmp_path):
    index = [
        {"case": "a", "material": "m", "body": "b", "reduction": 0.1},
        {"case": "c", "material": "m", "body": "b", "reduction": 0.2},
    ]
    paths = [
        _result(tmp_path / "a.nc", [1000.0], lines=["waist"]),
        _result(tmp_path / "c.nc", [np.nan], lines=["waist"]),
    ]
    (row,) = design(collect(index, paths), [{"landmark": "waist", "pressure_mmHg": 10}])
    assert row["status"] == "no_data" and row["message"] == "fewer than two swept reductions"


def test_confirm_reads_each_answered_row_s_result_and_its_error(swept, tmp_path):
    index, paths = swept
    rows = design(collect(index, paths), [{"landmark": "waist", "pressure_mmHg": 12.0}])
    header = design_header(rows)
    write_rows(rows, tmp_path / "design.csv", header)
    read = read_design(tmp_path / "design.csv")
    read.append({**read[0], "status": "out_of_range"})  # an unanswered row: not confirmed
    goal = 12.0 * MMHG
    confirmations = [
        _result(tmp_path / "c0.nc", [1.02 * goal, 1.0], [3.0, 1.0]),
        _result(tmp_path / "c1.nc", [0.97 * goal, 1.0], [4.0, 1.0], converged=0),
    ]
    out = confirm(read, confirmations)
    assert len(out) == 3
    for record, factor, error, converged in zip(
        out, (1.02, 0.97), (3.0, 4.0), (1, 0), strict=False
    ):
        assert record["confirmed_Pa"] == pytest.approx(factor * goal)
        assert record["confirmed_mmHg"] == pytest.approx(factor * 12.0)
        assert record["confirmed_error_Pa"] == error
        assert record["confirmed_error_mmHg"] == pytest.approx(error / MMHG)
        assert record["error_percent"] == pytest.approx(100 * (factor - 1), rel=1e-4)
        assert record["converged"] == converged
    assert "confirmed_Pa" not in out[2]  # the unanswered row is passed on as it was
    with pytest.raises(InputError) as caught:
        confirm(read, confirmations[:1])
    assert caught.value.field == "results"
    assert "give one result.nc per answered target (2), got 1" in str(caught.value)


def test_the_design_figure_draws_each_line_its_errors_and_the_target(swept, tmp_path, monkeypatch):
    """design.png: a panel per girth line, the mean against the reduction in %, in mmHg, one
    line per variant (new and worn, each its own style, the body's one colour), its stated
    errors as bars, the target level; the legend below the panels, in no panel."""
    import cloth.pipeline.designplots

    index, paths = swept
    ds = collect(index, paths)
    drawn = {}
    monkeypatch.setattr(
        cloth.pipeline.designplots, "save_figure", lambda fig, path: drawn.setdefault("fig", fig)
    )
    plot_design(ds, [{"landmark": "waist", "pressure_mmHg": 12.0}], tmp_path / "d.png")
    fig = drawn["fig"]
    waist, hip = fig.axes
    assert (waist.get_title(), hip.get_title()) == ("waist", "hip")
    new, worn = waist.containers  # one errorbar line per variant
    for container, factor, error in ((new, 1.0, 10.0), (worn, 0.8, 20.0)):
        line = container.lines[0]
        np.testing.assert_allclose(line.get_xdata(), [10.0, 20.0])
        np.testing.assert_allclose(line.get_ydata(), factor * np.array([1000.0, 2000.0]) / MMHG)
        segments = np.asarray(container.lines[2][0].get_segments())  # +- its error at each
        np.testing.assert_allclose(np.ptp(segments[:, :, 1], axis=1), 2 * error / MMHG)
    assert new.lines[0].get_color() == worn.lines[0].get_color()
    assert new.lines[0].get_linestyle() != worn.lines[0].get_linestyle()
    assert [c.get_label() for c in waist.containers] == ["b", "b, worn"]
    assert not waist.collections or all(
        "spread" not in str(c.get_label()) for c in waist.collections
    )
    target = [ln for ln in waist.lines if ln.get_label() == "target"]
    assert len(target) == 1 and np.allclose(target[0].get_ydata(), 12.0)
    assert not [ln for ln in hip.lines if ln.get_label() == "target"]
    assert waist.get_legend() is None and hip.get_legend() is None
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == ["b", "b, worn", "target"]
    # the real file: the legend below every panel
    monkeypatch.undo()
    path = plot_design(ds, [{"landmark": "waist", "pressure_mmHg": 12.0}], tmp_path / "d.png")
    assert path.stat().st_size > 10_000


def test_the_profile_figure_draws_targets_uniform_and_confirmed_at_each_height(
    tmp_path, monkeypatch
):
    import cloth.pipeline.designplots
    from cloth.pipeline.designplots import plot_profile_design

    rows = [
        {
            "landmark": name,
            "height_m": z,
            "target_mmHg": t,
            "uniform_mmHg": u,
            "uniform_reduction": 0.2,
            "confirmed_mmHg": c,
            "confirmed_error_mmHg": e,
        }
        for name, z, t, u, c, e in (
            ("hip", 0.86, 15.0, 14.0, 15.1, 0.2),
            ("waist", 1.04, 20.0, 16.0, 19.9, float("nan")),
        )
    ]
    drawn = {}
    monkeypatch.setattr(
        cloth.pipeline.designplots, "save_figure", lambda fig, path: drawn.setdefault("fig", fig)
    )
    plot_profile_design(rows, tmp_path / "p.png")
    (ax,) = drawn["fig"].axes
    lines = {ln.get_label(): ln for ln in ax.lines}
    np.testing.assert_allclose(lines["target"].get_xdata(), [15.0, 20.0])
    np.testing.assert_allclose(lines["target"].get_ydata(), [0.86, 1.04])
    np.testing.assert_allclose(lines["uniform reduction 0.200"].get_xdata(), [14.0, 16.0])
    confirmed = ax.containers[0]
    np.testing.assert_allclose(np.asarray(confirmed[0].get_xdata(), float), [15.1, 19.9])
    segments = np.asarray(confirmed[2][0].get_segments())
    np.testing.assert_allclose(np.ptp(segments[:, :, 0], axis=1), [0.4, 0.0])  # NaN: no bar
    assert [t.get_text() for t in ax.texts] == ["hip", "waist"]


def _one_line_sweep(pressures, errors, reductions=(0.1, 0.15, 0.25)):
    shape = (1, 1, len(reductions), 1)
    dims = ("material", "body", "reduction", "landmark")
    return xr.Dataset(
        {
            "pressure_mean": (dims, np.asarray(pressures, float).reshape(shape)),
            "pressure_mean_error": (dims, np.asarray(errors, float).reshape(shape)),
        },
        coords={"material": ["m"], "body": ["b"], "reduction": list(reductions), "landmark": ["w"]},
    )


@pytest.mark.parametrize(
    ("goal", "reduction", "error"),
    [
        (1250.0, 0.125, (0.5 * 30 + 0.5 * 40) / 10000),  # half-way in the first interval
        (1500.0, 0.15, 40 / 20000),  # on the middle knot: the interval above it, t = 0
        (3000.0, 0.225, (0.25 * 40 + 0.75 * 80) / 20000),  # three quarters into the second
        (3500.0, 0.25, 80 / 20000),  # on the last knot
    ],
)
def test_the_design_interval_interpolates_the_errors_of_the_interval_it_lies_in(
    goal, reduction, error
):
    """Mean 1000, 1500, 3500 Pa at 0.1, 0.15, 0.25 (slopes 10000 and 20000 Pa), errors 30, 40,
    80 Pa: the error at the answer is interpolated within its own interval, over its slope."""
    (row,) = design(
        _one_line_sweep([1000, 1500, 3500], [30, 40, 80]),
        [{"landmark": "w", "pressure_kPa": goal / 1e3}],
    )
    assert row["reduction"] == pytest.approx(reduction)
    assert row["reduction_error"] == pytest.approx(error)


def test_a_flat_sweep_gives_an_unbounded_interval_and_unknown_lines_name_the_config():
    (row,) = design(
        _one_line_sweep([1000, 1000, 1000], [5, 5, 5]), [{"landmark": "w", "pressure_kPa": 1.0}]
    )
    assert row["status"] == "ok" and row["reduction_error"] == math.inf and row["slope_Pa"] == 0
    with pytest.raises(InputError) as caught:
        design(_one_line_sweep([1, 2, 3], [0, 0, 0]), [{"landmark": "knee", "pressure_mmHg": 2}])
    assert caught.value.field == "targets" and str(caught.value.source) == "config"
    low = design(
        _one_line_sweep([1000, 1500, 3500], [1, 1, 1]), [{"landmark": "w", "pressure_kPa": 9}]
    )
    assert low[0]["message"].endswith("widen the reductions or choose another fabric")
    assert low[0]["status"] == "out_of_range" and low[0]["slope_Pa"] != low[0]["slope_Pa"]


def test_confirm_and_the_header_with_one_row(tmp_path):
    """A confirmation without its mean is refused naming it; one without a convergence flag
    counts as not converged; the header of a single variant row names its key."""
    from cloth.pipeline.sweep import design_header

    row = {"material": "m", "body": "b", "landmark": "w", "status": "ok", "target_Pa": "1000"}
    assert design_header([{**row, "worn": 1}])[:3] == ["material", "body", "worn"]
    with pytest.raises(InputError, match="pressure_mean"):
        confirm([row], [_without_mean(tmp_path / "bare.nc", "w")])
    flagless = tmp_path / "flagless.nc"
    xr.Dataset(
        {"pressure_mean": ("landmark", [900.0])},
        coords={"landmark": ["w"]},
        attrs={"cloth_kind": "result"},
    ).to_netcdf(flagless)
    (record,) = confirm([row], [flagless])
    assert record["converged"] == 0 and math.isnan(record["confirmed_error_Pa"])
