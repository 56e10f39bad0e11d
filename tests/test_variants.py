"""Sweeps over tissue, friction and wear: names, blocks, sweep.nc dimensions, side by side."""

from __future__ import annotations

import copy
import csv
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from cloth.case import Tissue
from cloth.errors import InputError
from cloth.pipeline.plan import make_plan
from cloth.pipeline.variants import Variant, sweep_variants
from cloth.stages.case import run_case
from cloth.stages.sweep import design_file, sweep_files

ROOT = Path(__file__).resolve().parents[1]
CONFIG = yaml.safe_load((ROOT / "config/config.yaml").read_text())


def test_a_sweep_over_variants_names_and_builds_every_case():
    config = copy.deepcopy(CONFIG)
    config["sweep"].update(
        tissue_moduli=[None, 20000],
        tissue_thickness=0.015,
        frictions=[0.0, 0.4],
        worn=[False, True],
    )
    plan = make_plan(config, ROOT)
    plain = len(config["sweep"]["bodies"]) * len(config["sweep"]["reductions"])
    # the default sweeps two lengthwise reductions; three variant axes of two values each
    assert len(plan.index) == plain * 2 * 2 * 2 * 2
    assert "powernet__torso_M__r150" in plan.cases  # the default variant keeps its name
    name = "powernet__torso_M__r150__tissue20000__mu040__worn__lw100"
    case = plan.cases[name]
    assert case.body.tissue == Tissue(thickness=0.015, modulus=20000.0)
    assert case.contact.friction == 0.4 and case.garment.worn is True
    assert case.garment.lengthwise_reduction == 0.1
    entry = next(e for e in plan.index if e["case"] == name)
    assert entry["tissue_modulus"] == 20000 and entry["friction"] == 0.4 and entry["worn"] == 1
    rigid = next(e for e in plan.index if e["case"] == "powernet__torso_M__r150")
    assert rigid["tissue_modulus"] == math.inf and plan.cases[rigid["case"]].body.tissue is None
    # a design row names its variant, and its confirmation case has it
    row = {
        "material": "powernet",
        "body": "torso_M",
        "reduction": "0.17",
        "tissue_modulus": "20000.0",
        "friction": "0.4",
        "worn": "1",
    }
    assert plan.design_case(row)["contact"] == {"friction": 0.4}


def test_swept_tissue_needs_its_thickness():
    config = copy.deepcopy(CONFIG)
    config["sweep"].update(tissue_moduli=[20000])
    with pytest.raises(InputError) as error:
        make_plan(config, ROOT)
    assert error.value.field == "sweep.tissue_thickness"


def test_variant_tags_and_labels():
    assert Variant().tag() == "" and Variant().label() == ""
    assert Variant(1e12, 0.25, True).tag() == "__tissue1e12__mu025__worn"
    assert Variant.of({"tissue_modulus": "inf", "worn": "0"}) == Variant()
    assert [v for _, v in sweep_variants({"worn": [False, True]})] == [
        Variant(),
        Variant(worn=True),
    ]


