"""The wearers of a size (issue 52, items 1, 2 and 4): charts with ranges, a population's
wearers, the shipped wearers, and one garment run on every wearer."""

from __future__ import annotations

import csv
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
import xarray as xr
import yaml
from scipy.spatial import ConvexHull

from cloth.bodies.avatar import chart_targets
from cloth.bodies.leg import read_leg_chart
from cloth.bodies.torso import read_chart
from cloth.bodies.wearers import (
    MAX_CORNERS,
    population_wearers,
    range_wearers,
    weighted_quantile,
)
from cloth.errors import InputError
from cloth.files.population import read_population
from cloth.files.wearers import DEFAULT_POPULATION, SHIPPED, shipped_wearers
from cloth.io import sha256
from cloth.results.pressure import MMHG
from tests.conftest import MMHG_BY_DEFINITION
from tests.test_avatars import tape as part_tape

ROOT = Path(__file__).resolve().parents[1]
CHARTS = ROOT / "data" / "bodies"
TORSO_CHART = CHARTS / "size_chart.csv"
LEG_CHART = CHARTS / "leg_chart.csv"


def _cloth(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "cloth", *args], capture_output=True, text=True, cwd=cwd
    )


def tape(mesh: trimesh.Trimesh, z: float, near: np.ndarray | None) -> float:
    """A tape at height z: around the leg nearest ``near``, or (None, a torso with its arms
    raised) around every curve of the section: both thighs where they part below the hip."""
    if near is not None:
        return part_tape(mesh, z, near)
    section = mesh.section(plane_origin=[0, 0, z], plane_normal=[0, 0, 1])
    points = np.concatenate([curve[:, :2] for curve in section.discrete])
    hull = points[ConvexHull(points).vertices]
    return float(np.sum(np.linalg.norm(np.roll(hull, -1, axis=0) - hull, axis=1)))


# --- charts with ranges -------------------------------------------------------------------


def test_the_shipped_charts_give_their_control_girths_as_ranges_around_the_size():
    """The torso chart's bust and hip are EN 13402-3's 4 cm intervals around the size; the leg
    chart's B and C are ranges around its values; the waist stays one value."""
    torso = read_chart(TORSO_CHART)
    for size, bust, hip in (("S", 0.88, 0.96), ("M", 0.96, 1.04), ("L", 1.04, 1.12)):
        chart = torso[size]
        assert chart.girth["bust"] == pytest.approx(bust)
        assert chart.girth_range == {
            "bust": pytest.approx((bust - 0.02, bust + 0.02)),
            "hip": pytest.approx((hip - 0.02, hip + 0.02)),
        }
    leg = read_leg_chart(LEG_CHART)
    assert leg["M"].girth_range == {
        "B": pytest.approx((0.22, 0.24)),
        "C": pytest.approx((0.34, 0.38)),
    }


def _rewrite(path: Path, old: str, new: str, target: Path) -> Path:
    """``path``'s chart with the header's and every row's columns edited by ``edit``."""
    target.write_text(path.read_text().replace(old, new))
    return target


def test_a_girth_given_only_as_a_range_is_its_centre_in_both_formats(tmp_path):
    text = TORSO_CHART.read_text()
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    k = header.index("bust_cm")
    rows = [",".join(c if i != k else "" for i, c in enumerate(r.split(","))) for r in lines[1:]]
    (tmp_path / "t.csv").write_text("\n".join([lines[0], *rows]) + "\n")
    assert read_chart(tmp_path / "t.csv")["M"].girth["bust"] == pytest.approx(0.96)
    leg = LEG_CHART.read_text().replace("S,21,", "S,,")
    (tmp_path / "l.csv").write_text(leg)
    chart = read_leg_chart(tmp_path / "l.csv")["S"]
    assert chart.girth["B"] == pytest.approx(0.21) and chart.girth_range["B"] == pytest.approx(
        (0.20, 0.22)
    )


