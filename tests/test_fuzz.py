"""Bad input never gets past the door, as a property: a mutated case, lab table, mesh file, leg
chart, command-line path or design target is either refused in one line with exit 2, leaving no
file where the output was asked for, or accepted as what its validator accepts (a case equal to
the one `validate_case` types, a chart `leg_size` reads, a target `Target.parse` reads), and
never raises past the command (a traceback). Strategies: tests/fuzz.py.

``make test`` draws 30 examples per target (200 for the case's validation alone, which is
cheap); ``make test-slow`` 200 per target. Draws are derandomised, so a run is reproducible;
hypothesis' database (.hypothesis/) is not committed.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from hypothesis import HealthCheck, given, settings

from cloth.bodies.leg import POINTS, leg_size
from cloth.case import Case
from cloth.case.case import validate_case
from cloth.cli import main
from cloth.errors import InputError
from cloth.files.material import KIND, fabric_from_dataset
from cloth.io import read_netcdf
from cloth.results.targets import Target
from tests.fuzz import TINY, bad_cases, corrupted_text, odd_paths, odd_targets

ROOT = Path(__file__).resolve().parents[1]
TABLE = (ROOT / "data" / "materials" / "powernet.csv").read_text()
COUNTS = [pytest.param(30, id="30"), pytest.param(200, id="200", marks=pytest.mark.slow)]


def _settings(count: int):
    return settings(
        max_examples=count,
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


def run_cloth(*args: str) -> tuple[int, str]:
    """``cloth ARGS`` in this process: (exit status, what it printed on stderr)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        try:
            code = main(["--log-level", "ERROR", *args])
        except SystemExit as exc:  # argparse's refusal of a malformed argument
            code = exc.code
    return code, err.getvalue()


def assert_ran_or_refused(code: int, err: str, output: Path, writes: bool = True) -> None:
    """Exit 0 (the caller checks what was accepted; the command wrote ``output`` where it
    ``writes`` one), or exit 2 with one line and nothing written at ``output``."""
    if code == 0:
        assert output.exists() or not writes, f"accepted, but nothing written at {output}"
        return
    assert code == 2, f"exit {code}: {err}"
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cloth: error: "), err
    left = [p for p in output.rglob("*")] if output.is_dir() else [output] * output.exists()
    assert left == [], f"a refusal left {left}"


@pytest.mark.parametrize("count", [200])
def test_a_mutated_case_is_typed_or_refused_naming_a_field(count):
    @_settings(count)
    @given(bad_cases())
    def check(case):
        try:
            typed = validate_case(case, "fuzz.yaml")
        except InputError as exc:
            assert exc.source == "fuzz.yaml" and "\n" not in str(exc)
        else:
            assert isinstance(typed, Case)

    check()


@pytest.mark.parametrize("count", COUNTS)
def test_a_mutated_case_runs_or_is_refused_in_one_line(count):
    @_settings(count)
    @given(bad_cases())
    def check(case):
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "case.yaml"
            path.write_text(yaml.safe_dump(case, allow_unicode=True))
            out = Path(tmp) / "out"
            code, err = run_cloth("run", str(path), "-o", str(out), "--base-dir", str(ROOT))
            assert_ran_or_refused(code, err, out)
            if code == 0:  # accepted: the case the validator types, and the one the run used
                typed = validate_case(yaml.safe_load(path.read_text()), path)
                with xr.open_dataset(out / "initial.nc") as initial:
                    used = json.loads(initial.attrs["case"])
                assert used == json.loads(json.dumps(typed.to_dict(), sort_keys=True))

    check()


@pytest.mark.parametrize("count", COUNTS)
def test_a_corrupted_lab_table_is_ingested_or_refused_in_one_line(count):
    @_settings(count)
    @given(corrupted_text(TABLE))
    def check(text):
        with tempfile.TemporaryDirectory() as tmp:
            table, out = Path(tmp) / "table.csv", Path(tmp) / "m.nc"
            table.write_text(text)
            code, err = run_cloth("material", "ingest", str(table), "-o", str(out))
            assert_ran_or_refused(code, err, out)
            if code == 0:  # accepted: curves a fabric is made of, every number finite
                fabric = fabric_from_dataset(read_netcdf(out, KIND))
                for curve in (fabric.weft, fabric.warp):
                    assert np.all(np.isfinite(curve.knot_stress))
                    assert np.all(np.diff(curve.knot_strain) > 0)

    check()


@pytest.fixture(scope="module")
def mesh_text(tmp_path_factory) -> str:
    """A small torso as an ASCII OBJ (16 points around, 12 rings)."""
    path = tmp_path_factory.mktemp("mesh") / "torso.obj"
    assert (
        main(["body", "torso", "--size", "M", "--around", "16", "--rings", "12", "-o", str(path)])
        == 0
    )
    return path.read_text()