@pytest.mark.slow  # four relaxations (7 s); test_sweep checks the stacking in process
def test_sweep_nc_gains_a_dimension_per_varied_key_and_csv_sets_worn_beside_new(tmp_path):
    block = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "top": 0.5}},
        "garment": {"bottom": 0.1, "top": 0.4, "grid": [24, 4]},
        "solver": {"tolerance": 1e-9},
    }
    index = []
    for reduction in (0.1, 0.2):
        for friction in (0.0, 0.3):
            for worn in (False, True):
                variant = Variant(friction=friction, worn=worn)
                case = variant.apply(
                    {
                        **block,
                        "garment": {
                            **block["garment"],
                            "reduction": reduction,
                            "set_strain": {"weft": 0.05, "warp": 0.0},
                        },
                    },
                    None,
                )
                name = f"c{reduction:g}{variant.tag()}"
                path = tmp_path / f"{name}.yaml"
                path.write_text(yaml.safe_dump(case))
                run_case(path, tmp_path / "results" / "cases" / name, {}, stop_after="aggregate")
                index.append(
                    {
                        "case": name,
                        "material": "powernet",
                        "body": "cylinder",
                        "reduction": reduction,
                        "friction": friction,
                        "worn": int(worn),
                    }
                )
    targets = [{"landmark": "middle", "pressure_mmHg": 18}]
    out = tmp_path / "results"
    results = [out / "cases" / entry["case"] / "result.nc" for entry in index]
    sweep_files(index, results, targets, out / "sweep.nc", out / "sweep.csv", out / "design.png")
    import xarray as xr

    with xr.open_dataset(out / "sweep.nc") as ds:
        assert ds["pressure_mean"].dims == (
            "material",
            "body",
            "reduction",
            "friction",
            "worn",
            "landmark",
        )
        assert ds["worn"].attrs["flag_meanings"] == "new worn"
        p = ds["pressure_mean"].sel(landmark="middle", material="powernet", body="cylinder")
        # on a cylinder friction carries nothing; worn costs pressure
        np.testing.assert_allclose(p.sel(friction=0.3), p.sel(friction=0.0), rtol=1e-6)
        assert np.all(p.sel(worn=1) < 0.95 * p.sel(worn=0))
    with open(out / "sweep.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 2 * 2  # reductions x frictions; worn beside new
    for row in rows:
        change = float(row["pressure_mean_mmHg_worn"]) / float(row["pressure_mean_mmHg"]) - 1
        assert abs(100 * change - float(row["worn_change_percent"])) < 1e-3
    design_file(out / "sweep.nc", targets, out / "design.csv")
    with open(out / "design.csv", newline="") as handle:
        design = list(csv.DictReader(handle))
    assert len(design) == 4 and {"friction", "worn"} <= set(design[0])


def test_a_sweep_over_lengthwise_reductions_names_its_cases_and_replaces_the_garments():
    config = copy.deepcopy(CONFIG)
    config["sweep"]["lengthwise_reductions"] = [0.0, 0.1]
    config["sweep"].pop("frictions", None)
    plan = make_plan(config, ROOT)
    names = {e["case"] for e in plan.index}
    assert {"powernet__torso_M__r150", "powernet__torso_M__r150__lw100"} <= names
    assert plan.cases["powernet__torso_M__r150__lw100"].garment.lengthwise_reduction == 0.1
    assert plan.cases["powernet__torso_M__r150"].garment.lengthwise_reduction == 0.0
    entry = next(e for e in plan.index if e["case"] == "powernet__torso_M__r150__lw100")
    assert entry["lengthwise_reduction"] == 0.1
    assert Variant(lengthwise_reduction=0.1).label() == "lengthwise 0.1"
    assert Variant.of({"lengthwise_reduction": "0.1"}).tag() == "__lw100"


def test_on_a_cylinder_the_lengthwise_reduction_scales_the_pressure_by_one_less_it(tmp_path):
    """Rows held at their heights on a cylinder: a lengthwise reduction r stretches the warp by
    1 / (1 - r) - 1 and leaves the hoop tension per rest width as it was, so Laplace's pressure,
    per deformed width, is (1 - r) times the unstretched one: sweep.nc's new dimension says so."""
    import xarray as xr

    block = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "top": 0.5}},
        "garment": {"bottom": 0.1, "top": 0.4, "grid": [24, 7], "reduction": 0.15},
        "solver": {"tolerance": 1e-10},
        "landmarks": {"middle": 0.25},
    }
    index = []
    for lengthwise in (0.0, 0.1):
        variant = Variant(lengthwise_reduction=lengthwise)
        name = f"c{variant.tag()}"
        path = tmp_path / f"{name}.yaml"
        path.write_text(yaml.safe_dump(variant.apply(block, None)))
        run_case(path, tmp_path / "results" / "cases" / name, {}, stop_after="aggregate")
        index.append(
            {
                "case": name,
                "material": "powernet",
                "body": "cylinder",
                "reduction": 0.15,
                "lengthwise_reduction": lengthwise,
            }
        )
    out = tmp_path / "results"
    results = [out / "cases" / entry["case"] / "result.nc" for entry in index]
    sweep_files(index, results, [], out / "sweep.nc", out / "sweep.csv", out / "design.png")
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert "lengthwise_reduction" in ds["pressure_mean"].dims
        assert ds["lengthwise_reduction"].attrs["units"] == "1"
        p = ds["pressure_mean"].sel(landmark="middle").squeeze()
        ratio = float(p.sel(lengthwise_reduction=0.1) / p.sel(lengthwise_reduction=0.0))
    assert ratio == pytest.approx(0.9, rel=1e-3)