@pytest.mark.parametrize(
    ("old", "new", "field"),
    [
        (",86,90,94,98", ",86,,94,98", "bust_max_cm"),  # half a range
        (",86,90,94,98", ",90,86,94,98", "bust_min_cm"),  # min above max
        (",86,90,94,98", ",89,90,94,98", "bust_cm"),  # the value outside its range
        (",86,90,94,98", ",86,x,94,98", "bust_max_cm"),  # not a number
    ],
)
def test_a_malformed_range_is_refused_in_one_line(tmp_path, old, new, field):
    chart = _rewrite(TORSO_CHART, old, new, tmp_path / "chart.csv")
    with pytest.raises(InputError) as info:
        read_chart(chart)
    assert info.value.field == field and "size S" in str(info.value)
    done = _cloth(
        "body", "torso", "--chart", str(chart), "--size", "S", "-o", str(tmp_path / "t.ply")
    )
    out = tmp_path / "t.ply"
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
    assert field in done.stderr and "Traceback" not in done.stderr
    assert not out.exists()


# --- wearers --------------------------------------------------------------------------------


def test_the_weighted_quantile_with_equal_weights_is_hazens():
    values = np.array([3.0, 1.0, 4.0, 1.5, 9.0, 2.6, 5.0])
    for q in (0.05, 0.3, 0.5, 0.95):
        expected = np.percentile(values, 100 * q, method="hazen")
        assert weighted_quantile(values, np.ones(7), q) == pytest.approx(expected)
    # a weight of 0 leaves the value out
    assert weighted_quantile(np.array([1.0, 2.0, 100.0]), np.array([1.0, 1.0, 0.0]), 0.5) == 1.5


def test_a_populations_wearers_are_its_size_s_quantiles():
    """Five people; three have a hip in M's 102-106 cm. The centre wearer is their median in
    waist and stature, each end wearer moves one measure to its 5th / 95th percentile, and the
    unshared girths stay the chart's; her girth lines scale with her stature."""
    centre = chart_targets(TORSO_CHART, "M")
    measures = {
        "hip": np.array([1.03, 1.05, 1.10, 1.04, 0.95]),
        "waist": np.array([0.80, 0.90, 1.00, 0.95, 0.70]),
        "stature": np.array([1.60, 1.70, 1.65, 1.50, 1.60]),
    }
    wearers = population_wearers(centre, centre.ranges, measures, np.ones(5))
    assert wearers.people == 3 and wearers.weight == 3.0
    assert [w.name for w in wearers.wearers] == [
        "centre",
        "hip_p5",
        "hip_p95",
        "waist_p5",
        "waist_p95",
        "stature_p5",
        "stature_p95",
        "centre_muscle_min",
        "centre_muscle_max",
        "centre_proportions_min",
        "centre_proportions_max",
    ]
    middle = wearers.wearers[0].targets
    assert middle.girth["waist"] == pytest.approx(0.90) and middle.girth["hip"] == pytest.approx(
        1.04
    )
    assert middle.stature == pytest.approx(1.60)
    assert middle.girth["bust"] == pytest.approx(0.96)  # the chart's: not in the population
    assert middle.height["waist"] == pytest.approx(1.04 * 1.60 / 1.68)
    low = wearers.wearers[3].targets
    assert low.girth["waist"] == pytest.approx(np.percentile([0.80, 0.90, 0.95], 5, method="hazen"))
    assert low.stature == pytest.approx(1.60)
    # with three people Hazen's 5th and 95th percentiles are the extremes: all are covered
    assert wearers.coverage == pytest.approx(1.0)


def test_the_coverage_is_the_share_inside_every_measure_s_range():
    rng = np.random.default_rng(7)
    centre = chart_targets(TORSO_CHART, "M")
    measures = {
        "hip": rng.uniform(1.02, 1.06, 400),
        "waist": rng.normal(0.90, 0.06, 400),
        "stature": rng.normal(1.63, 0.07, 400),
    }
    wearers = population_wearers(centre, centre.ranges, measures, np.ones(400))
    inside = np.ones(400, dtype=bool)
    for values in measures.values():
        low, high = np.percentile(values, [5, 95], method="hazen")
        inside &= (values >= low) & (values <= high)
    assert wearers.coverage == pytest.approx(inside.mean())
    assert 0.7 < wearers.coverage < 0.9  # about 0.9 cubed


