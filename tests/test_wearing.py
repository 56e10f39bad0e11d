"""One garment, many wearers (issue 52, item 0): a pattern cut once and worn unchanged, placed
by a girth line (`cloth.garment.cut`)."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.bodies.leg import read_leg_chart
from cloth.cli import main
from cloth.files.body import body_from_config
from cloth.files.pattern import write_pattern
from cloth.garment.grid import WEFT
from cloth.stages.case import initial_state, run_case
from tests.test_relax import THICKNESS, hoop_tension, pressure, solve

ROOT = Path(__file__).resolve().parents[1]

TORSO = {
    "material": "powernet",
    "body": {"torso": {"size": "S"}},
    "garment": {"bottom": 0.80, "top": 1.20, "reduction": 0.2, "grid": [32, 16]},
    "solver": {"tolerance": 1e-8},
}


def _write(folder: Path, data: dict) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "case.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def read_netcdf(path: Path) -> xr.Dataset:
    with xr.open_dataset(path) as ds:
        return ds.load()


def _worn(data: dict, pattern: dict) -> dict:
    out = copy.deepcopy(data)
    out["garment"]["pattern"] = pattern
    return out


@pytest.fixture(scope="module")
def torso_runs(tmp_path_factory):
    """The chart's torso S cut at 0.2 by a reduction, and the same pattern given as cut for
    the same body: both run to result.nc with their error estimates."""
    root = tmp_path_factory.mktemp("wearing")
    out = {}
    for name, data in {
        "reduction": TORSO,
        "pattern": _worn(TORSO, {"body": {"torso": {"size": "S"}}, "place": "hip"}),
    }.items():
        case = _write(root / name, data)
        run_case(case, root / name / "out", {}, stop_after="aggregate")
        out[name] = root / name / "out"
    return root, out


def test_a_pattern_on_the_body_it_was_cut_for_is_the_reduction_bit_for_bit(torso_runs):
    """Worn by the body it was cut for (placed by its hip: no shift), the pattern is the case
    with the reduction it came from: every rest length, the equilibrium and the coarser levels
    of the error estimate are equal to the last bit."""
    _, runs = torso_runs
    a = read_netcdf(runs["reduction"] / "relaxed.nc")
    b = read_netcdf(runs["pattern"] / "relaxed.nc")
    assert float(b.attrs["cut_shift"]) == 0.0
    names = [v for v in a.data_vars if v in b.data_vars]
    assert "x" in names and any(name.startswith("level") for name in names), names
    for name in names:
        if np.issubdtype(a[name].dtype, np.number):
            assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name
    ra = read_netcdf(runs["reduction"] / "result.nc")
    rb = read_netcdf(runs["pattern"] / "result.nc")
    compared = ("rest_circumference", "pattern_height", "pressure_mean", "level_pressure_mean")
    for name in (*compared, "pressure_mean_error"):
        assert np.array_equal(ra[name].values, rb[name].values, equal_nan=True), name


def test_a_pattern_file_on_its_own_body_gives_the_equilibrium_to_the_files_precision(
    torso_runs, tmp_path
):
    """pattern.csv written from the reduction's result and worn by the same body: its rows
    to 1e-4 mm, the girth-line pressures to 1e-5 of their value."""
    _, runs = torso_runs
    csv_path = write_pattern(runs["reduction"] / "result.nc", tmp_path / "pattern.csv", "tube")[0]
    text = csv_path.read_text()
    assert "# girth line hip 0.860000000 m" in text
    data = copy.deepcopy(TORSO)
    data["garment"].pop("reduction")
    data["garment"]["pattern"] = {"file": str(csv_path)}
    case = _write(tmp_path / "file", data)
    run_case(case, tmp_path / "file" / "out", {}, stop_after="aggregate")
    a = read_netcdf(runs["reduction"] / "result.nc")
    b = read_netcdf(tmp_path / "file" / "out" / "result.nc")
    np.testing.assert_allclose(b["rest_circumference"], a["rest_circumference"], atol=1e-7)
    np.testing.assert_allclose(b["pattern_height"], a["pattern_height"], atol=1e-7)
    np.testing.assert_allclose(b["pressure_mean"], a["pressure_mean"], rtol=1e-5)


@pytest.mark.parametrize("wider", [0.09, 0.10])
def test_a_pattern_worn_on_a_wider_cylinder_reads_laplace_at_the_strain_it_imposes(wider):
    """Cut at 0.1 for a cylinder of 8 cm, worn by one of ``wider``: each weft spring's rest
    length is 0.9 x 2 pi 0.08 / n, so the strain is the wider chord 2 R sin(pi/n) over it and
    the pressure sigma(eps) t / R, to 1e-10."""
    n, cut_radius = 64, 0.08
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": wider, "bottom": 0.0, "top": 0.5}},
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": 0.1,
            "grid": [n, 6],
            "pattern": {"body": {"cylinder": {"radius": cut_radius, "bottom": 0.0, "top": 0.5}}},
        },
    }
    state = initial_state(case)
    grid = state.grid
    rest = 0.9 * 2 * np.pi * cut_radius / n
    np.testing.assert_allclose(grid.rest_length[grid.family_slices[WEFT]], rest, rtol=1e-12)
    result = solve(state)
    assert result.converged
    tension = hoop_tension(state, result)
    assert tension.max() / tension.min() - 1 < 1e-3
    eps = 2 * wider * np.sin(np.pi / n) / rest - 1
    held, p = pressure(state, result)
    assert np.all(held)
    np.testing.assert_allclose(p, state.fabric.weft.stress(eps) * THICKNESS / wider, rtol=1e-10)


def test_a_pattern_is_placed_by_its_lowest_shared_girth_line(caplog):
    """Leg M-long's stocking on leg M: placed by B (the lowest line both have), the rows move
    down by M-long's B height minus M's; each row keeps the rest circumference cut on M-long
    at its own cut height."""
    chart = read_leg_chart(ROOT / "data" / "bodies" / "leg_chart.csv")
    shift = chart["M"].height["B"] - chart["M-long"].height["B"]
    data = {
        "material": "powernet",
        "body": {"leg": {"size": "M"}},
        "garment": {
            "bottom": 0.12,
            "top": 0.60,
            "reduction": 0.15,
            "grid": [24, 10],
            "pattern": {"body": {"leg": {"size": "M-long"}}},
        },
    }
    with caplog.at_level("INFO", logger="cloth.garment.predeform"):
        state = initial_state(data)
    assert "girth line B" in caplog.text
    assert float(state.attrs["cut_shift"]) == pytest.approx(shift, abs=1e-12)
    z = state.x[:, 2].reshape(10, 24)
    np.testing.assert_allclose(z[[0, -1]].mean(axis=1), [0.12 + shift, 0.60 + shift], atol=2e-3)
    cut_body, _ = body_from_config({"leg": {"size": "M-long"}})
    heights = np.linspace(0.12, 0.60, 10)
    girth = np.array([cut_body.girth(float(h))[1] for h in heights])
    grid = state.grid
    weft = grid.rest_length[grid.family_slices[WEFT]].reshape(10, 24).sum(axis=1)
    np.testing.assert_allclose(weft, 0.85 * girth, rtol=1e-9)


BAD = {
    "both": ({"body": {"torso": {"size": "S"}}, "file": "p.csv"}, "garment.pattern"),
    "unknown_line": ({"body": {"torso": {"size": "S"}}, "place": "knee"}, "garment.pattern.place"),
    "missing_file": ({"file": "nowhere.csv"}, "pattern file not found"),
    "bad_column": ({"file": "bad.csv"}, "rest_circumference_mm"),
    "past_the_pattern": ({"file": "short.csv"}, "garment.bottom"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_a_bad_pattern_is_refused_in_one_line(tmp_path, capsys, name):
    pattern, expected = BAD[name]
    (tmp_path / "bad.csv").write_text("row,cut_height_m,pattern_height_mm\n0,0.8,0\n1,1.2,400\n")
    (tmp_path / "short.csv").write_text(
        "cut_height_m,pattern_height_mm,rest_circumference_mm\n0.9,0,700\n1.1,200,650\n"
    )
    data = _worn(TORSO, pattern)
    if "file" in pattern:
        data["garment"].pop("reduction")
    path = _write(tmp_path, data)
    out = tmp_path / "initial.nc"
    assert main(["predeform", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and expected in err[0], err
    assert not out.exists()


def test_a_pattern_file_forbids_a_reduction(tmp_path, capsys):
    data = _worn(TORSO, {"file": "p.csv"})
    path = _write(tmp_path, data)
    assert main(["predeform", str(path), "-o", str(tmp_path / "i.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert "garment.reduction" in err and "remove reduction" in err


def test_the_state_keeps_the_pattern_for_its_levels(torso_runs):
    """relaxed.nc records the body the pattern was cut for, so the coarser levels rebuild it
    without the case's folder."""
    _, runs = torso_runs
    with xr.open_dataset(runs["pattern"] / "relaxed.nc") as ds:
        record = json.loads(ds.attrs["pattern_body"])
    assert record["kind"] == "torso" and record["landmarks"]["hip"] == pytest.approx(0.86)
