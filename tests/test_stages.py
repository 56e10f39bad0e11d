"""The stages behind the CLI: a diverged relaxation's file and exit status, and `cloth run`'s
folder of every stage's files."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import xarray as xr
import yaml

import cloth.solvers
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

    monkeypatch.setattr(cloth.solvers, "relax", diverging)
    capsys.readouterr()
    out = tmp_path / "relaxed.nc"
    code = main(["relax", str(tmp_path / "i.nc"), "--base-dir", str(ROOT), "-o", str(out)])
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
