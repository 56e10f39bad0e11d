"""The design loop (issue 30, item 3): a graded pattern to a pressure profile.

* A cylinder with a profile target: on a circle of radius R a ring of n nodes is a regular
  polygon, its springs chords of 2 R sin(pi/n), and the body's reaction over the node's area is
  exactly Laplace's sigma(eps) t / (R (1 + eps_warp)). So each target line on a row has a closed
  answer: eps = sigma^-1(p R (1 + eps_warp) / t), r = 1 - sinc(1/n) / (1 + eps). The loop finds it
  within 0.1 % of the reduction, warp coupling off (a soft warp, lengthwise reduction 0) and on.
* Torso M, hip 15 / waist 20 / underbust 18 / bust 15 mmHg: within 0.5 mmHg after the
  confirmation from scratch, in at most 8 equilibria.
* A target out of reach: one line, exit 2, the best pattern written and marked.
"""

from __future__ import annotations

import csv
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.errors import InputError
from cloth.files.body import body_from_record
from cloth.files.material import load_fabric, material_dataset
from cloth.io import write_netcdf
from cloth.materials.curves import Fabric, StressStrainCurve
from cloth.materials.labtables import Material
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.stages.case import initial_state
from cloth.stages.design import MAX_SOLVES, design
from cloth.stages.graded import confirmed_rows
from tests import crossrefs
from tests.conftest import MMHG_BY_DEFINITION

ROOT = Path(__file__).resolve().parents[1]
RADIUS = 0.1
N = 24
#: Rows at 0.1 + 0.025 j: the lines are rows 3, 6 and 9.
LINES = {"low": 0.175, "middle": 0.25, "high": 0.325}
TARGETS = {"low": 12.0, "middle": 20.0, "high": 15.0}


def _soft_warp(folder: Path) -> Path:
    """powernet's weft with a warp of 1 kPa: the rows barely pull on each other."""
    powernet = load_fabric("powernet", ROOT)
    fabric = Fabric(
        "powernet, soft warp", powernet.weft, StressStrainCurve.linear(1.0e3), powernet.thickness
    )
    return write_netcdf(material_dataset(Material(fabric)), folder / "soft.nc")


def _cylinder_case(material: str, lengthwise: float = 0.0, lines: dict = LINES) -> dict:
    """A power-net tube on the cylinder, rows 2.5 cm apart, girth ``lines`` on rows."""
    return {
        "material": material,
        "body": {"cylinder": {"radius": RADIUS}},
        "landmarks": lines,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "grid": [N, 13],
            "reduction": 0.2,
            "lengthwise_reduction": lengthwise,
            "error_estimate": False,
        },
        "solver": {"tolerance": 1.0e-12},
        # a band within the line's own row's span (rows 2.5 cm apart): the row's pressure alone,
        # so that Laplace's law row by row is the answer (a 2 cm band mixes graded rows)
        "girth_reading": {"half_width": 0.01},
    }


def _cylinder_design(material: str, lengthwise: float):
    state = initial_state(_cylinder_case(material, lengthwise), ROOT)
    targets = [Target(line, p * MMHG) for line, p in TARGETS.items()]
    return design(state, body_from_record(state.body), targets, tolerance=0.01 * MMHG)


def _laplace_reduction(fabric: Fabric, pressure: float, strain_warp: float) -> float:
    curve = fabric.weft
    stress = pressure * RADIUS * (1.0 + strain_warp) / fabric.thickness
    strain = float(np.interp(stress, curve.knot_stress, curve.knot_strain))
    return 1.0 - np.sinc(1.0 / N) / (1.0 + strain)


