"""The command line starts fast: ``cloth --version`` and ``cloth --help`` import no stage and
none of the numerical stack (numpy, scipy, xarray, trimesh), so they answer in well under a
second. The time is asserted as the issue asks (a subprocess, the median of 3); the imports are
checked exactly, which is what keeps the time."""

from __future__ import annotations

import json
import resource
import statistics
import subprocess
import sys
import time

import pytest

#: Most seconds ``cloth --version`` may take (the median of 3 runs of a new interpreter).
STARTUP_LIMIT = 0.3
HEAVY = (
    "numpy",
    "scipy",
    "xarray",
    "trimesh",
    "matplotlib",
    "cholespy",
    "cloth.stages",
    "cloth.io",
    "cloth.solvers",
)


def _modules_loaded(argv: list[str]) -> set[str]:
    """The modules a new interpreter has loaded after ``cloth argv`` exits."""
    code = (
        "import sys, json\n"
        "from cloth.cli import main\n"
        "try:\n"
        f"    main({argv!r})\n"
        "except SystemExit:\n"
        "    pass\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    return set(json.loads(out.splitlines()[-1]))


@pytest.mark.parametrize(
    "argv",
    [["--version"], ["--help"], ["run", "--help"], ["design", "--help"], ["run"]],
    ids=["version", "help", "run-help", "design-help", "refused"],
)
def test_version_help_and_refusals_import_no_stage(argv):
    loaded = _modules_loaded(argv)
    assert "cloth.cli.parser" in loaded  # the probe sees the parser it ran
    assert sorted(m for m in loaded if m.split(".")[0] in HEAVY or m in HEAVY) == []
    assert not any(m == h or m.startswith(h + ".") for m in loaded for h in HEAVY)


def test_a_verb_imports_its_stage_when_it_runs(tmp_path):
    loaded = _modules_loaded(["case", "check", str(tmp_path / "missing.yaml")])
    assert "cloth.case.validate" in loaded
    assert "cloth.stages.design" not in loaded  # another verb's stage stays out


def _median_seconds(argv: list[str]) -> tuple[float, float]:
    """The median of 3 runs of ``python -m cloth ARGV`` in a new process: (wall, CPU) s."""
    walls, cpus = [], []
    for _ in range(3):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "cloth", *argv], check=True, capture_output=True)
        walls.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return statistics.median(walls), statistics.median(cpus)


@pytest.mark.parametrize("argv", [["--version"], ["--help"]], ids=["version", "help"])
def test_version_and_help_answer_within_the_limit(argv):
    """The median of 3 under `STARTUP_LIMIT` (measured 0.11-0.12 s; 2.2 s before). The test
    suite runs on both cores beside it: where the wall time is over, the child's own CPU time
    tells load from work, and one more round of 3 is taken."""
    wall, cpu = _median_seconds(argv)
    if wall >= STARTUP_LIMIT and cpu < STARTUP_LIMIT:
        wall, cpu = _median_seconds(argv)
    assert wall < STARTUP_LIMIT, (wall, cpu)
