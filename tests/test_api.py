"""The front door (issue 70, item 3): ``import cloth`` and its public names only - a case from a
file or a mapping validated as the command validates it, a run returning its datasets and its
summary (the same numbers as ``cloth run``), a fabric and a body, the command's one-line error;
every public name documented."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import yaml

import cloth

CASE = {
    "material": "powernet",
    "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [32, 8]},
    "landmarks": {"middle": 0.25},
}


def test_import_cloth_loads_no_stage():
    code = (
        "import sys, cloth; print(cloth.__version__); "
        "print(any(m.startswith('cloth.stages') for m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.split()[-1] == "False"


def test_every_public_name_is_documented():
    for name in cloth.__all__:
        value = getattr(cloth, name)
        if name == "__version__":
            continue
        assert (value.__doc__ or "").strip(), name
    assert "shape" in cloth.Run.__doc__ or "(row, col)" in cloth.run.__doc__
    assert "(row, col)" in cloth.run.__doc__ and "SI" in cloth.run.__doc__


def test_a_case_from_a_file_or_a_mapping_is_validated_as_the_command_validates(tmp_path, capsys):
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(CASE))
    assert cloth.Case.load(path) == cloth.Case.of(CASE)
    bad = {**CASE, "garment": {**CASE["garment"], "reduction": 1.5}}
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(bad))
    with pytest.raises(cloth.InputError) as raised:
        cloth.Case.load(tmp_path / "bad.yaml")
    from cloth.cli import main

    assert main(["case", "check", str(tmp_path / "bad.yaml")]) == 2
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert str(raised.value) in line  # the command's one line


def test_a_run_returns_its_result_and_summary_as_the_command_writes_them(tmp_path):
    run = cloth.run(CASE, tmp_path / "api")
    assert int(run.result.attrs["converged"]) == 1
    assert run.result["pressure"].dims == ("row", "col")
    assert run.result["pressure"].attrs["units"] == "Pa"
    row = run.summary[run.summary["landmark"] == "middle"].iloc[0]
    # Laplace on the cylinder: the chord-consistent weft stress t / r, within the grid's error
    fabric = cloth.material("powernet")
    expected = fabric.thickness * float(fabric.weft.stress(1 / 0.8 - 1)) / 0.1
    assert row["pressure_mean_Pa"] == pytest.approx(expected, rel=2e-2)
    from cloth.cli import main

    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(CASE))
    assert main(["run", str(path), "-o", str(tmp_path / "cli"), "--stop-after", "aggregate"]) == 0
    assert (tmp_path / "cli" / "summary.csv").read_text().replace("cli", "api") == (
        tmp_path / "api" / "summary.csv"
    ).read_text().replace("cli", "api")


def test_a_fabric_and_a_body_by_their_shipped_names():
    fabric = cloth.material("elastic25")
    assert fabric.thickness == pytest.approx(1.2e-3)
    body = cloth.body({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}})
    distance, _, normal = body.query(np.array([[0.2, 0.0, 0.25]]))
    assert distance[0] == pytest.approx(0.1) and normal[0] == pytest.approx([1.0, 0.0, 0.0])
    with pytest.raises(cloth.InputError, match="unknown material"):
        cloth.material("nosuchnet")


def test_the_python_tutorial_runs_as_written(tmp_path, monkeypatch):
    """docs/tutorials/python.md's blocks, in order, in an empty folder: its runs, its sweep in
    a loop (the waist's pressure rises with the reduction), its figure and its xarray read."""
    import re
    from pathlib import Path

    page = Path(__file__).resolve().parents[1] / "docs" / "tutorials" / "python.md"
    code = re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
    assert len(code) >= 4
    monkeypatch.chdir(tmp_path)
    space: dict = {}
    for block in code:
        exec(compile(block, str(page), "exec"), space)
    assert space["waist"] == sorted(space["waist"])
    assert (tmp_path / "waist.png").stat().st_size > 5_000
    assert (tmp_path / "runs" / "r150" / "result.nc").is_file()
