"""The pipeline's plan from its config: case names, the sweep's expansion, the checks of
targets and names, the design's confirmation cases, and finding bundled files."""

from __future__ import annotations

import copy
import json
from dataclasses import replace
from pathlib import Path

import pytest
import yaml

from cloth.case import Case
from cloth.case.case import validate_case
from cloth.errors import InputError
from cloth.pipeline.plan import (
    body_files,
    data_path,
    local_body,
    make_plan,
    reduction_tag,
    sweep_name,
)

ROOT = Path(__file__).resolve().parents[1]
CONFIG = yaml.safe_load((ROOT / "config/config.yaml").read_text())


STUDY = yaml.safe_load((ROOT / "config/study.yaml").read_text())


def test_the_default_config_answers_size_m_in_twelve_cases():
    """make run: torso M and its avatar, reductions 0.15, 0.20, 0.25, each with lengthwise 0
    and 0.10, at 288 x 144; 20 mmHg at the waist for both bodies; the graded design on
    torso M."""
    plan = make_plan(CONFIG, ROOT)
    assert len(plan.index) == len(plan.sweep) == len(plan.cases) == 12
    assert sorted({e["body"] for e in plan.index}) == ["avatar_M", "torso_M"]
    assert sorted({e["reduction"] for e in plan.index}) == [0.15, 0.2, 0.25]
    assert sorted({e["lengthwise_reduction"] for e in plan.index}) == [0.0, 0.1]
    assert {tuple(case.garment.grid) for case in plan.cases.values()} == {(288, 144)}
    assert CONFIG["targets"] == [{"landmark": "waist", "pressure_mmHg": 20}]
    assert set(plan.designs) == {"graded"} and CONFIG["profile_designs"]["graded"]["body"] == (
        "torso_M"
    )


def test_the_study_sweep_expands_to_every_material_body_and_reduction():
    plan = make_plan(STUDY, ROOT)
    sweep = STUDY["sweep"]
    count = (
        len(sweep["materials"])
        * len(sweep["bodies"])
        * len(sweep["reductions"])
        * len(sweep["lengthwise_reductions"])
    )
    assert len(plan.index) == len(plan.sweep) == len(plan.cases) == count == 32
    assert "powernet__torso_M__r150" in plan.cases
    case = plan.cases["powernet__torso_S__r250"]
    assert case.garment.reduction == 0.25 and case.body.params["size"] == "S"
    assert case.material == "results/materials/powernet.nc"
    plain = [e for e in plan.index if e["lengthwise_reduction"] == 0.0]
    assert [e["reduction"] for e in plain[:4]] == sweep["reductions"]
    assert plan.cases["powernet__torso_S__r250__lw100"].garment.lengthwise_reduction == 0.1
    # an avatar is the mesh that ships, fitted once over every garment's span (0.86-1.22 m)
    avatar = plan.cases["powernet__avatar_M__r200"].body
    assert avatar.kind == "mesh" and Path(avatar.option("mesh")).name == "torso_M.ply"
    assert avatar.option("region") == [0.86, 1.22]
    assert avatar.option("surface_file") == "results/bodies/avatar_M.surface.nc"


def test_names_of_sweep_cases():
    assert reduction_tag(0.15) == "r150" and reduction_tag(0.05) == "r050"
    assert reduction_tag(0.1 + 0.2) == "r300"  # rounding, not truncation
    assert sweep_name("lycra", "scan", 0.2) == "lycra__scan__r200"


def _chart_of(bodies: list[str]):
    """A config change: the default design over ``bodies`` in place of its body."""

    def change(config: dict) -> None:
        config["profile_designs"]["graded"].pop("body")
        config["profile_designs"]["graded"]["bodies"] = bodies

    return change


@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda c: c["sweep"].update(bodies=["torso_XL"]), "sweep.bodies"),
        (lambda c: c["sweep"].update(materials=["silk"]), "sweep.materials"),
        (lambda c: c.update(targets=[{"landmark": "knee", "pressure_mmHg": 20}]), "targets.0"),
        (lambda c: c.update(targets=[{"landmark": "waist"}]), "targets.0"),
        (
            lambda c: c.update(
                cases={
                    "powernet__torso_M__r150": {
                        "material": "powernet",
                        "body": {"torso": {"size": "M"}},
                    }
                }
            ),
            "cases.powernet__torso_M__r150",
        ),
        (
            lambda c: c.update(
                cases={"mine": {"material": "silk", "body": {"torso": {"size": "M"}}}}
            ),
            "cases.mine.material",
        ),
        (
            lambda c: c["profile_designs"]["graded"].update(bodies=["torso_S"]),
            "profile_designs.graded",  # body and bodies
        ),
        (
            lambda c: c["profile_designs"]["graded"].pop("body"),
            "profile_designs.graded",  # neither
        ),
        (_chart_of(["torso_S", "torso_XL"]), "profile_designs.graded.bodies.1"),
        (_chart_of(["torso_S", "torso_S"]), "profile_designs.graded.bodies"),
        (
            lambda c: c.update(comparisons={"nobody": "data/measurements/example_cone.csv"}),
            "comparisons.nobody",
        ),
        (
            lambda c: c.update(comparisons={"powernet__torso_M__r150": "readings/none.csv"}),
            "comparisons.powernet__torso_M__r150",
        ),
    ],
)
def test_a_bad_config_is_refused_naming_its_key(change, field):
    config = copy.deepcopy(STUDY)  # two sizes of the torso
    change(config)
    with pytest.raises(InputError) as error:
        make_plan(config, ROOT)
    assert error.value.field.startswith(field)