def test_a_chart_s_ranges_give_their_corners_and_centre():
    centre = chart_targets(LEG_CHART, "M")
    wearers = range_wearers(centre, centre.ranges)
    assert len(wearers.wearers) == 1 + 2**2 + 4  # the centre, the corners, the shapes
    corners = {w.name: (w.targets.girth["B"], w.targets.girth["C"]) for w in wearers.wearers}
    assert corners["B_min_C_max"] == pytest.approx((0.22, 0.38))
    assert corners["centre"] == pytest.approx((0.23, 0.36))
    many = {n: (0.9 * g, 1.1 * g) for n, g in centre.girth.items()}
    sampled = range_wearers(centre, many)
    assert len(sampled.wearers) == 1 + MAX_CORNERS + 4
    for wearer in sampled.wearers[1 : 1 + MAX_CORNERS]:
        for name, (low, high) in many.items():
            assert low <= wearer.targets.girth[name] <= high


def test_the_shape_wearers_pin_the_body_model_s_extremes_at_the_centre_s_girths():
    centre = chart_targets(LEG_CHART, "S")
    shapes = range_wearers(centre, centre.ranges).wearers[-4:]
    assert [w.name for w in shapes] == [
        "centre_muscle_min",
        "centre_muscle_max",
        "centre_proportions_min",
        "centre_proportions_max",
    ]
    assert [w.targets.pinned for w in shapes] == [
        {"muscle": 0.0},
        {"muscle": 1.0},
        {"proportions": 0.0},
        {"proportions": 1.0},
    ]
    for wearer in shapes:
        assert wearer.targets.girth == centre.girth and wearer.targets.stature == centre.stature


POPULATIONS = {
    "no_measure": ("seqn,age_years,exam_weight\n1,30,100\n", "header"),
    "millimetres": ("waist_cm,hip_cm,height_cm\n800,1040,1630\n", "waist_cm"),
    "nobody_in_size": ("waist_cm,hip_cm,height_cm\n80,90,163\n", "hip_cm"),
    "not_a_number": ("waist_cm,hip_cm,height_cm\n80,abc,163\n", "hip_cm"),
    "no_shared_range": ("waist_cm,height_cm\n80,163\n", "hip_cm"),
}


@pytest.mark.parametrize("name", sorted(POPULATIONS))
def test_a_malformed_population_is_refused_in_one_line(tmp_path, name):
    text, column = POPULATIONS[name]
    (tmp_path / "people.csv").write_text(text)
    out = tmp_path / "out"
    done = _cloth(
        "body",
        "wearers",
        str(TORSO_CHART),
        "--size",
        "M",
        "--population",
        str(tmp_path / "people.csv"),
        "-o",
        str(out),
    )
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "people.csv" in lines[0] and column in lines[0], lines
    assert not out.exists()


def test_the_shipped_survey_holds_the_sizes_people():
    """The size's people counted here with numpy from the shipped survey: women aged 18-45,
    not pregnant, hip within the size's 4 cm range; their weighted median waist."""
    rows = [
        r
        for r in csv.DictReader(
            line for line in DEFAULT_POPULATION.open() if not line.startswith("#")
        )
    ]
    age = np.array([float(r["age_years"]) for r in rows])
    hip = np.array([float(r["hip_cm"]) for r in rows])
    waist = np.array([float(r["waist_cm"]) for r in rows])
    keep = (age >= 18) & (age <= 45) & np.array([r["pregnant"] != "1" for r in rows])
    in_m = keep & (hip >= 102) & (hip <= 106)
    people = read_population(DEFAULT_POPULATION)
    centre = chart_targets(TORSO_CHART, "M")
    wearers = population_wearers(centre, centre.ranges, people.measures, people.weight)
    assert wearers.people == int(in_m.sum())
    assert 150 <= wearers.people <= 300  # the 221 within 2 cm, from the same survey
    w = np.array([float(r["exam_weight"]) for r in rows])[in_m]
    order = np.argsort(waist[in_m])
    cumulative = np.cumsum(w[order]) - 0.5 * w[order]
    expected = np.interp(0.5 * w.sum(), cumulative, waist[in_m][order]) / 100
    assert wearers.wearers[0].targets.girth["waist"] == pytest.approx(expected)
    assert 0.88 <= expected <= 0.93  # the 90.6 cm


# --- the shipped wearers ----------------------------------------------------------------------

INDICES = sorted(SHIPPED.glob("*/wearers.json"))


def test_the_default_charts_ship_their_wearers():
    names = sorted(p.parent.name for p in INDICES)
    assert names == [f"{k}_{s}" for k in ("leg", "torso") for s in ("L", "M", "S")]
    for size in ("S", "M", "L"):
        assert shipped_wearers(TORSO_CHART, size, DEFAULT_POPULATION) is not None
        assert shipped_wearers(LEG_CHART, size) is not None