@pytest.mark.parametrize("coupling", ["off", "on"])
def test_the_cylinder_design_is_laplace_row_by_row(tmp_path, coupling):
    """Warp off: within 0.1 % of Laplace's reduction on every line (measured: 2e-9). Warp on
    (the power net's warp stretched 11 % by a lengthwise reduction of 0.1): the tension per
    deformed width is 1/(1 + eps_warp) of the rest width's, so the same pressure needs 7.5-7.9 %
    more reduction than uncoupled (0.1429, 0.2044, 0.1686 against 0.1327, 0.1902, 0.1564). The
    closed form with eps_warp from the equilibrium then holds within 0.19 % (measured): the
    warp's areas follow the graded rows, so the warp pulls unequally and the rows move up to
    0.2 mm off the lines, where the line's value is interpolated between rows of other
    reductions. Asserted: 0.1 % off, 0.25 % on."""
    material = str(_soft_warp(tmp_path)) if coupling == "off" else "powernet"
    result = _cylinder_design(material, 0.0 if coupling == "off" else 0.1)
    fabric = load_fabric(material, ROOT)
    assert result.met and result.shortfall is None
    rows = {line: round((z - 0.1) / 0.025) for line, z in LINES.items()}
    warp = _warp_strain(result)
    for k, line in enumerate(result.lines):
        expected = _laplace_reduction(fabric, TARGETS[line] * MMHG, warp[rows[line]])
        assert result.values[k] == pytest.approx(
            expected, rel=1e-3 if coupling == "off" else 2.5e-3
        )
    if coupling == "on":
        assert np.all(warp[1:-1] > 0.05)


def test_a_target_past_the_lab_range_stops_at_its_end_and_says_so(tmp_path):
    """One line, the soft warp (its tension barely changes the rows): the lab curve's last knot
    caps the weft strain, and Laplace's law gives the pressure there in closed form,
    p_cap = sigma_last t / R. A target 2 mmHg past it, with a 0.5 mmHg tolerance, stops at p_cap
    (measured: equal to 1e-9) and reports the shortfall (the bound that binds named)."""
    material = str(_soft_warp(tmp_path))
    fabric = load_fabric(material, ROOT)
    p_cap = float(fabric.weft.knot_stress[-1]) * fabric.thickness / RADIUS
    state = initial_state(_cylinder_case(material, lines={"middle": 0.25}), ROOT)
    target = Target("middle", p_cap + 2.0 * MMHG)
    result = design(state, body_from_record(state.body), [target], tolerance=0.5 * MMHG)
    assert result.achieved[0] == pytest.approx(p_cap, rel=1e-6)
    assert result.shortfall is not None and not result.met
    assert "middle" in result.shortfall and "lab curve" in result.shortfall


def test_the_confirmed_values_are_the_confirmation_file_s(tmp_path):
    """design_confirmed.csv's confirmed column is read from the confirmation's own result.nc
    (here one whose line reads 3 % above the loop's equilibrium), never the loop's value; met
    and the error follow the file too."""
    result = _cylinder_design(str(_soft_warp(tmp_path)), 0.0)
    lines = list(result.lines)
    confirmed = xr.Dataset(
        {
            "pressure_mean": ("landmark", 1.03 * result.achieved),
            "pressure_mean_error": ("landmark", np.full(len(lines), 0.25 * MMHG)),
            "landmark_height": ("landmark", [LINES[line] for line in lines]),
        },
        coords={"landmark": lines},
    )
    path = write_netcdf(confirmed, tmp_path / "result.nc")
    rows = confirmed_rows(result, xr.load_dataset(path))
    for k, row in enumerate(rows):
        assert row["confirmed_mmHg"] == pytest.approx(1.03 * result.achieved[k] / MMHG, rel=1e-12)
        assert row["designed_mmHg"] == pytest.approx(result.achieved[k] / MMHG, rel=1e-12)
        assert row["confirmed_error_mmHg"] == pytest.approx(0.25)
        # its stated 0.25 mmHg is past the 0.01 mmHg tolerance: the grid cannot tell
        assert row["met"] == 0 and row["verdict"] == "grid cannot tell"
        assert row["error_past_tolerance_mmHg"] == pytest.approx(0.25 - 0.01)


