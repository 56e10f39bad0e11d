"""Sizes that fit (issue 62): the fast model, the chart's search worked out by hand on
cylinders, the population's columns and refusals, a person as a body, and the command's bad
input."""

from __future__ import annotations

import csv
import importlib.util
import itertools
import json
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

from cloth.bodies.avatar import chart_targets
from cloth.bodies.person import person_body, template_girths
from cloth.files.population import read_population
from cloth.results.fabricneed import linear_modulus, requirement
from cloth.results.pressure import MMHG
from cloth.results.sizechart import (
    Band,
    People,
    centred_rest,
    design_chart,
    span,
    stabbing_rest,
)
from cloth.results.tubemodel import Calibration, LineModel, Tension, laplace
from tests import inventory
from tests.test_fuzz import run_cloth

ROOT = Path(__file__).resolve().parents[1]
ANSUR = ROOT / "data" / "bodies" / "population" / "ansur2_women.csv"
LEG_CHART = ROOT / "data" / "bodies" / "leg_chart.csv"
BAND = Band("B", 23 * MMHG, 32 * MMHG)
#: a fabric linear through zero whose size from 20 cm ends at 21 cm (Laplace on a cylinder):
#: 1/b = 1/a - (high - low) / (2 pi E) with (high - low) / (2 pi E) = 1/0.20 - 1/0.21 = 5/21
E = (BAND.high - BAND.low) * 21 / (2 * np.pi * 5)
LINEAR = LineModel(Tension(np.array([0.0, 1.0]), np.array([0.0, E])), Calibration.exact())


def edge(k: int) -> float:
    """The k-th edge of the chain from 20 cm, by hand: 1/a_k = 5 - 5k/21, a_k = 21/(105 - 5k)."""
    return 21.0 / (105.0 - 5.0 * k)


# --- the fast model -----------------------------------------------------------------------------


def test_the_tension_s_inverse_is_exact_on_and_past_the_knots():
    tension = Tension(np.array([0.0, 0.1, 0.3, 0.6]), np.array([0.0, 20.0, 90.0, 300.0]))
    strain = np.array([0.0, 0.05, 0.1, 0.2, 0.45, 0.6, 0.9])
    assert np.allclose(tension.strain_at(tension(strain)), strain, rtol=0, atol=1e-12)
    # past the last knot the last slope: 300 + 700 x 0.3 at 0.9
    assert tension(np.array([0.9]))[0] == pytest.approx(300 + (210 / 0.3) * 0.3)


def test_laplace_on_a_cylinder_is_t_over_r():
    g, c0 = 0.22, 0.19
    e = g / c0 - 1
    expected = E * e / (g / (2 * np.pi))
    assert float(laplace(LINEAR.tension, g, c0)) == pytest.approx(expected, rel=1e-12)
    assert float(LINEAR.rest_for(g, expected)) == pytest.approx(c0, rel=1e-12)


def test_the_calibration_recovers_a_known_shape_term_from_many_equilibria():
    rng = np.random.default_rng(3)
    weft = rng.uniform(2500, 5000, 60)
    features = rng.normal(size=(60, 2))
    pressure = 0.9 * weft + 400 - 300 * features[:, 0] + 150 * features[:, 1]
    fit = Calibration.fit(weft, features, pressure)
    assert fit.hoop == pytest.approx(0.9, rel=0.01)
    assert fit.shape == pytest.approx([400, -300, 150], rel=0.05, abs=20)
    assert Calibration.fit([], np.zeros((0, 2)), []).hoop == 1.0


# --- the chart, worked out by hand on cylinders ---------------------------------------------------


def test_a_size_from_a_girth_ends_where_the_hand_formula_says():
    start = np.array([0.20, 0.21, 0.23])
    expected = 1 / (1 / start - 5 / 21)
    assert np.allclose(span(LINEAR, BAND, start), expected, rtol=1e-12)


def test_the_chart_s_sizes_counts_and_coverage_are_the_hand_values():
    # 70 people evenly over 20-23.5 cm and one at 30 cm; all must fit: 4 sizes reach 21/85 m
    girth = np.concatenate([np.linspace(0.20, 0.235, 70), [0.30]])
    people = People({"B": girth}, {"B": np.zeros_like(girth)}, np.ones_like(girth))
    chart = design_chart(people, ("B",), {"B": LINEAR}, {"B": BAND}, 70 / 71, 6)
    assert len(chart.sizes) == 4
    for k, size in enumerate(chart.sizes):
        assert size.ranges["B"][0] == pytest.approx(edge(k), rel=1e-9)
        assert size.ranges["B"][1] == pytest.approx(edge(k + 1), rel=1e-9)
        low, high = edge(k), edge(k + 1)
        inside = (girth >= low) & (girth <= high)
        if k:  # a person on a shared edge belongs to the lower size
            inside &= girth > low
        assert len(size.members) == int(inside.sum())
        assert size.fits.all()
    assert chart.coverage == pytest.approx(70 / 71)
    assert chart.met
    # one more size is not enough for the woman at 30 cm: the most sizes cover the most
    whole = design_chart(people, ("B",), {"B": LINEAR}, {"B": BAND}, 1.0, 5)
    assert len(whole.sizes) == 5 and whole.coverage == pytest.approx(70 / 71)
    assert not whole.met


