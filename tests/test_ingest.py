"""Lab tables -> curves: unit conversion, cycle/branch choice, fit accuracy, round trip."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from cloth.cli import main
from cloth.files.material import fabric_from_dataset, material_dataset
from cloth.materials.curves import StressStrainCurve
from cloth.materials.fitting import fit_monotone
from cloth.materials.labtables import IngestOptions, ingest

ROOT = Path(__file__).resolve().parents[1]
TRUE = StressStrainCurve([0.0, 0.1, 0.35, 0.6, 0.8], [0.0, 0.08e6, 0.5e6, 1.3e6, 2.4e6])


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_noisy_dense_curve_is_recovered_within_reported_error(seed):
    rng = np.random.default_rng(seed)
    eps = np.sort(rng.uniform(0, 0.8, 600))
    noise = 0.01 * 2.4e6
    sigma = TRUE.stress(eps) + rng.normal(scale=noise / 3, size=eps.size)
    knots_x, knots_y, report = fit_monotone(eps, sigma, n_knots=8)
    fitted = StressStrainCurve(knots_x, knots_y)
    assert np.all(np.diff(knots_y) >= 0)  # monotone
    deviation = np.abs(fitted.stress(eps) - TRUE.stress(eps))
    assert np.max(deviation) <= report.max_error
    assert report.rms_error <= 1.2 * noise / 3  # no worse than the noise itself, near enough
    assert report.max_error_percent == pytest.approx(100 * report.max_error / np.max(np.abs(sigma)))


def test_exact_curve_is_fitted_exactly_when_knots_allow():
    eps = np.linspace(0, 0.8, 161)  # candidates of the greedy placement include every true knot
    knots_x, knots_y, report = fit_monotone(eps, TRUE.stress(eps), n_knots=5, n_candidates=159)
    np.testing.assert_allclose(knots_x, TRUE.knot_strain, atol=1e-12)
    np.testing.assert_allclose(knots_y, TRUE.knot_stress, rtol=1e-8)
    assert report.max_error <= 1e-6 * 2.4e6


def test_raw_force_export_converts_units_and_picks_last_unload(tmp_path):
    width, thickness, k_weft, k_warp = 50.0, 0.5, 20.0, 30.0  # force = k x strain (N)
    rows = []
    for direction, k in (("weft", k_weft), ("warp", k_warp)):
        for cycle in (1, 2):
            for branch, scale in (("load", 1.0), ("unload", 0.9 if cycle == 2 else 0.95)):
                for pct in np.linspace(0, 60, 13):
                    rows.append(
                        f"{direction},{cycle},{branch},{pct:.1f},{scale * k * pct / 100:.6f}"
                    )
    table = write(
        tmp_path / "raw.csv",
        f"# specimen_width_mm: {width}\n# thickness_mm: {thickness}\n# lab note ignored\n"
        "direction,cycle,branch,elongation_percent,force_N\n" + "\n".join(rows) + "\n",
    )
    material = ingest([table], options=IngestOptions(n_knots=3))
    area = width * thickness * 1e-6
    for direction, k in (("weft", k_weft), ("warp", k_warp)):
        curve = material.fabric.curve(direction)
        # the default takes cycle 2's unloading branch: 0.9 x the loading force
        assert float(curve.stress(0.4)) == pytest.approx(0.9 * k * 0.4 / area, rel=1e-6)
        assert material.data[direction].raw_strain.size == 13
    assert material.fabric.thickness == pytest.approx(thickness * 1e-3)
    loading = ingest([table], options=IngestOptions(n_knots=3, branch="load", cycle=1))
    assert float(loading.fabric.weft.stress(0.4)) == pytest.approx(k_weft * 0.4 / area, rel=1e-6)
    # both branches of cycle 2 at the same strains: the least-squares line is their mean slope
    both = ingest([table], options=IngestOptions(n_knots=3, branch="all", cycle=2))
    assert both.data["weft"].raw_strain.size == 26
    assert float(both.fabric.weft.stress(0.4)) == pytest.approx(
        0.95 * k_weft * 0.4 / area, rel=1e-6
    )


def test_extension_and_clean_tables_one_file_per_direction(tmp_path):
    weft = write(
        tmp_path / "weft.csv",
        "# gauge_length_mm: 200\n# specimen_width_mm: 25\n# thickness_mm: 1.0\n"
        "extension_mm,force_cN\n0,0\n20,500\n40,1500\n",
    )
    warp = write(tmp_path / "warp.csv", "strain_percent,stress_kPa\n0,0\n10,50\n30,400\n")
    material = ingest([weft, warp], ["weft", "warp"])
    np.testing.assert_allclose(material.fabric.weft.knot_strain, [0.0, 0.1, 0.2])
    np.testing.assert_allclose(material.fabric.weft.knot_stress, [0.0, 5.0 / 25e-6, 15.0 / 25e-6])
    np.testing.assert_allclose(material.fabric.warp.knot_strain, [0.0, 0.1, 0.3])
    np.testing.assert_allclose(material.fabric.warp.knot_stress, [0.0, 5e4, 4e5])
    assert material.data["warp"].report.max_error == 0.0


def test_material_file_round_trip(tmp_path):
    out = tmp_path / "m.nc"
    assert (
        main(
            [
                "--log-level",
                "WARNING",
                "material",
                "ingest",
                str(ROOT / "data/materials/powernet.csv"),
                "-o",
                str(out),
                "--plot",
                str(tmp_path / "m.png"),
            ]
        )
        == 0
    )
    with xr.open_dataset(out, engine="netcdf4") as ds:
        ds.load()
    assert ds.attrs["Conventions"] == "CF-1.11"
    for name, var in ds.data_vars.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    fabric = fabric_from_dataset(ds)
    reference = ingest([ROOT / "data/materials/powernet.csv"])
    for direction in ("weft", "warp"):
        np.testing.assert_array_equal(
            fabric.curve(direction).knot_stress, reference.fabric.curve(direction).knot_stress
        )
        assert float(ds[f"{direction}_fit_max_error_percent"]) < 2.0
    assert fabric.thickness == pytest.approx(0.55e-3)
    assert (tmp_path / "m.png").stat().st_size > 10_000
    again = material_dataset(reference)
    assert set(again.data_vars) == set(ds.data_vars)


GOOD_HEADER = "# thickness_mm: 0.5\n"
BAD_TABLES = {
    "missing column": (GOOD_HEADER + "direction,strain\nweft,0\n", "missing stress column"),
    "non-numeric": (GOOD_HEADER + "direction,strain,stress\nweft,0,0\nweft,0.1,abc\n", "row 4"),
    "non-monotone": (
        GOOD_HEADER + "direction,strain,stress\nweft,0,0\nweft,0.3,5\nweft,0.2,6\n",
        "decreases",
    ),
    "falling stress": (
        GOOD_HEADER + "direction,strain,stress\nweft,0,0\nweft,0.5,1e5\nweft,0.6,9e4\n"
        "warp,0,0\nwarp,1,1e5\n",
        "the stress falls from knot 1 to knot 2",
    ),
    "nan": (GOOD_HEADER + "direction,strain,stress\nweft,0,0\nweft,0.1,nan\n", "not finite"),
    "duplicate knots": (
        GOOD_HEADER + "direction,strain,stress\nweft,0,0\nweft,0.1,5\nweft,0.1,6\n",
        "repeats",
    ),
    "unknown units": (GOOD_HEADER + "direction,strain,stress_psi\nweft,0,0\n", "unknown unit"),
    "empty": ("", "no header row"),
    "header only": (GOOD_HEADER + "direction,strain,stress\n", "no data rows"),
    "unknown direction": (
        GOOD_HEADER + "direction,strain,stress\nwarp,0,0\nwarp,1,1\nweft,0,0\nbias45,1,1\n",
        "unknown direction",
    ),
    "missing thickness": (
        "direction,strain,stress\nweft,0,0\nweft,1,1\nwarp,0,0\nwarp,1,1\n",
        "thickness",
    ),
    "negative thickness": (
        "# thickness_mm: -1\ndirection,strain,stress\nweft,0,0\nweft,1,1\nwarp,0,0\nwarp,1,1\n",
        "thickness",
    ),
    "no warp": (GOOD_HEADER + "direction,strain,stress\nweft,0,0\nweft,1,1\n", "no warp"),
}


@pytest.mark.parametrize("case", sorted(BAD_TABLES))
def test_bad_table_one_line_exit_2_no_output(tmp_path, capsys, case):
    text, expected = BAD_TABLES[case]
    table = write(tmp_path / "lab.csv", text)
    out = tmp_path / "out" / "m.nc"
    status = main(
        ["material", "ingest", str(table), "-o", str(out), "--plot", str(tmp_path / "p.png")]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2
    assert len(err) == 1 and "Traceback" not in err[0]
    assert str(table) in err[0] and expected in err[0]
    assert not out.exists() and not (tmp_path / "p.png").exists()
    assert not list(tmp_path.rglob("*.tmp"))


def test_missing_file_is_one_line(tmp_path, capsys):
    assert (
        main(["material", "ingest", str(tmp_path / "nope.csv"), "-o", str(tmp_path / "m.nc")]) == 2
    )
    assert "file not found" in capsys.readouterr().err


def _generator():
    """data/materials/generate_powernet.py as a module: exports with a known set."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "data" / "materials" / "generate_powernet.py"
    spec = importlib.util.spec_from_file_location("generate_powernet", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: How close the set is recovered (strain, 1; docs/materials.md): the toe's curvature biases
#: it by at most 0.3e-3; the example's noise (0.05 N on a 50 mm strip) scatters it by 0.6e-3
#: (standard deviation over 60 seeds x 4 sets x 2 directions, largest 2.4e-3).
SET_TOLERANCE = {0.0: 0.5e-3, 0.05: 2.5e-3}


@pytest.mark.parametrize("noise", [0.0, 0.05])
@pytest.mark.parametrize("per_cycle", [0.002, 0.006, 0.01, 0.02])
def test_the_set_of_a_generated_export_is_recovered(tmp_path, per_cycle, noise):
    """The export's last unloading branch reaches zero force at 3 x per_cycle in both directions
    (the generator's definition); ingest recovers it within SET_TOLERANCE, noise or not, though
    it falls between the table's strain samples (0.8 / 119 = 0.0067 apart)."""
    generator = _generator()
    table = tmp_path / "export.csv"
    table.write_text("\n".join(generator.export_lines(per_cycle, noise, seed=7)) + "\n")
    measured = ingest([table]).fabric.set_strain
    expected = per_cycle * generator.CYCLES
    for direction in ("weft", "warp"):
        assert measured[direction] == pytest.approx(expected, abs=SET_TOLERANCE[noise]), direction


def test_the_set_of_the_example_fabric_is_the_one_it_was_generated_with():
    """data/materials/powernet.csv was generated with a set of 0.018 after its third cycle."""
    fabric = ingest([Path(__file__).resolve().parents[1] / "data/materials/powernet.csv"]).fabric
    assert fabric.set_strain["weft"] == pytest.approx(0.018, abs=SET_TOLERANCE[0.05])
    assert fabric.set_strain["warp"] == pytest.approx(0.018, abs=SET_TOLERANCE[0.05])


def test_a_bias_table_gives_the_fabric_its_bias_curve(tmp_path):
    """A clean table per direction, the third one ``bias`` (the direction named on the command
    line, as the config's ``directions``): its points are the bias curve's knots."""
    header = "# thickness_mm: 0.5\nstrain_percent,stress_kPa\n"
    tables = [
        write(tmp_path / f"{name}.csv", header + body)
        for name, body in (
            ("weft", "0,0\n10,50\n30,400\n"),
            ("warp", "0,0\n10,80\n30,500\n"),
            ("bias", "0,0\n20,30\n40,90\n"),
        )
    ]
    material = ingest(tables, ["weft", "warp", "bias"])
    np.testing.assert_allclose(material.fabric.bias.knot_strain, [0.0, 0.2, 0.4])
    np.testing.assert_allclose(material.fabric.bias.knot_stress, [0.0, 3e4, 9e4])
    assert material.fabric.curve("bias") is material.fabric.bias
