"""The shapewear pipeline (issue 69): config/shapewear.yaml at CI size (the parametric torso M
alone, one reduction, a coarse grid, given on top of it), end to end: its bands read as girth
lines with their errors and the lines beside them, the layer and bands in each case's fabrics,
the design question answered and confirmed."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
import xarray as xr
import yaml

from tests.pipeline import from_checkout, snakemake

pytestmark = pytest.mark.slow

SMALL = {
    "sweep": {
        "bodies": ["torso_M"],
        "reductions": [0.15, 0.20],
        "garment": {"grid": [48, 32]},
    },
}
TARGETS = ("results-shapewear/sweep.csv", "results-shapewear/design_confirmed.csv")
LINES = {"waistband", "waistband_beside", "legband", "legband_beside"}


@pytest.fixture(scope="module")
def shapewear(tmp_path_factory) -> Path:
    where = tmp_path_factory.mktemp("shapewear")
    small = where / "small.yaml"
    small.write_text(yaml.safe_dump(SMALL))
    config = from_checkout(where, "config/shapewear.yaml")
    done = snakemake(where, *TARGETS, *config, str(small))
    assert done.returncode == 0, done.stderr[-3000:]
    return where / "results-shapewear"


def test_the_bands_read_as_lines_with_their_errors(shapewear):
    rows = list(csv.DictReader((shapewear / "sweep.csv").open()))
    assert LINES <= {r["landmark"] for r in rows}
    for row in rows:
        if row["landmark"] in LINES:
            assert float(row["pressure_mean_mmHg"]) > 0
            assert float(row["pressure_mean_error_mmHg"]) >= 0  # an error stated


def test_each_case_wears_the_power_net_its_bands_and_its_layer(shapewear):
    case = shapewear / "cases" / "powernet__torso_M__r200"
    result = xr.load_dataset(case / "result.nc")
    names = json.loads(result.attrs["fabrics"])  # the case's material first, as it names it
    assert names[0].endswith("powernet.nc") and names[1:] == ["elastic25", "controlnet"]
    node = result["node_fabric"].values
    z = result["z"].values.mean(axis=1)
    assert (node[z > 1.10 - 0.02] == 1).all()  # the waistband's rows, all round
    assert (node[z < 0.86 + 0.015] == 1).all()  # the leg band's
    assert set(result["band"].values.tolist()) == {"waistband", "legband"}
    confirmed = list(csv.DictReader((shapewear / "design_confirmed.csv").open()))
    assert confirmed and all(r["landmark"] == "waist" for r in confirmed)