def test_a_person_exactly_at_a_band_s_edge_is_inside():
    # a size saturated from 20 cm: its rest gives exactly 23 mmHg at 20 cm, 32 at 21 cm
    girth = np.array([0.20, 0.205, 0.21])
    people = People({"B": girth}, {"B": np.zeros(3)}, np.ones(3))
    chart = design_chart(people, ("B",), {"B": LINEAR}, {"B": BAND}, 1.0, 3)
    (size,) = chart.sizes
    pressure = LINEAR.pressure(girth, size.rest["B"])
    assert pressure[0] == pytest.approx(BAND.low, rel=1e-9)
    assert pressure[-1] == pytest.approx(BAND.high, rel=1e-9)
    assert size.fits.all()


def test_the_centred_rest_puts_both_ends_equally_inside_the_band():
    a, b = 0.205, 0.209  # narrower than the widest size from 20.5 cm
    c0 = centred_rest(LINEAR, BAND, a, b)
    slack_low = float(LINEAR.pressure(a, c0)) - BAND.low
    slack_high = BAND.high - float(LINEAR.pressure(b, c0))
    assert slack_low == pytest.approx(slack_high, rel=1e-9) and slack_low > 0
    # by hand: 2 / c0 = (low + high) / (2 pi E) + 1/a + 1/b
    assert 1 / c0 == pytest.approx(0.5 * ((BAND.low + BAND.high) / (2 * np.pi * E) + 1 / a + 1 / b))


def test_a_riding_line_s_rest_holds_the_most_people():
    calf = np.array([0.33, 0.335, 0.34, 0.345, 0.40])
    c0 = stabbing_rest(LINEAR, Band("C", BAND.low, BAND.high), calf, np.ones(5), np.zeros(5))
    p = LINEAR.pressure(calf, c0)
    inside = (p >= BAND.low) & (p <= BAND.high)
    assert inside[:4].all() and not inside[4]


def test_variants_split_a_size_by_the_second_measure():
    rng = np.random.default_rng(0)
    ankle = rng.uniform(0.20, 0.21, 200)
    calf = np.where(np.arange(200) % 2, 0.32, 0.36) + rng.uniform(0, 0.004, 200)
    bands = {"B": BAND, "C": Band("C", BAND.low, BAND.high)}
    people = People({"B": ankle, "C": calf}, {"B": np.zeros(200), "C": np.zeros(200)}, np.ones(200))
    chart = design_chart(people, ("B", "C"), {"B": LINEAR, "C": LINEAR}, bands, 1.0, 2, 3)
    assert chart.coverage == 1.0
    names = [s.name for s in chart.sizes]
    assert names == ["S1a", "S1b"]  # two calf groups 4 cm apart: two variants of one size
    for size in chart.sizes:
        low, high = size.ranges["C"]
        assert np.all((calf[size.members] >= low) & (calf[size.members] <= high))


def test_the_needed_fabric_holds_its_sizes_and_the_stiffest_linear_one_touches_the_corridor():
    girth = np.linspace(0.19, 0.25, 500)
    needs = requirement(girth, np.ones(500), LINEAR, BAND, 1.0, 3)
    assert needs[0].low == pytest.approx(0.19) and needs[-1].high == pytest.approx(0.25)
    ratios = [n.high / n.low for n in needs]
    assert np.allclose(ratios, ratios[0])
    for need in needs:
        modulus = linear_modulus(BAND.low, BAND.high, need.low, need.high, 1.0)
        assert need.linear_modulus == pytest.approx(modulus)
        stiffest = LineModel(
            Tension(np.array([0.0, 1.0]), np.array([0.0, modulus])), Calibration.exact()
        )
        assert float(stiffest.pressure(need.low, need.rest)) == pytest.approx(BAND.low)
        assert float(stiffest.pressure(need.high, need.rest)) == pytest.approx(BAND.high)
        floor, roof = need.corridor(np.array([need.strain_min, need.strain_max]))
        assert floor[0] == pytest.approx(need.tension_floor)
        assert roof[1] == pytest.approx(need.tension_roof)
        # the power-like fabric of this test (E): sizes of 20 -> 21 cm hold; these are wider
        assert need.fabric_holds == (need.high <= 1 / (1 / need.low - 5 / 21))


# --- the population -------------------------------------------------------------------------------


