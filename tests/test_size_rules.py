"""Rules, not examples (issue 71, item 5): the size search's fast model and its inverse, a
size's extreme wearers, and the calibration's linear algebra, each checked over random
problems against what must hold for any of them, so a slip cannot hide on one example where it
happens to cancel. Each rule's plant is in benchmarks/known_bugs.py."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from cloth.results.calibration import PARAMETERS, determined, intervals
from cloth.results.sizechart import Band, People, Size, extreme_wearers, span
from cloth.results.tubemodel import Calibration, Correction, LineModel, Tension
from cloth.stages.calibrate import jacobian


def _fabric(rng: np.random.Generator) -> Tension:
    """A random weft tension, N m-1: rising and piecewise linear through zero, its first
    segment flat one time in three (a slack toe)."""
    count = int(rng.integers(2, 7))
    strain = np.concatenate([[0.0], np.sort(rng.uniform(0.01, 1.5, count))])
    slope = rng.uniform(10.0, 2000.0, count)
    if rng.random() < 1 / 3:
        slope[0] = 0.0
    return Tension(strain, np.concatenate([[0.0], np.cumsum(slope * np.diff(strain))]))


def _model(rng: np.random.Generator, features: int) -> LineModel:
    """A fast model of a random fabric and a random calibration: any hoop, any shape terms."""
    shape = rng.normal(0.0, 400.0, features + 1)
    return LineModel(_fabric(rng), Calibration(float(rng.uniform(0.6, 1.8)), shape))


def _by_hand(model: LineModel, girth: float, rest: float, offset: float) -> float:
    """The fast model's pressure (Pa) of one wearer, written out: hoop 2 pi T(g/c - 1) / g
    plus her shape term, T by the knots (linear past the last)."""
    t = model.tension
    e = girth / rest - 1.0
    if e <= 0:
        weft = 0.0
    elif e > t.strain[-1]:
        slope = (t.tension[-1] - t.tension[-2]) / (t.strain[-1] - t.strain[-2])
        weft = t.tension[-1] + slope * (e - t.strain[-1])
    else:
        weft = float(np.interp(e, t.strain, t.tension))
    return model.calibration.hoop * 2.0 * math.pi * weft / girth + offset


@pytest.mark.parametrize("seed", range(12))
def test_the_fast_model_s_inverse_gives_back_the_pressure_it_was_asked_for(seed):
    """rest_for and pressure round-trip on random fabrics, calibrations, people and
    pressures; and a size's end by the search (`span`) is where the pressure reaches the
    band's top from a cut that puts the band's floor at its start."""
    rng = np.random.default_rng(seed)
    features = int(rng.integers(0, 4))
    model = _model(rng, features)
    people = 40
    girth = rng.uniform(0.15, 1.2, people)
    offset = model.calibration.offset(rng.normal(size=(people, features)))
    asked = offset + rng.uniform(300.0, 8000.0, people)  # a weft term to carry
    rest = model.rest_for(girth, asked, offset)
    assert model.pressure(girth, rest, offset) == pytest.approx(asked, rel=1e-9)
    for g, c, o, p in zip(girth[:5], rest[:5], offset[:5], asked[:5], strict=True):
        assert _by_hand(model, g, c, o) == pytest.approx(p, rel=1e-9)
    low = float(rng.uniform(1000.0, 3000.0))
    band = Band("B", low, low + float(rng.uniform(500.0, 3000.0)))
    ends = (float(rng.normal(0.0, 200.0)), float(rng.normal(0.0, 200.0)))
    ends = (min(ends), max(ends))
    start = rng.uniform(0.18, 0.4, 8)
    end = span(model, band, start, ends)
    cut = model.rest_for(start, band.low, ends[0])
    assert model.pressure(start, cut, ends[0]) == pytest.approx(band.low, rel=1e-9)
    reached = end < 3.0 * start * (1 - 1e-12)
    top = model.pressure(end[reached], cut[reached], ends[1])
    assert top == pytest.approx(np.full(reached.sum(), band.high), rel=1e-9)


def test_above_a_slack_toe_the_inverse_rises_from_the_toe_s_end():
    """A lab curve slack to 10 % (no tension) then rising to 100 N/m at 50 %: 50 N/m is at
    30 %, not at the 25 % a line from the origin would give (found by the rule above)."""
    toe = Tension(np.array([0.0, 0.1, 0.5]), np.array([0.0, 0.0, 100.0]))
    assert float(toe.strain_at(50.0)) == pytest.approx(0.3, rel=1e-12)
    assert float(toe.strain_at(0.0)) == 0.0  # exactly at the slack level: its least strain


@pytest.mark.parametrize("seed", range(10))
def test_a_size_s_extreme_wearers_are_the_brute_force_extremes_of_the_full_fast_model(seed):
    """Of a size's members who fit, at each line the lowest and the highest pressure of the
    full fast model (her girth and her shape term, the size's correction where it was recut),
    found one wearer at a time."""
    rng = np.random.default_rng(100 + seed)
    lines = ("B", "C")
    features = 2
    models = {line: _model(rng, features) for line in lines}
    count = 80
    shape = rng.normal(size=(count, features))
    girth = {"B": rng.uniform(0.19, 0.25, count), "C": rng.uniform(0.3, 0.42, count)}
    offset = {line: models[line].calibration.offset(shape) for line in lines}
    people = People(girth, offset, np.ones(count))
    members = np.sort(rng.choice(count, 30, replace=False))
    fits = rng.random(30) < 0.7
    rest = {"B": 0.8 * float(girth["B"].min()), "C": 0.8 * float(girth["C"].min())}
    fixes = {"C": Correction(float(rng.normal(0, 100)), float(rng.uniform(0.8, 1.2)))}
    size = Size("S1", {"B": (0.19, 0.25)}, rest, members, fits, fixes if seed % 2 else {})
    found = extreme_wearers(size, people, models, lines)
    expected: dict[str, int] = {}
    for line in lines:
        fix = size.corrections.get(line, Correction())
        values = {
            int(k): float(fix(_by_hand(models[line], girth[line][k], rest[line], offset[line][k])))
            for k in members[fits]
        }
        for end, pick in (("min", min), ("max", max)):
            person = pick(values, key=values.get)
            if person not in expected.values():
                expected[f"{line}_{end}"] = person
    assert found == expected


def test_which_parameters_the_readings_determine_does_not_depend_on_their_order():
    """QR with column pivoting orders the columns by what they tell; the answer, per
    parameter, is the same for every order the parameters are given in."""
    mixed = 0
    for seed in range(40):
        rng = np.random.default_rng(seed)
        rows, p = int(rng.integers(1, 6)), 3
        jacobian_ = rng.normal(size=(rows, p)) * 10.0 ** rng.uniform(-3, 2, p)
        spans = rng.uniform(0.1, 2.0, p)
        base = determined(jacobian_, spans, 1.0)
        mixed += bool(base.any() and not base.all())
        for order in itertools.permutations(range(p)):
            order = list(order)
            again = determined(jacobian_[:, order], spans[order], 1.0)
            assert again.tolist() == base[order].tolist(), (seed, order)
    assert mixed >= 5  # the rule met parameters determined and not, side by side


class _Quadratic:
    """Readings with a closed-form Jacobian in the internal coordinates u (friction as
    itself, the tissue modulus as ln E): r = a mu + c mu^2 + b ln E, Pa."""

    def __init__(self, rng: np.random.Generator, rows: int) -> None:
        self.a, self.b, self.c = (rng.normal(0.0, 500.0, rows) for _ in range(3))

    def readings(self, values: dict[str, float]) -> np.ndarray:
        mu, modulus = values["friction"], values["tissue_modulus"]
        return self.a * mu + self.c * mu**2 + self.b * math.log(modulus)

    def exact(self, mu: float) -> np.ndarray:
        return np.column_stack([self.a + 2 * self.c * mu, self.b])


@pytest.mark.parametrize("seed", range(5))
def test_the_calibration_s_slopes_and_intervals_are_the_closed_form_s(seed):
    """Central differences are exact on readings quadratic in u, forward ones off by c x
    step; the intervals are u +- t sd with sd^2 = sigma^2 (J^T J)^-1 at the closed-form J."""
    from scipy.stats import t as student

    rng = np.random.default_rng(seed)
    rows = 7
    model = _Quadratic(rng, rows)
    params = [PARAMETERS["friction"], PARAMETERS["tissue_modulus"]]
    u = np.array([float(rng.uniform(0.1, 0.8)), math.log(float(rng.uniform(5e3, 5e4)))])
    exact = model.exact(u[0])
    central = jacobian(model, {}, params, u, central=True)
    assert central == pytest.approx(exact, rel=1e-6, abs=1e-6)
    forward = jacobian(model, {}, params, u)
    step = params[0].step
    assert forward[:, 0] == pytest.approx(exact[:, 0] + model.c * step, rel=1e-6, abs=1e-6)
    residual = rng.normal(0.0, 50.0, rows)
    found, sigma = intervals(central, residual, u, params, 1.0)
    assert sigma == pytest.approx(math.sqrt(residual @ residual / (rows - 2)))
    covariance = sigma**2 * np.linalg.inv(exact.T @ exact)
    quantile = student.ppf(0.975, rows - 2)
    for k, (parameter, interval) in enumerate(zip(params, found, strict=True)):
        sd = math.sqrt(covariance[k, k])
        assert interval.sd == pytest.approx(sd, rel=1e-6)
        low = max(u[k] - quantile * sd, parameter.bound)
        assert interval.low == pytest.approx(parameter.of_u(low), rel=1e-6)
        assert interval.high == pytest.approx(parameter.of_u(u[k] + quantile * sd), rel=1e-6)