@pytest.mark.parametrize("index", INDICES, ids=lambda p: p.parent.name)
def test_every_shipped_wearer_measures_her_targets(index):
    """Each fitted wearer's mesh, measured here with trimesh's sections at her heights, has her
    girths within 2 mm; her index belongs to the chart and population as shipped."""
    record = json.loads(index.read_text())
    assert record["chart_sha256"] == sha256(CHARTS / record["chart"])
    if record["population"] is not None:
        assert record["population_sha256"] == sha256(DEFAULT_POPULATION)
    fitted = [w for w in record["wearers"] if "mesh" in w]
    assert fitted and fitted[0]["name"] == "centre"
    for wearer in fitted:
        mesh = trimesh.load(index.parent / wearer["mesh"], process=False)
        assert mesh.is_watertight
        side = json.loads((index.parent / wearer["mesh"]).with_suffix(".json").read_text())
        near = np.array(side["loop_point_m"]) if record["kind"] == "leg" else None
        for name, target in wearer["girths_m"].items():
            measured = tape(mesh, wearer["heights_m"][name], near)
            assert abs(measured - target) <= 2e-3, (wearer["name"], name, measured, target)
        assert side["landmarks"] == pytest.approx(wearer["heights_m"])


# --- one garment on every wearer -----------------------------------------------------------


@pytest.fixture(scope="module")
def leg_wearers(tmp_path_factory):
    """A stocking cut for the chart's leg S on two of its shipped wearers (a small grid)."""
    root = tmp_path_factory.mktemp("wearers")
    source = SHIPPED / "leg_S"
    folder = root / "two"
    folder.mkdir()
    record = json.loads((source / "wearers.json").read_text())
    record["wearers"] = [w for w in record["wearers"] if w["name"] in ("centre", "B_max_C_min")]
    for wearer in record["wearers"]:
        for suffix in (".ply", ".json"):
            shutil.copy(source / (wearer["name"] + suffix), folder)
    (folder / "wearers.json").write_text(json.dumps(record))
    case = {
        "material": "powernet",
        "body": {"leg": {"size": "S"}},
        "garment": {
            "bottom": 0.09,
            "top": 0.5,
            "reduction": 0.16,
            "lengthwise_reduction": 0.15,
            "grid": [12, 14],
            "error_estimate": False,
        },
        "judge": {"bands": [{"name": "target", "low_mmHg": 20, "high_mmHg": 30}]},
        "solver": {"tolerance": 1e-8, "max_iterations": 150},
    }
    (root / "case.yaml").write_text(yaml.safe_dump(case))
    done = _cloth(
        "wearers", str(root / "case.yaml"), "--wearers", str(folder), "-o", str(root / "out")
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return root


@pytest.mark.slow
def test_each_wearers_pressures_are_a_direct_run_of_her_case_bit_for_bit(leg_wearers):
    root = leg_wearers
    with xr.open_dataset(root / "out" / "wearers.nc") as ds:
        table = ds.load()
    assert [str(n) for n in table["wearer"].values] == ["size", "centre", "B_max_C_min"]
    done = _cloth(
        "run", str(root / "out" / "B_max_C_min" / "case.yaml"), "-o", str(root / "direct")
    )
    assert done.returncode == 0, done.stderr[-2000:]
    with xr.open_dataset(root / "direct" / "result.nc") as direct:
        for line in table["landmark"].values:
            if line in direct["landmark"].values:
                got = float(table["pressure_mean"].sel(wearer="B_max_C_min", landmark=line))
                assert got == float(direct["pressure_mean"].sel(landmark=line)), line


#: RAL-GZ 387/1's classes at B, by hand (mmHg).
RAL = {"I": (18, 21), "II": (23, 32), "III": (34, 46), "IV": (49, math.inf)}


def grade(mmhg: float) -> str:
    """The class of a pressure at B, or '-' between and below the classes."""
    return next((k for k, (lo, hi) in RAL.items() if lo <= mmhg <= hi), "-")


@pytest.mark.slow
def test_wearers_csv_is_the_range_of_wearers_nc(leg_wearers):
    """wearers.csv's min, centre and max per line, in mmHg, are the wearers' values in
    wearers.nc (Pa) read independently, and name the wearer of each extreme."""
    root = leg_wearers
    with xr.open_dataset(root / "out" / "wearers.nc") as ds:
        p = ds["pressure_mean"].load()
    rows = list(csv.DictReader((root / "out" / "wearers.csv").open()))
    assert rows and rows[0].keys() >= {
        "pressure_min_mmHg",
        "max_wearer",
        "discretisation_error_mmHg",
    }
    for row in rows:
        values = {
            w: float(p.sel(wearer=w, landmark=row["landmark"])) / MMHG
            for w in ("centre", "B_max_C_min")
        }
        assert float(row["pressure_min_mmHg"]) == pytest.approx(min(values.values()), abs=1e-4)
        assert float(row["pressure_max_mmHg"]) == pytest.approx(max(values.values()), abs=1e-4)
        assert float(row["pressure_centre_mmHg"]) == pytest.approx(values["centre"], abs=1e-4)
        assert row["max_wearer"] == max(values, key=values.get)
        assert row["min_wearer"] == min(values, key=values.get) and row["wearers"] == "2"
        spread = max(values.values()) - min(values.values())
        assert float(row["spread_mmHg"]) == pytest.approx(spread, abs=2e-4)
        if row["landmark"] == "B":
            assert row["class_min"] == grade(min(values.values()))
            assert row["class_max"] == grade(max(values.values()))
        else:
            assert row["class_min"] == row["class_max"] == ""
        inside = all(20 <= v <= 30 for v in values.values())  # the case's band "target"
        assert row["bands_every_wearer"] == ("target" if inside else "-")
        size = float(p.sel(wearer="size", landmark=row["landmark"])) / MMHG
        assert float(row["size_body_mmHg"]) == pytest.approx(size, abs=1e-4)
    assert (root / "out" / "wearers.png").stat().st_size > 10_000
    assert (root / "out" / "size" / "summary.csv").is_file()


def test_a_body_without_a_size_has_no_wearers(tmp_path):
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [12, 6]},
    }
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    done = _cloth("wearers", str(tmp_path / "case.yaml"), "-o", str(tmp_path / "out"))
    assert done.returncode == 2 and "no size" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not (tmp_path / "out").exists()


