"""The Snakemake pipeline: config validation, a dry run, and the tiny config end to end."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from tests.conftest import MMHG_BY_DEFINITION as MMHG
from tests.pipeline import ROOT, SNAKEMAKE, environment, from_checkout, snakemake, workspace

#: The tiny pipeline (config/ci.yaml end to end, about 3-5 minutes on 2 cores) and the tests
#: that read it run in the slow suite (make test-slow, which CI runs), keeping make test near
#: five minutes: the fixture took 159-281 s of one worker's time there.
TINY = pytest.mark.slow


def test_default_config_dry_run(tmp_path):
    result = snakemake(workspace(tmp_path), "-n")
    assert result.returncode == 0, result.stderr
    assert "predeform" in result.stdout


def _jobs(dry_run: str, rule: str) -> dict[str, str]:
    """The job blocks of ``rule`` in a dry run's output, by their ``case`` wildcard."""
    blocks = dry_run.split("\nrule ")
    found = {}
    for block in blocks:
        if block.startswith(f"{rule}:"):
            case = block.split("wildcards: case=")[1].split()[0]
            found[case] = block.split("\n[")[0]
    return found


def test_relax_asks_for_the_threads_its_case_uses_and_the_design_path_goes_first(tmp_path):
    """relax holds BLAS to ``solver.blas_threads`` threads (1 by default), so its job asks for
    that many cores (two relax side by side on two cores), or every core where it is null; the
    rules on the way to the design answers have a priority over figures and views."""
    where = workspace(tmp_path)
    case = {
        "material": "powernet",
        "body": {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [16, 6]},
    }
    config = {
        "materials": {"powernet": {"table": "data/materials/powernet.csv", "knots": 6}},
        "cases": {"one": case, "all_cores": {**case, "solver": {"blas_threads": None}}},
    }
    (where / "config/config.yaml").write_text(yaml.safe_dump(config))
    result = snakemake(where, "-n")
    assert result.returncode == 0, result.stderr[-3000:]
    relax = _jobs(result.stdout, "relax")
    assert "threads:" not in relax["one"]  # Snakemake prints threads above 1 only
    assert "threads: 2" in relax["all_cores"]  # every core of the two given
    assert all("priority: 1" in block for block in relax.values())
    figures = _jobs(result.stdout, "figures")
    assert figures and not any("priority:" in block for block in figures.values())


def bad_config(tmp_path: Path, mutate) -> Path:
    config = yaml.safe_load((ROOT / "config/ci.yaml").read_text())
    mutate(config)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


@pytest.mark.parametrize(
    ("mutate", "expected"),
    [
        (lambda c: c.update(materilas={}), "materilas"),
        (lambda c: c["materials"]["powernet"].update(knots="eight"), "knots"),
        (lambda c: c["cases"]["tiny"].update(material="silk"), "cases.tiny.material"),
        (lambda c: c["cases"]["tiny"]["garment"].update(reduction=1.5), "garment.reduction"),
        (lambda c: c["cases"]["tiny"]["garment"].update(edgez="fixed"), "edgez"),
        (lambda c: c["sweep"].update(bodies=["giant"]), "sweep.bodies"),
        (lambda c: c["sweep"].update(reductions=[]), "reductions"),
        (lambda c: c["targets"].append({"landmark": "waist"}), "targets.1"),
        (lambda c: c["targets"].append({"landmark": "waist", "pressure_psi": 3}), "pressure_psi"),
        (
            lambda c: c["targets"].append({"landmark": "knee", "pressure_mmHg": 20}),
            "targets.1.landmark",
        ),
    ],
)
def test_bad_config_stops_before_any_job(tmp_path, mutate, expected):
    where = workspace(tmp_path)
    path = bad_config(where, mutate)
    result = snakemake(where, "--configfile", str(path), "-n")
    assert result.returncode != 0
    assert expected in result.stdout + result.stderr
    assert not [p for p in where.iterdir() if p.name.startswith("results")]


