"""``cloth compare``: a measurements file read, placed on a result and compared, checked on a
cylinder, where every probe reads Laplace's T / R, against statistics computed by hand."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.cli import main
from cloth.results.pressure import MMHG
from tests import crossrefs, inventory

RADIUS = 0.1
CASE = {
    "material": "powernet",
    "body": {"cylinder": {"radius": RADIUS, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [32, 12]},
    "landmarks": {"low": 0.2, "mid": 0.25},
}
HEADER = "point,height_m,angle_deg,pressure_mmHg,probe_mm,repeat\n"
#: Readings: two repeats at one place, a girth line by name at another probe size, an angle
#: past 180 degrees (270 is -90), and a line named with an angle below zero.
READINGS = (
    ",0.15,0,20.0,50,1\n"
    ",0.15,0,22.0,50,2\n"
    "mid,,90,15.0,30,1\n"
    ",0.30,270,25.0,50,1\n"
    "low,,-45,19.0,50,1\n"
)


def read_rows(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    """A cylinder's result.nc, with its error estimate (two coarser levels)."""
    folder = tmp_path_factory.mktemp("cylinder")
    case = folder / "case.yaml"
    case.write_text(yaml.safe_dump(CASE))
    out = folder / "run"
    argv = ["--log-level", "WARNING", "run", str(case), "-o", str(out), "--stop-after", "aggregate"]
    assert main(argv) == 0
    return out / "result.nc"


@pytest.fixture(scope="module")
def compared(cylinder, tmp_path_factory):
    folder = tmp_path_factory.mktemp("compared")
    measured = folder / "measured.csv"
    measured.write_text("# made up for the test\n" + HEADER + READINGS)
    out = folder / "out"
    assert (
        main(["--log-level", "WARNING", "compare", str(cylinder), str(measured), "-o", str(out)])
        == 0
    )
    return out


def test_every_probe_on_a_cylinder_reads_laplace_s_t_over_r(cylinder, compared):
    with xr.open_dataset(cylinder) as ds:
        tension = float(ds["tension_mean"].sel(landmark="mid"))  # N m-1, the band's weft tension
    laplace = tension / RADIUS / MMHG
    rows = read_rows(compared / "compare.csv")
    assert len(rows) == 4  # the two repeats are one place
    for row in rows:
        assert float(row["model_mmHg"]) == pytest.approx(laplace, rel=0.01)


def test_places_heights_angles_and_repeats_are_the_file_s(cylinder, compared):
    rows = read_rows(compared / "compare.csv")
    assert [r["point"] for r in rows] == ["", "mid", "", "low"]
    np.testing.assert_allclose([float(r["height_m"]) for r in rows], [0.15, 0.25, 0.30, 0.20])
    np.testing.assert_allclose([float(r["angle_deg"]) for r in rows], [0, 90, -90, -45])
    np.testing.assert_allclose([float(r["probe_mm"]) for r in rows], [50, 30, 50, 50])
    assert [int(r["repeats"]) for r in rows] == [2, 1, 1, 1]
    np.testing.assert_allclose([float(r["measured_mmHg"]) for r in rows], [21, 15, 25, 19])
    assert float(rows[0]["repeat_sd_mmHg"]) == pytest.approx(math.sqrt(2.0), rel=1e-5)
    assert rows[1]["repeat_sd_mmHg"] == ""


def test_the_agreement_is_bland_and_altman_s_by_hand(compared):
    rows = read_rows(compared / "compare.csv")
    model = np.array([float(r["model_mmHg"]) for r in rows])
    measured = np.array([21.0, 15.0, 25.0, 19.0])
    d = model - measured
    np.testing.assert_allclose([float(r["difference_mmHg"]) for r in rows], d, atol=2e-4)
    (pooled,) = read_rows(compared / "agreement.csv")
    assert pooled["subject"] == "all" and int(pooled["places"]) == 4
    sd = math.sqrt(np.sum((d - d.mean()) ** 2) / 3)
    assert float(pooled["bias_mmHg"]) == pytest.approx(d.mean(), abs=2e-4)
    assert float(pooled["sd_mmHg"]) == pytest.approx(sd, abs=2e-4)
    assert float(pooled["loa_low_mmHg"]) == pytest.approx(d.mean() - 1.96 * sd, abs=2e-4)
    assert float(pooled["loa_high_mmHg"]) == pytest.approx(d.mean() + 1.96 * sd, abs=2e-4)
    assert float(pooled["rmse_mmHg"]) == pytest.approx(math.sqrt(np.mean(d * d)), abs=2e-4)
    assert pooled["r"] == ""  # the model reads one pressure everywhere: no correlation
    assert float(pooled["repeat_sd_mmHg"]) == pytest.approx(math.sqrt(2.0), abs=2e-4)


def test_each_model_error_is_its_nearest_line_s_relative_error(cylinder, compared):
    with xr.open_dataset(cylinder) as ds:
        names = [str(v) for v in ds["landmark"].values]
        heights = ds["landmark_height"].values
        relative = np.nanmax(
            [
                ds[f"{f}_error"].values / np.abs(ds[f].values)
                for f in ("pressure_max", "pressure_min", "pressure_mean")
            ],
            axis=0,
        )
    assert np.isfinite(relative).all()
    for row in read_rows(compared / "compare.csv"):
        nearest = int(np.argmin(np.abs(heights - float(row["height_m"]))))
        assert row["error_line"] == names[nearest]
        expected = float(row["model_mmHg"]) * relative[nearest]
        assert float(row["model_error_mmHg"]) == pytest.approx(expected, rel=1e-4)