def test_every_column_of_design_confirmed_is_its_own_number(tmp_path):
    """Each row of design_confirmed.csv, column by column, from a design whose numbers are
    exact in binary (targets 2048, 4096, 8192 Pa, tolerance 64 Pa), so that a line exactly one
    tolerance off with an error of exactly the tolerance is met, one just past it is missed, and
    one on target whose error is just past the tolerance is undecided by the grid."""
    result = replace(
        _cylinder_design(str(_soft_warp(tmp_path)), 0.0),
        targets=np.array([2048.0, 4096.0, 8192.0]),
        tolerance=64.0,
    )
    lines = list(result.lines)
    offsets = np.array([64.0, -64.0 - 2.0**-30 * 4096.0, 0.0])  # met, missed, on target
    errors = np.array([64.0, 32.0, 64.0 + 2.0**-20 * 64.0])  # at, within, past the tolerance
    confirmed = xr.Dataset(
        {
            "pressure_mean": ("landmark", result.targets + offsets),
            "pressure_mean_error": ("landmark", errors),
            "landmark_height": ("landmark", [LINES[line] for line in lines]),
        },
        coords={"landmark": lines},
    )
    rows = confirmed_rows(result, confirmed)
    knots = [f"reduction_{key}" for key in result.knots]
    assert list(rows[0]) == [
        "landmark",
        "height_m",
        "target_mmHg",
        "designed_mmHg",
        "confirmed_mmHg",
        "confirmed_error_mmHg",
        "tolerance_mmHg",
        "met",
        "verdict",
        "error_past_tolerance_mmHg",
        "uniform_reduction",
        "uniform_mmHg",
        *knots,
        "equilibria",
    ]
    mmhg = 133.322387415  # Pa, by definition (13.5951 g/cm3 x 9.80665 m/s2 x 1 mm)
    for k, row in enumerate(rows):
        assert row["landmark"] == lines[k]
        assert row["height_m"] == LINES[lines[k]]
        assert row["target_mmHg"] == pytest.approx(result.targets[k] / mmhg, rel=1e-9)
        assert row["tolerance_mmHg"] == pytest.approx(64.0 / mmhg, rel=1e-9)
        assert row["confirmed_error_mmHg"] == pytest.approx(errors[k] / mmhg, rel=1e-9)
        assert row["uniform_reduction"] == result.uniform[0]
        assert row["uniform_mmHg"] == pytest.approx(result.uniform[1][k] / mmhg, rel=1e-9)
        assert [row[key] for key in knots] == list(result.values)
        assert row["equilibria"] == result.solves + 1
    assert [row["met"] for row in rows] == [1, 0, 0]
    assert [row["verdict"] for row in rows] == ["met", "missed", "grid cannot tell"]
    past = [row["error_past_tolerance_mmHg"] for row in rows]
    assert past[:2] == [0.0, 0.0] and past[2] == pytest.approx(2.0**-20 * 64.0 / mmhg, rel=1e-6)


@pytest.mark.parametrize(
    ("miss", "error", "verdict", "past"),
    [
        (0.5, 0.5, "met", 0.0),  # both at the tolerance
        (-0.5, 0.25, "met", 0.0),
        (0.5 + 1e-9, 0.5, "missed", 0.0),  # off by just past it, the grid can tell
        (-0.51, 0.0, "missed", 0.0),
        (0.0, 0.5 + 1e-9, "grid cannot tell", 1e-9),  # on target, the error just past it
        (3.0, 3.7, "grid cannot tell", 3.2),  # the stocking's B: 3.7 mmHg stated, 0.5 asked
        (0.0, float("nan"), "grid cannot tell", float("nan")),  # no error stated
    ],
)
def test_a_line_is_met_only_when_its_stated_error_is_within_the_tolerance(
    miss, error, verdict, past
):
    """Issue 54: `met` only where the confirmed value is within the tolerance and so is its
    stated error; otherwise the grid cannot tell, by the error's excess (mmHg; here with a
    tolerance of 0.5 mmHg, every number in mmHg)."""
    from cloth.stages.graded import judge_confirmed

    judged = judge_confirmed(miss * MMHG, error * MMHG, 0.5 * MMHG)
    assert judged["verdict"] == verdict and judged["met"] == int(verdict == "met")
    if np.isnan(past):
        assert np.isnan(judged["error_past_tolerance_mmHg"])
    else:
        assert judged["error_past_tolerance_mmHg"] == pytest.approx(past, abs=1e-12)


