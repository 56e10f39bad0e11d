"""The uniform design answer met (issue 52, item 7): confirmations iterated by a secant."""

from __future__ import annotations

import copy
import csv
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.pipeline.sweep import DESIGN_HEADER, mean_error, reduction_interval
from cloth.results.pressure import MMHG
from cloth.stages.case import run_case
from cloth.stages.secant import next_reduction
from cloth.stages.sweep import confirm_file
from tests.conftest import MMHG_BY_DEFINITION

#: An elliptic tube: its girth line's mean pressure has a discretisation error the estimate
#: states (a circular one's is exact), and is smooth in the reduction.
CASE = {
    "material": "powernet",
    "body": {"elliptic_cylinder": {"a": 0.12, "b": 0.08, "bottom": 0.0, "top": 0.5}},
    "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": [64, 16]},
    "solver": {"tolerance": 1e-9},
}


def test_the_secant_step_is_exact_on_a_line_and_uses_the_slope_first():
    assert next_reduction([(0.2, 10.0)], 12.0, 20.0) == pytest.approx(0.3)
    # two points on p = 5 + 25 r: the secant lands on the root of p = 15 whatever the slope
    assert next_reduction([(0.2, 10.0), (0.3, 12.5)], 15.0, 1.0) == pytest.approx(0.4)


def _run(folder: Path, reduction: float) -> xr.Dataset:
    data = copy.deepcopy(CASE)
    data["garment"]["reduction"] = reduction
    folder.mkdir(parents=True)
    (folder / "case.yaml").write_text(yaml.safe_dump(data))
    run_case(folder / "case.yaml", folder, {}, stop_after="aggregate")
    with xr.open_dataset(folder / "result.nc") as ds:
        return ds.load()


def test_a_confirmation_off_its_target_is_met_by_the_secant(tmp_path):
    """A 'sweep' of two reductions far apart (0.05, 0.30) interpolated linearly to 15 mmHg on
    the line misses when confirmed; the secant's confirmations from scratch meet the target
    within their stated error, and the CSV's final value is the last step's result.nc."""
    low, high = _run(tmp_path / "r050", 0.05), _run(tmp_path / "r300", 0.30)
    goal = 15.0 * MMHG
    p = np.array([float(ds["pressure_mean"].sel(landmark="middle")) for ds in (low, high)])
    e = np.array([float(mean_error(ds).sel(landmark="middle")) for ds in (low, high)])
    r = np.array([0.05, 0.30])
    answer = float(np.interp(goal, p, r))
    row = {
        "material": "powernet",
        "body": "ellipse",
        "landmark": "middle",
        "target_Pa": goal,
        "target_mmHg": 15.0,
        "reduction": answer,
        **reduction_interval(r, p, e, answer),
        "status": "ok",
        "message": "",
    }
    design = tmp_path / "design.csv"
    with design.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=DESIGN_HEADER)
        writer.writeheader()
        writer.writerow(row)
    first = _run(tmp_path / "confirm", answer)
    miss = abs(float(first["pressure_mean"].sel(landmark="middle")) - goal)
    stated = float(mean_error(first).sel(landmark="middle"))
    assert miss > stated  # the linear interpolation misses by more than the confirmation says
    out = tmp_path / "design_confirmed.csv"
    confirm_file(design, [tmp_path / "confirm" / "result.nc"], out, tmp_path / "secant")
    (done,) = list(csv.DictReader(out.open()))
    assert done["how"] == "secant" and done["met"] == "1", done
    steps = int(done["secant_steps"])
    with xr.open_dataset(tmp_path / "secant" / "confirm" / f"step{steps}" / "result.nc") as ds:
        final = float(ds["pressure_mean"].sel(landmark="middle"))
        error = float(mean_error(ds).sel(landmark="middle"))
    assert float(done["final_mmHg"]) == pytest.approx(final / MMHG, abs=1e-4)
    assert float(done["final_error_mmHg"]) == pytest.approx(error / MMHG_BY_DEFINITION, rel=1e-5)
    assert abs(final - goal) <= error
    # the last miss in reduction over design.csv's slope; met, so the total is the interval
    slope = float(row["slope_Pa"])
    interpolation = abs(final - goal) / abs(slope)  # written to 4 significant digits
    assert float(done["interpolation_error"]) == pytest.approx(interpolation, rel=1e-3)
    assert float(done["reduction_error_total"]) == pytest.approx(row["reduction_error"], rel=1e-5)
    assert float(done["final_reduction"]) == pytest.approx(  # the CSV keeps 4 decimals
        yaml.safe_load(
            (tmp_path / "secant" / "confirm" / f"step{steps}" / "case.yaml").read_text()
        )["garment"]["reduction"]
    )


def test_a_confirmation_that_did_not_converge_is_never_met(tmp_path):
    """A confirmation stopped after 3 Newton iterations reads its own target to the last bit,
    within any error: the row says `not converged` and not met, for it is no equilibrium
    (its secant steps, run with the same solver block, stop short too)."""
    data = copy.deepcopy(CASE)
    data["solver"] = {"tolerance": 1e-9, "max_iterations": 3, "continuation": False}
    folder = tmp_path / "confirm"
    folder.mkdir()
    (folder / "case.yaml").write_text(yaml.safe_dump(data))
    run_case(folder / "case.yaml", folder, {}, stop_after="aggregate")
    with xr.open_dataset(folder / "result.nc") as ds:
        assert int(ds.attrs["converged"]) == 0
        value = float(ds["pressure_mean"].sel(landmark="middle"))
        error = float(mean_error(ds).sel(landmark="middle"))
    assert np.isfinite(error)
    row = {
        "material": "powernet",
        "body": "ellipse",
        "landmark": "middle",
        "target_Pa": value,  # the unconverged value itself: within its error
        "target_mmHg": value / MMHG,
        "reduction": 0.15,
        "slope_Pa": 2.0e4,
        "reduction_error": 1e-4,
        "status": "ok",
        "message": "",
    }
    design = tmp_path / "design.csv"
    with design.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=DESIGN_HEADER, extrasaction="ignore")
        writer.writeheader()
        writer.writerow(row)
    out = tmp_path / "design_confirmed.csv"
    confirm_file(design, [folder / "result.nc"], out, tmp_path / "secant")
    (done,) = list(csv.DictReader(out.open()))
    assert done["how"] == "not converged" and done["met"] == "0", done