@TINY
def test_tiny_pipeline_end_to_end(tiny_run):
    where, result, _ = tiny_run
    assert result.returncode == 0, result.stderr[-3000:]
    with xr.open_dataset(where / "results-ci/materials/powernet.nc") as material:
        knots = material["weft_knot_stress"].values
        assert knots.size == 6 and np.all(np.diff(knots) >= 0)
        assert float(material["weft_fit_max_error_percent"]) < 3.0
    with xr.open_dataset(where / "results-ci/cases/tiny/initial.nc") as initial:
        assert initial["x"].shape == (8, 24)
        # every row is cut 15 % short of the hull girth: its node ring is 1/0.85 times its rest
        # circumference, less the 24-gon's chord shortfall, plus the 0.1 mm offset (< 0.5 %)
        x = np.stack([initial[c].values for c in ("x", "y", "z")], axis=-1)
        ring = np.linalg.norm(np.roll(x, -1, axis=1) - x, axis=2).sum(axis=1)
        rest = initial["rest_length"].values[: 8 * 24].reshape(8, 24).sum(axis=1)
        np.testing.assert_allclose(ring / rest, 1 / 0.85, rtol=5e-3)
    with xr.open_dataset(where / "results-ci/cases/tiny/relaxed.nc") as relaxed:
        assert relaxed.attrs["solver_converged"] == 1
        residual = relaxed["residual"].values
        assert residual[-1] <= 1e-8 < residual[0]
        # relaxed on the body: the fabric is still stretched by about the pattern's reduction
        x = np.stack([relaxed[c].values for c in ("x", "y", "z")], axis=-1)
        ring = np.linalg.norm(np.roll(x, -1, axis=1) - x, axis=2).sum(axis=1)
        assert np.all(ring / rest > 1.1)
        assert float(relaxed["penetration"].values.max()) <= 1e-6
    with xr.open_dataset(where / "results-ci/cases/tiny/result.nc") as result:
        # Newton's third law for the whole garment: the spring forces cancel in sum, so what
        # the fabric puts on the body is what the edge supports hold, vertical only
        total = result["total_force"].values
        support = float(result["edge_support_force"].values.sum())
        scale = float(result["normal_force"])
        np.testing.assert_allclose(total, [0.0, 0.0, support], atol=1e-6 * scale)
        # the garment spans 0.90-1.15 m: the hip line (0.86 m) and the bust (1.22 m) lie outside
        assert set(result["landmark"].values.tolist()) == {"waist", "underbust"}
        waist = float(result["pressure_mean"].sel(landmark="waist"))
        assert 300 < waist < 5000  # a 15 % reduction of power net: shapewear range, Pa
    summary = (where / "results-ci/cases/tiny/summary.csv").read_text().splitlines()
    assert len(summary) == 3 and "pressure_mean_mmHg" in summary[0]
    from cloth.figures.plots import FIGURES

    figures = {f.stem for f in (where / "results-ci/cases/tiny/figures").glob("*.png")}
    assert figures == set(FIGURES)
    assert (where / "results-ci/sweep_on_body.png").stat().st_size > 20_000
    page = (where / "results-ci/cases/tiny/garment.html").read_text()
    assert '<meta name="cloth:nodes" content="192">' in page
    with xr.open_dataset(where / "results-ci/sweep.nc") as sweep:
        assert dict(sweep.sizes) == {
            "material": 1,
            "body": 1,
            "reduction": 2,
            "worn": 2,
            "lengthwise_reduction": 1,
            "landmark": 2,
        }
        for lengthwise in (0.0,):
            at = sweep["pressure_mean"].sel(landmark="waist", lengthwise_reduction=lengthwise)
            waist = at.sel(worn=0).values.ravel()
            assert waist[1] > waist[0] > 0  # a tighter pattern presses harder
            assert np.all(at.sel(worn=1).values.ravel() < waist)  # the set costs compression
    rows = (where / "results-ci/sweep.csv").read_text().splitlines()
    # one row per new case (reductions x one lengthwise reduction) and line, the worn beside it
    assert len(rows) == 1 + 2 * 2 and "pressure_mean_mmHg_worn" in rows[0]
    confirmed = (where / "results-ci/design_confirmed.csv").read_text().splitlines()
    assert len(confirmed) == 3  # the new and the worn garment's answers
    header = confirmed[0].split(",")
    records = [dict(zip(header, row.split(","), strict=True)) for row in confirmed[1:]]
    assert {record["worn"] for record in records} == {"0", "1"}
    assert {float(record["lengthwise_reduction"]) for record in records} == {0.0}
    for record in records:
        assert record["status"] == "ok" and 0.1 < float(record["reduction"]) < 0.2
        # two swept reductions, linear interpolation of a convex curve: within 5 % of the target
        assert abs(float(record["error_percent"])) < 5
    for lengthwise in ("0.0",):
        worn, new = sorted(
            (r for r in records if f"{float(r['lengthwise_reduction']):.1f}" == lengthwise),
            key=lambda r: r["worn"],
            reverse=True,
        )
        assert float(worn["reduction"]) > float(new["reduction"])  # a worn one is cut tighter
    # 48 around, 30 rings (the landmarks among them), and the two caps: 48 x 29 x 2 + 2 x 48
    assert "faces: 2880" in (where / "results-ci/bodies/small.txt").read_text()
    assert sorted(p.name for p in where.iterdir() if not p.name.startswith(".")) == [
        "benchmarks",
        "logs",
        "results-ci",
    ]  # run from an empty folder: nothing of the workflow's was copied there
    report = snakemake(where, *from_checkout(where), "--report", "report.html")
    assert report.returncode == 0, report.stderr[-2000:]
    assert (where / "report.html").stat().st_size > 100_000
    again = snakemake(where, *from_checkout(where), "-n")
    assert "Nothing to be done" in again.stdout + again.stderr


