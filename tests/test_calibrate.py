"""``cloth calibrate``: friction and tissue recovered from noisy readings of a known case within
the intervals the tool states, the parameters readings cannot determine named, and the fitted
readings the calibrated case's own."""

from __future__ import annotations

import csv
import logging

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.cli import main
from cloth.results.pressure import MMHG
from cloth.stages.calibrate import fit

FRICTION, MODULUS = 0.3, 2.0e4
#: A steep cone (the garment slides on it until friction holds it, so the readings tell the
#: friction) under a soft layer.
BODY = {
    "cone": {"radius_bottom": 0.14, "radius_top": 0.04, "bottom": 0.0, "top": 0.2},
    "tissue": {"thickness": 0.02, "modulus": MODULUS},
}
HEIGHTS = 0.05 + 0.10 * np.arange(10) / 9
SENSORS = [{"name": f"s{k}", "height": float(h), "angle": 36.0 * k} for k, h in enumerate(HEIGHTS)]
CASE = {
    "material": "powernet",
    "body": BODY,
    "garment": {"bottom": 0.04, "top": 0.16, "reduction": 0.2, "grid": [24, 10]},
    "contact": {"friction": FRICTION},
    "sensors": SENSORS,
}
NOISE = 1.5  # mmHg


def run(case: dict, folder):
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "case.yaml"
    path.write_text(yaml.safe_dump(case))
    out = folder / "run"
    argv = ["--log-level", "WARNING", "run", str(path), "-o", str(out), "--stop-after", "aggregate"]
    assert main(argv) == 0
    return out / "result.nc"


def start_case(folder, **changes) -> object:
    """The case the fit starts from: friction 0, a modulus of 50 kPa."""
    case = yaml.safe_load(yaml.safe_dump(CASE))
    case["contact"]["friction"] = 0.0
    case["body"]["tissue"]["modulus"] = 5.0e4
    case.update(changes)
    path = folder / "start.yaml"
    path.write_text(yaml.safe_dump(case))
    return path


def write_readings(path, values_mmhg, rows=None):
    rows = range(len(values_mmhg)) if rows is None else rows
    with open(path, "w") as handle:
        handle.write("# synthetic: the case's own readings plus noise\n")
        handle.write("height_m,angle_deg,pressure_mmHg,probe_mm\n")
        for k, value in zip(rows, values_mmhg, strict=True):
            handle.write(f"{HEIGHTS[k]:.9f},{36.0 * k:g},{value:.9f},50\n")
    return path


@pytest.fixture(scope="module")
def truth(tmp_path_factory):
    """The known case's sensor readings (mmHg)."""
    with xr.open_dataset(run(CASE, tmp_path_factory.mktemp("truth"))) as ds:
        return ds["sensor_pressure"].values / MMHG


def noisy(truth, seed: int) -> np.ndarray:
    return truth + np.random.default_rng(seed).normal(0.0, NOISE, truth.size)


@pytest.fixture(scope="module")
def calibrated(truth, tmp_path_factory):
    folder = tmp_path_factory.mktemp("calibrated")
    measured = write_readings(folder / "measured.csv", noisy(truth, 0))
    out = folder / "out"
    argv = ["--log-level", "WARNING", "calibrate", str(start_case(folder)), str(measured)]
    assert main([*argv, "--fit", "friction,tissue_modulus", "-o", str(out)]) == 0
    return folder, out