def test_the_variation_runs_each_value_on_the_centre_wearer_once():
    """friction [0, 0.4], tissue [2e4] and worn [false, true] on a frictionless, rigid, new
    case: three runs of the centre wearer, each with its one setting, the solver's path
    defaults left to the skin (friction needs the path from the wrap)."""
    from cloth.case import Case
    from cloth.pipeline.variants import variation_cases

    data = {
        "material": "powernet",
        "body": {"leg": {"size": "S"}},
        "garment": {"bottom": 0.09, "top": 0.5, "reduction": 0.16, "grid": [12, 14]},
        "solver": {"continuation": True, "reuse": True},
        "variation": {
            "friction": [0.0, 0.4],
            "tissue_modulus": [2e4],
            "tissue_thickness": 0.01,
            "worn": [False, True],
        },
    }
    centre = {**data, "body": {"mesh": "centre.ply"}}
    runs = variation_cases(data, centre, "centre")
    assert sorted(runs) == ["centre~mu0.4", "centre~tissue20000", "centre~worn"]
    assert runs["centre~mu0.4"]["contact"]["friction"] == 0.4
    assert runs["centre~tissue20000"]["body"]["tissue"] == {"thickness": 0.01, "modulus": 2e4}
    assert runs["centre~worn"]["garment"]["worn"] is True
    for block in runs.values():
        assert "continuation" not in block["solver"] and block["body"]["mesh"] == "centre.ply"
    assert (
        Case.from_dict({**runs["centre~mu0.4"], "body": data["body"]}).solver.continuation is False
    )
    with pytest.raises(InputError, match="tissue_thickness"):
        variation_cases({**data, "variation": {"tissue_modulus": [2e4]}}, centre, "centre")


# --- robust design ----------------------------------------------------------------------------


def test_the_min_max_step_of_a_linear_model_is_its_exact_optimum():
    """Two wearers 10 mmHg apart, each p = a + 100 theta (mmHg), band 25-35: the min-max puts
    them at 25 and 35 (theta 0.15, t = 1) in one step from 0.12."""
    from cloth.stages.robust import measure, minmax_step

    means = np.array([[10.0 + 12.0], [20.0 + 12.0]]) * MMHG
    jacobians = np.array([[[100.0]], [[100.0]]]) * MMHG
    bands = np.array([[25.0, 35.0]]) * MMHG
    step, t = minmax_step(means, jacobians, bands, np.array([0.12]), np.array([0.6]))
    assert step == pytest.approx([0.03], abs=1e-9) and t == pytest.approx(1.0, abs=1e-9)
    assert measure(means + jacobians[:, :, 0] * step[0], bands) == pytest.approx(1.0)


