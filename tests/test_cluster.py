"""Scale-out through a real scheduler: the tiny pipeline on a single-node SLURM (tests/slurm.py).

Run alone with ``make test-cluster``; ``make test`` runs it too where SLURM can start (root, the
Debian packages that `.ci/run` installs, the ``cluster`` extra), else it skips with one line.
The cluster runs the project's own profile, ``workflow/profiles/slurm``, plus what this
cluster needs: no accounting database, so jobs are followed with ``squeue`` (docs/cluster.md),
and short status intervals, since its jobs take seconds.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import time

import numpy as np
import pytest
import xarray as xr
import yaml

from tests import slurm
from tests.pipeline import environment, workspace

pytestmark = pytest.mark.cluster

SLURM_ARGS = (
    "--workflow-profile",
    "workflow/profiles/slurm",
    "--slurm-status-command",
    "squeue",
    "--slurm-init-seconds-before-status-checks",
    "2",
    "--seconds-between-status-checks",
    "2",
    "--latency-wait",
    "5",
)
#: "Job 13 has been submitted with SLURM jobid 1 (log: .../slurm_logs/rule_write_case/...)"
SUBMITTED = re.compile(r"submitted with SLURM jobid (\d+) \(log: \S*/slurm_logs/rule_([a-z_]+)/")


def skip_reason() -> str | None:
    reason = slurm.missing()
    if reason is None and importlib.util.find_spec("snakemake_executor_plugin_slurm") is None:
        reason = "the SLURM executor plugin is not installed (make install OPTIONAL=cluster)"
    return reason


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    reason = skip_reason()
    if reason:
        pytest.skip(reason)
    memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") // 2**20
    running = slurm.start(tmp_path_factory.mktemp("slurm"), os.cpu_count() or 1, memory * 3 // 4)
    try:
        yield running
    finally:
        running.stop()


def on_slurm(cluster, where, *args, timeout=900) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["snakemake", *SLURM_ARGS, *args],
        cwd=where,
        capture_output=True,
        text=True,
        env=environment(cluster.env),
        timeout=timeout,
    )


def data(path) -> dict[str, np.ndarray]:
    """Every variable and coordinate of a netCDF file (its attributes hold paths and times)."""
    with xr.open_dataset(path) as ds:
        return {name: ds[name].values for name in ds.variables}


def assert_same_data(a, b) -> None:
    first, second = data(a), data(b)
    assert first.keys() == second.keys(), b
    for name, value in first.items():
        nan = value.dtype.kind in "fc"
        assert np.array_equal(value, second[name], equal_nan=nan), f"{b}: {name}"


def test_the_tiny_pipeline_runs_through_slurm_as_it_runs_here(cluster, tiny_run, tmp_path):
    """Every job through the scheduler, the design checkpoint and its confirmation included:
    the scheduler's record has each one completed, every result.nc and sweep.nc hold the
    same data as the local run's to the bit, and a second run has nothing to do."""
    local, local_result, local_seconds = tiny_run
    assert local_result.returncode == 0, local_result.stderr[-3000:]
    where = workspace(tmp_path)
    start = time.perf_counter()
    result = on_slurm(cluster, where, "--configfile", "config/ci.yaml")
    seconds = time.perf_counter() - start
    assert result.returncode == 0, result.stderr[-3000:]
    jobs = dict(SUBMITTED.findall(result.stdout + result.stderr))
    assert {
        "ingest_material",
        "write_case",
        "predeform",
        "relax",
        "aggregate",
        "figures",
        "sweep",
        "design",
        "confirm",
    } <= set(jobs.values())
    record = {job["JobId"]: job for job in cluster.jobs()}
    for job_id, rule in jobs.items():
        assert record[job_id]["JobState"] == "COMPLETED", (rule, record[job_id])
        assert record[job_id]["ExitCode"] == "0:0", (rule, record[job_id])
    cases = sorted(path.parent.name for path in (local / "results-ci/cases").glob("*/result.nc"))
    assert any(name.startswith("design__") for name in cases)  # the confirmation case
    assert cases == sorted(p.parent.name for p in (where / "results-ci/cases").glob("*/result.nc"))
    for name in cases:
        assert_same_data(
            local / f"results-ci/cases/{name}/result.nc",
            where / f"results-ci/cases/{name}/result.nc",
        )
    assert_same_data(local / "results-ci/sweep.nc", where / "results-ci/sweep.nc")
    confirmed = "results-ci/design_confirmed.csv"
    assert (where / confirmed).read_text() == (local / confirmed).read_text()
    again = on_slurm(cluster, where, "--configfile", "config/ci.yaml", "-n")
    assert "Nothing to be done" in again.stdout + again.stderr
    print(
        f"\nlocal {local_seconds:.1f} s, SLURM {seconds:.1f} s for {len(jobs)} jobs: "
        f"{(seconds - local_seconds) / len(jobs):.2f} s per job"
    )


def test_a_cancelled_relax_job_is_reported_and_a_rerun_completes(cluster, tmp_path):
    """``scancel`` on a running relaxation: the workflow fails naming the rule, leaves no
    relaxed.nc, and a rerun completes it."""
    where = workspace(tmp_path)
    config = yaml.safe_load((where / "config/ci.yaml").read_text())
    config["cases"]["tiny"]["garment"]["grid"] = [96, 48]  # a relaxation of a few seconds
    (where / "config/one.yaml").write_text(yaml.safe_dump(config))
    target = ("results-one/cases/tiny/relaxed.nc", "--configfile", "config/one.yaml")
    process = subprocess.Popen(
        ["snakemake", *SLURM_ARGS, "--retries", "0", *target],
        cwd=where,
        env=environment(cluster.env),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    cancelled = None
    deadline = time.monotonic() + 600
    while cancelled is None and time.monotonic() < deadline and process.poll() is None:
        for job_id, _, state, comment in cluster.queue():
            if "rule_relax" in comment and state == "RUNNING":
                subprocess.run(["scancel", job_id], env=cluster.env, check=True)
                cancelled = job_id
        time.sleep(0.2)
    output, _ = process.communicate(timeout=600)
    assert cancelled is not None, output[-3000:]
    assert process.returncode != 0
    assert "Error in rule relax" in output and f"SLURM-job '{cancelled}' failed" in output
    assert not (where / "results-one/cases/tiny/relaxed.nc").exists()
    record = {job["JobId"]: job for job in cluster.jobs()}
    assert record[cancelled]["JobState"] == "CANCELLED"
    rerun = on_slurm(cluster, where, *target)
    assert rerun.returncode == 0, rerun.stderr[-3000:]
    with xr.open_dataset(where / "results-one/cases/tiny/relaxed.nc") as relaxed:
        assert relaxed.attrs["solver_converged"] == 1