def read_rows(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


def test_calibrate_recovers_friction_and_tissue_within_its_intervals(calibrated):
    _, out = calibrated
    rows = {r["parameter"]: r for r in read_rows(out / "calibration.csv")}
    assert list(rows) == ["friction", "tissue_modulus"]
    for name, true, start, units in (
        ("friction", FRICTION, 0.0, "1"),
        ("tissue_modulus", MODULUS, 5.0e4, "Pa"),
    ):
        row = rows[name]
        assert row["determined"] == "1" and row["units"] == units
        assert float(row["start"]) == start
        assert float(row["low"]) <= true <= float(row["high"]), row
        assert float(row["low"]) <= float(row["value"]) <= float(row["high"])
    # the modulus's interval is one of factors (fitted as ln E): its ends are one factor apart
    row = rows["tissue_modulus"]
    ratio = float(row["value"]) / float(row["low"]), float(row["high"]) / float(row["value"])
    assert ratio[0] == pytest.approx(ratio[1], rel=1e-4)


def test_fit_csv_is_the_model_before_and_after_read_again(calibrated, tmp_path):
    folder, out = calibrated
    rows = read_rows(out / "fit.csv")
    np.testing.assert_allclose([float(r["height_m"]) for r in rows], HEIGHTS, atol=1e-6)
    after = yaml.safe_load((out / "case.yaml").read_text())
    assert after["contact"]["friction"] > 0 and after["body"]["tissue"]["modulus"] < 5.0e4
    for column, case in (
        ("before_mmHg", yaml.safe_load((folder / "start.yaml").read_text())),
        ("after_mmHg", after),
    ):
        with xr.open_dataset(run(case, tmp_path / column)) as ds:
            read = ds["sensor_pressure"].values / MMHG
        np.testing.assert_allclose([float(r[column]) for r in rows], read, rtol=1e-5)
    measured = np.loadtxt(folder / "measured.csv", delimiter=",", skiprows=2)[:, 2]
    np.testing.assert_allclose([float(r["measured_mmHg"]) for r in rows], measured, rtol=1e-5)
    misfit = [
        np.sqrt(np.mean((np.array([float(r[c]) for r in rows]) - measured) ** 2))
        for c in (
            "before_mmHg",
            "after_mmHg",
        )
    ]
    assert misfit[1] < misfit[0]


@pytest.mark.slow
def test_the_intervals_hold_in_18_of_20_seeds(truth, tmp_path):
    start = start_case(tmp_path)
    held = {"friction": 0, "tissue_modulus": 0}
    for seed in range(20):
        measured = write_readings(tmp_path / f"m{seed}.csv", noisy(truth, seed))
        found = fit(start, measured, ("friction", "tissue_modulus"))
        for name, true in (("friction", FRICTION), ("tissue_modulus", MODULUS)):
            item = found.interval[name]
            held[name] += item is not None and item.low <= true <= item.high
    assert held["friction"] >= 18 and held["tissue_modulus"] >= 18, held


def test_one_reading_and_two_parameters_names_the_one_not_determined(truth, tmp_path, caplog):
    measured = write_readings(tmp_path / "one.csv", [truth[4]], rows=[4])
    out = tmp_path / "out"
    argv = ["calibrate", str(start_case(tmp_path)), str(measured), "--fit"]
    with caplog.at_level(logging.WARNING, logger="cloth.stages.calibrate"):
        assert main([*argv, "friction,tissue_modulus", "-o", str(out)]) == 0
    rows = {r["parameter"]: r for r in read_rows(out / "calibration.csv")}
    undetermined = [name for name, row in rows.items() if row["determined"] == "0"]
    assert len(undetermined) >= 1  # one reading determines one parameter at most
    warned = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert any("1 reading place cannot determine 2 parameters" in m for m in warned), warned
    for name in undetermined:
        assert rows[name]["low"] == rows[name]["high"] == ""
        assert float(rows[name]["value"]) == float(rows[name]["start"])
        assert any(f"do not determine {name}" in message for message in warned), warned


def test_friction_on_a_cylinder_is_not_determined(tmp_path):
    """A tube on a cylinder does not slide: friction leaves every reading as it is."""
    cylinder = {"cylinder": {"radius": 0.08, "bottom": 0.0, "top": 0.3}}
    case = {
        "material": "powernet",
        "body": {**cylinder, "tissue": {"thickness": 0.02, "modulus": MODULUS}},
        "garment": {"bottom": 0.05, "top": 0.25, "reduction": 0.2, "grid": [24, 8]},
        "contact": {"friction": 0.0},
    }
    path = tmp_path / "cylinder.yaml"
    path.write_text(yaml.safe_dump(case))
    measured = tmp_path / "m.csv"
    measured.write_text("height_m,angle_deg,pressure_mmHg,probe_mm\n0.1,0,20,50\n0.15,90,21,50\n")
    found = fit(path, measured, ("friction",))
    assert found.determined == {"friction": False}
    assert found.value["friction"] == 0.0


def test_a_fabric_scale_scales_the_tension_and_laplace_s_pressure(tmp_path):
    """On a rigid cylinder the strain is the geometry's, so the tension and T / R scale."""
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [24, 6]},
        "landmarks": {"mid": 0.25},
    }
    values = []
    for scale in (1.0, 1.25):
        result = run({**case, "fabric_scale": scale}, tmp_path / str(scale))
        with xr.open_dataset(result) as ds:
            values.append(
                [float(ds[v].sel(landmark="mid")) for v in ("pressure_mean", "tension_mean")]
            )
    np.testing.assert_allclose(np.array(values[1]) / np.array(values[0]), 1.25, rtol=1e-6)


@pytest.mark.parametrize(
    ("argv", "where"),
    [
        (["--fit", "friction,stiffness"], "--fit"),
        (["--fit", "friction,friction"], "--fit"),
        (["--fit", "friction", "--noise", "0"], "--noise"),
        (["--fit", "tissue_modulus", "--no-tissue"], "body.tissue"),
        (["--fit", "friction", "--two-subjects"], "subject"),
        (["--fit", "friction", "--grid-auto"], "garment.grid"),
    ],
)
def test_bad_calibrate_input_is_one_line_and_exit_2_with_nothing_written(
    tmp_path, capsys, argv, where
):
    changes = {"body": {"cone": BODY["cone"]}} if "--no-tissue" in argv else {}
    if "--grid-auto" in argv:
        changes["garment"] = {**CASE["garment"], "grid": "auto"}
    start = start_case(tmp_path, **changes)
    measured = tmp_path / "m.csv"
    if "--two-subjects" in argv:
        measured.write_text(
            "height_m,angle_deg,pressure_mmHg,probe_mm,subject\n0.1,0,20,50,a\n0.1,0,21,50,b\n"
        )
    else:
        write_readings(measured, [20.0, 21.0])
    argv = [a for a in argv if a not in ("--no-tissue", "--two-subjects", "--grid-auto")]
    out = tmp_path / "out"
    assert main(["calibrate", str(start), str(measured), *argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and where in err[0], err
    assert not out.exists()
