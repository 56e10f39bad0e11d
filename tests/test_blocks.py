"""Options from a JSON block (``--json``): the workflow hands its material and body blocks to
the commands as they are, so the config's keys and the commands' options cannot drift apart."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.case.validate import case_schema
from cloth.cli import build_parser, main
from cloth.cli.blocks import apply_block

ROOT = Path(__file__).resolve().parents[1]
TABLE = str(ROOT / "data" / "materials" / "powernet.csv")
#: A valid value per JSON type, for blocks built from a schema.
EXAMPLE = {"string": "m", "number": 0.5, "integer": 8, "boolean": True}


def _verb(*words: str) -> argparse.ArgumentParser:
    """The parser of a verb (``material ingest``, ``body fit``, ...)."""
    parser = build_parser()
    for word in words:
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = sub.choices[word]
    return parser


def _example(spec: dict) -> object:
    if "enum" in spec:
        return spec["enum"][0]
    kind = spec.get("type", "string")
    kind = kind[0] if isinstance(kind, list) else kind
    if kind == "array":
        return [_example(spec["items"])]
    return EXAMPLE[kind]


def _accepted(words: tuple[str, ...], block: dict, *line: str) -> argparse.Namespace:
    parser = _verb(*words)
    output = ["-o", "out"] if any(a.dest == "output" for a in parser._actions) else []
    args = parser.parse_args([*line, "--json", json.dumps(block), *output])
    apply_block(parser, args, args.block_ignores)
    return args


def _config_schema() -> dict:
    return yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())


def test_every_key_of_a_config_material_block_is_an_option_of_ingest():
    spec = _config_schema()["properties"]["materials"]["additionalProperties"]["properties"]
    block = {key: _example(sub) for key, sub in spec.items() if key != "table"}
    block["table"] = [TABLE]
    args = _accepted(("material", "ingest"), block)
    assert args.tables == [Path(TABLE)] and args.knots == 8 and args.direction == ["weft"]
    assert args.thickness_mm == 0.5 and args.branch == spec["branch"]["enum"][0]


def test_every_key_of_a_mesh_body_block_is_an_option_of_fit_and_check():
    spec = case_schema()["properties"]["body"]["properties"]
    mesh_keys = ("mesh", "units", "up", "repair", "smoothing", "refine", "denoise", "spacing")
    block = {key: _example(spec[key]) for key in mesh_keys}
    block |= {"surface": "smooth", "surface_file": "s.nc", "tissue": {"thickness": 0.01}}
    for verb in ("fit", "check"):
        args = _accepted(("body", verb), block)
        assert (args.mesh, args.units, args.repair, args.refine) == (Path("m"), "m", True, 8)
        assert args.smoothing == 0.5 and args.denoise is True
    assert _accepted(("body", "check"), block).surface_file == Path("s.nc")


def test_a_torso_block_gives_its_size_chart_and_mesh_resolution():
    spec = case_schema()["properties"]["body"]["properties"]["torso"]["properties"]
    block = {"torso": {key: _example(sub) for key, sub in spec.items()}, "tissue": {}}
    args = _accepted(("body", "torso"), block)
    assert (args.size, args.chart, args.around, args.rings) == ("m", Path("m"), 8, 8)


@pytest.mark.parametrize(
    ("block", "line", "field", "says"),
    [
        ({"table": TABLE, "knotz": 8}, (), "knotz", "not an option of this command"),
        ({"table": TABLE, "knots": 1}, (), "knots", "must be >= 2"),
        ({"table": TABLE, "branch": "up"}, (), "branch", "is not one of unload, load, all"),
        ({"table": TABLE, "knots": 8}, ("--knots", "8"), "knots", "given both"),
        ({"table": TABLE, "knots": [8]}, (), "knots", "single number"),
        ({"table": TABLE, "plot": "p.png"}, (), "plot", "not an option"),
    ],
)
def test_a_bad_block_is_one_line_naming_its_key(tmp_path, capsys, block, line, field, says):
    out = tmp_path / "m.nc"
    code = main(["material", "ingest", *line, "--json", json.dumps(block), "-o", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists()
    assert len(err.splitlines()) == 1 and f"--json: {field}: " in err and says in err


def test_a_block_ingests_the_same_material_as_the_options(tmp_path):
    by_block, by_line = tmp_path / "block.nc", tmp_path / "line.nc"
    block = {"table": [TABLE], "knots": 6, "branch": "load", "thickness_mm": 0.6}
    assert main(["material", "ingest", "--json", json.dumps(block), "-o", str(by_block)]) == 0
    line = [TABLE, "--knots", "6", "--branch", "load", "--thickness-mm", "0.6"]
    assert main(["material", "ingest", *line, "-o", str(by_line)]) == 0
    with xr.open_dataset(by_block) as a, xr.open_dataset(by_line) as b:
        assert float(a["thickness"]) == pytest.approx(0.6e-3)  # m
        for name in a.data_vars:
            np.testing.assert_array_equal(a[name].values, b[name].values)


def test_without_a_table_or_a_block_ingest_says_what_to_give(tmp_path, capsys):
    assert main(["material", "ingest", "-o", str(tmp_path / "m.nc")]) == 2
    assert "give the lab table(s), or --json with a table" in capsys.readouterr().err