def test_the_tolerance_given_on_the_line_is_the_design_s(tmp_path):
    """``cloth design --tolerance 0.8``: the loop stops within 0.8 mmHg and
    design_confirmed.csv says so (the default is 0.5)."""
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": RADIUS}},
        "landmarks": {"middle": 0.25},
        "garment": {"bottom": 0.1, "top": 0.4, "grid": [16, 7], "reduction": 0.2},
    }
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    command = [sys.executable, "-m", "cloth", "--log-level", "ERROR", "design"]
    command += [str(tmp_path / "case.yaml"), "--target", "middle=20", "--tolerance", "0.8"]
    done = subprocess.run([*command, "-o", str(tmp_path / "out")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    (row,) = _rows(tmp_path / "out" / "design_confirmed.csv")
    assert float(row["tolerance_mmHg"]) == pytest.approx(0.8)
    with xr.open_dataset(tmp_path / "out" / "confirmed" / "result.nc") as ds:
        value = float(ds["pressure_mean"].sel(landmark="middle")) / MMHG
    assert row["confirmed_mmHg"] == f"{value:.6g}"  # read from the confirmation's file


@pytest.mark.parametrize("text", ["hip=1e400", "hip=inf", "hip=nan", "hip=-inf"])
def test_a_target_that_is_not_a_finite_number_is_refused(text):
    with pytest.raises(InputError, match="not a target") as caught:
        Target.parse(text)
    assert caught.value.field == "--target"


def _warp_strain(result) -> np.ndarray:
    """(m,) the mean warp strain at each row of the design's equilibrium."""
    from cloth.garment.grid import WARP
    from cloth.garment.mechanics import spring_state

    grid = result.state.grid
    strain = spring_state(result.state.x, grid).strain[grid.family_slices[WARP]]
    per_cell = strain.reshape(grid.m - 1, grid.n).mean(axis=1)
    return np.concatenate(([per_cell[0]], 0.5 * (per_cell[1:] + per_cell[:-1]), [per_cell[-1]]))


def _run_design(folder: Path, grid: list[int], targets: list[str]) -> subprocess.CompletedProcess:
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {"bottom": 0.86, "top": 1.22, "grid": grid, "reduction": 0.2},
    }
    (folder / "case.yaml").write_text(yaml.safe_dump(case))
    command = [
        sys.executable,
        "-m",
        "cloth",
        "--log-level",
        "ERROR",
        "design",
        str(folder / "case.yaml"),
        "-o",
        str(folder / "out"),
    ]
    command += [f"--target={t}" for t in targets]
    return subprocess.run(command, capture_output=True, text=True, cwd=ROOT)


def _rows(path: Path) -> list[dict[str, str]]:
    """A written table's rows, its ``#`` comment lines (a pattern's girth lines) left out."""
    with path.open() as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


@pytest.mark.slow  # a 96 x 48 torso design (16 s; the in-process cylinder design is fast)
def test_the_torso_profile_is_met_after_confirmation_in_eight_equilibria(tmp_path):
    done = _run_design(tmp_path, [96, 48], ["hip=15", "waist=20", "underbust=18", "bust=15"])
    assert done.returncode == 0, done.stderr[-2000:]
    rows = _rows(tmp_path / "out" / "design_confirmed.csv")
    assert [r["landmark"] for r in rows] == ["hip", "waist", "underbust", "bust"]
    for row in rows:
        assert abs(float(row["confirmed_mmHg"]) - float(row["target_mmHg"])) <= 0.5
        decided = float(row["confirmed_error_mmHg"]) <= 0.5  # NaN: not decided (issue 54)
        assert (row["met"], row["verdict"]) == (
            ("1", "met") if decided else ("0", "grid cannot tell")
        )
        assert int(row["equilibria"]) <= MAX_SOLVES
    # the uniform answer misses the profile; the graded one is graded
    assert max(abs(float(r["uniform_mmHg"]) - float(r["target_mmHg"])) for r in rows) > 3
    designed = yaml.safe_load((tmp_path / "out" / "case.yaml").read_text())
    assert set(designed["garment"]["reduction"]) == {"hip", "waist", "underbust", "bust"}
    confirmed = xr.load_dataset(tmp_path / "out" / "confirmed" / "result.nc")
    assert float(np.ptp(confirmed["row_reduction"].values)) > 0.05
    for name in ("pattern.csv", "pattern.svg", "design_profile.png", "design_iterations.csv"):
        assert (tmp_path / "out" / name).stat().st_size > 0


@pytest.mark.slow  # the CLI's design (8 s); the in-process out-of-reach test is fast
def test_an_unreachable_target_is_one_line_and_the_best_pattern_is_written(tmp_path):
    """bust 150 mmHg: the bust's knot stops where the weft reaches the power net's last lab
    strain (0.8); the other lines are still met. (80 mmHg, the issue's example, is reachable on
    the bust edge row: reduction 0.42, 86 mmHg at the lab range's end; docs/outputs.md.)"""
    done = _run_design(tmp_path, [48, 24], ["waist=20", "bust=150"])
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cloth: error: "), done.stderr
    assert "bust" in lines[0] and "not reached" in lines[0] and "lab curve" in lines[0]
    rows = {r["landmark"]: r for r in _rows(tmp_path / "out" / "design_confirmed.csv")}
    assert rows["bust"]["met"] == "0" and rows["bust"]["verdict"] != "met"
    waist = rows["waist"]  # met where the grid can tell (issue 54)
    decided = float(waist["confirmed_error_mmHg"]) <= 0.5
    assert waist["verdict"] == ("met" if decided else "grid cannot tell")
    assert float(rows["bust"]["confirmed_mmHg"]) < 150
    assert (tmp_path / "out" / "pattern.csv").is_file()


@pytest.mark.parametrize(
    ("text", "pressure"),
    [
        ("waist=20", 20 * MMHG),
        ("hip=2.0kPa", 2000.0),
        ("bust=1500Pa", 1500.0),
        ("a=1.5e1mmHg", 15 * MMHG),
    ],
)
def test_targets_read_in_mmhg_kpa_or_pa(text, pressure):
    target = Target.parse(text)
    assert target.pressure == pytest.approx(pressure)


@pytest.mark.parametrize(
    "text",
    [
        "waist",
        "waist=20psi",
        *(pytest.param(t, marks=pytest.mark.slow) for t in ("waist=", "waist=-3", "=20")),
    ],
)
def test_a_bad_target_is_one_line(tmp_path, text):
    done = _run_design(tmp_path, [12, 6], [text])
    assert done.returncode == 2 and "--target" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not (tmp_path / "out").exists()


def test_a_design_on_soft_tissue_is_refused_before_any_equilibrium():
    """The adjoint takes a rigid smooth body: tissue is named in one line, nothing solved."""
    case = {
        "material": "powernet",
        "landmarks": LINES,
        "body": {"cylinder": {"radius": RADIUS}, "tissue": {"thickness": 0.01, "modulus": 2e4}},
        "garment": {"bottom": 0.1, "top": 0.4, "grid": [12, 5], "reduction": 0.2},
    }
    state = initial_state(case, ROOT)
    with pytest.raises(InputError, match=r"body\.tissue"):
        design(state, body_from_record(state.body), [Target("middle", 20 * MMHG)])


def test_a_target_at_a_height_becomes_a_girth_line(tmp_path):
    """A target profile over height (``0.25=20``): the line at 0.25 m joins the case's lines
    and gets Laplace's reduction, as a named one does."""
    case = {
        "material": str(_soft_warp(tmp_path)),
        "body": {"cylinder": {"radius": RADIUS}},
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "grid": [N, 13],
            "reduction": 0.2,
            "error_estimate": False,
        },
        "solver": {"tolerance": 1.0e-12},
    }
    state = initial_state(case, ROOT)
    result = design(state, body_from_record(state.body), [Target.parse("0.25=20")], 0.01 * MMHG)
    assert result.lines == ("0.25",) and result.state.case.landmarks == {"0.25": 0.25}
    fabric = load_fabric(case["material"], ROOT)
    expected = _laplace_reduction(fabric, 20 * MMHG, 0.0)
    assert result.values[0] == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize(
    ("body", "cut", "expected"),
    [
        ({"leg": {"size": "M"}}, "auto", "tube"),  # a stocking is knitted in the round
        ({"torso": {"size": "M"}}, "auto", "two-panel"),
        ({"cylinder": {"radius": 0.1}}, "auto", "two-panel"),
        ({"leg": {"size": "M"}}, "two-panel", "two-panel"),
        ({"torso": {"size": "M"}}, "tube", "tube"),
    ],
)
def test_the_cut_auto_is_a_tube_on_a_leg_and_two_panels_elsewhere(body, cut, expected):
    from cloth.case.case import validate_case
    from cloth.stages.graded import cut_of

    case = validate_case(
        {
            "material": "powernet",
            "body": body,
            "garment": {"bottom": 0.3, "top": 0.5, "reduction": 0.15, "grid": [16, 8]},
        }
    )
    assert cut_of(case, cut) == expected
    with pytest.raises(InputError) as caught:
        cut_of(case, "spiral")
    assert caught.value.field == "--cut"
    assert "unknown cut 'spiral'; give auto or one of two-panel, tube" in str(caught.value)