@TINY
def test_the_tiny_pipeline_wears_the_garment_on_an_avatar_at_its_chart_s_lines(tiny_run):
    """The config's avatar case (torso S's avatar, shipped): its case.yaml names the shipped
    mesh with the region every garment of the config spans, its one surface file is fitted
    there, and its girth lines are the chart's at the chart's heights, each a finite, positive
    band value."""
    import csv

    from cloth.bodies.torso import read_chart

    where, result, _ = tiny_run
    assert result.returncode == 0, result.stderr[-3000:]
    case = yaml.safe_load((where / "results-ci/cases/avatar/case.yaml").read_text())
    assert Path(case["body"]["mesh"]).name == "torso_S.ply"
    assert case["body"]["region"] == [0.9, 1.15]
    heights = read_chart(ROOT / "data/bodies/size_chart.csv")["S"].height
    with xr.open_dataset(where / "results-ci/cases/avatar/result.nc") as ds:
        body = json.loads(ds.attrs["body"])
        assert body["region"] == [0.9, 1.15]
        assert body["avatar"]["size"] == "S" and body["avatar"]["model"] == "anny"
        assert Path(body["surface"]["file"]).name == "case-avatar.surface.nc"
        lines = dict(zip(ds["landmark"].values.tolist(), ds["landmark_height"].values, strict=True))
    # the garment spans 0.90-1.15 m: the chart's waist (1.04) and underbust (1.15) lines
    assert lines == {name: heights[name] for name in ("waist", "underbust")}
    rows = list(csv.DictReader((where / "results-ci/cases/avatar/summary.csv").open()))
    assert [r["landmark"] for r in rows] == ["waist", "underbust"]
    assert all(0 < float(r["pressure_mean_Pa"]) < 1e4 for r in rows)


def _positions(path: Path) -> np.ndarray:
    with xr.open_dataset(path) as ds:
        return np.stack([ds[c].values for c in ("x", "y", "z")], axis=-1)


