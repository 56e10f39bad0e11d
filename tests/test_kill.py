"""kill -9 at every stage of ``cloth run``: the folder never holds a half-written file, and a
rerun completes. (The pipeline's own kill test, a rule killed mid-run, is in test_workflow.)

The kill is exact, not timed: ``cloth run`` runs in a child process whose ``os.replace`` (the
rename that publishes every file, `cloth.io.atomic_output`) or whose stage function sends it
SIGKILL, so a stage dies either as it starts or with its output written in full but not yet
renamed, the worst moment for a file that is not written atomically.
"""

from __future__ import annotations

import csv
import signal
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr
import yaml

ROOT = Path(__file__).resolve().parents[1]
CASE = {
    "material": "powernet",
    "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [32, 8]},
}
#: Runs ``cloth`` and kills itself (SIGKILL) when it renames a file named ``KILL_FILE`` into
#: place, or when it enters the stage function ``KILL_STAGE`` of the module that defines it
#: (cloth.stages.case, or cloth.stages.results, which ``cloth run`` imports as it aggregates).
CHILD = """
import os, signal, sys
kind, name = sys.argv[1], sys.argv[2]
import cloth.stages.case as case
import cloth.stages.results as results
if kind == "file":
    real = os.replace
    def replace(src, dst, *args, **kwargs):
        if os.path.basename(dst) == name:
            os.kill(os.getpid(), signal.SIGKILL)
        return real(src, dst, *args, **kwargs)
    os.replace = replace
else:
    def killed(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGKILL)
    setattr(case if hasattr(case, name) else results, name, killed)
from cloth.cli import main
sys.exit(main(sys.argv[3:]))
"""
#: Each stage of ``cloth run``: the function that does it and a file it writes.
STAGES = {
    "predeform": ("initial_state", "initial.nc"),
    "relax": ("relax_state", "relaxed.nc"),
    "aggregate": ("write_result", "result.nc"),
    "figures": ("figures", "stress_weft.png"),
}
#: Where a run is killed: as each stage starts, and as each kind of file it writes is renamed
#: into place (a file written without `cloth.io.atomic_output` is never renamed, so the child
#: is not killed and the test fails: the kill point proves the write is atomic).
#: The stage points resume a run killed as a stage starts; the file points prove each kind of
#: file written atomically: result.nc's and summary.csv's in make test, every point in
#: make test-slow (90 s).
POINTS = [
    pytest.param("stage", function, written, marks=pytest.mark.slow, id=function)
    for function, written in STAGES.values()
] + [
    pytest.param("file", name, name, id=name, marks=() if fast else pytest.mark.slow)
    for name, fast in (
        ("initial.nc", False),
        ("relaxed.nc", False),
        ("result.nc", True),
        ("summary.csv", True),
        ("stress_weft.png", False),
        ("body_pressure.png", False),
        ("garment.html", False),
    )
]


def _complete(path: Path) -> None:
    """``path`` reads in full as the file it claims to be."""
    if path.suffix == ".nc":
        with xr.open_dataset(path) as ds:
            ds.load()
    elif path.suffix == ".png":
        data = path.read_bytes()
        assert data.startswith(b"\x89PNG") and data.rstrip().endswith(b"IEND\xaeB`\x82"), path
    elif path.suffix == ".csv":
        lines = path.read_text().splitlines()
        assert len(lines) >= 2 and all(line.count(",") == lines[0].count(",") for line in lines)
    elif path.suffix == ".html":
        assert path.read_text().rstrip().endswith("</html>"), path


def _published(folder: Path) -> list[Path]:
    """The files of ``folder`` a user sees (not the hidden temporary files of a write)."""
    return [p for p in folder.rglob("*") if p.is_file() and not p.name.startswith(".")]