def test_a_band_target_is_parsed_in_its_unit():
    from cloth.results.targets import Target

    target = Target.parse("B=23:32")
    assert target.band == pytest.approx((23 * MMHG, 32 * MMHG))
    assert target.pressure == pytest.approx(27.5 * MMHG)
    assert Target.parse("B=3:4kPa").band == pytest.approx((3000.0, 4000.0))
    for bad in ("B=32:23", "B=0:10", "B=x:3"):
        with pytest.raises(InputError):
            Target.parse(bad)


def test_a_band_without_wearers_is_refused_in_one_line(tmp_path):
    case = {
        "material": "powernet",
        "body": {"leg": {"size": "S"}},
        "garment": {"bottom": 0.09, "top": 0.5, "reduction": 0.16, "grid": [12, 14]},
    }
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    out = tmp_path / "x"
    done = _cloth("design", str(tmp_path / "case.yaml"), "--target", "B=23:32", "-o", str(out))
    assert done.returncode == 2 and "--wearers" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not out.exists()


def _robust(root: Path, band: str, out: str) -> subprocess.CompletedProcess:
    case, wearers = str(root / "case.yaml"), str(root / "two")
    command = ["--log-level", "ERROR", "design", case, "--wearers", wearers, "--target", band]
    return _cloth(*command, "-o", str(root / out))


@pytest.mark.slow
def test_the_robust_design_puts_every_wearer_in_the_band_from_scratch(leg_wearers):
    """robust.csv says met, and every wearer's confirmed B, read from her own run's result.nc,
    is inside 15-45 mmHg; the designed case is the size's body with the profile."""
    root = leg_wearers
    done = _robust(root, "B=15:45", "robust")
    assert done.returncode == 0, done.stderr[-2000:]
    (row,) = list(csv.DictReader((root / "robust" / "robust.csv").open()))
    assert row["landmark"] == "B" and row["met"] == "1" and float(row["t"]) <= 1.0
    assert row["shortfall"] == ""
    values = []
    for name in ("centre", "B_max_C_min"):
        with xr.open_dataset(root / "robust" / "confirmed" / name / "result.nc") as ds:
            values.append(float(ds["pressure_mean"].sel(landmark="B")) / MMHG)
    assert all(15 <= v <= 45 for v in values)
    assert float(row["confirmed_min_mmHg"]) == pytest.approx(min(values), abs=1e-4)
    assert float(row["confirmed_max_mmHg"]) == pytest.approx(max(values), abs=1e-4)
    designed = yaml.safe_load((root / "robust" / "case.yaml").read_text())
    assert designed["body"]["leg"]["size"] == "S" and "B" in designed["garment"]["reduction"]


@pytest.mark.slow
def test_a_band_no_profile_can_hold_is_refused_naming_the_line_and_wearers(leg_wearers):
    root = leg_wearers
    done = _robust(root, "B=27:28", "narrow")
    assert done.returncode == 2
    line = done.stderr.strip().splitlines()
    assert len(line) == 1 and "B:" in line[0] and "narrowest band" in line[0], line
    assert "centre" in line[0] and "B_max_C_min" in line[0]
    (row,) = list(csv.DictReader((root / "narrow" / "robust.csv").open()))
    assert row["met"] == "0" and float(row["spread_mmHg"]) > 1.0 and row["shortfall"]