@TINY
def test_every_written_case_runs_as_written_after_its_folder_moves(tiny_run, tmp_path, monkeypatch):
    """The cases the pipeline writes (each case's case.yaml, a design's start.yaml and its
    designed case.yaml) store their paths relative to their own folder: the results folder
    moved elsewhere, each runs from an unrelated working directory and gives what the pipeline
    gave (the designed case: its confirmation's initial state)."""
    from cloth.cli import main

    where, result, _ = tiny_run
    assert result.returncode == 0, result.stderr[-3000:]
    moved = tmp_path / "moved" / "elsewhere"
    shutil.copytree(where / "results-ci", moved)
    (tmp_path / "cwd").mkdir()
    monkeypatch.chdir(tmp_path / "cwd")
    cases = sorted(moved.glob("cases/*/case.yaml"))
    designs = sorted(moved.glob("designs/*/case.yaml"))
    assert len(cases) >= 5 and designs  # the tiny case, the sweep's, the confirmations'
    for case in [*cases, *designs]:
        pipeline = case.parent / ("confirmed" if case in designs else "") / "initial.nc"
        out = tmp_path / "out" / case.parent.name / "initial.nc"
        assert main(["--log-level", "WARNING", "predeform", str(case), "-o", str(out)]) == 0
        np.testing.assert_array_equal(_positions(out), _positions(pipeline), err_msg=str(case))
    for start in moved.glob("designs/*/start.yaml"):
        out = tmp_path / "out" / "start" / "initial.nc"
        assert main(["--log-level", "WARNING", "predeform", str(start), "-o", str(out)]) == 0
    # the tiny case end to end: the same pressures as the pipeline's
    out = tmp_path / "out" / "tiny-run"
    assert (
        main(["--log-level", "WARNING", "run", str(moved / "cases/tiny/case.yaml"), "-o", str(out)])
        == 0
    )
    with (
        xr.open_dataset(out / "result.nc") as again,
        xr.open_dataset(moved / "cases/tiny/result.nc") as first,
    ):
        np.testing.assert_allclose(
            again["pressure"].values, first["pressure"].values, rtol=1e-9, atol=1e-9
        )
    text = (moved / "cases/tiny/case.yaml").read_text()
    assert "material: ../../materials/powernet.nc" in text  # relative to the case's folder


def test_design_interpolates_and_explains_out_of_range():
    import xarray as xr

    from cloth.errors import InputError
    from cloth.pipeline.sweep import design
    from cloth.results.pressure import MMHG

    reductions = np.array([0.1, 0.2, 0.3])
    pressure = np.array([10.0, 20.0, 40.0]) * MMHG  # mean waist pressure, Pa
    ds = xr.Dataset(
        {
            "pressure_mean": (
                ("material", "body", "reduction", "landmark"),
                pressure.reshape(1, 1, 3, 1),
            )
        },
        coords={"material": ["m"], "body": ["b"], "reduction": reductions, "landmark": ["waist"]},
    )
    rows = design(
        ds, [{"landmark": "waist", "pressure_mmHg": 30}, {"landmark": "waist", "pressure_kPa": 9}]
    )
    assert rows[0]["status"] == "ok" and rows[0]["reduction"] == pytest.approx(0.25)
    assert (
        rows[1]["status"] == "out_of_range"
        and "no reduction in 0.1-0.3 reaches" in rows[1]["message"]
    )
    with pytest.raises(InputError, match="unknown landmark"):
        design(ds, [{"landmark": "knee", "pressure_mmHg": 20}])


@pytest.mark.slow  # the tiny pipeline twice (1.5 min); atomic writes are tested in test_io
def test_a_killed_run_leaves_no_corrupt_output_and_resumes(tmp_path):
    import os
    import signal
    import time

    where = workspace(tmp_path)
    env = environment()
    process = subprocess.Popen(
        [str(SNAKEMAKE), "--cores", "2", "--configfile", "config/ci.yaml"],
        cwd=where,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and not list((where / "logs").glob("relax/*.log")):
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGKILL)  # kill -9 the whole run during relax
    process.wait()
    for path in (where / "results-ci").rglob("*.nc"):  # whatever exists is complete
        with xr.open_dataset(path) as ds:
            ds.load()
    # Snakemake keeps its lock after a kill -9 and asks for --unlock first (docs/cluster.md)
    assert snakemake(where, "--configfile", "config/ci.yaml", "--unlock").returncode == 0
    result = snakemake(where, "--configfile", "config/ci.yaml", "--rerun-incomplete")
    assert result.returncode == 0, result.stderr[-2000:]
    assert (where / "results-ci/design_confirmed.csv").exists()


