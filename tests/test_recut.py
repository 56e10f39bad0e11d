"""A size chart ships confirmed, or says why not (issue 71, item 1): a size whose confirmation
misses its band is recut from what its own equilibria read (`cloth.results.recut`), worked out
by hand on cylinders of a fabric linear through zero, where Laplace's pressure is
2 pi E (1/c - 1/g); and ``cloth sizes`` on a cylinder leg, where the first confirmation misses
by 0.05 mmHg."""

from __future__ import annotations

import csv
import logging
from pathlib import Path

import numpy as np
import pytest
import yaml

from cloth.cli import main
from cloth.results.pressure import MMHG
from cloth.results.recut import RECUT_MARGIN, recut
from cloth.results.sizechart import Band, People, Size
from cloth.results.tubemodel import Calibration, Correction, LineModel, Tension
from tests.test_fuzz import run_cloth

#: a fabric linear through zero: T = E e, N m-1
E = 300.0
LINEAR = LineModel(Tension(np.array([0.0, 1.0]), np.array([0.0, E])), Calibration.exact())
BAND = Band("C", 18 * MMHG, 30 * MMHG)


def _laplace(girth, rest):
    """Laplace's pressure of the linear fabric on a cylinder, Pa: 2 pi E (1/c - 1/g)."""
    return 2 * np.pi * E * (1 / np.asarray(rest) - 1 / np.asarray(girth))


def _people(girths, offsets=None) -> People:
    g = np.asarray(girths, dtype=float)
    o = np.zeros_like(g) if offsets is None else np.asarray(offsets, dtype=float)
    return People({"C": g}, {"C": o}, np.ones_like(g))


def _size(girths, rest) -> Size:
    members = np.arange(len(girths))
    ranges = {"C": (float(np.min(girths)), float(np.max(girths)))}
    return Size("S1", ranges, {"C": rest}, members, np.ones(len(girths), dtype=bool))


def test_a_correction_reads_every_confirmation_as_it_was_read():
    fast = np.array([20.0, 25.0, 29.0]) * MMHG
    read = 0.5 * MMHG + 1.02 * fast
    fix = Correction.fit(fast, read)
    assert fix(fast) == pytest.approx(read, rel=1e-12)
    # a slope that would reverse the wearers' order falls back to a shift alone
    back = Correction.fit(fast, fast[::-1])
    assert back.scale == 1.0 and back.shift == pytest.approx(np.mean(fast[::-1] - fast))


def test_a_recut_centres_the_confirmed_extremes_by_hand():
    """Two wearers read delta above Laplace: the centred cut solves
    2 pi E (2/c - 1/a - 1/b) + 2 delta = low + high."""
    girths = np.array([0.30, 0.305, 0.31])
    rest, delta = 0.26, -0.4 * MMHG
    people = _people(girths)
    reads = [(0, {"C": float(_laplace(0.30, rest)) + delta})]
    reads.append((2, {"C": float(_laplace(0.31, rest)) + delta}))
    found = recut(_size(girths, rest), reads, people, {"C": LINEAR}, {"C": BAND})
    assert found.size is not None and found.size.recuts == 1
    inverse = (BAND.low + BAND.high - 2 * delta) / (4 * np.pi * E) + 0.5 * (1 / 0.30 + 1 / 0.31)
    assert found.size.rest["C"] == pytest.approx(1 / inverse, rel=1e-12)
    assert found.size.ranges == {"C": (0.30, 0.31)}  # the range kept
    low, high = (_laplace(g, found.size.rest["C"]) + delta for g in (0.30, 0.31))
    assert low - BAND.low == pytest.approx(BAND.high - high, abs=1e-6)
    assert found.size.fits.all()


def test_a_spread_wider_than_the_band_narrows_the_range_to_the_widest_window_that_holds():
    """On the linear fabric the spread of a window [a, b] is 2 pi E (1/a - 1/b) at any cut:
    the window holds where that is within the band less twice the margin; the recut keeps
    the most wearers of the windows that do (counted here over every window)."""
    girths = np.linspace(0.24, 0.40, 17)
    rest = 0.21
    people = _people(girths)
    reads = [(k, {"C": float(_laplace(girths[k], rest))}) for k in (0, 16)]
    found = recut(_size(girths, rest), reads, people, {"C": LINEAR}, {"C": BAND})
    room = BAND.high - BAND.low - 2 * RECUT_MARGIN
    best = max(
        (j - i + 1, i, j)
        for i in range(17)
        for j in range(i, 17)
        if 2 * np.pi * E * (1 / girths[i] - 1 / girths[j]) <= room
    )
    count, i, j = best
    assert found.size is not None and len(found.size.members) == count < 17
    assert found.size.ranges["C"] == (pytest.approx(girths[i]), pytest.approx(girths[j]))
    assert "narrowed" in found.why
    assert found.size.fits.all()