@pytest.mark.slow
def test_the_pipeline_runs_a_job_per_wearer_and_gathers_them(tmp_path):
    """A config's wearers entry: one relax job per wearer and one for the size's body, and
    wearers.nc's values are each case's own result.nc, bit for bit."""
    config = {
        "materials": {"powernet": {"table": str(ROOT / "data/materials/powernet.csv"), "knots": 6}},
        "bodies": {"leg_S": {"leg": {"size": "S"}}},
        "sweep": {
            "materials": ["powernet"],
            "bodies": ["leg_S"],
            "reductions": [0.16],
            "garment": {
                "bottom": 0.09,
                "top": 0.5,
                "grid": [12, 14],
                "lengthwise_reduction": 0.15,
                "error_estimate": False,
            },
            "solver": {"method": "newton", "tolerance": 1e-8, "max_iterations": 150},
        },
        "wearers": {"S": {"material": "powernet", "body": "leg_S", "reduction": 0.16}},
        "results": str(tmp_path / "results"),
    }
    (tmp_path / "config.yaml").write_text(yaml.safe_dump(config))
    target = tmp_path / "results" / "wearers" / "S" / "wearers.csv"
    done = subprocess.run(
        [
            str(Path(sys.executable).parent / "snakemake"),
            str(target),
            "-s",
            str(ROOT / "Snakefile"),
            "--cores",
            "2",
            "--configfile",
            str(tmp_path / "config.yaml"),
        ],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={
            **os.environ,
            "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
        },
    )
    assert done.returncode == 0, done.stderr[-3000:]
    index = json.loads((SHIPPED / "leg_S" / "wearers.json").read_text())
    fitted = [w["name"] for w in index["wearers"] if "mesh" in w]
    relaxed = done.stderr.count("rule relax:") + done.stdout.count("rule relax:")
    assert relaxed == len(fitted) + 1
    with xr.open_dataset(target.with_suffix(".nc")) as ds:
        table = ds.load()
    assert [str(n) for n in table["wearer"].values] == ["size", *fitted]
    for name in ["size", *fitted]:
        case = tmp_path / "results" / "cases" / f"wearers__S__{name}" / "result.nc"
        with xr.open_dataset(case) as own:
            mine = own["pressure_mean"].load()
        for line in mine["landmark"].values:
            assert float(table["pressure_mean"].sel(wearer=name, landmark=line)) == float(
                mine.sel(landmark=line)
            )


def _line_result(path: Path, means: dict[str, float], errors: dict[str, float]) -> Path:
    """A result.nc reduced to what wearers.nc reads: per girth line the mean and its error."""
    lines = list(means)
    xr.Dataset(
        {
            "pressure_mean": ("landmark", [means[k] for k in lines]),
            "pressure_mean_error": ("landmark", [errors[k] for k in lines]),
        },
        coords={"landmark": lines},
    ).to_netcdf(path)
    return path


def test_every_column_of_wearers_nc_and_wearers_csv_by_hand(tmp_path):
    """Three wearers and the size's body with known means and errors (one wearer misses the
    top line): wearers.nc holds them and the index's statures, wearers.csv each line's range,
    who gives it, the size's value and the largest stated error, in mmHg."""
    from cloth.stages.wearers import collect, write_table

    mm = MMHG_BY_DEFINITION
    means = {
        "size": {"B": 20 * mm, "C": 15 * mm},
        "centre": {"B": 22 * mm, "C": 16 * mm},
        "wide": {"B": 18 * mm, "C": 17 * mm},
        "tall": {"B": 25 * mm},
    }
    errors = {
        "size": {"B": 0.1 * mm, "C": 0.2 * mm},
        "centre": {"B": 0.3 * mm, "C": float("nan")},
        "wide": {"B": 0.5 * mm, "C": 0.4 * mm},
        "tall": {"B": 0.2 * mm},
    }
    paths = {n: _line_result(tmp_path / f"{n}.nc", means[n], errors[n]) for n in means}
    index = {
        "size": "M",
        "wearers": [
            {"name": "centre", "stature_m": 1.65},
            {"name": "wide", "stature_m": 1.60},
            {"name": "tall", "stature_m": 1.75},
        ],
    }
    ds = collect(paths, index)
    assert ds["wearer"].values.tolist() == ["size", "centre", "wide", "tall"]
    assert ds["landmark"].values.tolist() == ["B", "C"]
    assert ds["pressure_mean"].attrs["units"] == "Pa" and ds["stature"].attrs["units"] == "m"
    np.testing.assert_array_equal(ds["stature"].values, [np.nan, 1.65, 1.60, 1.75])
    assert float(ds["pressure_mean"].sel(wearer="wide", landmark="C")) == 17 * mm
    assert np.isnan(float(ds["pressure_mean"].sel(wearer="tall", landmark="C")))
    assert float(ds["pressure_mean_error"].sel(wearer="wide", landmark="B")) == 0.5 * mm
    write_table(ds, tmp_path / "wearers.csv")
    with open(tmp_path / "wearers.csv", newline="") as handle:
        rows = {row["landmark"]: row for row in csv.DictReader(handle)}
    expected = {
        "B": {
            "wearers": "3",
            "pressure_min_mmHg": 18.0,
            "min_wearer": "wide",
            "pressure_centre_mmHg": 22.0,
            "pressure_max_mmHg": 25.0,
            "max_wearer": "tall",
            "spread_mmHg": 7.0,
            "size_body_mmHg": 20.0,
            "discretisation_error_mmHg": 0.5,
        },
        "C": {
            "wearers": "2",
            "pressure_min_mmHg": 16.0,
            "min_wearer": "centre",
            "pressure_centre_mmHg": 16.0,
            "pressure_max_mmHg": 17.0,
            "max_wearer": "wide",
            "spread_mmHg": 1.0,
            "size_body_mmHg": 15.0,
            "discretisation_error_mmHg": 0.4,
        },
    }
    for line, want in expected.items():
        for column, value in want.items():
            got = rows[line][column]
            assert (
                (float(got) == pytest.approx(value, abs=1e-4))
                if isinstance(value, float)
                else got == value
            ), (line, column)
        # without a judge there is no class and no band
        assert rows[line]["class_min"] == rows[line]["class_max"] == ""
        assert rows[line]["bands_every_wearer"] == ""


