"""Guardrails: a case too big for the machine is refused before any work, in one line, exit 2;
--force runs it; the default cases are never refused."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

import cloth.pipeline.guard
import cloth.stages.case
from cloth.cli import main
from cloth.errors import InputError
from cloth.pipeline.guard import BYTES_PER_FACE, check_fits, estimate, free_memory_mb, mesh_faces
from cloth.pipeline.resources import MODEL

ROOT = Path(__file__).resolve().parents[1]


def _case(tmp_path, grid, body=None):
    case = {
        "material": "powernet",
        "body": body or {"torso": {"size": "M"}},
        "garment": {"bottom": 0.9, "top": 1.1, "reduction": 0.15, "grid": grid},
    }
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(case))
    return path


@pytest.fixture
def no_work(monkeypatch):
    """Fails the test if predeform starts: a refusal must come before any work."""

    def refuse(*args, **kwargs):
        raise AssertionError("predeform started")

    monkeypatch.setattr(cloth.stages.case, "predeform", refuse)


def _one_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("verb", ["predeform", "run"])
def test_a_grid_of_forty_billion_nodes_is_refused_before_any_work(tmp_path, capsys, verb, no_work):
    case = _case(tmp_path, [200000, 200000])
    out = tmp_path / ("initial.nc" if verb == "predeform" else "out")
    args = [verb, str(case), "--base-dir", str(ROOT), "-o", str(out)]
    assert main(["--log-level", "WARNING", *args]) == 2
    line = _one_line(capsys)
    assert str(case) in line and "garment.grid" in line and "--force" in line
    assert re.search(r"40,000,000,000 garment nodes need an estimated [\d,]+ MB", line)
    assert not out.exists()


def test_a_hundred_million_face_mesh_is_refused_from_its_header(tmp_path, capsys, no_work):
    header = "ply\nformat binary_little_endian 1.0\nelement vertex 50000000\nproperty float x\n"
    header += "property float y\nproperty float z\nelement face 100000000\n"
    header += "property list uchar int vertex_indices\nend_header\n"
    (tmp_path / "scan.ply").write_text(header)  # the header alone: nothing else is read
    assert mesh_faces(tmp_path / "scan.ply") == 100_000_000
    case = _case(tmp_path, [96, 48], {"mesh": "scan.ply", "units": "mm"})
    assert main(["predeform", str(case), "-o", str(tmp_path / "initial.nc")]) == 2
    line = _one_line(capsys)
    assert "body.mesh" in line and "100,000,000 faces" in line
    # the estimate alone, as for any 100M-face mesh: its faces dominate
    assert estimate("relax", 96 * 48, 100_000_000).memory_mb > 0.9 * BYTES_PER_FACE * 100


def test_force_runs_what_the_estimate_would_refuse(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cloth.pipeline.guard, "free_memory_mb", lambda: 10.0)  # a machine of 10 MB
    case = _case(tmp_path, [24, 6])
    args = ["predeform", str(case), "--base-dir", str(ROOT)]
    assert main([*args, "-o", str(tmp_path / "a.nc")]) == 2
    assert "10 MB are free" in _one_line(capsys)
    assert main([*args, "-o", str(tmp_path / "b.nc"), "--force"]) == 0
    monkeypatch.setenv("CLOTH_FORCE", "1")
    assert main([*args, "-o", str(tmp_path / "c.nc")]) == 0
    assert (tmp_path / "b.nc").is_file() and (tmp_path / "c.nc").is_file()
    monkeypatch.delenv("CLOTH_FORCE")
    relax = ["relax", str(tmp_path / "b.nc"), "-o"]
    assert main([*relax, str(tmp_path / "r.nc")]) == 2  # the relax stage checks its own need
    assert "in relax" in _one_line(capsys) and not (tmp_path / "r.nc").exists()
    assert main([*relax, str(tmp_path / "r.nc"), "--force"]) == 0


def test_the_default_cases_fit_a_small_machine():
    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    n, m = config["sweep"]["garment"]["grid"]
    # a 2 GB machine runs every stage of every default case
    assert check_fits(tuple(MODEL), n * m, 0, "config", force=False)
    worst = max(estimate(stage, n * m).memory_mb for stage in MODEL)
    assert worst < 2000
    free = free_memory_mb()
    assert free is None or 0 < free < 1e9


def test_face_counts_come_from_headers_or_bound_the_file(tmp_path):
    import numpy as np
    import trimesh

    mesh = trimesh.creation.icosphere(subdivisions=3)
    for suffix in ("ply", "stl"):
        mesh.export(tmp_path / f"ball.{suffix}")
        assert mesh_faces(tmp_path / f"ball.{suffix}") == len(mesh.faces)
    mesh.export(tmp_path / "ball.obj")
    assert mesh_faces(tmp_path / "ball.obj") >= len(mesh.faces)  # a bound from the size
    assert mesh_faces(tmp_path / "missing.obj") == 0
    assert np.isfinite(estimate("predeform", 1000, len(mesh.faces)).seconds)


def test_long_work_off_a_terminal_reports_in_log_lines(caplog):
    import logging

    import numpy as np

    from cloth.progress import LogProgress, progress

    with caplog.at_level(logging.INFO, logger="cloth.progress"):
        bar = progress(total=1000, desc="fit", unit="sample")  # pytest's stderr: no terminal
        assert isinstance(bar, LogProgress)
        with bar:
            for _ in range(100):
                bar.update(10)
        assert list(progress(range(5), desc="rows", show=None)) == list(range(5))
        heights = np.linspace(0.8, 1.2, 7)  # predeform's rows: an array, not a list
        assert list(progress(heights, desc="rows", unit="row")) == list(heights)
    lines = [r.getMessage() for r in caplog.records if r.getMessage().startswith("fit:")]
    assert len(lines) == 10 and lines[-1].startswith("fit: 100 % (1,000 of 1,000 sample")


def test_a_large_predeform_off_a_terminal_logs_its_progress(caplog):
    import logging

    from cloth.garment.predeform import PROGRESS_NODES
    from cloth.stages.case import initial_state

    n, m = 400, 130  # 52,000 nodes: above the progress threshold
    assert n * m > PROGRESS_NODES
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [n, m]},
    }
    with caplog.at_level(logging.INFO, logger="cloth.progress"):
        state = initial_state(case)
    assert state.x.shape == (n * m, 3)
    assert any(r.getMessage().startswith("predeform: row sections: 100 %") for r in caplog.records)


def test_the_estimate_follows_the_backend_relax_will_take(tmp_path):
    """auto on the tension field factorises by Cholesky, half an LU's memory: the guard
    estimates relax and aggregate by the Cholesky model there, and by LU's for a case that is
    not positive definite by construction (a compressible material, bending springs, friction,
    a backend asked for). A 200k-node garment is estimated to fit in 8 GB either way (measured:
    1,793 and 3,228 MiB, docs/performance.md)."""
    from dataclasses import replace

    from cloth.case.case import validate_case
    from cloth.cli import main
    from cloth.pipeline.guard import takes_cholesky

    pytest.importorskip("cholespy")

    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {"bottom": 0.86, "top": 1.22, "reduction": 0.2, "grid": [640, 320]},
    }
    assert takes_cholesky(validate_case(case), ROOT)
    bending = {**case, "garment": {**case["garment"], "bend_modulus": 1e4}}
    assert not takes_cholesky(validate_case(bending), ROOT)
    assert not takes_cholesky(validate_case({**case, "contact": {"friction": 0.5}}), ROOT)
    asked = {**case, "solver": {"linear_solver": "superlu"}}
    assert not takes_cholesky(validate_case(asked), ROOT)
    material = tmp_path / "compressible.nc"
    csv = str(ROOT / "data/materials/powernet.csv")
    assert (
        main(["material", "ingest", csv, "--compression-ratio", "0.01", "-o", str(material)]) == 0
    )
    compressible = replace(validate_case(case), material=str(material))
    assert not takes_cholesky(compressible, ROOT)
    nodes = 640 * 320
    for stage in ("relax", "aggregate"):
        lu, cholesky = estimate(stage, nodes), estimate(stage, nodes, cholesky=True)
        assert cholesky.memory_mb < 0.7 * lu.memory_mb
        assert lu.memory_mb < 8000 * 1.048576
    assert estimate("relax", nodes, cholesky=True).memory_mb > 1793 * 1.048576  # not below it


@pytest.mark.parametrize(
    ("spare", "force", "refused"),
    [(0.0, "", False), (-1.0, "", True), (-1.0, "0", True), (-1.0, "1", False)],
)
def test_the_guard_refuses_only_past_the_free_memory_unless_forced(
    monkeypatch, spare, force, refused
):
    """The largest stage's estimate at exactly the free memory runs, 1 MB past it is refused
    (naming the grid), and CLOTH_FORCE other than empty or 0 runs it anyway."""
    worst = max(estimate(stage, 50_000).memory_mb for stage in ("predeform", "relax"))
    monkeypatch.setattr(cloth.pipeline.guard, "free_memory_mb", lambda: worst + spare)
    monkeypatch.setenv("CLOTH_FORCE", force)
    if refused:
        with pytest.raises(InputError) as caught:
            check_fits(("predeform", "relax"), 50_000, 0, "case.yaml")
        assert caught.value.field == "garment.grid"
    else:
        assert len(check_fits(("predeform", "relax"), 50_000, 0, "case.yaml")) == 2


@pytest.mark.parametrize(("mesh_share", "field"), [(0.49, "garment.grid"), (0.51, "body.mesh")])
def test_a_refusal_names_the_mesh_where_its_faces_take_over_half_the_memory(
    monkeypatch, mesh_share, field
):
    """The fix named is the mesh (decimate it) where the mesh's faces take more than half the
    estimated peak, else the grid."""
    monkeypatch.setattr(cloth.pipeline.guard, "free_memory_mb", lambda: 1.0)
    monkeypatch.delenv("CLOTH_FORCE", raising=False)
    garment = estimate("relax", 1000).memory_mb  # without faces
    # faces of BYTES_PER_FACE each making ``mesh_share`` of the total: f / (garment + f) = share
    faces = round(mesh_share / (1 - mesh_share) * garment * 1e6 / BYTES_PER_FACE)
    with pytest.raises(InputError) as caught:
        check_fits(("relax",), 1000, faces, "case.yaml")
    assert caught.value.field == field
