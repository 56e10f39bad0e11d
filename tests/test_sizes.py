"""Sizes that fit (issue 62): the fast model, the chart's search worked out by hand on
cylinders, the population's columns and refusals, a person as a body, and the command's bad
input."""

from __future__ import annotations

import csv
from pathlib import Path

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
