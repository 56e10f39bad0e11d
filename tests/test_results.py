"""Results: pressure and totals against Laplace, node stresses, CF attributes, figures, export."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from cloth.cli import main
from cloth.garment.grid import rectangle
from cloth.garment.mechanics import spring_state
from cloth.io import write_netcdf
from cloth.results.fields import node_fields
from cloth.results.pressure import MMHG, comfort_group, ral_class
from cloth.stages.results import aggregate
from tests.conftest import make_fabric
from tests.test_relax import THICKNESS, solve, tube


def relaxed_file(tmp_path, state, result, settings_tol=1e-10):
    from cloth.files.relaxed import relaxed_dataset
    from cloth.solvers import Settings

    ds = relaxed_dataset(state, result, Settings(tolerance=settings_tol))
    return write_netcdf(ds, tmp_path / "relaxed.nc")


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cyl")
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2)
    path = relaxed_file(tmp, state, solve(state))
    return state, aggregate(path)[0], tmp


def test_cylinder_pressure_and_totals(cylinder):
    state, ds, _ = cylinder
    expected = float(state.fabric.weft.stress(1 / 0.8 - 1)) * THICKNESS / 0.1
    np.testing.assert_allclose(ds["pressure"].values, expected, rtol=5e-3)
    np.testing.assert_allclose(ds["pressure_mmHg"].values * MMHG, ds["pressure"].values)
    # the pressure integral against the hoop forces: each weft spring of force S pulls its two
    # nodes inward by S sin(pi / n) each (a regular n-gon), so the body carries their sum
    grid = state.grid
    weft = grid.family_slices[0]
    spring_force = np.abs(ds["spring_stress"].values[weft] * grid.area[weft])
    hoop = 2 * np.sin(np.pi / grid.n) * spring_force.sum()
    assert float(ds["pressure_integral"]) == pytest.approx(hoop, rel=1e-9)
    assert np.linalg.norm(ds["total_force"].values) < 1e-6 * float(ds["normal_force"])
    assert ds.attrs["converged"] == 1
    assert ds.attrs["unstable_modes"] == 0  # a tensioned tube on a cylinder is stable


def test_result_file_is_cf_and_round_trips(cylinder, tmp_path):
    _, ds, _ = cylinder
    path = write_netcdf(ds, tmp_path / "result.nc")
    with xr.open_dataset(path, engine="netcdf4") as again:
        again.load()
    assert again.attrs["Conventions"] == "CF-1.11"
    for name, var in again.data_vars.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
        if "flag_values" in var.attrs:
            values = np.asarray(var.attrs["flag_values"])
            assert len(values) == len(var.attrs["flag_meanings"].split())
            assert set(np.unique(var.values)) <= set(values.tolist())
        np.testing.assert_array_equal(var.values, ds[name].values)
    for name in again.coords:
        assert (
            "_FillValue" not in again[name].encoding or again[name].encoding["_FillValue"] is None
        )


def test_elliptic_laplace_diagnostic(tmp_path):
    state = tube(
        {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}, 0.2, n=128
    )
    ds, rows = aggregate(relaxed_file(tmp_path, state, solve(state)))
    inner = slice(1, -1)  # away from the edge rows
    p = ds["pressure"].values[inner]
    np.testing.assert_allclose(ds["p_laplace"].values[inner], p, rtol=2e-2)
    # pressure = T kappa with the ellipse's exact curvature at the nodes
    from cloth.bodies import EllipticCylinder

    xy = np.stack([ds["x"].values.ravel(), ds["y"].values.ravel()], axis=1)
    kappa = EllipticCylinder(0.15, 0.10).curvature(xy).reshape(ds["x"].shape)
    np.testing.assert_allclose(p, (ds["tension_weft"].values * kappa)[inner], rtol=2e-2)
    assert rows and rows[0]["landmark"] == "middle"  # no chart, no extrema on a cylinder


def test_laplace_diagnostic_uses_tension_per_deformed_width(tmp_path):
    """A cylinder with the warp also stretched (lengthwise_reduction 0.1): p_laplace equals the
    pressure within 0.1 % (it was 1.1111 x the pressure with the tension per rest width)."""
    from cloth.stages.case import initial_state

    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": 0.2,
            "grid": [64, 6],
            "edges": "sliding",
            "lengthwise_reduction": 0.1,
        },
    }
    state = initial_state(case)
    ds, _ = aggregate(relaxed_file(tmp_path, state, solve(state)))
    inner = slice(1, -1)
    assert float(ds["strain_warp"].values[inner].mean()) > 0.05  # the warp is stretched
    np.testing.assert_allclose(
        ds["p_laplace"].values[inner], ds["pressure"].values[inner], rtol=1e-3
    )


@pytest.mark.parametrize("compression", [None, 0.01], ids=["default-tension-field", "one-percent"])
def test_flat_patch_node_stress_is_the_lab_curve_with_its_sign(compression):
    """Stretched 35 % along the weft and compressed 10 % along the warp: node stresses are the
    lab curve's; the warp's 0 in the default pure tension field, negative with a compression
    modulus of 1 % of the first slope."""
    fabric = make_fabric(compression=compression)
    grid = rectangle(7, 5, 0.3, 0.2, fabric)
    u, v = grid.rest_uv.T
    x = np.stack([1.35 * u, 0.9 * v, np.zeros_like(u)], axis=1)
    fields = node_fields(grid, x, spring_state(x, grid), fabric.thickness)
    np.testing.assert_allclose(fields.stress_weft, float(fabric.weft.stress(0.35)), rtol=1e-12)
    np.testing.assert_allclose(fields.stress_warp, float(fabric.warp.stress(-0.1)), rtol=1e-12)
    assert np.all(fields.stress_weft > 0)
    assert (
        np.all(fields.stress_warp == 0) if compression is None else np.all(fields.stress_warp < 0)
    )
    assert np.all(fields.pressure == 0)


def test_strain_beyond_the_lab_range_is_reported(tmp_path, caplog):
    """A 50 % reduction strains the weft to 1.0, past the power net's last measured strain
    (0.8): a warning names the direction and the strains, every node is flagged, summary rows
    carry the strains; the unstrained warp springs are flagged slack."""
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.5)
    path = relaxed_file(tmp_path, state, solve(state))
    with caplog.at_level("WARNING", logger="cloth.results.fields"):
        ds, rows = aggregate(path)
    assert "weft springs (the fabric's weft) strained up to 0.99" in caplog.text
    assert "beyond the lab curve's last strain 0.8" in caplog.text
    assert np.all(ds["beyond_lab_range"].values == 1)
    assert float(ds["max_strain_weft"]) == pytest.approx(1.0, abs=5e-3)
    assert float(ds["lab_max_strain_weft"]) == pytest.approx(0.8)
    assert rows[0]["max_strain_weft"] == pytest.approx(float(ds["max_strain_weft"]))
    family = ds["spring_family"].values
    assert np.all(ds["spring_slack"].values[family == 1] == 1)
    assert np.all(ds["spring_slack"].values[family == 0] == 0)


def test_classes():
    assert ral_class(20.0) == "I" and ral_class(25.0) == "II" and ral_class(10.0) == "-"
    assert comfort_group(1.5) == "II" and comfort_group(3.5) == "IV"


def test_cli_figures_export_and_non_converged(tmp_path, capsys):
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=24, m=4)
    result = solve(state, tolerance=1e-14, iterations=1)  # stopped early: NOT converged
    path = relaxed_file(tmp_path, state, result, settings_tol=1e-14)
    out = tmp_path / "result.nc"
    assert (
        main(
            [
                "--log-level",
                "WARNING",
                "aggregate",
                str(path),
                "-o",
                str(out),
                "--summary",
                str(tmp_path / "summary.csv"),
            ]
        )
        == 0
    )
    with xr.open_dataset(out) as ds:
        ds.load()
    assert ds.attrs["converged"] == 0 and "NOT" in ds["pressure"].attrs["long_name"]
    assert "0" == (tmp_path / "summary.csv").read_text().splitlines()[1].split(",")[-1]
    assert main(["plot", str(out), "-o", str(tmp_path / "fig")]) == 0
    from cloth.figures.plots import FIGURES

    figures = sorted((tmp_path / "fig").glob("*.png"))
    assert {f.stem for f in figures} == set(FIGURES)
    assert all(f.stat().st_size > 15_000 for f in figures)
    for suffix in (".ply", ".csv"):
        assert main(["export", str(out), "-o", str(tmp_path / f"garment{suffix}")]) == 0
    import trimesh

    mesh = trimesh.load(tmp_path / "garment.ply", process=False)
    np.testing.assert_allclose(mesh.vertices[:, 2], ds["z"].values.ravel(), atol=1e-6)
    lines = (tmp_path / "garment.csv").read_text().splitlines()
    assert len(lines) == 1 + 24 * 4 and "pressure_Pa" in lines[0]
    capsys.readouterr()
    (tmp_path / "corrupt.nc").write_bytes(b"not netcdf")
    for bad in (tmp_path / "corrupt.nc", tmp_path / "missing.nc"):
        target = tmp_path / "r2.nc"
        assert main(["aggregate", str(bad), "-o", str(target)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and str(bad) in err[0] and not target.exists()


def test_plotted_arrays_are_the_datasets(cylinder, tmp_path, monkeypatch):
    _, ds, _ = cylinder
    import matplotlib.axes

    seen = []
    original = matplotlib.axes.Axes.pcolormesh

    def spy(self, *args, **kwargs):
        if len(args) == 3 and np.shape(args[2]) == ds["u"].shape:  # maps, not colour bars
            seen.append(np.asarray(args[2]))
        return original(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.axes.Axes, "pcolormesh", spy)
    from cloth.figures.plots import plot_result

    plot_result(ds, tmp_path)
    np.testing.assert_array_equal(seen[0], ds["stress_weft"].values)
    np.testing.assert_array_equal(seen[1], ds["stress_warp"].values)
    np.testing.assert_array_equal(seen[2], ds["pressure_mmHg"].values)


def _with_a_hotter_peer(ds, folder):
    """``ds`` and a copy with its stresses doubled and its pressure tripled, written to
    ``folder`` (result.nc, peer.nc): the copy sets the upper ends of any shared range."""
    peer = ds.assign(
        stress_weft=2.0 * ds["stress_weft"],
        stress_warp=2.0 * ds["stress_warp"],
        pressure_mmHg=3.0 * ds["pressure_mmHg"],
    )
    return write_netcdf(ds, folder / "result.nc"), peer, write_netcdf(peer, folder / "peer.nc")


def _map_limits(monkeypatch, shape) -> list:
    """The (vmin, vmax) of every flat map of ``shape`` drawn from now on (not colour bars)."""
    import matplotlib.axes

    limits = []
    original = matplotlib.axes.Axes.pcolormesh

    def spy(self, *args, **kwargs):
        if len(args) == 3 and np.shape(args[2]) == shape:
            limits.append((kwargs["vmin"], kwargs["vmax"]))
        return original(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.axes.Axes, "pcolormesh", spy)
    return limits


def test_a_case_s_figures_share_their_colour_ranges_with_its_peers(cylinder, tmp_path, monkeypatch):
    """`cloth plot --peers` (the pipeline's figures): the flat maps' colour ranges are the 1st
    to 95th percentile of every node of the result and its peers (from 0 where all are
    positive), the weft and the warp on one stress scale, the pressure in mmHg; read from the
    peers' files, here a copy of the cylinder with its stresses doubled and its pressure
    tripled (so that the peer, not the result, sets the upper ends)."""
    from cloth.stages.results import figures

    _, ds, _ = cylinder
    result, peer, peer_path = _with_a_hotter_peer(ds, tmp_path)
    limits = _map_limits(monkeypatch, ds["u"].shape)
    figures(result, tmp_path / "figures", peers=[peer_path])

    def expected(*arrays):
        values = np.concatenate([np.ravel(a) for a in arrays])
        low, high = np.percentile(values[np.isfinite(values)], [1, 95])
        return min(0.0, low), high

    weft = expected(ds["stress_weft"].values, peer["stress_weft"].values)
    warp = expected(ds["stress_warp"].values, peer["stress_warp"].values)
    stress = (min(weft[0], warp[0]), max(weft[1], warp[1]))
    pressure = expected(ds["pressure_mmHg"].values, peer["pressure_mmHg"].values)
    assert len(limits) == 3  # weft, warp, pressure
    np.testing.assert_allclose(limits[0], stress, rtol=1e-12)
    np.testing.assert_allclose(limits[1], stress, rtol=1e-12)
    np.testing.assert_allclose(limits[2], pressure, rtol=1e-12)
    assert limits[2][1] > 2.0 * float(np.nanmax(ds["pressure_mmHg"].values))  # the peer's


def test_a_sweep_s_colour_ranges_are_read_once_into_a_file_its_figures_take(
    cylinder, tmp_path, monkeypatch
):
    """`cloth ranges` (the pipeline's colour_ranges rule) writes the 1st to 95th percentile of
    every node of every result once, and `cloth plot --ranges` colours the maps by it: here two
    results, the cylinder and a copy with its stresses doubled and its pressure tripled, so
    that the copy sets the upper ends; each case's figures get the same ranges (before, each
    counted its own result twice)."""
    import json

    from cloth.cli import main

    _, ds, _ = cylinder
    result, peer, peer_path = _with_a_hotter_peer(ds, tmp_path)
    ranges = tmp_path / "colour_ranges.json"
    assert main(["ranges", str(result), str(peer_path), "-o", str(ranges)]) == 0

    def expected(name):
        values = np.concatenate([np.ravel(ds[name].values), np.ravel(peer[name].values)])
        low, high = np.percentile(values[np.isfinite(values)], [1, 95])
        return min(0.0, low), high

    weft, warp = expected("stress_weft"), expected("stress_warp")
    stress = (min(weft[0], warp[0]), max(weft[1], warp[1]))
    record = json.loads(ranges.read_text())
    np.testing.assert_allclose(record["stress_Pa"], stress, rtol=1e-12)
    np.testing.assert_allclose(record["pressure_mmHg"], expected("pressure_mmHg"), rtol=1e-12)
    assert record["results"] == [str(result), str(peer_path)]
    limits = _map_limits(monkeypatch, ds["u"].shape)
    for case in (result, peer_path):  # the same ranges for each
        out = tmp_path / f"figures_{case.stem}"
        assert main(["plot", str(case), "--ranges", str(ranges), "-o", str(out)]) == 0
    assert len(limits) == 6
    for low_high in limits[0:2] + limits[3:5]:
        np.testing.assert_allclose(low_high, stress, rtol=1e-12)
    for low_high in (limits[2], limits[5]):
        np.testing.assert_allclose(low_high, expected("pressure_mmHg"), rtol=1e-12)


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("{not json", None),
        ('{"stress_Pa": [0, 1]}', "pressure_mmHg"),
        ('{"stress_Pa": [2, 1], "pressure_mmHg": [0, 1]}', "stress_Pa"),
        ('{"stress_Pa": [0, "1"], "pressure_mmHg": [0, 1]}', "stress_Pa"),
        ('{"stress_Pa": [0, 1], "pressure_mmHg": [false, true]}', "pressure_mmHg"),
    ],
    ids=["not-json", "missing", "reversed", "not-a-number", "booleans"],
)
def test_a_bad_colour_range_file_is_one_line_naming_the_file_and_exit_2(
    cylinder, tmp_path, capsys, text, field
):
    from cloth.cli import main

    _, ds, _ = cylinder
    result = write_netcdf(ds, tmp_path / "result.nc")
    ranges = tmp_path / "ranges.json"
    ranges.write_text(text)
    assert main(["plot", str(result), "--ranges", str(ranges), "-o", str(tmp_path / "f")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "ranges.json" in err[0] and "Traceback" not in err[0]
    assert field is None or field in err[0]
    assert not (tmp_path / "f").exists() or not any((tmp_path / "f").iterdir())


@pytest.mark.slow  # a scan relaxed (8 s; make test-slow)
def test_landmarks_of_a_scan_come_from_the_girth_profile(tmp_path):
    from cloth.bodies.torso import chart_size, torso_mesh
    from cloth.results.landmarks import girth_extrema
    from cloth.stages.case import initial_state
    from tests.conftest import write_obj

    chart = chart_size("M")
    vertices, faces = torso_mesh(chart, around=64, rings=60)
    write_obj(tmp_path / "scan.obj", vertices, faces)
    state = initial_state(
        {
            "material": "powernet",
            # sampled at 6 mm (the default 3 mm takes four times the samples): the girth
            # profile's minimum, not the surface's fine shape, is what is checked
            "body": {"mesh": "scan.obj", "smoothing": 0.012, "spacing": 0.006},
            "garment": {"bottom": 0.9, "top": 1.2, "reduction": 0.15, "grid": [24, 31]},
        },
        tmp_path,
    )
    marks = girth_extrema(state)
    minima = [z for name, z in marks.items() if name.startswith("girth_min")]
    assert len(minima) == 1
    assert minima[0] == pytest.approx(chart.height["waist"], abs=0.011)  # within a row (1 cm)


@pytest.mark.parametrize("lengthwise", [0.0, 0.1])
def test_cone_edge_rows_carry_the_body_share_only(tmp_path, lengthwise):
    """A cone (radius 0.15 to 0.07 m over 0.3 m) with sliding edges. Interior contact nodes on a
    straight meridian: pressure = hoop Laplace, T per deformed width x cos(alpha) / r, within
    0.5 %; every interior contact node: p_laplace within 1 %. Edge rows on the cone: pressure x
    area = lambda of R = -lambda n - mu e_z, solved here from the spring forces (least squares on
    n and e_z), and edge_support_force = mu; -R . n would differ by mu n_z. With the warp also
    stretched (lengthwise 0.1) it pulls the upper edge 2 mm off the cone: no pressure there."""
    from cloth.bodies import Cone
    from cloth.garment.grid import WEFT
    from cloth.stages.case import initial_state

    body = {"cone": {"radius_bottom": 0.15, "radius_top": 0.07, "bottom": 0.0, "top": 0.3}}
    case = {
        "material": "powernet",
        "body": body,
        "garment": {
            "bottom": 0.05,
            "top": 0.25,
            "reduction": 0.15,
            "grid": [64, 8],
            "edges": "sliding",
            "lengthwise_reduction": lengthwise,
        },
    }
    state = initial_state(case)
    result = solve(state, iterations=100)
    assert result.converged
    ds, _ = aggregate(relaxed_file(tmp_path, state, result))
    grid, x = state.grid, result.final.x
    cone = Cone(0.15, 0.07, 0.0, 0.3)
    _, _, normal = cone.query(x)
    # the resultant spring force on every node, from the springs one by one
    springs = result.final.springs
    force = np.zeros_like(x)
    spring_force = springs.stress * grid.area  # S_k, N, tension positive
    pull = spring_force[:, None] * springs.direction  # on node a, towards b
    np.add.at(force, grid.ends[:, 0], pull)
    np.add.at(force, grid.ends[:, 1], -pull)
    pressure = ds["pressure"].values.ravel()
    area = ds["node_area"].values.ravel()
    n, m = grid.n, grid.m
    inner = np.arange(n, (m - 1) * n)
    # hoop tension per deformed width: weft spring force / (rest width x (1 + warp strain))
    weft = grid.family_slices[WEFT]
    hoop = (np.abs(spring_force[weft]) / (grid.area[weft] / THICKNESS)).reshape(m, n)
    strain_warp = ds["strain_warp"].values
    radius = np.hypot(x[:, 0], x[:, 1]).reshape(m, n)
    cos_alpha = 0.3 / np.hypot(0.08, 0.3)  # the normal's radial share
    laplace = (hoop / (1 + strain_warp) * cos_alpha / radius).ravel()
    contact = ds["contact"].values.astype(bool)
    # where a node's warp neighbours lie on the cone too, its meridian is straight: hoop only
    straight = np.zeros((m, n), bool)
    straight[1:-1] = contact[1:-1] & contact[:-2] & contact[2:]
    assert straight.sum() >= 4 * n
    np.testing.assert_allclose(pressure[straight.ravel()], laplace[straight.ravel()], rtol=5e-3)
    held = contact.ravel()[inner]  # next to a lifted edge the warp bends: p_laplace has it
    np.testing.assert_allclose(
        ds["p_laplace"].values.ravel()[inner][held], pressure[inner][held], rtol=1e-2
    )
    for k in np.concatenate([np.arange(n), np.arange((m - 1) * n, m * n)]):
        basis = np.column_stack([normal[k], [0.0, 0.0, 1.0]])
        (lam, mu), *_ = np.linalg.lstsq(basis, -force[k], rcond=None)
        if not contact.ravel()[k]:  # an edge the warp pulls off the cone: no pressure, mu = -R_z
            assert pressure[k] == 0 and lam <= 1e-9 * np.linalg.norm(force[k])
            assert ds["edge_support_force"].values.ravel()[k] == pytest.approx(-force[k, 2])
            continue
        assert pressure[k] * area[k] == pytest.approx(lam, rel=1e-6)
        assert ds["edge_support_force"].values.ravel()[k] == pytest.approx(mu, rel=1e-6)
        assert abs(-force[k] @ normal[k] - lam) > 1e-3 * lam  # -R . n is not the body's share


@pytest.mark.parametrize("kind", [None, "torso"])
def test_a_scan_s_wiggles_are_not_landmarks_and_its_kind_names_them(tmp_path, kind):
    """The torso mesh with a girth wiggle of +-3 mm every 3 cm (a scan's ripple): find_peaks'
    prominence keeps the hip, waist and bust extrema only (without it, 15 extrema: every
    ripple was a landmark), named so when the case says the body is a torso."""
    from cloth.bodies.torso import chart_size, torso_mesh
    from cloth.results.landmarks import girth_extrema
    from cloth.stages.case import initial_state
    from tests.conftest import write_obj

    chart = chart_size("M")
    vertices, faces = torso_mesh(chart, around=96, rings=160)
    ripple = 1.0 + 0.003 / 0.9 * np.sin(2 * np.pi * vertices[:, 2] / 0.03)
    vertices[:, :2] *= ripple[:, None]
    write_obj(tmp_path / "scan.obj", vertices, faces)
    body = {"mesh": "scan.obj", "surface": "mesh", **({"kind": kind} if kind else {})}
    state = initial_state(
        {
            "material": "powernet",
            "body": body,
            "garment": {"bottom": 0.80, "top": 1.28, "reduction": 0.15, "grid": [24, 49]},
        },
        tmp_path,
    )
    marks = girth_extrema(state)
    names = ["hip", "waist", "bust"] if kind else ["girth_max_1", "girth_min_2", "girth_max_3"]
    assert list(marks) == names
    for name, line in zip(names, ("hip", "waist", "bust"), strict=True):
        # within half the ripple's period and a row: a flat extremum moves with the ripple
        assert marks[name] == pytest.approx(chart.height[line], abs=0.025)


def test_a_mesh_body_s_kind_names_its_girth_extrema_in_height_order():
    """``body.kind``: on a torso the lowest minimum above a maximum is the waist, the maximum
    below it the hip, the one above it the bust; on a leg the lowest minimum is B, the maximum
    above it C, the minimum above that D; extrema past those keep their numbered names."""
    from cloth.results.landmarks import anatomical

    torso = {"girth_min_1": 0.70, "girth_max_2": 0.86, "girth_min_3": 1.04, "girth_max_4": 1.2}
    assert anatomical(torso, "torso") == {
        "girth_min_1": 0.70,  # no maximum below it: not a waist
        "hip": 0.86,
        "waist": 1.04,
        "bust": 1.2,
    }
    leg = {"girth_max_1": 0.05, "girth_min_2": 0.1, "girth_max_3": 0.3, "girth_min_4": 0.45}
    leg["girth_max_5"] = 0.6
    assert anatomical(leg, "leg") == {
        "girth_max_1": 0.05,  # below the ankle
        "B": 0.1,
        "C": 0.3,
        "D": 0.45,
        "girth_max_5": 0.6,
    }


def test_the_3d_garment_shows_every_stride_th_node_in_its_own_colour(tmp_path, monkeypatch):
    """A 192 x 96 tube drawn in 3D (`plot_garment_3d`) shows every second row and column
    (96 x 48 nodes, the most it draws), each dot at its node's position and coloured by that
    node's value: here its row x 1000 + its column, so a dot names the node it stands for."""
    from mpl_toolkits.mplot3d import Axes3D

    from cloth.figures.plots import plot_garment_3d

    n, m = 192, 96
    row, col = np.meshgrid(np.arange(m), np.arange(n), indexing="ij")
    angle = 2 * np.pi * col / n
    x = np.stack([0.1 * np.cos(angle), 0.1 * np.sin(angle), 0.01 * row], axis=-1).reshape(-1, 3)
    values = (1000.0 * row + col).ravel()
    seen = []
    original = Axes3D.scatter

    def spy(self, xs, ys, zs, *args, **kwargs):
        seen.append((np.asarray(xs), np.asarray(ys), np.asarray(zs), np.asarray(kwargs["c"])))
        return original(self, xs, ys, zs, *args, **kwargs)

    monkeypatch.setattr(Axes3D, "scatter", spy)
    plot_garment_3d(x, n, m, values, "value [1]", tmp_path / "g.png")
    ((xs, ys, zs, colours),) = seen
    rows = np.rint(zs / 0.01).astype(int)
    cols = np.rint(np.mod(np.arctan2(ys, xs), 2 * np.pi) * n / (2 * np.pi)).astype(int) % n
    np.testing.assert_array_equal(colours, 1000.0 * rows + cols)
    assert sorted(set(rows)) == list(range(0, m, 2)) and sorted(set(cols)) == list(range(0, n, 2))
    assert len(colours) == 48 * 96
