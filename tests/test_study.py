"""``cloth compare STUDY.yaml``: one pattern on several subjects, each compared with her own
readings; on cylinders every probe reads Laplace's T / R of its subject."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.cli import main
from cloth.results.pressure import MMHG

CYLINDER = {"bottom": 0.0, "top": 0.5}
CASE = {
    "material": "powernet",
    "body": {"cylinder": {"radius": 0.1, **CYLINDER}},
    "garment": {
        "bottom": 0.1,
        "top": 0.4,
        "reduction": 0.2,
        "grid": [24, 6],
        "pattern": {"body": {"cylinder": {"radius": 0.1, **CYLINDER}}},
    },
    "landmarks": {"mid": 0.25},
}
RADII = {"ann": 0.095, "bea": 0.105}
READINGS = {
    "ann": "point,height_m,angle_deg,pressure_mmHg,probe_mm\nmid,,0,14,50\n,0.2,90,16,50\n",
    "bea": "point,height_m,angle_deg,pressure_mmHg,probe_mm\n,0.3,180,25,50\nmid,,-90,27,50\n",
}


def read_rows(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


def write_study(folder, subjects=None, case=None):
    (folder / "case.yaml").write_text(yaml.safe_dump(case or CASE))
    for name, text in READINGS.items():
        (folder / f"{name}.csv").write_text(text)
    subjects = subjects or [
        {
            "name": name,
            "body": {"cylinder": {"radius": radius, **CYLINDER}},
            "measurements": f"{name}.csv",
        }
        for name, radius in RADII.items()
    ]
    path = folder / "study.yaml"
    path.write_text(yaml.safe_dump({"case": "case.yaml", "subjects": subjects}))
    return path


def test_a_study_compares_one_pattern_on_each_subject_and_pools_the_rows(tmp_path):
    out = tmp_path / "out"
    assert (
        main(["--log-level", "WARNING", "compare", str(write_study(tmp_path)), "-o", str(out)]) == 0
    )
    rows = read_rows(out / "compare.csv")
    assert [r["subject"] for r in rows] == ["ann", "ann", "bea", "bea"]
    for name, radius in RADII.items():
        with xr.open_dataset(out / name / "result.nc") as ds:
            laplace = float(ds["tension_mean"].sel(landmark="mid")) / radius / MMHG
        for row in (r for r in rows if r["subject"] == name):
            assert float(row["model_mmHg"]) == pytest.approx(laplace, rel=0.01)
    model = np.array([float(r["model_mmHg"]) for r in rows])
    assert model[2] > model[0]  # one pattern: the larger leg stretches it more
    groups = {r["subject"]: r for r in read_rows(out / "agreement.csv")}
    assert list(groups) == ["ann", "bea", "all"]
    measured = np.array([14.0, 16.0, 25.0, 27.0])
    for name, keep in (("ann", slice(0, 2)), ("bea", slice(2, 4)), ("all", slice(0, 4))):
        d = model[keep] - measured[keep]
        assert int(groups[name]["places"]) == d.size
        assert float(groups[name]["bias_mmHg"]) == pytest.approx(d.mean(), abs=2e-4)
        assert float(groups[name]["rmse_mmHg"]) == pytest.approx(
            math.sqrt(np.mean(d * d)), abs=2e-4
        )
    r = np.corrcoef(model, measured)[0, 1]
    assert float(groups["all"]["r"]) == pytest.approx(r, abs=1e-4)
    assert groups["ann"]["r"] == ""  # two places: no correlation


@pytest.mark.parametrize(
    ("change", "where"),
    [
        ({"subjects": [{"name": "ann", "body": {"cylinder": {"radius": 0.1}}}]}, "subjects[0]"),
        (
            {
                "subjects": [
                    {
                        "name": "ann",
                        "body": {"cylinder": {"radius": 0.1}},
                        "measurements": "ann.csv",
                    },
                    {
                        "name": "ann",
                        "body": {"cylinder": {"radius": 0.1}},
                        "measurements": "bea.csv",
                    },
                ]
            },
            "subjects[1].name",
        ),
        (
            {
                "subjects": [
                    {"name": "ann", "body": {"cylinder": {"radius": 0.1}}, "measurements": "no.csv"}
                ]
            },
            "no.csv",
        ),
        (
            {
                "subjects": [
                    {"name": "ann", "body": {"cylinder": {"radius": -1}}, "measurements": "ann.csv"}
                ]
            },
            "subjects[0]",
        ),
        ({"case": {**CASE, "garment": {**CASE["garment"], "pattern": None}}}, "garment.pattern"),
        (  # her chart is read as her case runs: the study's folder is not left half-written
            {
                "subjects": [
                    {
                        "name": "ann",
                        "body": {"cylinder": {"radius": 0.1}},
                        "measurements": "ann.csv",
                    },
                    {
                        "name": "bea",
                        "body": {"leg": {"chart": "bea_chart.csv", "size": "bea"}},
                        "measurements": "bea.csv",
                    },
                ]
            },
            "subjects[1].body",
        ),
    ],
)
def test_a_bad_study_is_one_line_and_exit_2_with_nothing_written(tmp_path, capsys, change, where):
    case = change.get("case")
    if case is not None:
        case = {**case, "garment": {k: v for k, v in case["garment"].items() if v is not None}}
    (tmp_path / "bea_chart.csv").write_text("size,B_cm,B_height_cm\nbea,22,11\n")
    path = write_study(tmp_path, change.get("subjects"), case)
    out = tmp_path / "out"
    assert main(["compare", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and where in err[0], err
    assert not out.exists() and not list(tmp_path.glob(".out.*"))