@pytest.mark.slow  # a pipeline on a mesh body (20 s; make test-slow)
def test_mesh_body_pipeline_fits_its_surface_once(tmp_path):
    """A case on a mesh body: rule body_surface fits the smooth surface once (the case's body is
    the configured body "tube"), the case and the check read it, the result records the
    smoothing, and a second run has nothing to do."""
    from tests.conftest import capped_cylinder, write_obj

    where = workspace(tmp_path)
    write_obj(where / "data/bodies/tube.obj", *capped_cylinder(0.1, 0.5, 48))
    tube = {"mesh": "data/bodies/tube.obj", "smoothing": 0.015, "spacing": 0.006}
    config = {
        "materials": {"powernet": {"table": "data/materials/powernet.csv", "knots": 6}},
        # sampled at 6 mm, not the default 3 mm (a quarter of the samples): the rules are tested
        "bodies": {"tube": tube},
        "cases": {
            "ontube": {
                "material": "powernet",
                "body": tube,
                "garment": {"bottom": 0.15, "top": 0.35, "reduction": 0.2, "grid": [32, 6]},
                "solver": {"tolerance": 1.0e-8, "max_iterations": 60},
            }
        },
    }
    path = where / "config/config.yaml"  # the workspace's default: no torso sweep merged in
    path.write_text(yaml.safe_dump(config))
    result = snakemake(where)
    assert result.returncode == 0, result.stderr[-3000:]
    assert sorted(p.name for p in (where / "results/bodies").glob("*.surface.nc")) == [
        "tube.surface.nc"
    ]
    check = (where / "results/bodies/tube.check.txt").read_text()
    assert "vertices from the smooth surface: max" in check
    assert (where / "results/bodies/tube.curvature.png").stat().st_size > 10_000
    with xr.open_dataset(where / "results/cases/ontube/result.nc") as ds:
        body = json.loads(ds.attrs["body"])
        assert body["surface"]["kind"] == "smooth" and body["surface"]["smoothing_m"] > 0
        assert body["surface"]["file"].endswith("tube.surface.nc")
        assert ds.attrs["converged"] == 1
    again = snakemake(where, "-n")
    assert "Nothing to be done" in again.stdout + again.stderr


#: sweep.csv's columns: result.nc's girth-line variable and the factor into the header's unit.
SWEEP_COLUMNS = {
    "pressure_mean_Pa": ("pressure_mean", 1.0),
    "pressure_mean_mmHg": ("pressure_mean", 1 / MMHG),
    "pressure_mean_error_mmHg": ("pressure_mean_error", 1 / MMHG),
    "pressure_max_mmHg": ("pressure_max", 1 / MMHG),
    "tension_mean_N_per_m": ("tension_mean", 1.0),
}


def _csv(path: Path) -> list[dict[str, str]]:
    """A written table's rows, its ``#`` comment lines (a pattern's girth lines) left out."""
    import csv

    with open(path, newline="") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def _close(written: str, value: float, rel: float = 1e-5) -> bool:
    """A CSV cell (6 significant digits) is ``value``; NaN only where it is NaN."""
    number = float(written)
    if np.isnan(value):
        return bool(np.isnan(number))
    return number == pytest.approx(value, rel=rel, abs=1e-12)


@TINY
def test_the_sweep_s_files_are_each_case_s_result_nc(tiny_run):
    """sweep.nc and sweep.csv, value by value, against each case's own result.nc (located by
    the index sweep.nc records), in the unit each header names; the worn column beside the new."""
    where = tiny_run[0] / "results-ci"
    with xr.open_dataset(where / "sweep.nc") as sweep:
        sweep = sweep.load()
    index = json.loads(sweep.attrs["cases"])
    keys = ("material", "body", "reduction", "worn", "lengthwise_reduction")
    assert len(index) == 4 and set(sweep["pressure_mean"].dims) == {*keys, "landmark"}
    results = {}
    for entry in index:
        with xr.open_dataset(where / "cases" / entry["case"] / "result.nc") as ds:
            results[entry["case"]] = ds = ds.load()
        at = {key: entry[key] for key in keys}
        assert int(sweep["converged"].sel(at)) == ds.attrs["converged"]
        for name in ("pressure_mean", "pressure_max", "pressure_min", "tension_mean"):
            for field in (name, f"{name}_error"):
                np.testing.assert_array_equal(
                    sweep[field].sel(at).sel(landmark=ds["landmark"].values).values,
                    ds[field].values,
                )
    rows = _csv(where / "sweep.csv")
    assert len(rows) == 4
    for row in rows:
        new, worn = (
            next(
                e
                for e in index
                if e["reduction"] == float(row["reduction"])
                and e["worn"] == flag
                and e["lengthwise_reduction"] == float(row["lengthwise_reduction"])
            )
            for flag in (0, 1)
        )
        ds = results[new["case"]].sel(landmark=row["landmark"])
        assert (row["material"], row["body"]) == (new["material"], new["body"])
        for column, (name, factor) in SWEEP_COLUMNS.items():
            assert _close(row[column], float(ds[name]) * factor), column
        assert int(row["converged"]) == results[new["case"]].attrs["converged"]
        worn_mean = float(results[worn["case"]]["pressure_mean"].sel(landmark=row["landmark"]))
        assert _close(row["pressure_mean_mmHg_worn"], worn_mean / MMHG)
        change = 100 * (worn_mean / float(ds["pressure_mean"]) - 1)
        assert _close(row["worn_change_percent"], change, rel=1e-5)
    checked = {*keys, "landmark", "converged", "pressure_mean_mmHg_worn", "worn_change_percent"}
    assert set(rows[0]) == (checked | set(SWEEP_COLUMNS)) - {"worn"}