@pytest.mark.parametrize("count", COUNTS)
def test_a_corrupted_mesh_is_checked_or_refused_in_one_line(count, mesh_text):
    @_settings(count)
    @given(corrupted_text(mesh_text))
    def check(text):
        with tempfile.TemporaryDirectory() as tmp:
            mesh = Path(tmp) / "body.obj"
            mesh.write_text(text)
            out = Path(tmp) / "curvature.png"
            code, err = run_cloth("body", "check", str(mesh), "--surface", "mesh")
            assert_ran_or_refused(code, err, out, writes=False)

    check()


def test_the_tiny_case_runs():
    """The fuzzer's starting point is valid, so its mutations test what they change."""
    assert isinstance(validate_case(TINY), Case)


def test_a_non_finite_solver_number_is_refused_before_any_file(tmp_path):
    """Regression: ``solver.tolerance: .inf`` passed the schema and was refused only when relax
    started, after initial.nc was written."""
    case = {**TINY, "solver": {"tolerance": float("inf")}}
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    code, err = run_cloth(
        "run", str(tmp_path / "case.yaml"), "-o", str(tmp_path / "out"), "--base-dir", str(ROOT)
    )
    assert code == 2 and "solver.tolerance" in err
    message = err.strip().split("solver.tolerance: ", 1)[1]  # the message alone, not the path
    assert "is not a finite number" in message
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("key", ["tolerance", "max_iterations"])
@pytest.mark.parametrize("value", [float("inf"), float("nan"), float("-inf")])
def test_the_validator_refuses_a_number_that_is_not_finite(key, value):
    """YAML's .inf and .nan pass JSON Schema's number type and its bounds (NaN compares false):
    the validator's own finite check names the key."""
    case = {**TINY, "solver": {key: value}}
    with pytest.raises(InputError) as caught:
        validate_case(case, "case.yaml")
    assert caught.value.field == f"solver.{key}"
    assert "not a finite number" in caught.value.detail