def test_every_column_of_robust_csv_by_hand():
    """A robust design with known bands, loop means and confirmed means: each robust.csv
    column in mmHg, met only where every wearer lies inside the band, the wearers counted
    without the size's body and every wearer's confirmation counted as an equilibrium."""
    from cloth.stages.robust import Robust
    from cloth.stages.wearerdesign import robust_rows

    mm = MMHG_BY_DEFINITION
    result = Robust(
        knots=("B", "C"),
        values=np.array([0.21, 0.155]),
        lines=("B", "C"),
        bands=np.array([[23.0, 32.0], [15.0, 20.0]]) * mm,
        wearers=("centre", "wide"),
        means=np.array([[24.0, 16.0], [30.0, 21.0]]) * mm,
        t=0.75,
        rounds=3,
        solves=9,
    )
    confirmed = xr.Dataset(
        {
            "pressure_mean": (
                ("wearer", "landmark"),
                np.array([[27.0, 18.0], [24.5, 16.0], [31.0, 20.5]]) * mm,
            ),
            "pressure_mean_error": (
                ("wearer", "landmark"),
                np.array([[0.9, 0.9], [0.2, np.nan], [0.3, 0.1]]) * mm,
            ),
        },
        coords={"wearer": ["size", "centre", "wide"], "landmark": ["B", "C"]},
    )
    rows = robust_rows(result, confirmed)
    expected = [
        {
            "landmark": "B",
            "band_low_mmHg": 23.0,
            "band_high_mmHg": 32.0,
            "loop_min_mmHg": 24.0,
            "loop_max_mmHg": 30.0,
            "confirmed_min_mmHg": 24.5,
            "min_wearer": "centre",
            "confirmed_max_mmHg": 31.0,
            "max_wearer": "wide",
            "spread_mmHg": 6.5,
            "discretisation_error_mmHg": 0.3,
            "met": 1,
            "t": 0.75,
            "reduction": "B=0.21000 C=0.15500",
            "wearers": 2,
            "equilibria": 11,
        },
        {
            "landmark": "C",
            "band_low_mmHg": 15.0,
            "band_high_mmHg": 20.0,
            "loop_min_mmHg": 16.0,
            "loop_max_mmHg": 21.0,
            "confirmed_min_mmHg": 16.0,
            "min_wearer": "centre",
            "confirmed_max_mmHg": 20.5,
            "max_wearer": "wide",
            "spread_mmHg": 4.5,
            "discretisation_error_mmHg": 0.1,
            "met": 0,  # the wide wearer reads 20.5 mmHg, above the band's 20
            "t": 0.75,
            "reduction": "B=0.21000 C=0.15500",
            "wearers": 2,
            "equilibria": 11,
        },
    ]
    assert len(rows) == 2
    for row, want in zip(rows, expected, strict=True):
        assert set(row) == set(want)
        for column, value in want.items():
            if isinstance(value, float):
                assert row[column] == pytest.approx(value, abs=1e-4), column
            else:
                assert row[column] == value, column
