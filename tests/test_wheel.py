"""The package carries its data (issue 70, item 1): the wheel holds every shipped file under
cloth/data and no tests, and an installed copy runs cases that name only shipped defaults from
an empty folder, outside the repository (the torso M in the power net, the leg's avatar M).

The sdist and the wheel are built and checked, and the wheel installed with its dependencies
into a fresh virtual environment outside the repository (no editable install, nothing of the
repository on sys.path); every command runs from an empty folder."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
import xarray as xr
import yaml

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
CASES = {
    "torso": {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {"bottom": 0.9, "top": 1.15, "reduction": 0.15, "grid": [24, 8]},
    },
    "leg_avatar": {
        "material": "powernet",
        "body": {"avatar": {"chart": "leg", "size": "M"}},
        "garment": {
            "bottom": 0.09,
            "top": 0.45,
            "reduction": 0.15,
            "lengthwise_reduction": 0.15,
            "grid": [24, 12],
        },
    },
}


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """The sdist and wheel built (``python -m build``) and checked (``twine check``), and the
    wheel installed with its dependencies into a fresh virtual environment outside the
    repository (uv where the project's environment has it: from its cache, seconds; else venv
    and pip): the wheel's path; the environment is ``site`` beside it."""
    where = tmp_path_factory.mktemp("wheel")
    uv = Path(sys.executable).with_name("uv")
    installer = ["--installer", "uv"] if uv.exists() else []
    built = subprocess.run(
        [sys.executable, "-m", "build", *installer, "-o", str(where / "dist"), str(ROOT)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert built.returncode == 0, built.stderr[-2000:]
    (wheel,) = (where / "dist").glob("cloth-*.whl")
    checked = subprocess.run(
        [
            str(Path(sys.executable).with_name("twine")),
            "check",
            *map(str, (where / "dist").iterdir()),
        ],
        capture_output=True,
        text=True,
    )
    assert checked.returncode == 0 and "PASSED" in checked.stdout, checked.stdout + checked.stderr
    fresh = where / "site"
    if uv.exists():
        steps = [
            [str(uv), "venv", "-q", "--python", sys.executable, str(fresh)],
            [
                str(uv),
                "pip",
                "install",
                "-q",
                "--python",
                str(fresh / "bin" / "python"),
                str(wheel),
            ],
        ]
    else:
        steps = [
            [sys.executable, "-m", "venv", str(fresh)],
            [str(fresh / "bin" / "python"), "-m", "pip", "install", "-q", str(wheel)],
        ]
    for step in steps:
        done = subprocess.run(step, capture_output=True, text=True, timeout=900)
        assert done.returncode == 0, done.stderr[-2000:]
    return wheel


def fresh_python(installed: Path, *args: str, cwd: Path, timeout: float = 600):
    """``python ARGS`` of the fresh environment in ``cwd``: its bin first on the path, no
    PYTHONPATH (nothing of the repository on sys.path); the finished process."""
    bin_dir = installed.parent.parent / "site" / "bin"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env.update(PATH=f"{bin_dir}{os.pathsep}{env.get('PATH', '')}", MPLBACKEND="Agg")
    return subprocess.run(
        [str(bin_dir / "python"), *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=timeout,
    )


def test_the_wheel_holds_the_shipped_data_and_no_tests(installed):
    names = zipfile.ZipFile(installed).namelist()
    shipped = {str(p.relative_to(ROOT / "data")) for p in (ROOT / "data").rglob("*") if p.is_file()}
    inside = {n.removeprefix("cloth/data/") for n in names if n.startswith("cloth/data/")}
    assert shipped <= inside
    assert not [n for n in names if n.startswith(("tests/", "cloth/tests", "results"))]
    assert not [n for n in names if n.endswith(".nc")]  # no result, no material.nc


@pytest.mark.parametrize("name", sorted(CASES))
def test_an_installed_copy_runs_shipped_defaults_from_an_empty_folder(installed, tmp_path, name):
    folder = tmp_path / "empty"
    folder.mkdir()
    (folder / "case.yaml").write_text(yaml.safe_dump(CASES[name]))
    done = fresh_python(
        installed,
        "-m",
        "cloth",
        "run",
        "case.yaml",
        "-o",
        "out",
        "--stop-after",
        "aggregate",
        cwd=folder,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    with xr.open_dataset(folder / "out" / "result.nc") as result:
        assert int(result.attrs["converged"]) == 1
        assert len(result["landmark"]) >= 2  # the shipped chart's girth lines
    where = fresh_python(installed, "-c", "import cloth; print(cloth.__file__)", cwd=folder)
    where = where.stdout.strip()
    assert where.startswith(str(installed.parent.parent / "site")), where


def test_an_installed_copy_starts_a_project_and_runs_its_pipeline_there(installed, tmp_path):
    """``cloth init demo`` then ``cloth pipeline`` in it, with the installed copy: the
    package's own workflow runs on the starter's config (its grid made smaller) and its
    results land in the project's folder; then the README's Python example runs there."""
    import re

    done = fresh_python(installed, "-m", "cloth", "init", "demo", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    demo = tmp_path / "demo"
    config = demo / "config.yaml"
    config.write_text(config.read_text().replace("grid: [48, 16]", "grid: [24, 8]"))
    done = fresh_python(
        installed,
        "-m",
        "cloth",
        "pipeline",
        "--cores",
        "2",
        "results/sweep.csv",
        cwd=demo,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "site-packages/cloth/workflow" in done.stderr  # the installed copy's own workflow
    rows = (demo / "results" / "sweep.csv").read_text().splitlines()
    assert len(rows) > 2 and rows[0].startswith("material,body")
    readme = (ROOT / "README.md").read_text()
    (example,) = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    done = fresh_python(installed, "-c", example.replace("demo/case.yaml", "case.yaml"), cwd=demo)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "waist" in done.stdout
