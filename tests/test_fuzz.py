"""Bad input never gets past the door, as a property: a mutated case, lab table or mesh file
either runs (exit 0) or is refused in one line with exit 2, leaving no file where the output was
asked for, and never raises past the command (a traceback). Strategies: tests/fuzz.py.

``make test`` draws 30 examples per target (200 for the case's validation alone, which is
cheap); ``make test-slow`` 200 per target. Draws are derandomised, so a run is reproducible;
hypothesis' database (.hypothesis/) is not committed.
"""

from __future__ import annotations

import contextlib
import io
import tempfile
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings

from cloth.case import Case
from cloth.cli import main
from cloth.errors import InputError
from cloth.pipeline.config import validate_case
from tests.fuzz import TINY, bad_cases, corrupted_text

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


def assert_ran_or_refused(code: int, err: str, output: Path) -> None:
    """The property: exit 0, or exit 2 with one line and nothing written at ``output``."""
    if code == 0:
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
            assert_ran_or_refused(code, err, out)

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
    assert len(err) < 400 and not (tmp_path / "out").exists()


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