def _design_in_process(
    tmp_path: Path, targets: dict[str, float], grid=(16, 7), estimate=False, **options
):
    """`design_files` run in this process on a tube on the cylinder (16 x 7 unless given, two
    lines, no error estimate unless asked), its lab table beside the case (a relative path),
    into a folder two levels down: the outcome, or the error it raised after writing its files,
    and the output folder."""
    from cloth.stages.graded import design_files

    (tmp_path / "tables").mkdir(parents=True, exist_ok=True)
    (tmp_path / "tables" / "net.csv").write_text((ROOT / "data/materials/powernet.csv").read_text())
    case = {
        "material": "tables/net.csv",
        "body": {"cylinder": {"radius": RADIUS}},
        # a line below the targets': a row read at a target's position, not its name, is off
        "landmarks": {"hem": 0.15, "low": 0.2, "high": 0.3},
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "grid": list(grid),
            "reduction": {"low": 0.2, "high": 0.2},
            "error_estimate": estimate,
        },
    }
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    goals = [Target(line, p * MMHG) for line, p in targets.items()]
    out = tmp_path / "designs" / "style"
    try:
        return design_files(tmp_path / "case.yaml", goals, out, **options), out
    except InputError as error:
        return error, out


def test_a_graded_design_s_files_are_its_loop_and_its_confirmation_in_process(tmp_path, caplog):
    """design_iterations.csv: one row per equilibrium of the loop, its knots and line means,
    the last the designed case's knots and the loop's values; design_confirmed.csv the
    confirmation's own result.nc; the pattern files in the cut, allowance and paper asked, the
    nest named after the folder and noting the targets; the log line counts the equilibria."""
    import logging

    caplog.set_level(logging.INFO, logger="cloth.stages.graded")
    result, out = _design_in_process(
        tmp_path, {"low": 18.0, "high": 22.0}, allowance=0.0, paper="letter"
    )
    with open(out / "design_iterations.csv", newline="") as handle:
        iterations = list(csv.DictReader(handle))
    assert [int(r["equilibrium"]) for r in iterations] == list(range(1, len(result.iterates) + 1))
    assert len(iterations) == result.solves  # a graded start: no uniform equilibrium
    for row, iterate in zip(iterations, result.iterates, strict=True):
        assert int(row["newton_iterations"]) == iterate.iterations
    last = iterations[-1]
    designed = yaml.safe_load((out / "case.yaml").read_text())
    assert designed["material"] == "../../tables/net.csv"  # relative to the design's folder
    confirmed = xr.load_dataset(out / "confirmed" / "result.nc")
    assert not (out / "confirmed" / "figures").exists()  # confirmed up to aggregate only
    # every row's line read by name in its source: its height and values (tests/crossrefs.py)
    assert crossrefs.problems(out / "design_confirmed.csv") == []
    assert crossrefs.problems(out / "confirmed" / "summary.csv") == []
    with open(out / "design_confirmed.csv", newline="") as handle:
        rows = {r["landmark"]: r for r in csv.DictReader(handle)}
    for line, target in (("low", 18.0), ("high", 22.0)):
        assert float(last[f"reduction_{line}"]) == pytest.approx(
            designed["garment"]["reduction"][line], rel=1e-5
        )
        assert float(last[f"{line}_mmHg"]) == pytest.approx(
            float(rows[line]["designed_mmHg"]), rel=1e-5
        )
        value = float(confirmed["pressure_mean"].sel(landmark=line)) / MMHG_BY_DEFINITION
        assert float(rows[line]["confirmed_mmHg"]) == pytest.approx(value, rel=1e-5)
        assert abs(value - target) <= 0.5  # met by the value, but no error stated (16 x 7):
        assert rows[line]["met"] == "0" and rows[line]["verdict"] == "grid cannot tell"
        assert rows[line]["error_past_tolerance_mmHg"] == "nan"
        assert float(rows[line]["target_mmHg"]) == pytest.approx(target)
        assert int(rows[line]["equilibria"]) == len(iterations) + 1
    with open(out / "pattern.csv", newline="") as handle:
        pattern = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    np.testing.assert_allclose(
        [float(r["rest_circumference_mm"]) for r in pattern],
        1e3 * confirmed["rest_circumference"].values,
        atol=1e-4,
    )
    assert {r["cut"] for r in pattern} == {"two-panel"}  # auto on a cylinder
    files = {p.name for p in out.iterdir()}
    assert {"pattern.svg", "pattern.pdf", "pattern_astm.dxf"} <= files
    assert "pattern_knitting.csv" not in files  # two panels are not knitted in the round
    nest = (out / "pattern_astm.dxf").read_text(errors="replace")
    assert "pressure targets (mmHg): low 18, high 22" in nest
    assert "Style Name: style" in nest and "Seam Allowance: 0 mm" in nest
    media = (out / "pattern.pdf").read_bytes()
    assert b"/MediaBox [ 0 0 612 792 ]" in media or b"/MediaBox [0 0 612 792]" in media
    assert (out / "design_profile.png").stat().st_size > 10_000
    equilibria = result.solves + 1
    logged = (
        f"design: NOT every target met (2 grid cannot tell) in {equilibria} equilibria "
        f"({result.solves} in the loop, 1 confirmation)"
    )
    assert logged in caplog.text and "no DXF" not in caplog.text
    assert "high: confirmed" in caplog.text and "the confirmation states no error" in caplog.text