def test_a_path_with_a_nul_character_is_refused_in_one_line(capsys, tmp_path):
    """A NUL cannot be in a path (the OS refuses it with ValueError, a traceback): it is named
    before any work, from the command line and from a case."""

    assert main(["body", "torso", "--size", "M", "-o", str(tmp_path / "a\0b.ply")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "NUL" in err[0] and "--output" in err[0]
    case = {**TINY, "body": {"mesh": "scan\0.obj"}}
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    assert main(["run", str(tmp_path / "case.yaml"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "NUL" in err[0] and "body.mesh" in err[0]
    assert not list(tmp_path.glob("a*")) and not (tmp_path / "out").exists()


def test_a_material_name_too_long_for_a_path_is_refused_in_one_line(tmp_path):
    """Regression: a 5,000-character material name ended in OSError (File name too long), exit
    status 1."""
    case = {**TINY, "material": "x" * 5000}
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    code, err = run_cloth(
        "run", str(tmp_path / "case.yaml"), "-o", str(tmp_path / "out"), "--base-dir", str(ROOT)
    )
    assert code == 2 and len(err.strip().splitlines()) == 1 and "material" in err
    # the name is shortened in the message; the case's own path, whatever its length, is not
    assert "x" * 300 not in err and len(err.replace(str(tmp_path), "")) < 400
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    ("make", "output", "says"),
    [
        (lambda d: (d / "f.txt").write_text("x"), "f.txt/out", "is a file"),
        (lambda d: (d / "f.txt").write_text("x"), "f.txt", "is a file; give a folder"),
        (lambda d: None, "", "give a path"),
    ],
)
def test_an_output_folder_that_cannot_be_is_refused_before_any_work(tmp_path, make, output, says):
    make(tmp_path)
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(TINY))
    target = str(tmp_path / output) if output else ""
    code, err = run_cloth("run", str(tmp_path / "case.yaml"), "-o", target, "--base-dir", str(ROOT))
    assert code == 2 and "output" in err and says in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("body", "field", "says"),
    [
        ({"mesh": "nowhere.obj"}, "body.mesh", "not found"),
        ({"mesh": "data"}, "body.mesh", "is a folder"),
        ({"torso": {"size": "M", "chart": "data/bodies"}}, "body.torso.chart", "is a folder"),
    ],
)
def test_a_case_path_is_checked_as_a_path(tmp_path, body, field, says):
    case = {**TINY, "body": body}
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    code, err = run_cloth(
        "run", str(tmp_path / "case.yaml"), "-o", str(tmp_path / "out"), "--base-dir", str(ROOT)
    )
    assert code == 2 and field in err and says in err and not (tmp_path / "out").exists()


def test_a_material_table_beside_a_case_in_a_relative_folder_is_found(tmp_path, monkeypatch):
    """A case in ``cases/`` naming ``my.csv`` reads ``cases/my.csv`` (relative to the case's
    folder, once), also when that folder is given relative to the working directory."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "cases").mkdir()
    (tmp_path / "cases" / "my.csv").write_text(TABLE)
    (tmp_path / "cases" / "case.yaml").write_text(yaml.safe_dump({**TINY, "material": "my.csv"}))
    code, err = run_cloth("run", "cases/case.yaml", "-o", "out", "--stop-after", "predeform")
    assert code == 0, err
    assert (tmp_path / "out" / "initial.nc").is_file()


LEG_CHART = (ROOT / "data" / "bodies" / "leg_chart.csv").read_text()


@pytest.mark.parametrize("count", COUNTS)
def test_a_corrupted_leg_chart_is_a_leg_or_refused_in_one_line(count):
    """Accepted: the chart `leg_size` reads, every circumference and height finite and
    positive, and the mesh written."""

    @_settings(count)
    @given(corrupted_text(LEG_CHART))
    def check(text):
        with tempfile.TemporaryDirectory() as tmp:
            chart, out = Path(tmp) / "legs.csv", Path(tmp) / "leg.ply"
            chart.write_text(text)
            args = ["body", "leg", "--size", "M", "--chart", str(chart), "--around", "12"]
            code, err = run_cloth(*args, "--rings", "20", "-o", str(out))
            assert_ran_or_refused(code, err, out)
            if code == 0:
                leg = leg_size("M", chart)
                for point in POINTS:
                    assert math.isfinite(leg.girth[point]) and leg.girth[point] > 0
                    assert math.isfinite(leg.height[point]) and leg.height[point] > 0

    check()


@pytest.mark.parametrize("count", COUNTS)
def test_an_odd_output_path_is_written_there_or_refused_in_one_line(count):
    """A path as users type them (empty, a NUL, too long, under a file, a folder, unicode):
    accepted means the file is at that path."""

    @_settings(count)
    @given(odd_paths())
    def check(name):
        with tempfile.TemporaryDirectory() as tmp:
            (Path(tmp) / "a_file").write_text("x")
            (Path(tmp) / "a_folder").mkdir()
            target = Path(tmp) / name if name else Path("")
            code, err = run_cloth(
                "body", "torso", "--size", "S", "--around", "12", "--rings", "10", "-o", str(target)
            )
            if code == 0:
                assert target.is_file() and target.stat().st_size > 0
            else:
                assert code == 2, f"exit {code}: {err}"
                lines = err.strip().splitlines()
                assert len(lines) == 1 and lines[0].startswith("cloth: error: "), err
                assert sorted(p.name for p in Path(tmp).iterdir()) == ["a_file", "a_folder"]

    check()


@pytest.mark.parametrize("count", COUNTS)
def test_a_design_target_is_read_as_the_parser_reads_it_or_refused_in_one_line(count, tmp_path):
    """``--target`` text: what `Target.parse` refuses, ``cloth design`` refuses in one line
    before any work (no output folder); what it reads is a named line at a finite positive
    pressure that reads back the same in Pa."""
    case = tmp_path / "case.yaml"
    case.write_text(yaml.safe_dump(TINY))

    @_settings(count)
    @given(odd_targets())
    def check(text):
        try:
            target = Target.parse(text)
        except InputError as exc:
            assert exc.field == "--target" and "\n" not in str(exc)
            out = tmp_path / "out"
            code, err = run_cloth("design", str(case), f"--target={text}", "-o", str(out))
            assert code == 2 and len(err.strip().splitlines()) == 1 and "--target" in err, err
            assert not out.exists()
        else:
            assert target.line and math.isfinite(target.pressure) and target.pressure > 0
            again = Target.parse(f"{target.line}={target.pressure!r}Pa")
            assert again == target

    check()


@pytest.mark.parametrize(
    ("name", "says"),
    [("out.ply/../out.ply", "goes up (..) out of"), ("out.ply/..", "goes up (..) out of")],
)
def test_an_output_going_up_out_of_a_folder_not_yet_made_is_refused(tmp_path, name, says):
    """Regressions the path fuzzer found: ``-o out.ply/../out.ply`` made the folder out.ply,
    then could not rename onto it (IsADirectoryError); ``-o out.ply/..`` renamed onto '..'."""
    code, err = run_cloth("body", "torso", "--size", "S", "-o", str(tmp_path / name))
    assert code == 2 and says in err and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
