"""Cases that travel: a case the tool writes stores its paths relative to its own folder
(`cloth.case.locations`), so it runs as written from any working directory, and a folder
holding it and its files can be moved whole. The pipeline's own cases (each case's, a design's
start and designed case) are run after a move in tests/test_workflow.py."""

from __future__ import annotations

import itertools
import json
import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import trimesh
import xarray as xr
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from cloth.case.locations import EVERY, PATH_KEYS, relocated
from cloth.cli import main

ROOT = Path(__file__).resolve().parents[1]
QUIET = ["--log-level", "WARNING"]

folder = st.lists(st.sampled_from(["a", "b", "c", ".."]), max_size=4).map(
    lambda parts: os.path.join("/base", *parts) if parts else "/base"
)


@settings(max_examples=200, deadline=None)
@given(source=folder, target=folder, name=st.sampled_from(["x.csv", "d/x.obj", "../x.nc"]))
def test_a_relocated_path_names_the_same_file(source, target, name):
    data = {
        "material": name,
        "body": {"mesh": name, "surface_file": "/abs/s.nc", "torso": {"chart": name}},
    }
    out = relocated(data, source, target)
    for keys in (("material",), ("body", "mesh"), ("body", "torso", "chart")):
        value = out
        for key in keys:
            value = value[key]
        assert not os.path.isabs(value)
        same = os.path.normpath(os.path.join(target, value))
        assert same == os.path.normpath(os.path.join(source, name)), (keys, value)
    assert out["body"]["surface_file"] == "/abs/s.nc"  # absolute stays absolute
    assert data["material"] == name  # the input is not changed


def test_a_bundled_material_name_is_not_a_path():
    data = {"material": "powernet", "body": {"leg": {"size": "M", "chart": "c.csv"}}}
    out = relocated(data, "/p", "/p/q")
    assert out["material"] == "powernet" and out["body"]["leg"]["chart"] == "../c.csv"


def _file_keys() -> set[tuple[str, ...]]:
    """Every string key of the case schema whose description says it names a file (a path, a
    file, a CSV, a mesh), following the pattern's body block to the body's: read from the
    schema, not from the module."""
    schema = yaml.safe_load((ROOT / "cloth" / "schemas" / "case.schema.yaml").read_text())
    out = set()

    def walk(node, keys):
        if "$ref" in node:
            target = schema
            for part in node["$ref"].split("#/")[1].split("/"):
                target = target[part]
            node = target
        said = node.get("description", "")
        if node.get("type") == "string" and re.search(r"\b(file|CSV|path|mesh)\b", said, re.I):
            out.add(keys)
        for key, child in node.get("properties", {}).items():
            walk(child, (*keys, key))
        if isinstance(node.get("items"), dict):  # every item of a list (a garment's bands)
            walk(node["items"], (*keys, EVERY))

    walk(schema, ())
    return out


def test_every_key_that_names_a_file_is_relocated_and_a_home_path_kept():
    keys = _file_keys()
    assert ("garment", "pattern", "file") in keys and len(keys) == 18
    assert ("garment", "bands", EVERY, "material") in keys
    assert set(PATH_KEYS) == keys
    data: dict = {}
    for path in keys:
        holder = data
        for key, after in itertools.pairwise(path):
            if key == EVERY:
                continue
            if after == EVERY:  # a list of two items, both relocated
                holder = holder.setdefault(key, [{}, {}])
                continue
            holder = holder.setdefault(key, {}) if isinstance(holder, dict) else holder
        for item in holder if isinstance(holder, list) else [holder]:
            item[path[-1]] = "d/x.csv"
    out = relocated(data, "/p", "/p/q")
    for path in keys:
        values = [out]
        for key in path:
            values = [v for item in values for v in (item if key == EVERY else [item[key]])]
        assert values and all(v == "../d/x.csv" for v in values), path
    bands = {"garment": {"bands": [{"material": "elastic25"}]}}
    assert relocated(bands, "/p", "/p/q") == bands  # a shipped fabric's name is no path
    home = relocated({"material": "~/tables/net.csv"}, "/p", "/p/q")
    assert home["material"] == "~/tables/net.csv"  # the user's home, wherever the case goes


