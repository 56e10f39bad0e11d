"""The stages behind the CLI: a diverged relaxation's file and exit status, and `cloth run`'s
folder of every stage's files."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import xarray as xr
import yaml

import cloth.solvers
import cloth.stages.case
from cloth.cli import main
from cloth.errors import EXIT_DIVERGED

ROOT = Path(__file__).resolve().parents[1]


def _case(tmp_path):
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [24, 4]},
    }
    (tmp_path / "case.yaml").write_text(yaml.safe_dump(case))
    return tmp_path / "case.yaml"


def test_a_diverged_relaxation_keeps_its_last_state_and_exits_3(tmp_path, capsys, monkeypatch):
    case = _case(tmp_path)
    assert (
        main(["predeform", str(case), "--base-dir", str(ROOT), "-o", str(tmp_path / "i.nc")]) == 0
    )
    real = cloth.solvers.relax

    def diverging(state, body, settings):
        result = real(state, body, settings)
        raise cloth.solvers.Diverged("energy grew", result.final.x, result.history)

    monkeypatch.setattr(cloth.stages.case, "relax", diverging)
    capsys.readouterr()
    out = tmp_path / "relaxed.nc"
    code = main(["relax", str(tmp_path / "i.nc"), "-o", str(out)])
    assert code == EXIT_DIVERGED == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "diverged (energy grew)" in err[0] and "explicit+newton" in err[0]
    assert not out.exists()
    with xr.open_dataset(tmp_path / "relaxed.diverged.nc") as ds:
        assert ds.attrs["solver_converged"] == 0 and ds["x"].shape == (4, 24)


def test_run_writes_every_stage_or_stops_where_asked(tmp_path):
    case = _case(tmp_path)
    base = ["--log-level", "WARNING", "run", str(case), "--base-dir", str(ROOT)]
    assert main([*base, "-o", str(tmp_path / "all")]) == 0
    files = {p.name for p in (tmp_path / "all").iterdir()}
    assert {"initial.nc", "relaxed.nc", "result.nc", "summary.csv", "figures"} <= files
    assert ("garment.html" in files) == (importlib.util.find_spec("plotly") is not None)
    assert len(list((tmp_path / "all/figures").glob("*.png"))) >= 8
    assert main([*base, "-o", str(tmp_path / "part"), "--stop-after", "relax"]) == 0
    assert {p.name for p in (tmp_path / "part").iterdir()} == {"initial.nc", "relaxed.nc"}


def test_later_stages_find_the_body_from_the_state_file_and_refuse_a_changed_one(
    tmp_path, capsys, monkeypatch
):
    from cloth.bodies.torso import chart_size, torso_mesh
    from tests.conftest import write_obj

    (tmp_path / "case").mkdir()
    write_obj(tmp_path / "case/scan.obj", *torso_mesh(chart_size("M"), 32, 30))
    case = {
        "material": "powernet",
        "body": {"mesh": "scan.obj", "surface": "mesh"},  # relative to the case's folder
        "garment": {"bottom": 0.95, "top": 1.1, "reduction": 0.15, "grid": [16, 4]},
        "solver": {"max_iterations": 3},
    }
    (tmp_path / "case/case.yaml").write_text(yaml.safe_dump(case))
    initial = tmp_path / "initial.nc"
    args = ["--log-level", "WARNING"]
    assert (
        main(
            [
                *args,
                "predeform",
                str(tmp_path / "case/case.yaml"),
                "--base-dir",
                str(ROOT),
                "-o",
                str(initial),
            ]
        )
        == 2
    )
    assert "scan.obj" in capsys.readouterr().err  # not found beside the repository
    assert main([*args, "predeform", str(tmp_path / "case/case.yaml"), "-o", str(initial)]) == 0
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # no base directory: relax reads the body's record
    assert main([*args, "relax", str(initial), "-o", str(tmp_path / "relaxed.nc")]) == 0
    assert (
        main([*args, "aggregate", str(tmp_path / "relaxed.nc"), "-o", str(tmp_path / "result.nc")])
        == 0
    )
    with (tmp_path / "case/scan.obj").open("a") as handle:
        handle.write("# edited\n")
    capsys.readouterr()
    assert main(["relax", str(initial), "-o", str(tmp_path / "again.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "changed since predeform" in err[0] and "scan.obj" in err[0]
    assert not (tmp_path / "again.nc").exists()


def test_a_case_is_validated_once_where_it_enters(tmp_path, monkeypatch):
    import cloth.case.validate
    from cloth.case.case import load_case, validate_case

    calls = []
    real = cloth.case.validate.Validator

    def counting(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(cloth.case.validate, "Validator", counting)
    case = _case(tmp_path)
    base = ["--log-level", "WARNING"]
    assert (
        main([*base, "predeform", str(case), "--base-dir", str(ROOT), "-o", str(tmp_path / "i.nc")])
        == 0
    )
    assert len(calls) == 1  # read from its file; predeform trusts the Case
    assert (
        main(
            [
                *base,
                "run",
                str(case),
                "--base-dir",
                str(ROOT),
                "-o",
                str(tmp_path / "r"),
                "--stop-after",
                "aggregate",
            ]
        )
        == 0
    )
    assert len(calls) == 2
    valid = load_case(case)
    assert validate_case(valid) is valid and len(calls) == 3