@TINY
def test_the_design_s_files_are_the_sweep_interpolated_by_hand(tiny_run):
    """design.csv's answer, slope and interval from sweep.csv's two reductions by hand; its
    confirmation's pressure and error from the confirmation case's own result.nc."""
    where = tiny_run[0] / "results-ci"
    with xr.open_dataset(where / "sweep.nc") as sweep:
        sweep = sweep.load()
    goal = 10 * MMHG  # config/ci.yaml's target: the waist at 10 mmHg
    rows = _csv(where / "design.csv")
    confirmed = _csv(where / "design_confirmed.csv")
    assert len(rows) == len(confirmed) == 2
    for row, final in zip(rows, confirmed, strict=True):
        at = sweep.sel(
            material=row["material"],
            body=row["body"],
            worn=int(row["worn"]),
            lengthwise_reduction=float(row["lengthwise_reduction"]),
            landmark="waist",
        )
        (r0, r1), (p0, p1) = at["reduction"].values, at["pressure_mean"].values
        (e0, e1) = at["pressure_mean_error"].values
        slope = (p1 - p0) / (r1 - r0)
        reduction = r0 + (goal - p0) / slope
        t = (reduction - r0) / (r1 - r0)
        half = ((1 - t) * e0 + t * e1) / abs(slope)
        assert row["landmark"] == "waist" and row["status"] == "ok" and row["message"] == ""
        assert _close(row["target_Pa"], goal) and _close(row["target_mmHg"], 10.0)
        assert _close(row["reduction"], reduction) and _close(row["slope_Pa"], slope)
        assert _close(row["reduction_error"], half, rel=1e-5)
        assert _close(row["reduction_low"], reduction - half, rel=1e-5)
        assert _close(row["reduction_high"], reduction + half, rel=1e-5)
        for key, value in row.items():
            assert final[key] == value, key  # the confirmation repeats the design's columns
        name = f"design__{row['material']}__{row['body']}__waist"
        name += "__worn" if row["worn"] == "1" else ""
        with xr.open_dataset(where / "cases" / name / "result.nc") as ds:
            case = ds.sel(landmark="waist").load()
            cut = json.loads(ds.attrs["case"])["garment"]["reduction"]
            assert cut == float(row["reduction"])  # confirmed at the answer design.csv gives
        value, error = float(case["pressure_mean"]), float(case["pressure_mean_error"])
        assert _close(final["confirmed_Pa"], value) and _close(
            final["confirmed_mmHg"], value / MMHG
        )
        assert _close(final["confirmed_error_Pa"], error)
        assert _close(final["confirmed_error_mmHg"], error / MMHG)
        written = float(final["target_Pa"])  # the target as design.csv holds it (6 digits)
        assert _close(final["error_percent"], 100 * (value - written) / written, rel=1e-5)
        assert int(final["converged"]) == 1


@TINY
def test_every_csv_row_the_tiny_pipeline_writes_names_its_line_s_own_values(tiny_run):
    """Each row that names a girth line carries that line's height and values from its source
    netCDF, read by name, found from the file alone (tests/crossrefs.py), in every CSV."""
    from tests import crossrefs

    files = sorted((tiny_run[0] / "results-ci").rglob("*.csv"))
    checked = {p.name for p in files if p.name in crossrefs.RULES}
    assert {"summary.csv", "design_confirmed.csv", "compare.csv"} <= checked
    assert [problem for path in files for problem in crossrefs.problems(path)] == []