def test_a_chart_design_has_a_case_per_body_in_order_and_its_pattern_options():
    config = copy.deepcopy(STUDY)
    graded = config["profile_designs"]["graded"]
    graded.pop("body")
    graded.update(bodies=["torso_M", "torso_S"], pattern={"cut": "tube", "seam_allowance_mm": 0})
    design = make_plan(config, ROOT).designs["graded"]
    assert design.chart and list(design.cases) == ["torso_M", "torso_S"]
    assert [c.body.params["size"] for c in design.cases.values()] == ["M", "S"]
    assert design.pattern == ["--cut=tube", "--seam-allowance=0.0", "--paper=A4"]
    single = make_plan(CONFIG, ROOT).designs["graded"]
    assert not single.chart and list(single.cases) == ["torso_M"]
    assert single.pattern == ["--cut=auto", "--seam-allowance=6.0", "--paper=A4"]


def test_a_confirmation_case_is_the_sweeps_case_at_the_designed_reduction():
    plan = make_plan(CONFIG, ROOT)
    row = {"material": "powernet", "body": "torso_M", "reduction": "0.1733"}
    block = plan.case("confirm", plan.design_case(row))
    reference = plan.cases["powernet__torso_M__r150"]
    assert block.garment == replace(reference.garment, reduction=0.1733)
    assert block.body == reference.body and block.solver == reference.solver


def _on(body: dict) -> Case:
    """A case of ``body``."""
    garment = {"bottom": 0.9, "top": 1.1, "grid": [8, 4], "reduction": 0.1}
    return validate_case({"material": "powernet", "body": body, "garment": garment})


def test_files_are_found_where_given_else_beside_the_workflow(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # an empty working directory
    table = "data/materials/powernet.csv"
    assert data_path(table, ROOT) == str(ROOT / table)  # the bundled copy
    (tmp_path / "data/materials").mkdir(parents=True)
    (tmp_path / table).write_text("mine")
    assert data_path(table, ROOT) == table  # the user's own, relative to the working directory
    assert data_path("nowhere.csv", ROOT) == "nowhere.csv"  # left for the rule to report
    body = local_body({"mesh": "scans/me.obj", "units": "mm"}, "me", ROOT)
    assert body["surface_file"] == "results/bodies/me.surface.nc"
    assert local_body({"mesh": "m.obj", "surface": "mesh"}, "m") == {
        "mesh": "m.obj",
        "surface": "mesh",
    }
    assert body_files(_on(body)) == ["scans/me.obj", "results/bodies/me.surface.nc"]
    assert Path(body_files(_on({"torso": {"size": "M"}}))[0]).is_file()  # the chart
    assert make_plan(CONFIG, ROOT).material_tables("powernet") == [table]  # the user's, here
    (tmp_path / table).unlink()
    assert make_plan(CONFIG, ROOT).material_tables("powernet") == [str(ROOT / table)]


def test_a_non_finite_config_number_is_refused_but_a_rigid_tissue_modulus_is_not():
    config = copy.deepcopy(CONFIG)
    config["targets"] = [{"landmark": "waist", "pressure_mmHg": float("nan")}]
    with pytest.raises(InputError) as error:
        make_plan(config, ROOT)
    assert error.value.field == "targets.0.pressure_mmHg" and "finite" in str(error.value)
    config = copy.deepcopy(CONFIG)
    config["sweep"] |= {"tissue_moduli": [float("inf"), 2e4], "tissue_thickness": 0.01}
    plan = make_plan(config, ROOT)  # .inf: a rigid body (the schema says so)
    assert sum(case.body.tissue is None for case in plan.cases.values()) == len(plan.cases) // 2


@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda c: c["materials"]["powernet"].update(table="nope.csv"), "materials.powernet.table"),
        (lambda c: c["bodies"].update(scan={"mesh": "data"}), "bodies.scan.mesh"),
        (lambda c: c["bodies"]["torso_M"]["torso"].update(chart="no.csv"), "bodies.torso_M.torso"),
        (lambda c: c["bodies"]["avatar_M"]["avatar"].update(chart="no.csv"), "bodies.avatar_M"),
        (lambda c: c["bodies"]["avatar_M"]["avatar"].update(size="XL"), "bodies.avatar_M.avatar"),
    ],
)
def test_a_config_file_that_is_not_there_is_named_before_any_job(
    tmp_path, monkeypatch, change, field
):
    monkeypatch.chdir(tmp_path)
    config = copy.deepcopy(CONFIG)
    change(config)
    with pytest.raises(InputError) as error:
        make_plan(config, ROOT)
    assert error.value.field.startswith(field) and error.value.source == "config"