def test_compare_nc_holds_the_csv_s_values_in_si_and_every_column_has_its_row(cylinder, compared):
    rows = read_rows(compared / "compare.csv")
    with xr.open_dataset(compared / "compare.nc") as ds:
        assert ds.attrs["cloth_kind"] == "compare"
        np.testing.assert_allclose(
            ds["measured_pressure"].values / MMHG, [float(r["measured_mmHg"]) for r in rows]
        )
        np.testing.assert_allclose(
            ds["model_pressure"].values / MMHG,
            [float(r["model_mmHg"]) for r in rows],
            rtol=1e-5,
        )
        np.testing.assert_allclose(ds["probe_diameter"].values, [0.05, 0.03, 0.05, 0.05])
        (pooled,) = read_rows(compared / "agreement.csv")
        assert float(ds["bias"].sel(group="all") / MMHG) == pytest.approx(
            float(pooled["bias_mmHg"]), rel=1e-5
        )
    files = [compared / n for n in ("compare.csv", "agreement.csv", "compare.nc")]
    assert inventory.unlisted(files) == []
    # each row named by a line is at its height, with its line's error (tests/crossrefs.py)
    assert crossrefs.problems(compared / "compare.csv") == []
    assert crossrefs.problems(cylinder.parent / "summary.csv") == []
    assert (compared / "compare.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("height_m,angle_deg,pressure_mmHg\n0.2,0,20\n", "probe_mm"),
        ("angle_deg,pressure_mmHg,probe_mm\n0,20,50\n", "point"),
        (HEADER + ",0.2,0,nan,50,1\n", "row 1, pressure_mmHg"),
        (HEADER + ",0.2,0,20,50,1\n,0.2,0,-3,50,1\n", "row 2, pressure_mmHg"),
        (HEADER + "ankle,,0,20,50,1\n", "row 1, point"),
        (HEADER + ",0.2,0,20,700,1\n", "row 1, probe_mm"),
        (HEADER + ",0.2,east,20,50,1\n", "row 1, angle_deg"),
        (HEADER + ",0.2,inf,20,50,1\n", "row 1, angle_deg"),
        (HEADER + ",0.9,0,20,50,1\n", "row 1, height_m"),
        (HEADER + ",,0,20,50,1\n", "row 1, point"),
        # a point and a height that disagree (low is at 0.2 m), by more than half a row
        (HEADER + "low,0.3,0,20,50,1\n", "row 1, height_m"),
        # kPa or Pa typed as mmHg: past any garment's pressure
        (HEADER + ",0.2,0,1.7e9,50,1\n", "row 1, pressure_mmHg"),
        (HEADER + ",0.2,0,20,50,1\n,0.2,90,2660,50,1\n", "row 2, pressure_mmHg"),
    ],
)
def test_a_bad_measurements_file_is_one_line_and_exit_2_with_nothing_written(
    cylinder, tmp_path, capsys, text, where
):
    measured = tmp_path / "bad.csv"
    measured.write_text(text)
    out = tmp_path / "out"
    assert main(["compare", str(cylinder), str(measured), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert str(measured) in err[0] and where in err[0], err[0]
    assert not out.exists()


def test_a_point_and_a_height_that_agree_are_taken_as_the_point(cylinder, tmp_path):
    """A row that gives both a point and its height, within half a row of it, is read at the
    point's height (the result's), as a row of the point alone."""
    both, alone = tmp_path / "both.csv", tmp_path / "alone.csv"
    both.write_text(HEADER + "low,0.201,0,20,50,1\n")
    alone.write_text(HEADER + "low,,0,20,50,1\n")
    for name, path in (("both", both), ("alone", alone)):
        assert main(["compare", str(cylinder), str(path), "-o", str(tmp_path / name)]) == 0
    assert (tmp_path / "both" / "compare.csv").read_text() == (
        tmp_path / "alone" / "compare.csv"
    ).read_text().replace(str(alone), str(both))


def test_the_shipped_example_is_the_tool_s_readings_plus_its_seeded_noise(tmp_path):
    """data/measurements/example_cone.csv regenerates (its header says it is synthetic)."""
    import importlib.util

    folder = inventory.ROOT / "data" / "measurements"
    spec = importlib.util.spec_from_file_location(
        "generate_example", folder / "generate_example.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    made = module.generate(tmp_path / "example.csv", tmp_path / "run")
    shipped = (folder / "example_cone.csv").read_text()
    assert shipped.startswith("# SYNTHETIC readings made by cloth, not a measurement")

    def table(text):
        return list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))

    again, ours = table(made.read_text()), table(shipped)
    assert len(ours) == 20
    for a, b in zip(again, ours, strict=True):
        assert {k: v for k, v in a.items() if k != "pressure_mmHg"} == {
            k: v for k, v in b.items() if k != "pressure_mmHg"
        }
        assert float(a["pressure_mmHg"]) == pytest.approx(float(b["pressure_mmHg"]), abs=0.011)