@TINY
def test_every_file_the_tiny_pipeline_writes_has_its_columns_in_the_inventory(tiny_run):
    """Every column of every CSV and every variable of result.nc, sweep.nc the tiny pipeline
    writes has a row in docs/testing.md's inventory, in the units the file states."""
    from tests import inventory

    where = tiny_run[0] / "results-ci"
    files = [p for p in where.rglob("*.csv")]
    files += [*where.rglob("result.nc"), where / "sweep.nc"]
    assert {inventory.family(p) for p in files} >= {
        "summary.csv",
        "sweep.csv",
        "design.csv",
        "design_confirmed.csv",
        "result.nc",
        "sweep.nc",
    }
    assert inventory.unlisted(files) == []


@TINY
def test_the_graded_design_s_files_are_its_loop_and_its_confirmation(tiny_run):
    """The tiny pipeline's graded design (config/ci.yaml: waist 10, underbust 12 mmHg):
    design_iterations.csv ends at the designed knots and values; design_confirmed.csv reads
    the confirmation's own result.nc; pattern.csv its rows, in the headers' units."""
    where = tiny_run[0] / "results-ci" / "designs" / "graded"
    iterations = _csv(where / "design_iterations.csv")
    confirmed = _csv(where / "design_confirmed.csv")
    designed = yaml.safe_load((where / "case.yaml").read_text())["garment"]["reduction"]
    with xr.open_dataset(where / "confirmed" / "result.nc") as ds:
        ds = ds.load()
    targets = {"waist": 10.0, "underbust": 12.0}
    assert [row["landmark"] for row in confirmed] == list(targets)
    assert [int(row["equilibrium"]) for row in iterations] == list(range(1, len(iterations) + 1))
    assert all(1 <= int(row["newton_iterations"]) <= 60 for row in iterations)
    last = iterations[-1]
    for row in confirmed:
        line = row["landmark"]
        at = ds.sel(landmark=line)
        # the loop's equilibria, the uniform answer's (the start is uniform) and the confirmation
        assert int(row["equilibria"]) == len(iterations) + 2
        assert _close(row["height_m"], float(at["landmark_height"]))
        assert _close(row["target_mmHg"], targets[line])
        assert _close(row["designed_mmHg"], float(last[f"{line}_mmHg"]))
        assert _close(row["confirmed_mmHg"], float(at["pressure_mean"]) / MMHG)
        assert _close(row["confirmed_error_mmHg"], float(at["pressure_mean_error"]) / MMHG)
        assert _close(row["tolerance_mmHg"], 0.5)  # the default
        off = abs(float(at["pressure_mean"]) / MMHG - targets[line])
        error = float(at["pressure_mean_error"]) / MMHG  # NaN fails both: not met, undecided
        verdict = "missed" if error <= 0.5 and off > 0.5 else "met" if error <= 0.5 else ""
        assert row["verdict"] == (verdict or "grid cannot tell")
        assert row["met"] == str(int(verdict == "met"))
        if verdict:  # decided: no excess
            assert float(row["error_past_tolerance_mmHg"]) == 0.0
        else:  # by how much the error is past the tolerance, NaN where none is stated
            assert _close(row["error_past_tolerance_mmHg"], error - 0.5)
        for knot, value in designed.items():
            assert _close(row[f"reduction_{knot}"], value)
            assert _close(last[f"reduction_{knot}"], value)
    rows = _csv(where / "pattern.csv")
    assert [int(r["row"]) for r in rows] == list(range(ds.sizes["row"]))
    for column, values in (
        ("pattern_height_mm", 1e3 * ds["pattern_height"].values),
        ("cut_height_m", ds["cut_height"].values),
        ("rest_circumference_mm", 1e3 * ds["rest_circumference"].values),
        ("width_mm", 1e3 * ds["rest_circumference"].values / 2),  # two panels
        ("reduction", ds["row_reduction"].values),
    ):
        np.testing.assert_allclose([float(r[column]) for r in rows], values, atol=1e-4, rtol=2e-6)
    assert {r["cut"] for r in rows} == {"two-panel"}