STOCKING = yaml.safe_load((ROOT / "config/stocking.yaml").read_text())


def test_a_wearers_entry_is_a_case_per_wearer_wearing_the_sizes_pattern():
    """config/stocking.yaml's leg_S: the chart's leg S and its shipped wearers, each a
    case of the sweep's garment at 0.16 cut for leg S (its pattern), the wearer's mesh as body."""
    plan = make_plan(copy.deepcopy(STOCKING), ROOT)
    run = plan.wearers["leg_S"]
    corners = ["B_min_C_min", "B_min_C_max", "B_max_C_min", "B_max_C_max"]
    index = json.loads(Path(run.index).read_text())
    fitted = [w["name"] for w in index["wearers"] if "mesh" in w]
    assert list(run.cases) == ["size", *fitted] and fitted[:5] == ["centre", *corners]
    assert index["size"] == "S" and index["kind"] == "leg"
    for wearer, name in run.cases.items():
        case = plan.cases[name]
        garment = case.to_dict()["garment"]
        assert garment["reduction"] == 0.16
        assert garment["pattern"]["body"]["leg"]["size"] == "S"
        assert garment["grid"] == STOCKING["sweep"]["garment"]["grid"]
        if wearer != "size":
            assert case.body.kind == "mesh" and case.body.option("mesh").endswith(f"{wearer}.ply")


def test_a_wearers_entry_with_targets_is_one_robust_design():
    config = copy.deepcopy(STOCKING)
    config["wearers"] = {"II_M": {"material": "powernet", "body": "leg_M", "targets": ["B=23:32"]}}
    run = make_plan(config, ROOT).wearers["II_M"]
    assert run.cases == {} and run.targets == ("B=23:32",)
    assert run.start.garment.reduction == 0.2 and run.start.garment.pattern is None


@pytest.mark.parametrize(
    ("entry", "field"),
    [
        ({"material": "powernet", "body": "leg_XL", "reduction": 0.1}, "wearers.w.body"),
        ({"material": "silk", "body": "leg_S", "reduction": 0.1}, "wearers.w.material"),
        ({"material": "powernet", "body": "leg_S", "targets": ["B=32:23"]}, "wearers.w.targets.0"),
        (
            {"material": "powernet", "body": "leg_S", "reduction": 0.1, "folder": "nowhere"},
            "wearers.w.folder",
        ),
    ],
)
def test_a_bad_wearers_entry_is_refused_naming_its_key(entry, field):
    config = copy.deepcopy(STOCKING)
    config["wearers"] = {"w": entry}
    with pytest.raises(InputError) as error:
        make_plan(config, ROOT)
    assert error.value.field.startswith(field), error.value


def test_a_wearers_entry_s_variation_is_one_more_case_per_value_on_the_centre_wearer():
    config = copy.deepcopy(STOCKING)
    config["wearers"] = {
        "v": {
            "material": "powernet",
            "body": "leg_S",
            "reduction": 0.16,
            "variation": {"friction": [0.0, 0.3]},
        }
    }
    plan = make_plan(config, ROOT)
    name = plan.wearers["v"].cases["centre~mu0.3"]
    case, centre = plan.cases[name], plan.cases[plan.wearers["v"].cases["centre"]]
    assert case.contact.friction == 0.3 and not case.solver.continuation
    assert case.body.option("mesh") == centre.body.option("mesh")
    config["wearers"]["v"]["variation"] = {"tissue_modulus": [2e4]}
    with pytest.raises(InputError) as error:
        make_plan(config, ROOT)
    assert error.value.field == "wearers.v.variation.tissue_thickness"


def test_a_comparison_names_its_case_s_measurements_file():
    config = yaml.safe_load((ROOT / "config/ci.yaml").read_text())
    plan = make_plan(config, ROOT)
    assert set(plan.comparisons) == {"cone"} and "cone" in plan.cases
    assert Path(plan.comparisons["cone"]).resolve() == (ROOT / "data/measurements/example_cone.csv")


def test_a_case_on_an_analytic_body_does_not_widen_the_fitted_surface_s_region():
    from cloth.pipeline.plan import config_span

    config = yaml.safe_load((ROOT / "config/ci.yaml").read_text())
    span = config_span(config)
    assert config["cases"]["cone"]["garment"]["bottom"] < span[0]  # the cone's is lower
    config["cases"]["cone"]["body"] = {"avatar": {"size": "S"}}
    assert config_span(config)[0] == config["cases"]["cone"]["garment"]["bottom"]