def _tree(tree: Path) -> None:
    """A project folder: a lab table, a leg chart and a mesh, as a user keeps them."""
    (tree / "tables").mkdir(parents=True)
    shutil.copy(ROOT / "data/materials/powernet.csv", tree / "tables/net.csv")
    (tree / "charts").mkdir()
    shutil.copy(ROOT / "data/bodies/leg_chart.csv", tree / "charts/legs.csv")
    (tree / "scans").mkdir()
    tube = trimesh.creation.cylinder(radius=0.1, height=0.6, sections=48)
    tube.apply_translation([0.0, 0.0, 0.3])
    tube.export(tree / "scans/tube.obj")


CASES = {
    "leg": {
        "material": "tables/net.csv",
        "body": {"leg": {"size": "M", "chart": "charts/legs.csv"}},
        "garment": {"bottom": 0.2, "top": 0.4, "reduction": 0.15, "grid": [16, 6]},
    },
    "mesh": {
        "material": "material/net.nc",
        "body": {"mesh": "scans/tube.obj", "surface": "mesh"},
        "garment": {"bottom": 0.2, "top": 0.4, "reduction": 0.15, "grid": [16, 6]},
    },
}


@pytest.mark.parametrize("kind", sorted(CASES))
def test_a_written_case_runs_from_anywhere_after_its_folder_moves(kind, tmp_path, monkeypatch):
    tree = tmp_path / "project"
    _tree(tree)
    monkeypatch.chdir(tree)
    if kind == "mesh":  # the material as its ingested file
        ingest = ["material", "ingest", "tables/net.csv", "-o", "material/net.nc"]
        assert main([*QUIET, *ingest]) == 0
    case = tree / "runs" / kind / "case.yaml"
    assert main([*QUIET, "case", "write", "--json", json.dumps(CASES[kind]), "-o", str(case)]) == 0
    written = yaml.safe_load(case.read_text())
    assert written["material"] == os.path.join("..", "..", CASES[kind]["material"])
    before = tmp_path / "before.nc"
    assert main([*QUIET, "predeform", str(case), "-o", str(before)]) == 0

    shutil.move(tree, tmp_path / "shared" / "copy")
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")
    moved = tmp_path / "shared" / "copy" / "runs" / kind / "case.yaml"
    out = tmp_path / "out"
    assert main([*QUIET, "run", str(moved), "-o", str(out), "--stop-after", "relax"]) == 0
    with xr.open_dataset(before) as first, xr.open_dataset(out / "initial.nc") as again:
        for c in ("x", "y", "z"):
            np.testing.assert_array_equal(first[c].values, again[c].values)
    # written again from its new folder (a relative --base-dir), it still names the same files
    again_case = tmp_path / "elsewhere" / "copy.yaml"
    base = os.path.relpath(moved.parent, tmp_path / "elsewhere")
    assert (
        main(
            [
                *QUIET,
                "case",
                "write",
                "--json",
                json.dumps(yaml.safe_load(moved.read_text())),
                "--base-dir",
                base,
                "-o",
                str(again_case),
            ]
        )
        == 0
    )
    assert main([*QUIET, "predeform", str(again_case), "-o", str(tmp_path / "again.nc")]) == 0


def test_a_path_from_the_home_folder_is_the_user_s_file_from_any_base(tmp_path, monkeypatch):
    """``~/tables/net.csv`` names the file in the user's home whatever the case's folder."""
    from cloth.paths import input_file

    home = tmp_path / "home"
    (home / "tables").mkdir(parents=True)
    shutil.copy(ROOT / "data/materials/powernet.csv", home / "tables/net.csv")
    monkeypatch.setenv("HOME", str(home))
    found = input_file("~/tables/net.csv", tmp_path / "cases", "case.yaml", "material")
    assert found == home / "tables" / "net.csv"