@pytest.mark.parametrize(("kind", "name", "written"), POINTS)
def test_a_run_killed_in_any_stage_leaves_whole_files_and_resumes(tmp_path, kind, name, written):
    if name == "garment.html":
        pytest.importorskip("plotly")
    case = tmp_path / "case.yaml"
    case.write_text(yaml.safe_dump(CASE))
    out = tmp_path / "out"
    args = ["--log-level", "WARNING", "run", str(case), "-o", str(out), "--base-dir", str(ROOT)]
    killed = subprocess.run(
        [sys.executable, "-c", CHILD, kind, name, *args],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert killed.returncode == -signal.SIGKILL, killed.stderr[-2000:]
    left = _published(out) if out.exists() else []
    assert written not in {p.name for p in left}  # the killed stage published nothing
    for path in left:
        _complete(path)
    again = subprocess.run(
        [sys.executable, "-m", "cloth", *args], capture_output=True, text=True, timeout=300
    )
    assert again.returncode == 0, again.stderr[-2000:]
    names = {p.name for p in _published(out)}
    assert {"initial.nc", "relaxed.nc", "result.nc", "summary.csv", "stress_weft.png"} <= names
    for path in _published(out):
        _complete(path)


#: Each kind of file ``cloth pattern --cut tube`` writes; the CSV in make test, the others in
#: make test-slow.
PATTERN_FILES = [
    pytest.param(name, id=name, marks=() if name == "pattern.csv" else pytest.mark.slow)
    for name in (
        "pattern.csv",
        "pattern.svg",
        "pattern.dxf",
        "pattern_astm.dxf",
        "pattern.pdf",
        "pattern_knitting.csv",
        "pattern_knitting.png",
    )
]


def _whole_pattern_file(path: Path) -> None:
    """``path``, a file of ``cloth pattern``, reads in full as what it claims to be."""
    if path.suffix == ".csv":  # comment lines first, quoted cells
        rows = list(csv.reader(line for line in path.read_text().splitlines() if line[:1] != "#"))
        assert len(rows) >= 2 and all(len(row) == len(rows[0]) for row in rows), path
    elif path.suffix in (".nc", ".png", ".html"):
        _complete(path)
    elif path.suffix == ".svg":
        assert path.read_text().rstrip().endswith("</svg>"), path
    elif path.suffix == ".pdf":
        data = path.read_bytes()
        assert data.startswith(b"%PDF") and data.rstrip().endswith(b"%%EOF"), path
    elif path.suffix == ".dxf":
        assert path.read_text().rstrip().endswith("EOF"), path


@pytest.fixture(scope="module")
def tube_result(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tube")
    case = folder / "case.yaml"
    case.write_text(yaml.safe_dump(CASE))
    args = ["--log-level", "WARNING", "run", str(case), "-o", str(folder / "run")]
    done = subprocess.run(
        [sys.executable, "-m", "cloth", *args, "--stop-after", "aggregate"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return folder / "run" / "result.nc"


@pytest.mark.parametrize("name", PATTERN_FILES)
def test_a_pattern_killed_as_it_publishes_any_file_leaves_whole_files_and_reruns(
    tube_result, tmp_path, name
):
    pytest.importorskip("ezdxf")
    out = tmp_path / "pattern"
    args = ["--log-level", "WARNING", "pattern", str(tube_result), "--cut", "tube"]
    args += ["-o", str(out / "pattern.csv")]
    killed = subprocess.run(
        [sys.executable, "-c", CHILD, "file", name, *args],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert killed.returncode == -signal.SIGKILL, killed.stderr[-2000:]
    left = _published(out) if out.exists() else []
    assert name not in {p.name for p in left}
    for path in left:
        _whole_pattern_file(path)
    again = subprocess.run(
        [sys.executable, "-m", "cloth", *args], capture_output=True, text=True, timeout=300
    )
    assert again.returncode == 0, again.stderr[-2000:]
    written = {p.name for p in _published(out)}
    assert {p.values[0] for p in PATTERN_FILES} <= written
    for path in _published(out):
        _whole_pattern_file(path)