def test_ansur_s_measures_map_to_the_leg_chart_s_points():
    people = read_population(ANSUR, None)
    rows = [r for r in csv.DictReader(x for x in ANSUR.open() if not x.startswith("#"))]
    assert len(people.weight) == len(rows) == 1986
    assert np.allclose(people.measures["B"], [float(r["ankle_cm"]) / 100 for r in rows])
    assert np.allclose(people.measures["C"], [float(r["calf_cm"]) / 100 for r in rows])
    assert np.allclose(people.measures["G"], [float(r["thigh_cm"]) / 100 for r in rows])
    assert np.allclose(
        people.measures["E_height"], [float(r["knee_height_midpatella_cm"]) / 100 for r in rows]
    )
    assert people.ids[0] == rows[0]["subject_id"]
    ankle = people.measures["B"]
    assert np.mean(ankle) == pytest.approx(0.216, abs=0.001)  # the 21.6 +- 1.5 cm
    young = read_population(ANSUR)  # 18-45 by default
    assert len(young.weight) < 1986


BAD = {
    "ankle in mm": ("subject_id,ankle_cm,calf_cm\n1,215,372\n", "ankle_cm"),
    "calf in inches": ("subject_id,ankle_cm,calf_cm\n1,21.5,14.6\n", "calf_cm"),
    "not a number": ("subject_id,ankle_cm,calf_cm\n1,21.5,abc\n", "calf_cm"),
    "no one of the ages": ("subject_id,age_years,ankle_cm\n1,60,21.5\n", "age_years"),
    "no rows": ("subject_id,ankle_cm\n", "rows"),
    "no measure": ("subject_id,age_years\n1,30\n", "header"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_cloth_sizes_refuses_a_bad_population_in_one_line_writing_nothing(leg_case, name):
    text, column = BAD[name]
    people = leg_case.parent / "people.csv"
    people.write_text(text)
    out = leg_case.parent / "out"
    args = ["--population", str(people), "--target", "B=23:32"]
    code, err = run_cloth("sizes", str(leg_case), *args, "-o", str(out))
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "people.csv" in lines[0] and column in lines[0], lines
    assert not out.exists()


@pytest.mark.parametrize("name", sorted(BAD))
def test_a_bad_population_is_refused_naming_the_file_and_column(tmp_path, name):
    from cloth.errors import InputError

    text, column = BAD[name]
    path = tmp_path / "people.csv"
    path.write_text(text)
    with pytest.raises(InputError) as caught:
        read_population(path)
    assert "people.csv" in str(caught.value) and column in str(caught.value)


# --- charts with ranges alone, and a person as a body ------------------------------------------


def _range_only(tmp_path: Path) -> Path:
    rows = list(csv.DictReader(x for x in LEG_CHART.open() if not x.startswith("#")))
    columns = [c for c in rows[0] if c not in ("B_cm", "C_cm")]
    path = tmp_path / "ranges.csv"
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, columns, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    return path


def test_a_chart_of_ranges_alone_reads_the_range_s_centre(tmp_path):
    targets = chart_targets(_range_only(tmp_path), "M")
    assert targets.kind == "leg"
    assert targets.girth["B"] == pytest.approx(0.23) and targets.ranges["B"] == (0.22, 0.24)
    assert targets.girth["C"] == pytest.approx(0.36)


def test_a_person_s_body_has_her_girths_and_heights_and_the_template_s_between():
    rows = list(csv.DictReader(x for x in LEG_CHART.open() if not x.startswith("#")))
    template = rows[1]  # M: B 23, B1 27.5, C 36; heights 11, 22, 33, ...; stature 168
    points = ("B", "B1", "C", "D", "E", "F", "G")
    row = person_body(template, points, {"B": 0.21, "C": 0.36}, {"E": 0.45}, 1.60, "her")
    girth, height, stature = template_girths(row, points)
    assert girth["B"] == pytest.approx(0.21) and girth["C"] == pytest.approx(0.36)
    # B1 (22 cm up, halfway B to C): the ratio 21/23 at B and 1 at C, linear in height
    assert girth["B1"] == pytest.approx(0.275 * (0.5 * (21 / 23) + 0.5), rel=1e-5)
    assert girth["G"] == pytest.approx(0.61)  # above C, C's ratio held
    assert height["E"] == pytest.approx(0.45) and stature == pytest.approx(1.60)
    # below E: the template's heights x 45 / 49; above: to her stature
    assert height["C"] == pytest.approx(0.33 * 45 / 49, rel=1e-5)
    assert height["G"] == pytest.approx(0.45 + (0.75 - 0.49) * (1.60 - 0.45) / (1.68 - 0.49))
    assert "B_min_cm" not in row


# --- the command's bad input -------------------------------------------------------------------


@pytest.fixture
def leg_case(tmp_path):
    path = tmp_path / "case.yaml"
    path.write_text(
        "material: powernet\n"
        "body: {leg: {size: M}}\n"
        "garment: {bottom: 0.09, top: 0.77, grid: [8, 12], edges: sliding, reduction: 0.16}\n"
        "solver: {method: newton, max_iterations: 20}\n"
    )
    return path


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--target", "B=32:23"], "--target"),
        (["--target", "B=27"], "needs a band"),
        (["--target", "B=23:32", "--by", "ankle,ankle"], "--by"),
        (["--target", "B=23:32", "--by", "calf"], "needs a band at its line"),
        (["--target", "B=23:32", "--coverage", "1.5"], "--coverage"),
        (["--target", "B=23:32", "--coverage", "abc"], "--coverage"),
        (["--target", "B=23:32", "--max-sizes", "0"], "--max-sizes"),
        (["--target", "Q=23:32"], "not a girth line"),
    ],
)
def test_bad_arguments_of_cloth_sizes_are_one_line_and_write_nothing(leg_case, args, words):
    out = leg_case.parent / "out"
    code, err = run_cloth("sizes", str(leg_case), *args, "-o", str(out))
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], lines
    assert not out.exists()