@pytest.mark.parametrize("tolerance", [0.5, 1.0])
def test_a_coarse_design_whose_error_exceeds_its_tolerance_is_not_met(tmp_path, tolerance):
    """Issue 54: the tube on the cylinder at 32 x 13 with its error estimate states 0.58-0.80
    mmHg (measured) on lines the loop meets to 0.01 mmHg: at a tolerance of 0.5 mmHg neither
    line is met, the grid cannot tell, by the confirmation's own stated error less 0.5; at
    1.0 mmHg both are met. Neither ends in an error."""
    result, out = _design_in_process(
        tmp_path,
        {"low": 18.0, "high": 22.0},
        grid=(32, 13),
        estimate=True,
        tolerance=tolerance * MMHG,
    )
    assert not isinstance(result, InputError), result
    confirmed = xr.load_dataset(out / "confirmed" / "result.nc")
    with open(out / "design_confirmed.csv", newline="") as handle:
        rows = {r["landmark"]: r for r in csv.DictReader(handle)}
    errors = confirmed["pressure_mean_error"].sel(landmark=["low", "high"]).values
    errors = errors / MMHG_BY_DEFINITION
    assert 0.5 < errors.min() and errors.max() < 1.0  # the measured 0.58-0.80 mmHg
    for line, error in zip(("low", "high"), errors, strict=True):
        row = rows[line]
        value = float(confirmed["pressure_mean"].sel(landmark=line)) / MMHG_BY_DEFINITION
        assert abs(value - float(row["target_mmHg"])) < 0.5  # within either tolerance
        if tolerance == 0.5:
            assert (row["met"], row["verdict"]) == ("0", "grid cannot tell")
            assert float(row["error_past_tolerance_mmHg"]) == pytest.approx(error - 0.5, rel=1e-4)
        else:
            assert (row["met"], row["verdict"]) == ("1", "met")
            assert float(row["error_past_tolerance_mmHg"]) == 0.0


