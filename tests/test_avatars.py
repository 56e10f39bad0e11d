"""Avatars (`cloth.bodies.avatar`, `cloth.files.avatar`): the shipped meshes measured back as
a tape would, the ``avatar`` body block, charts refused in one line, and, where the extra
``bodies`` is installed (make test-slow), the fit itself: every girth within 2 mm, the stature
within 5 mm, watertight, and a second fit byte for byte the same."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import ConvexHull

from cloth.bodies.leg import read_leg_chart
from cloth.bodies.torso import read_chart
from cloth.errors import InputError
from cloth.files.avatar import SHIPPED, avatar_mesh, shipped, write_ply
from cloth.files.body import body_from_config
from cloth.io import sha256

ROOT = Path(__file__).resolve().parents[1]
CHARTS = ROOT / "data" / "bodies"
SIDECARS = sorted(SHIPPED.glob("*.json"))
#: Largest tape-girth error (m) the issue allows a shipped avatar, and its stature's.
GIRTH_TOLERANCE = 2e-3
STATURE_TOLERANCE = 5e-3


def chart_rows(record: dict) -> tuple[dict, dict]:
    """(girth, height) in m of the avatar's size, read from its chart with the chart readers
    (independent of the fit's own reading)."""
    path = CHARTS / record["chart"]
    spec = (read_chart if record["kind"] == "torso" else read_leg_chart)(path)[record["size"]]
    names = record["landmarks"]
    return {n: spec.girth[n] for n in names}, {n: spec.height[n] for n in names}


def tape(mesh: trimesh.Trimesh, z: float, near: np.ndarray) -> float:
    """A tape around the part at height z nearest ``near`` (xy): trimesh's section, split into
    its closed curves, the one whose centre is nearest, and the perimeter of its convex hull."""
    section = mesh.section(plane_origin=[0, 0, z], plane_normal=[0, 0, 1])
    curves = [curve[:, :2] for curve in section.discrete]
    centre = [np.linalg.norm(c.mean(axis=0) - near) for c in curves]
    points = curves[int(np.argmin(centre))]
    hull = points[ConvexHull(points).vertices]
    return float(np.sum(np.linalg.norm(np.roll(hull, -1, axis=0) - hull, axis=1)))


def test_the_default_charts_each_ship_their_avatars():
    names = sorted(p.stem for p in SIDECARS)
    assert names == [f"{k}_{s}" for k in ("leg", "torso") for s in ("L", "M", "S")]


@pytest.mark.parametrize("side", SIDECARS, ids=lambda p: p.stem)
def test_every_shipped_avatar_measures_its_chart_at_the_chart_s_heights(side):
    """Each shipped avatar belongs to its chart as shipped (sha256), is closed and outward, in
    metres with the floor at z = 0 at the most, and a tape at each of the chart's heights reads
    the chart's girth within 2 mm (measured here with trimesh's sections, not the fit's)."""
    record = json.loads(side.read_text())
    assert record["chart_sha256"] == sha256(CHARTS / record["chart"])
    mesh = trimesh.load(side.with_suffix(".ply"), process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    assert mesh.vertices[:, 2].min() >= -1e-6
    girth, height = chart_rows(record)
    low, high = record["crop_m"]
    assert mesh.vertices[:, 2].min() == pytest.approx(low, abs=1e-6)
    assert mesh.vertices[:, 2].max() == pytest.approx(high, abs=1e-6)
    near = np.array(record["loop_point_m"])
    for name, target in girth.items():
        measured = tape(mesh, height[name], near if record["kind"] == "leg" else np.zeros(2))
        assert abs(measured - target) <= GIRTH_TOLERANCE, (name, measured, target)
        assert record["girths_m"][name]["avatar"] == pytest.approx(measured, abs=2e-4), name
    assert abs(record["stature_m"]["residual"]) <= STATURE_TOLERANCE
    assert record["stature_m"]["chart"] == pytest.approx(1.68)


def test_an_avatar_block_is_its_shipped_mesh_with_the_chart_s_girth_lines():
    body, ref = body_from_config({"avatar": {"size": "M"}}, ROOT)
    assert ref["path"] == str(SHIPPED / "torso_M.ply")
    heights = read_chart(CHARTS / "size_chart.csv")["M"].height
    assert ref["landmarks"] == {n: heights[n] for n in ("hip", "waist", "underbust", "bust")}
    assert body.loop_point == (0.0, 0.0)
    _, ref = body_from_config({"avatar": {"size": "S", "chart": "data/bodies/leg_chart.csv"}}, ROOT)
    assert ref["path"] == str(SHIPPED / "leg_S.ply")
    assert set(ref["landmarks"]) == {"B", "B1", "C", "D", "E", "F", "G"}


def test_an_avatar_of_a_chart_that_ships_none_says_how_to_make_one(tmp_path):
    chart = tmp_path / "mine.csv"
    chart.write_text((CHARTS / "size_chart.csv").read_text().replace("M,96,", "M,97,"))
    assert shipped(chart, "M") is None and shipped(CHARTS / "size_chart.csv", "M") is not None
    with pytest.raises(InputError, match=r"cloth body avatar .*--size M") as error:
        avatar_mesh({"chart": str(chart), "size": "M"})
    assert "\n" not in str(error.value)


def test_an_avatar_a_user_made_is_given_by_its_mesh_and_needs_its_sidecar(tmp_path):
    """avatar.mesh: a file cloth body avatar wrote (here a copy of a shipped one, renamed) is
    used with its sidecar's girth lines; the same mesh without its sidecar is refused."""
    import shutil

    for suffix in (".ply", ".json"):
        shutil.copy(SHIPPED / f"leg_M{suffix}", tmp_path / f"mine{suffix}")
    block = {"avatar": {"size": "M", "mesh": "mine.ply"}}
    body, ref = body_from_config(block, tmp_path)
    assert ref["path"] == str(tmp_path / "mine.ply") and set(ref["landmarks"]) >= {"B", "G"}
    assert body.loop_point == tuple(
        json.loads((tmp_path / "mine.json").read_text())["loop_point_m"]
    )
    (tmp_path / "mine.json").unlink()
    with pytest.raises(InputError, match="no avatar sidecar"):
        body_from_config(block, tmp_path)


def test_the_ply_writer_writes_what_trimesh_reads_the_same_bytes_each_time(tmp_path):
    mesh = trimesh.creation.icosphere(2)
    write_ply(mesh.vertices, mesh.faces, tmp_path / "a.ply")
    write_ply(mesh.vertices, mesh.faces, tmp_path / "b.ply")
    assert (tmp_path / "a.ply").read_bytes() == (tmp_path / "b.ply").read_bytes()
    back = trimesh.load(tmp_path / "a.ply", process=False)
    assert np.array_equal(back.faces, mesh.faces)
    assert np.array_equal(back.vertices, mesh.vertices.astype(np.float32).astype(np.float64))


def avatar_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "cloth", "--log-level", "ERROR", "body", "avatar", *args],
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.mark.parametrize(
    ("text", "size", "words"),
    [
        ("size,waist\nM,70\n", "M", "neither a torso chart"),
        (None, "XXL", "unknown size 'XXL'"),
        ("stature", "M", "stature 16.8 cm is not an adult's"),
        ("bust_cm", "M", "bust_cm 'ninety-six' is not a number"),
    ],
)
def test_a_bad_chart_is_refused_in_one_line_and_nothing_is_written(tmp_path, text, size, words):
    chart = tmp_path / "chart.csv"
    shipped_text = (CHARTS / "size_chart.csv").read_text()
    if text is None:
        text = shipped_text
    elif text == "stature":
        text = shipped_text.replace(",0.44,168,", ",0.44,16.8,")
        assert text != shipped_text
    elif text == "bust_cm":
        text = shipped_text.replace("M,96,", "M,ninety-six,")
    chart.write_text(text)
    out = tmp_path / "avatar.ply"
    result = avatar_cli(str(chart), "--size", size, "-o", str(out))
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "chart.csv" in lines[0], lines
    assert list(tmp_path.iterdir()) == [chart]


def test_without_the_extra_an_avatar_fit_says_which_package_to_install(monkeypatch):
    import importlib.util

    from cloth.bodies import avatar

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "anny" else real(name, *a)
    )
    with pytest.raises(InputError, match=r"anny is not installed\): pip install 'cloth\[bodies\]'"):
        avatar._modules()


