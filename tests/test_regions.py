"""Gathering and lifting, reported (issue 40, item 5): where the warp is slack and where the
garment is off the body, their share of the area, their heights and the girth lines they meet
(`cloth.results.regions`), by hand and on the torso."""

from __future__ import annotations

import csv

import numpy as np
import pytest
import xarray as xr

from cloth.results.regions import height_ranges, note, region
from tests.conftest import run_result


def test_height_ranges_are_runs_of_rows_from_their_lowest_to_their_highest_flagged_node():
    """Rows at 0.1 .. 0.5 m, two nodes each: rows 0-1 and 3 flagged; a run's ends are its
    flagged nodes' heights, not the rows' means."""
    z = np.array([0.10, 0.11, 0.20, 0.21, 0.30, 0.31, 0.40, 0.41, 0.50, 0.51])
    flag = np.array([0, 1, 1, 0, 0, 0, 1, 1, 0, 0], bool)
    np.testing.assert_array_equal(height_ranges(flag, z, 5), [[0.11, 0.20], [0.40, 0.41]])
    assert height_ranges(np.zeros(10, bool), z, 5).shape == (0, 2)


def test_a_region_s_share_is_of_the_area_and_it_names_the_lines_its_ranges_meet_by_the_band():
    x = np.zeros((6, 3))
    x[:, 2] = [0.1, 0.1, 0.2, 0.2, 0.3, 0.3]
    area = np.array([1.0, 1.0, 1.0, 1.0, 2.0, 2.0])
    flag = np.array([0, 0, 0, 0, 1, 0], bool)
    lines = {"low": 0.1, "near": 0.285, "far": 0.2}
    found = region("off_body", flag, x, area, 3, lines, 0.02)
    assert found.share == pytest.approx(2.0 / 8.0)
    assert found.lines == ("near",)  # 0.285 is within 2 cm of the range 0.3-0.3; 0.2 is not


def test_the_words_say_what_the_frictionless_model_leaves_out():
    assert note(False, False, 0.0) == ""
    assert "gathers" in note(True, False, 0.0) and "friction" in note(True, False, 0.0)
    assert "bridges" in note(False, True, 0.0)
    assert "mu = 0.5 holds" in note(True, True, 0.5)


def _torso(folder, lengthwise: float) -> xr.Dataset:
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {
            "bottom": 0.80,
            "top": 1.25,
            "reduction": 0.20,
            "grid": [48, 24],
            "lengthwise_reduction": lengthwise,
            "error_estimate": False,
        },
    }
    out = run_result(folder, case)
    with xr.open_dataset(out / "result.nc") as ds:
        return ds.load(), out / "summary.csv"


@pytest.mark.parametrize(("lengthwise", "region_name"), [(0.10, "off_body"), (0.0, "slack_warp")])
def test_on_the_torso_the_waist_is_where_the_frictionless_answer_depends_on_friction(
    tmp_path, lengthwise, region_name
):
    """With the warp stretched 10 % the garment lifts off the waist's hollow; with none the
    warp is slack and the fabric gathers there. Either way the region meets the waist, its
    share and heights are in result.nc and summary.csv says so in words."""
    ds, summary = _torso(tmp_path, lengthwise)
    share = float(ds[f"{region_name}_share"])
    assert 0.0 < share < 1.0
    ranges = ds[f"{region_name}_ranges"].values
    waist = float(ds["landmark_height"].sel(landmark="waist"))
    assert any(low - 0.02 <= waist <= high + 0.02 for low, high in ranges)
    assert int(ds[f"landmark_{region_name}"].sel(landmark="waist")) == 1
    assert ds[f"{region_name}_share"].attrs["units"] == "1"
    if region_name == "slack_warp":  # the flag is the node warp strain's sign
        slack = ds["slack_warp"].values.astype(bool)
        assert (ds["strain_warp"].values[slack] < 0).all()
        assert (np.nan_to_num(ds["strain_warp"].values[~slack]) >= -1e-9).all()
    with open(summary, newline="") as handle:
        rows = {row["landmark"]: row for row in csv.DictReader(handle)}
    column = "off_body" if region_name == "off_body" else "warp_slack"
    assert rows["waist"][column] == "1"
    assert "friction" in rows["waist"]["friction_note"]