def test_a_target_out_of_reach_is_refused_after_the_files_are_written(tmp_path):
    """A low line at 150 mmHg, past the lab curve: one error naming the case and the targets,
    the best pattern's files written (into an output folder that already exists)."""
    (tmp_path / "designs" / "style").mkdir(parents=True)
    error, out = _design_in_process(tmp_path, {"low": 150.0, "high": 20.0})
    assert isinstance(error, InputError) and error.field == "targets"
    assert str(error.source) == str(tmp_path / "case.yaml")
    assert "low" in str(error) and "not reached" in str(error)
    assert (out / "design_confirmed.csv").is_file() and (out / "pattern.csv").is_file()
    (tmp_path / "none").mkdir()
    error, _ = _design_in_process(tmp_path / "none", {})
    assert isinstance(error, InputError) and error.field == "--target"
    assert "give at least one target, e.g. --target waist=20" in str(error)


def test_a_design_confirmed_off_its_target_names_the_worst_line(caplog):
    """The loop met its targets but the confirmation from scratch did not: the error names the
    missed line furthest off, its confirmed value and its target +- the tolerance, in mmHg; a
    line the grid cannot decide is a warning naming its excess error, not an error."""
    import logging
    from types import SimpleNamespace

    from cloth.stages.graded import raise_unmet

    rows = [
        {"landmark": "low", "confirmed_mmHg": 18.2, "target_mmHg": 18.0, "verdict": "met"},
        # missed, by less (0.6 mmHg, though its value is larger) and first: not the one named
        {"landmark": "mid", "confirmed_mmHg": 30.6, "target_mmHg": 30.0, "verdict": "missed"},
        {"landmark": "high", "confirmed_mmHg": 21.1, "target_mmHg": 22.0, "verdict": "missed"},
        {"landmark": "top", "confirmed_mmHg": 14.5, "target_mmHg": 15.0, "verdict": "met"},
        # furthest off, but undecided by the grid: a warning, not the error
        {
            "landmark": "edge",
            "confirmed_mmHg": 12.0,
            "target_mmHg": 15.0,
            "confirmed_error_mmHg": 4.0,
            "error_past_tolerance_mmHg": 3.5,
            "verdict": "grid cannot tell",
        },
    ]
    done = SimpleNamespace(shortfall=None)
    with pytest.raises(InputError) as caught:
        raise_unmet(done, rows, 0.5 * MMHG, "case.yaml")
    assert str(caught.value.source) == "case.yaml" and caught.value.field == "targets"
    assert "high: confirmed at 21.10 mmHg from scratch, target 22.00 +- 0.5 mmHg" in str(
        caught.value
    )
    assert "differ (see design_confirmed.csv)" in str(caught.value)
    met = [{**row, "verdict": "met"} for row in rows]
    raise_unmet(done, met, 0.5 * MMHG, "case.yaml")  # no error
    undecided = [{**row, "verdict": "met"} for row in rows[:3]] + rows[3:]
    caplog.set_level(logging.WARNING, logger="cloth.stages.graded")
    raise_unmet(done, undecided, 0.5 * MMHG, "case.yaml")  # no error either
    assert (
        "case.yaml: edge: confirmed 12.00 +- 4.00 mmHg, target 15.00 +- 0.5 mmHg: the grid "
        "cannot tell whether it is met (its stated error is 3.50 mmHg past the tolerance)"
    ) in caplog.text
    with pytest.raises(InputError) as short:
        raise_unmet(SimpleNamespace(shortfall="bust: not reached"), rows, 1.0, "c.yaml")
    assert str(short.value).endswith("bust: not reached") and short.value.field == "targets"
    assert str(short.value.source) == "c.yaml"