needs_extra = pytest.mark.skipif(
    importlib.util.find_spec("anny") is None or importlib.util.find_spec("torch") is None,
    reason="the bodies extra (torch, anny) is not installed: make bodies",
)


@pytest.mark.slow
@needs_extra
@pytest.mark.parametrize(("chart", "size"), [("size_chart.csv", "S"), ("leg_chart.csv", "M")])
def test_a_torso_and_a_leg_size_are_fitted_to_their_chart(tmp_path, chart, size):
    """The fit on the machine: girths within 2 mm as trimesh measures them, the stature within
    5 mm, watertight; a second fit writes the same bytes; and both are the shipped avatar."""
    out = [tmp_path / "first.ply", tmp_path / "second.ply"]
    for path in out:
        result = avatar_cli(str(CHARTS / chart), "--size", size, "-o", str(path))
        assert result.returncode == 0, result.stderr
    assert out[0].read_bytes() == out[1].read_bytes()
    first, second = (json.loads(p.with_suffix(".json").read_text()) for p in out)
    assert first == second
    mesh = trimesh.load(out[0], process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent
    girth, height = chart_rows(first)
    near = np.array(first["loop_point_m"]) if first["kind"] == "leg" else np.zeros(2)
    for name, target in girth.items():
        assert abs(tape(mesh, height[name], near) - target) <= GIRTH_TOLERANCE, name
    assert abs(first["stature_m"]["residual"]) <= STATURE_TOLERANCE
    ship = SHIPPED / f"{first['kind']}_{size}.ply"
    assert out[0].read_bytes() == ship.read_bytes(), "make avatars regenerates the shipped file"


@pytest.mark.slow
@needs_extra
def test_a_girth_the_model_cannot_reach_is_refused_naming_it_and_its_range(tmp_path):
    chart = tmp_path / "chart.csv"
    chart.write_text((CHARTS / "size_chart.csv").read_text().replace("S,88,74,70,", "S,88,74,20,"))
    out = tmp_path / "avatar.ply"
    result = avatar_cli(str(chart), "--size", "S", "-o", str(out))
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert "cannot reach the waist girth of 20.0 cm at 104.0 cm" in lines[0], lines
    assert "spans" in lines[0] and "waist_cm" in lines[0]
    assert list(tmp_path.iterdir()) == [chart]


def test_an_avatar_case_written_back_validates_again():
    """An avatar case's mapping (what case.yaml files the tool writes hold) carries no mesh
    option the avatar refuses, so a written case runs as written (cloth design, cloth wearers)."""
    from cloth.case.case import validate_case

    case = validate_case(
        {
            "material": "powernet",
            "body": {"avatar": {"size": "S"}, "smoothing": 0.012},
            "garment": {"bottom": 0.9, "top": 1.15, "reduction": 0.15, "grid": [24, 8]},
        }
    )
    body = case.to_dict()["body"]
    assert "units" not in body and "up" not in body and body["smoothing"] == 0.012
    assert validate_case(case.to_dict()) == case