def test_a_population_without_the_asked_measure_is_named_with_its_column(leg_case):
    people = leg_case.parent / "people.csv"
    people.write_text("subject_id,ankle_cm\n1,21.5\n2,22.0\n")
    out = leg_case.parent / "out"
    args = ["--population", str(people), "--target", "B=23:32", "--target", "C=18:24"]
    code, err = run_cloth("sizes", str(leg_case), *args, "-o", str(out))
    assert code == 2 and "people.csv" in err and "C_cm" in err and "calf_cm" in err, err
    assert not out.exists()


# --- the whole command at CI size -----------------------------------------------------------------

#: the columns of ANSUR II the test's population keeps
KEEP = ("subject_id", "age_years", "stature_cm", "ankle_cm", "calf_cm", "thigh_cm")


@pytest.fixture(scope="module")
def sized(tmp_path_factory):
    """``cloth sizes`` on a tiny stocking and 60 women of ANSUR II aged 18-45 with ankles of
    20-23 cm (seeded), class II at B."""
    folder = tmp_path_factory.mktemp("sizes")
    rows = [r for r in csv.DictReader(x for x in ANSUR.open() if not x.startswith("#"))]
    rows = [r for r in rows if 18 <= float(r["age_years"]) <= 45]
    rows = [r for r in rows if 20.0 <= float(r["ankle_cm"]) <= 23.0]
    pick = np.random.default_rng(7).choice(len(rows), 60, replace=False)
    people = folder / "people.csv"
    with people.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, KEEP, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows[k] for k in sorted(pick))
    case = folder / "case.yaml"
    case.write_text(
        "material: powernet\n"
        "body: {leg: {size: M}}\n"
        "garment: {bottom: 0.09, top: 0.77, grid: [12, 36], edges: sliding,\n"
        "  lengthwise_reduction: 0.15, reduction: 0.16, error_estimate: false}\n"
        "solver: {method: newton, tolerance: 1.0e-8, max_iterations: 100}\n"
    )
    out = folder / "out"
    args = ["--population", str(people), "--target", "B=23:32", "--max-sizes", "2"]
    import cloth.figures.sizes as figures

    drawn = figures.plot_sizes

    def record(*args, **kwargs):  # what sizes.png's panels are drawn from
        DRAWN["corridors"], DRAWN["tension"] = args[5], args[6]
        return drawn(*args, **kwargs)

    with mock.patch.object(figures, "plot_sizes", record):
        code, err = run_cloth("sizes", str(case), *args, "--rounds", "1", "-o", str(out))
    assert code == 0, err
    return people, out


#: what the ``sized`` fixture's sizes.png was drawn from: its corridors and the fabric's tension
DRAWN: dict[str, object] = {}