def test_no_recut_holds_wearers_of_one_girth_who_read_wider_than_the_band():
    girths = np.array([0.30, 0.30])
    people = _people(girths, offsets=[0.0, 13 * MMHG])  # her shape: 13 mmHg more
    rest = 0.26
    reads = [(0, {"C": float(_laplace(0.30, rest))})]
    reads.append((1, {"C": float(_laplace(0.30, rest)) + 13 * MMHG}))
    size = _size(girths, rest)
    found = recut(size, reads, people, {"C": LINEAR}, {"C": BAND})
    assert found.size is None
    assert "C" in found.why and "18-30 mmHg" in found.why


# --- the command on a cylinder leg ------------------------------------------------------------

HEIGHTS = {"B": 11, "B1": 22, "C": 33, "D": 43, "E": 49, "F": 64, "G": 75}


def _table(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


#: ``cloth sizes``'s options on the cylinder: class C = 18-30 mmHg, no margin (each size as
#: wide as the band), two sizes
ARGS = ["--target", "C=18:30", "--max-sizes", "2", "--coverage", "0.9", "--margin", "0"]


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    """A leg chart whose size M is a cylinder of 30 cm (every girth, circular sections), 13
    people of 28-34 cm at C: ``cloth sizes`` with two rounds (`ARGS`), every line it logs
    kept in `LOGGED`."""
    folder = tmp_path_factory.mktemp("cylinder")
    points = list(HEIGHTS)
    columns = ["size", *(f"{p}_cm" for p in points), *(f"{p}_height_cm" for p in points)]
    columns += [f"{p}_depth_ratio" for p in points] + ["stature_cm"]
    row = ["M", *["30"] * 7, *(str(HEIGHTS[p]) for p in points), *["1.0"] * 7, "168"]
    (folder / "chart.csv").write_text(",".join(columns) + "\n" + ",".join(row) + "\n")
    people = folder / "people.csv"
    girths = np.linspace(28.0, 34.0, 13)
    people.write_text(
        "subject_id,C_cm\n" + "".join(f"{k + 1},{g:.4f}\n" for k, g in enumerate(girths))
    )
    case = folder / "case.yaml"
    case.write_text(
        "material: powernet\n"
        "body: {leg: {chart: chart.csv, size: M}}\n"
        "garment: {bottom: 0.15, top: 0.60, grid: [12, 8], edges: sliding, reduction: 0.16,\n"
        "  error_estimate: false}\n"
        "solver: {method: newton, tolerance: 1.0e-8, max_iterations: 100}\n"
    )
    keep = _Keep(logging.INFO)
    root = logging.getLogger("cloth")
    level = root.level
    root.setLevel(logging.INFO)  # the command's default --log-level: every line it logs
    root.addHandler(keep)
    try:
        args = ["--population", str(people), *ARGS, "--rounds", "2"]
        code = main(["sizes", str(case), *args, "-o", str(folder / "twice")])
    finally:
        root.removeHandler(keep)
        root.setLevel(level)
    LOGGED[:] = [r.getMessage() for r in keep.records]
    return folder, code


#: every log line of the ``cylinder`` fixture's run
LOGGED: list[str] = []


class _Keep(logging.Handler):
    def __init__(self, level: int) -> None:
        super().__init__(level)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


def test_every_number_cloth_sizes_logs_has_sensible_digits(cylinder):
    """The log-digits rule (`tests/test_log_numbers.py`) over cloth sizes, recut included."""
    from tests.test_log_numbers import too_long

    assert any("recut" in line for line in LOGGED) and len(LOGGED) > 20
    bad = {line: too_long(line) for line in LOGGED if too_long(line)}
    assert not bad, bad


def test_a_size_that_missed_ships_recut_and_confirmed_where_laplace_puts_it(cylinder):
    """Its first confirmation (kept in ``confirm_round1/``) misses the band's floor by a
    small margin. The recut's cut is the one that centres Laplace's pressures on the cylinder
    (the powernet's weft, 2 pi T(g/c - 1) / g) plus what each extreme wearer read above
    Laplace then; confirmed again, the two read equally far inside the band."""
    from cloth.files.material import load_fabric

    folder, code = cylinder
    assert code == 0, LOGGED[-3:]
    fabric = load_fabric("powernet")
    strain = np.asarray(fabric.weft.knot_strain)
    tension = fabric.thickness * np.asarray(fabric.weft.knot_stress)

    def laplace(girth, rest):
        return 2 * np.pi * np.interp(girth / rest - 1, strain, tension) / girth

    out = folder / "twice"
    rows = {r["size"]: r for r in _table(out / "sizes.csv")}
    assert all(r["confirmed"] == "1" for r in rows.values())
    (name,) = [s for s, r in rows.items() if r["recut"] == "1"]
    assert [r["recut"] for r in rows.values()].count("0") == len(rows) - 1
    assert any(f"{name} recut" in line for line in LOGGED)
    assert any("2 confirmed, 1 recut" in line for line in LOGGED)
    # the size's first confirmation: each extreme wearer's girth, cut and what she read
    first = out / name / "confirm_round1"
    girth, residual, read = {}, {}, {}
    for wearer in ("C_min", "C_max"):
        (row,) = [r for r in _table(first / wearer / "summary.csv") if r["landmark"] == "C"]
        (body,) = [r for r in _table(first / "people.csv") if r["size"] == wearer]
        case = yaml.safe_load((first / wearer / "case.yaml").read_text())
        cut_on = case["garment"]["pattern"]["body"]["leg"]
        assert cut_on["size"] == name
        girth[wearer] = float(body["C_cm"]) / 100
        read[wearer] = float(row["pressure_mean_mmHg"])
        rest1 = (1 - case["garment"]["reduction"]["C"]) * _first_cut(folder, name)
        residual[wearer] = float(row["pressure_mean_Pa"]) - laplace(girth[wearer], rest1)
    assert 17.8 < read["C_min"] < 18.0  # the premise: it missed the floor, by a small margin

    def imbalance(rest):
        low = laplace(girth["C_min"], rest) + residual["C_min"]
        high = laplace(girth["C_max"], rest) + residual["C_max"]
        return (low - 18 * MMHG) - (30 * MMHG - high)

    small, large = 0.8 * girth["C_min"], girth["C_min"]
    for _ in range(60):
        middle = 0.5 * (small + large)
        small, large = (middle, large) if imbalance(middle) > 0 else (small, middle)
    rest2 = float(rows[name]["C_rest_circumference_cm"]) / 100
    assert rest2 == pytest.approx(small, rel=2e-4)
    assert rest2 != pytest.approx(rest1, rel=1e-3)  # the cut moved
    # the written pattern is that cut: the confirmation's reduction on chart.csv's body
    case = yaml.safe_load((out / name / "confirm" / "C_min" / "case.yaml").read_text())
    (body,) = [r for r in _table(out / "chart.csv") if r["size"] == name]
    cut = (1 - case["garment"]["reduction"]["C"]) * float(body["C_cm"]) / 100
    assert cut == pytest.approx(rest2, rel=1e-5)
    low = float(rows[name]["C_confirmed_min_mmHg"])
    high = float(rows[name]["C_confirmed_max_mmHg"])
    assert 18 < low and high < 30
    assert low - 18 == pytest.approx(30 - high, abs=0.05)


def _first_cut(folder: Path, name: str) -> float:
    """The girth (m) at C of the body size ``name`` is cut on: its range's centre, a cylinder
    (the recut kept the range)."""
    (row,) = [r for r in _table(folder / "twice" / "sizes.csv") if r["size"] == name]
    return 0.5 * (float(row["C_min_cm"]) + float(row["C_max_cm"])) / 100


@pytest.mark.slow  # three more commands at CI size (make test-slow; .ci/run runs it)
@pytest.mark.parametrize("how", ["once", "report", "no_recut"])
def test_a_size_not_confirmed_after_its_rounds_ends_in_one_line_with_its_files_written(
    cylinder, how, caplog, monkeypatch
):
    """With one round the size that missed is not recut ("once"): one line naming the size,
    the wearer, her value and the band, exit status 2, its files written with confirmed 0;
    with --report-unmet the same line as a warning and exit status 0 ("report"). Where no
    recut can hold the size ("no_recut", two rounds, the recut answering as it does where
    wearers of one girth read wider than the band: tested by hand above; the cylinder's
    wearers never do), the line says why, and not that a further round would help."""
    import cloth.stages.sizes as stage
    from cloth.results.recut import Recut

    folder, _ = cylinder
    out = folder / how
    rounds = "2" if how == "no_recut" else "1"
    args = ["--population", str(folder / "people.csv"), *ARGS, "--rounds", rounds, "-o", str(out)]
    why = "its wearers at C read 13.00 mmHg apart, wider than the band of 18-30 mmHg"
    if how == "no_recut":
        monkeypatch.setattr(stage, "recut", lambda *a, **k: Recut(None, why))
    if how == "report":
        with caplog.at_level(logging.WARNING, logger="cloth"):
            code = main(["sizes", str(folder / "case.yaml"), *args, "--report-unmet"])
        assert code == 0
        warned = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
        line = next(m for m in warned if m.startswith("size S"))
    else:
        code, err = run_cloth("sizes", str(folder / "case.yaml"), *args)
        assert code == 2, err
        line = err.strip()
        assert "\n" not in line and "Traceback" not in err
    rows = {r["size"]: r for r in _table(out / "sizes.csv")}
    missed = [r for r in rows.values() if r["confirmed"] == "0"]
    assert len(missed) == 1 and missed[0]["recut"] == "0"
    low = float(missed[0]["C_confirmed_min_mmHg"])
    assert 17.8 < low < 18.0
    name, ident = missed[0]["C_confirmed_min_who"].split(": ")  # "C_min: 3"
    for words in (f"size {missed[0]['size']}", f"{name} (id {ident})", f"{low:.2f} mmHg", "at C"):
        assert words in line, (words, line)
    assert "18-30 mmHg" in line
    if how == "no_recut":
        assert f"no recut holds it: {why}" in line and "--rounds" not in line
    else:
        assert "--rounds" in line
    for file in ("sizes.csv", "chart.csv", "fabric_requirement.csv", "sizes.png"):
        assert (out / file).is_file()
