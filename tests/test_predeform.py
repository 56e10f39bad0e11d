"""Pre-deformation: the garment starts on or just outside the body, with the predicted strain."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import trimesh
import xarray as xr
import yaml
from scipy.spatial import ConvexHull

from cloth.bodies import EllipticCylinder
from cloth.bodies.torso import chart_size, torso_mesh
from cloth.cli import main
from cloth.files.state import read_state, state_dataset
from cloth.garment.grid import FIXED, FREE, SLIDING, WARP, WEFT
from cloth.garment.mechanics import spring_state
from cloth.io import write_netcdf
from cloth.stages.case import initial_state
from tests.conftest import write_obj

OFFSET = 1e-4
CYLINDER = {
    "material": "powernet",
    "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [64, 6], "offset": OFFSET},
}


def case(**garment):
    out = copy.deepcopy(CYLINDER)
    out["garment"].update(garment)
    return out


def test_cylinder_wrap_is_exact():
    state = initial_state(case())
    grid, n, m = state.grid, 64, 6
    r = np.hypot(state.x[:, 0], state.x[:, 1])
    np.testing.assert_allclose(r, 0.1 + OFFSET, atol=1e-12)
    np.testing.assert_allclose(
        state.x[:, 2].reshape(m, n), np.linspace(0.1, 0.4, m)[:, None].repeat(n, 1), atol=1e-12
    )
    # weft strain: chord of the placed ring over the rest length (1 - reduction) 2 pi r / n
    chord = 2 * (0.1 + OFFSET) * np.sin(np.pi / n)
    rest = 0.8 * 2 * np.pi * 0.1 / n
    strain = spring_state(state.x, grid).strain
    np.testing.assert_allclose(strain[grid.family_slices[WEFT]], chord / rest - 1, rtol=1e-9)
    np.testing.assert_allclose(strain[grid.family_slices[WARP]], 0.0, atol=1e-12)
    assert np.all(state.on_body == 1)
    assert np.all(state.constraint.reshape(m, n)[[0, -1]] == SLIDING)
    assert np.all(state.constraint.reshape(m, n)[1:-1] == FREE)


@pytest.mark.parametrize(("edges", "flag"), [("fixed", 2), ("sliding", 1), ("free", 0)])
def test_the_edges_option_sets_how_the_edge_rows_move(edges, flag):
    """``garment.edges``: the top and bottom rows fixed (flag 2), sliding (1) or free (0), the
    rows between always free; the flags are result.nc's ``constraint`` meanings, free sliding
    fixed."""
    state = initial_state(case(edges=edges))
    rows = state.constraint.reshape(6, 64)
    assert np.all(rows[[0, -1]] == flag) and np.all(rows[1:-1] == 0)


@pytest.mark.parametrize(
    "body",
    [
        {"elliptic_cylinder": {"a": 0.15, "b": 0.10}},
        {"cone": {"radius_bottom": 0.12, "radius_top": 0.08}},
        {"torso": {"size": "S", "around": 64, "rings": 40}},
    ],
)
def test_wrapped_nodes_start_on_or_just_outside(body):
    c = case(bottom=0.2, top=0.4, grid=[48, 5], edges="fixed")
    c["body"] = body
    if "torso" in body:
        c["garment"].update(bottom=0.88, top=1.2)
    state = initial_state(c)
    from cloth.files.body import body_from_config

    solid, _ = body_from_config(state.case.body.block)
    distance = solid.query(state.x)[0]
    assert distance.min() >= -1e-12
    assert distance.max() <= OFFSET + 1e-9
    # each row's weft strain: the perimeter of the (convex) node ring over the rest circumference
    grid = state.grid
    strain = spring_state(state.x, grid).strain[grid.family_slices[WEFT]].reshape(grid.m, grid.n)
    rest = grid.rest_length[grid.family_slices[WEFT]].reshape(grid.m, grid.n).sum(axis=1)
    for j in range(grid.m):
        ring = state.x.reshape(grid.m, grid.n, 3)[j]
        assert len(ConvexHull(ring[:, :2]).vertices) == grid.n  # every node on the hull, in order
        perimeter = np.sum(np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1))
        assert np.mean(strain[j]) == pytest.approx(perimeter / rest[j] - 1, rel=1e-6)
    assert np.all(state.constraint.reshape(grid.m, grid.n)[[0, -1]] == FIXED)


def test_elliptic_rows_have_the_ellipse_girth():
    c = case(grid=[128, 3])
    c["body"] = {"elliptic_cylinder": {"a": 0.15, "b": 0.10}}
    state = initial_state(c)
    girth = EllipticCylinder(0.15, 0.10).girth(0.2)[0]
    rest = state.grid.rest_length[state.grid.family_slices[WEFT]].reshape(3, 128).sum(axis=1)
    np.testing.assert_allclose(rest, 0.8 * girth, rtol=1e-12)


def test_state_file_round_trip(tmp_path):
    state = initial_state(case(shear_modulus=1e4))
    path = write_netcdf(state_dataset(state, "initial"), tmp_path / "initial.nc")
    again, ds = read_state(path, "initial")
    np.testing.assert_array_equal(again.x, state.x)
    np.testing.assert_array_equal(again.grid.ends, state.grid.ends)
    np.testing.assert_array_equal(again.grid.area, state.grid.area)
    assert again.case == state.case and again.body == state.body
    assert ds.attrs["Conventions"] == "CF-1.11"
    for name, var in ds.data_vars.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    for flag in ("constraint", "contact", "spring_family"):
        assert len(ds[flag].attrs["flag_values"]) == len(ds[flag].attrs["flag_meanings"].split())
    x = np.random.default_rng(0).normal(scale=1e-3, size=state.x.shape) + state.x
    from cloth.garment.mechanics import forces

    np.testing.assert_array_equal(forces(x, again.grid), forces(x, state.grid))


def test_units_and_axes_give_identical_initial_positions(tmp_path):
    vertices, faces = torso_mesh(chart_size("S"), around=48, rings=30)
    y_up_mm = np.column_stack([vertices[:, 0], vertices[:, 2], -vertices[:, 1]]) * 1000
    # x up, in cm: the body turned -90 degrees about y (file x, y, z = body z, y, -x)
    x_up_cm = np.column_stack([vertices[:, 2], vertices[:, 1], -vertices[:, 0]]) * 100
    write_obj(tmp_path / "m.obj", vertices, faces)
    write_obj(tmp_path / "mm.obj", y_up_mm, faces)
    write_obj(tmp_path / "cm.obj", x_up_cm, faces)
    results = []
    for name, units, up in (("m.obj", "m", "z"), ("mm.obj", "mm", "y"), ("cm.obj", "cm", "x")):
        c = case(bottom=0.9, top=1.15, grid=[32, 4])
        # the mesh itself (units and axes are converted before any surface is fitted to it;
        # the fit, the same on both, took 75 s of this test)
        c["body"] = {"mesh": name, "units": units, "up": up, "surface": "mesh"}
        results.append(initial_state(c, tmp_path).x)
    np.testing.assert_allclose(results[0], results[1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(results[0], results[2], rtol=0, atol=1e-9)


def write_case(tmp_path: Path, data) -> Path:
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def with_body(body):
    c = case()
    c["body"] = body
    return c


BAD_CASES = {
    "missing mesh": (with_body({"mesh": "nope.obj"}), "mesh file not found"),
    "not a mesh": (with_body({"mesh": "junk.obj"}), "no triangles"),
    "hole": (with_body({"mesh": "hole.ply"}), "not watertight"),
    "winding": (with_body({"mesh": "winding.ply"}), "inconsistently wound"),
    "units typo": (with_body({"mesh": "box.ply", "units": "inch"}), "body.units"),
    "axis typo": (with_body({"mesh": "box.ply", "up": "w"}), "body.up"),
    "bottom above top": (case(bottom=0.4, top=0.1), "must be below top"),
    "outside the body": (case(top=0.7), "outside the body"),
    "no section": (with_body({"mesh": "gap.ply"}), "no cross-section at height"),
    "grid too small": (case(grid=[2, 2]), "too small"),
    "both patterns": (case(circumference=0.5), "exactly one of reduction"),
    "reduction too big": (case(reduction=0.95), "garment.reduction"),
    "negative reduction": (case(reduction=-0.1), "garment.reduction"),
    "unknown key": ({**case(), "solvr": {}}, "solvr"),
}


def make_meshes(tmp_path: Path) -> None:
    box = trimesh.creation.box(extents=[0.3, 0.2, 1.0])
    box.apply_translation([0, 0, 0.5])
    box.export(tmp_path / "box.ply")
    trimesh.Trimesh(box.vertices, box.faces[1:], process=False).export(tmp_path / "hole.ply")
    faces = box.faces.copy()
    faces[0] = faces[0][::-1]
    trimesh.Trimesh(box.vertices, faces, process=False).export(tmp_path / "winding.ply")
    low = trimesh.creation.box(extents=[0.3, 0.2, 0.2])
    low.apply_translation([0, 0, 0.1])
    high = trimesh.creation.box(extents=[0.3, 0.2, 0.2])
    high.apply_translation([0, 0, 0.4])
    trimesh.util.concatenate([low, high]).export(tmp_path / "gap.ply")  # nothing at 0.2-0.3 m
    (tmp_path / "junk.obj").write_text("this is not a mesh\n")


@pytest.mark.parametrize("name", sorted(BAD_CASES))
def test_bad_case_one_line_exit_2_no_output(tmp_path, capsys, name):
    make_meshes(tmp_path)
    data, expected = BAD_CASES[name]
    path = write_case(tmp_path, data)
    out = tmp_path / "initial.nc"
    assert main(["predeform", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and expected in err[0], err
    assert "Traceback" not in err[0]
    assert not out.exists() and not list(tmp_path.glob(".*.tmp"))


def test_cli_writes_initial_state_and_figure(tmp_path):
    path = write_case(tmp_path, case())
    out = tmp_path / "initial.nc"
    assert (
        main(
            [
                "--log-level",
                "WARNING",
                "predeform",
                str(path),
                "-o",
                str(out),
                "--plot",
                str(tmp_path / "i.png"),
            ]
        )
        == 0
    )
    with xr.open_dataset(out) as ds:
        assert ds.attrs["stage"] == "initial" and ds["x"].shape == (6, 64)
    assert (tmp_path / "i.png").stat().st_size > 20_000