def _table(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


def test_the_count_per_size_is_the_population_recounted_by_hand(sized):
    people, out = sized
    ankle = np.array([float(r["ankle_cm"]) for r in _table(people)])
    sizes = _table(out / "sizes.csv")
    assert sizes, "no size"
    for k, row in enumerate(sizes):
        low, high = float(row["B_min_cm"]), float(row["B_max_cm"])
        inside = (ankle <= high + 1e-4) & ((ankle >= low - 1e-4) if k == 0 else (ankle > low))
        assert int(row["people"]) == int(inside.sum()), row["size"]
        assert float(row["share"]) == pytest.approx(inside.sum() / len(ankle), abs=1e-6)
    # the sizes follow one another with no gap
    for before, after in itertools.pairwise(sizes):
        assert float(after["B_min_cm"]) == pytest.approx(float(before["B_max_cm"]), abs=1e-4)


def test_the_confirmations_are_the_runs_beside_them_and_the_verdict_follows(sized):
    _, out = sized
    for row in _table(out / "sizes.csv"):
        runs = sorted((out / row["size"] / "confirm").glob("*/summary.csv"))
        if not runs:
            continue
        values, converged = {}, True
        for path in runs:
            (b,) = [r for r in _table(path) if r["landmark"] == "B"]
            values[path.parent.name] = float(b["pressure_mean_mmHg"])
            converged &= b["converged"] == "1"
        low = min(values, key=values.get)
        high = max(values, key=values.get)
        assert float(row["B_confirmed_min_mmHg"]) == pytest.approx(values[low], rel=1e-5)
        assert float(row["B_confirmed_max_mmHg"]) == pytest.approx(values[high], rel=1e-5)
        assert row["B_confirmed_min_who"].startswith(f"{low}: ")
        inside = all(23 <= v <= 32 for v in values.values())
        assert row["confirmed"] == str(int(inside and converged))


def test_a_confirmation_is_a_plain_run_of_its_case(sized, tmp_path):
    _, out = sized
    case = next(iter(sorted(out.glob("*/confirm/*/case.yaml"))))
    code, err = run_cloth(
        "run", str(case), "-o", str(tmp_path / "again"), "--stop-after", "aggregate"
    )
    assert code == 0, err
    (again,) = [r for r in _table(tmp_path / "again" / "summary.csv") if r["landmark"] == "B"]
    (first,) = [r for r in _table(case.parent / "summary.csv") if r["landmark"] == "B"]
    assert again["pressure_mean_Pa"] == first["pressure_mean_Pa"]


def test_the_written_chart_reads_back_with_each_size_s_range(sized):
    _, out = sized
    for row in _table(out / "sizes.csv"):
        targets = chart_targets(out / "chart.csv", row["size"])
        low, high = targets.ranges["B"]
        assert 100 * low == pytest.approx(float(row["B_min_cm"]), abs=1e-4)
        assert 100 * high == pytest.approx(float(row["B_max_cm"]), abs=1e-4)
        assert targets.girth["B"] == pytest.approx(0.5 * (low + high), abs=1e-6)
        assert (out / row["size"] / "case.yaml").is_file()
    assert (out / "pattern_knitting.csv").is_file() and (out / "sizes.png").is_file()


def test_every_column_of_the_sizes_tables_has_its_inventory_row(sized):
    _, out = sized
    files = [out / "sizes.csv", out / "fabric_requirement.csv", out / "fast_model.csv"]
    assert inventory.unlisted(files) == []


def _template() -> dict[str, float]:
    rows = csv.DictReader(x for x in LEG_CHART.open() if not x.startswith("#"))
    (row,) = [r for r in rows if r["size"] == "M"]
    return {k: float(row[k]) for k in ("B_cm", "C_cm", "G_cm", "stature_cm")}


def _predicted(people: Path, model: dict[str, str]) -> tuple[list[dict], np.ndarray]:
    """Every person's fast-model shape term at B (Pa), recomputed with numpy from the file,
    the template's chart row and fast_model.csv's coefficients."""
    t = _template()
    rows = _table(people)
    b = np.array([float(r["ankle_cm"]) for r in rows])
    c = np.array([float(r["calf_cm"]) for r in rows])
    g = np.array([float(r["thigh_cm"]) for r in rows])
    s = np.array([float(r["stature_cm"]) for r in rows])
    raw = {
        "stature": s / t["stature_cm"] - 1,
        "C_over_B": (c / b) / (t["C_cm"] / t["B_cm"]) - 1,
        "G_over_B": (g / b) / (t["G_cm"] / t["B_cm"]) - 1,
    }
    offset = np.full(len(rows), float(model["constant_Pa"]))
    for name, values in raw.items():
        assert float(model[f"{name}_std"]) == pytest.approx(np.std(values), rel=1e-6)
        offset += float(model[f"{name}_Pa_per_std"]) * values / np.std(values)
    return rows, offset


def test_the_predicted_pressures_and_who_fits_are_the_fast_model_recomputed(sized):
    from cloth.files.material import load_fabric

    people, out = sized
    (model,) = _table(out / "fast_model.csv")
    assert model["line"] == "B" and int(model["equilibria"]) >= 3
    rows, offset = _predicted(people, model)
    fabric = load_fabric("powernet")
    tension = Tension(
        np.asarray(fabric.weft.knot_strain), fabric.thickness * np.asarray(fabric.weft.knot_stress)
    )
    ankle = np.array([float(r["ankle_cm"]) for r in rows]) / 100
    ids = [r["subject_id"] for r in rows]
    hoop = float(model["hoop"])
    for k, row in enumerate(_table(out / "sizes.csv")):
        low, high = float(row["B_min_cm"]) / 100, float(row["B_max_cm"]) / 100
        inside = (ankle <= high + 1e-6) & ((ankle >= low - 1e-6) if k == 0 else (ankle > low))
        rest = float(row["B_rest_circumference_cm"]) / 100
        p = (hoop * 2 * np.pi * tension(ankle / rest - 1) / ankle + offset) / MMHG
        fits = inside & (p >= 23 - 1e-6) & (p <= 32 + 1e-6)
        assert float(row["fit_share"]) == pytest.approx(fits.sum() / len(rows), abs=1e-6)
        chosen = np.flatnonzero(fits if fits.any() else inside)
        if len(chosen) == 0:
            continue
        lo, hi = chosen[np.argmin(p[chosen])], chosen[np.argmax(p[chosen])]
        assert float(row["B_min_mmHg"]) == pytest.approx(p[lo], rel=1e-4)
        assert float(row["B_max_mmHg"]) == pytest.approx(p[hi], rel=1e-4)
        assert (row["B_min_who"], row["B_max_who"]) == (ids[lo], ids[hi])


def test_the_fabric_requirement_is_its_corridor_by_hand(sized):
    people, out = sized
    (model,) = _table(out / "fast_model.csv")
    hoop = float(model["hoop"])
    needs = _table(out / "fabric_requirement.csv")
    assert len(needs) == 2  # --max-sizes
    ends = [(float(n["B_min_cm"]) / 100, float(n["B_max_cm"]) / 100) for n in needs]
    # the central 95 % of the ankles (Hazen's quantiles), split in equal ratios
    ankle = np.sort([float(r["ankle_cm"]) / 100 for r in _table(people)])
    middle = np.arange(len(ankle)) + 0.5
    assert ends[0][0] == pytest.approx(np.interp(0.025 * len(ankle), middle, ankle))
    assert ends[-1][1] == pytest.approx(np.interp(0.975 * len(ankle), middle, ankle))
    offsets = np.sort(_predicted(people, model)[1])
    shape = [np.interp(q * len(offsets), middle, offsets) for q in (0.025, 0.975)]
    ratios = [b / a for a, b in ends]
    assert np.allclose(ratios, ratios[0])
    for (a, b), row in zip(ends, needs, strict=True):
        weft_low = float(row["tension_floor_N_per_m"]) * 2 * np.pi * hoop / a
        weft_high = float(row["tension_roof_N_per_m"]) * 2 * np.pi * hoop / b
        room = max(weft_high - weft_low, 0)
        modulus = room / (2 * np.pi * hoop * (1 / a - 1 / b))
        # the file's 6 significant digits, through the difference of two near values
        rel = 3e-6 * (weft_high + weft_low) / room if room > 0 else 1e-9
        rel *= 1 + (a + b) / (b - a)
        assert float(row["linear_modulus_N_per_m"]) == pytest.approx(modulus, rel=rel, abs=1e-9)
        if modulus > 0:
            stiffest = float(row["linear_modulus_N_per_m"])
            rest = 1 / (1 / a + weft_low / (2 * np.pi * hoop * stiffest))
            assert float(row["rest_circumference_cm"]) == pytest.approx(100 * rest, rel=1e-4)
            written = float(row["rest_circumference_cm"]) / 100
            assert float(row["strain_min"]) == pytest.approx(a / written - 1, rel=1e-4)
            assert float(row["strain_max"]) == pytest.approx(b / written - 1, rel=1e-4)
        # the band less the central 95 % of the people's shape terms (Hazen's quantiles)
        assert weft_low == pytest.approx(23 * MMHG - shape[0], rel=1e-4)
        assert weft_high == pytest.approx(32 * MMHG - shape[1], rel=1e-4)
        assert row["fabric_holds"] in ("0", "1")


def test_sizes_png_draws_each_corridor_where_the_fabric_is_cut_as_the_table_says(sized):
    """The third panel's corridors are the table's: each size's strain window where the case's
    fabric is cut, the corridor's floor at its start and roof at its end, the fabric's tension
    there; the fabric's curve is inside the drawn corridor exactly where ``fabric_holds``."""
    _, out = sized
    needs = _table(out / "fabric_requirement.csv")
    corridors, tension = DRAWN["corridors"], DRAWN["tension"]
    assert len(corridors) == len(needs) == 2
    for row, corridor in zip(needs, corridors, strict=True):
        rest = float(row["fabric_rest_circumference_cm"]) / 100
        a, b = float(row["B_min_cm"]) / 100, float(row["B_max_cm"]) / 100
        # the file's 6 significant digits of cm, through a / rest - 1
        assert float(row["fabric_strain_min"]) == pytest.approx(a / rest - 1, abs=2e-5)
        assert float(row["fabric_strain_max"]) == pytest.approx(b / rest - 1, abs=2e-5)
        assert corridor.strain[0] == pytest.approx(float(row["fabric_strain_min"]), rel=1e-5)
        assert corridor.strain[-1] == pytest.approx(float(row["fabric_strain_max"]), rel=1e-5)
        assert corridor.floor[0] == pytest.approx(float(row["tension_floor_N_per_m"]), rel=1e-5)
        assert corridor.roof[-1] == pytest.approx(float(row["tension_roof_N_per_m"]), rel=1e-5)
        ends = tension(corridor.strain[[0, -1]])
        assert ends[0] == pytest.approx(float(row["fabric_tension_min_N_per_m"]), rel=1e-5)
        assert ends[1] == pytest.approx(float(row["fabric_tension_max_N_per_m"]), rel=1e-5)
        inside = ends[0] >= corridor.floor[0] * (1 - 1e-6) and ends[1] <= corridor.roof[-1] * (
            1 + 1e-6
        )
        assert row["fabric_holds"] == str(int(inside)) and corridor.holds == inside
        if inside:  # the whole curve, not only its ends (the pressure rises with the girth)
            curve = tension(corridor.strain)
            assert np.all(curve >= corridor.floor * (1 - 1e-6))
            assert np.all(curve <= corridor.roof * (1 + 1e-6))


def test_the_fast_model_s_error_is_its_rms_on_the_equilibria_it_was_fitted_to(sized):
    import yaml

    from cloth.files.material import load_fabric

    _, out = sized
    (model,) = _table(out / "fast_model.csv")
    t = _template()
    fabric = load_fabric("powernet")
    strain = np.asarray(fabric.weft.knot_strain)
    tension = fabric.thickness * np.asarray(fabric.weft.knot_stress)
    residuals = []
    bodies = {row["size"]: row for row in _table(out / "calibration" / "people.csv")}
    for name, row in bodies.items():
        if name.endswith("_size"):
            continue  # the body her pattern is cut on: the template with her ankle
        folder = out / "calibration" / name
        (b,) = [r for r in _table(folder / "summary.csv") if r["landmark"] == "B"]
        reduction = yaml.safe_load((folder / "case.yaml").read_text())["garment"]["reduction"]
        cut_on = bodies[f"{name}_size"]
        assert float(cut_on["B_cm"]) == float(row["B_cm"])
        rest = (1 - reduction["B"]) * float(cut_on["B_cm"]) / 100
        girth = float(row["B_cm"]) / 100
        weft = 2 * np.pi * np.interp(girth / rest - 1, strain, tension) / girth
        shape = {
            "stature": float(row["stature_cm"]) / t["stature_cm"] - 1,
            "C_over_B": (float(row["C_cm"]) / float(row["B_cm"])) / (t["C_cm"] / t["B_cm"]) - 1,
            "G_over_B": (float(row["G_cm"]) / float(row["B_cm"])) / (t["G_cm"] / t["B_cm"]) - 1,
        }
        offset = float(model["constant_Pa"]) + sum(
            float(model[f"{k}_Pa_per_std"]) * v / float(model[f"{k}_std"]) for k, v in shape.items()
        )
        residuals.append(float(model["hoop"]) * weft + offset - float(b["pressure_mean_Pa"]))
    assert int(model["equilibria"]) == len(residuals) >= 3
    rms = np.sqrt(np.mean(np.square(residuals))) / MMHG
    assert float(model["rms_error_mmHg"]) == pytest.approx(rms, rel=1e-4)


def test_the_grid_s_verdict_is_the_stated_errors_against_the_criterion(sized):
    _, out = sized
    for row in _table(out / "sizes.csv"):
        runs = sorted((out / row["size"] / "confirm").glob("*/summary.csv"))
        pairs = []
        for path in runs:
            (b,) = [r for r in _table(path) if r["landmark"] == "B"]
            error = float(b["pressure_mean_error_mmHg"] or "nan")
            pairs.append((float(b["pressure_mean_mmHg"]), error))
        errors = [e for _, e in pairs if np.isfinite(e)]
        stated = row["B_confirmed_error_mmHg"]
        if errors:
            assert float(stated) == pytest.approx(max(errors), rel=1e-5)
        else:
            assert stated in ("", "nan")
        tells = bool(pairs) and all(np.isfinite(e) and e <= max(0.01 * p, 0.1) for p, e in pairs)
        assert row["grid_tells"] == str(int(tells))


@pytest.mark.slow  # two more commands at CI size (make test-slow; .ci/run runs it)
def test_the_written_chart_is_taken_by_cloth_design_sizes_and_the_wearers(sized, tmp_path):
    from cloth.bodies.wearers import range_wearers

    _, out = sized
    names = [row["size"] for row in _table(out / "sizes.csv")][:2]
    case = tmp_path / "case.yaml"
    case.write_text(
        "material: powernet\n"
        f"body: {{leg: {{size: {names[0]}, chart: {out / 'chart.csv'}}}}}\n"
        "garment: {bottom: 0.09, top: 0.77, grid: [12, 36], edges: sliding,\n"
        "  lengthwise_reduction: 0.15, reduction: 0.16, error_estimate: false}\n"
        "solver: {method: newton, tolerance: 1.0e-8, max_iterations: 100}\n"
    )
    args = ["--sizes", ",".join(names), "--target", "B=27.5", "-o", str(tmp_path / "d")]
    code, err = run_cloth("design", str(case), *args)
    assert code == 0, err
    rows = _table(tmp_path / "d" / "design_confirmed.csv")
    assert [r["size"] for r in rows] == names
    for row in rows:
        assert float(row["confirmed_mmHg"]) == pytest.approx(27.5, abs=0.5)
    # the wearers of a designed size: its range's ends (cloth body wearers fits them)
    targets = chart_targets(out / "chart.csv", names[0])
    wearers = range_wearers(targets, targets.ranges)
    ends = sorted({w.targets.girth["B"] for w in wearers.wearers})
    assert ends[0] == pytest.approx(targets.ranges["B"][0])
    assert ends[-1] == pytest.approx(targets.ranges["B"][1])


def corridor_fabric(requirement: Path, path: Path) -> Path:
    """A lab table (SYNTHETIC, and says so) whose weft is linear through zero at 0.8 x the
    stiffest linear fabric of ``requirement`` (fabric_requirement.csv) and whose warp is the
    power net's fitted curve: a fabric inside every corridor of the chart asked for."""
    from cloth.files.material import load_fabric

    modulus = 0.8 * min(float(r["linear_modulus_N_per_m"]) for r in _table(requirement))
    net = load_fabric("powernet")
    lines = [
        "# SYNTHETIC: made by tests/test_sizes.py inside the corridor cloth sizes asked for;",
        "# not a measurement",
        "# name: synthetic corridor weft",
        f"# thickness_mm: {net.thickness * 1e3:g}",
        "direction,strain,stress_kPa",
    ]
    lines += [f"weft,{e},{modulus * e / net.thickness / 1e3:.9g}" for e in (0, 1, 2, 3)]
    lines += [
        f"warp,{e:.9g},{s / 1e3:.9g}"
        for e, s in zip(net.warp.knot_strain, net.warp.knot_stress, strict=True)
    ]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.slow  # two more commands at CI size (make test-slow; .ci/run runs it)
def test_a_fabric_inside_the_corridor_covers_the_share_when_designed_again(sized, tmp_path):
    people, out = sized
    assert all(r["fabric_holds"] == "0" for r in _table(out / "fabric_requirement.csv"))
    table = corridor_fabric(out / "fabric_requirement.csv", tmp_path / "synthetic.csv")
    case = tmp_path / "case.yaml"
    text = (people.parent / "case.yaml").read_text()
    case.write_text(text.replace("material: powernet", f"material: {table}"))
    args = ["--population", str(people), "--target", "B=23:32", "--max-sizes", "2"]
    code, err = run_cloth("sizes", str(case), *args, "-o", str(tmp_path / "again"))
    assert code == 0, err
    sizes = _table(tmp_path / "again" / "sizes.csv")
    assert len(sizes) <= 2
    assert sum(float(r["fit_share"]) for r in sizes) >= 0.95
    assert all(r["confirmed"] == "1" for r in sizes), [
        (r["B_confirmed_min_mmHg"], r["B_confirmed_max_mmHg"]) for r in sizes
    ]


@pytest.mark.slow
@pytest.mark.skipif(
    importlib.util.find_spec("anny") is None or importlib.util.find_spec("torch") is None,
    reason="the bodies extra (torch, anny) is not installed: make bodies",
)
def test_cloth_body_wearers_fits_a_designed_size_s_range_wearers(sized, tmp_path):
    _, out = sized
    (first, *_) = _table(out / "sizes.csv")
    folder = tmp_path / "wearers"
    chart = str(out / "chart.csv")
    args = ["body", "wearers", chart, "--size", first["size"], "--population", "none"]
    code, err = run_cloth(*args, "-o", str(folder))
    assert code == 0, err
    index = json.loads((folder / "wearers.json").read_text())
    girths = [w["girths_m"]["B"] for w in index["wearers"]]
    low, high = float(first["B_min_cm"]) / 100, float(first["B_max_cm"]) / 100
    assert min(girths) == pytest.approx(low, abs=1e-6)
    assert max(girths) == pytest.approx(high, abs=1e-6)


# --- the pipeline's size charts -----------------------------------------------------------------


def test_the_stocking_config_s_size_chart_is_one_cloth_sizes_job_with_its_options():
    import yaml

    from cloth.pipeline.plan import make_plan

    config = yaml.safe_load((ROOT / "config" / "stocking.yaml").read_text())
    run = make_plan(config, ROOT).size_charts["class_II"]
    assert run.arguments == "--target B=23:32 --by ankle --max-sizes 8"
    assert run.start.body.kind == "leg" and run.start.garment.grid == (96, 288)


@pytest.mark.parametrize(
    ("body", "words"),
    [("nobody", "is not defined under bodies"), ("avatar_leg_M", "a leg or torso")],
)
def test_a_size_chart_entry_with_a_wrong_body_is_one_line_naming_its_key(body, words):
    import yaml

    from cloth.errors import InputError
    from cloth.pipeline.plan import make_plan

    config = yaml.safe_load((ROOT / "config" / "stocking.yaml").read_text())
    config["size_charts"]["class_II"]["body"] = body
    with pytest.raises(InputError) as caught:
        make_plan(config, ROOT)
    assert words in str(caught.value) and "size_charts.class_II.body" in str(caught.value)
