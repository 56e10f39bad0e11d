"""Reintroduce, one at a time, the reporting bugs that once passed every test (issue 34), each on
a copy of the tree, and check that the tests now fail on it.

    .venv/bin/python benchmarks/known_bugs.py

Prints one row per bug: the one-line change, the tests run, and whether they failed (they
must). Exit status 1 if any bug survives.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: (name, file, line as it is, line with the bug, tests that must fail)
BUGS = [
    (
        "mmHg is 100 Pa",
        "cloth/results/pressure.py",
        "MMHG = 13.5951e3 * 9.80665 * 1e-3",
        "MMHG = 100.0",
        "tests/test_reporting.py",
    ),
    (
        "RAL class from the mean in Pa",
        "cloth/results/landmarks.py",
        '"ral_gz_387_class": ral_class(self.mean / MMHG),',
        '"ral_gz_387_class": ral_class(self.mean),',
        "tests/test_reporting.py",
    ),
    (
        "girth-line mean is the max",
        "cloth/results/landmarks.py",
        "                float(values.mean()),",
        "                float(values.max()),",
        "tests/test_reporting.py",
    ),
    (
        "kPa target x 100",
        "cloth/pipeline/sweep.py",
        'else target["pressure_kPa"] * 1e3',
        'else target["pressure_kPa"] * 1e2',
        "tests/test_reporting.py",
    ),
    (
        "set strain doubled",
        "cloth/materials/labtables.py",
        "return zero_force_strain(strain[unloading], stress[unloading])",
        "return 2 * zero_force_strain(strain[unloading], stress[unloading])",
        "tests/test_ingest.py tests/test_worn.py",
    ),
]


def survives(file: str, line: str, bug: str, tests: str) -> tuple[bool, str]:
    """Whether ``tests`` pass on a copy of the tree with ``line`` of ``file`` made ``bug``."""
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / "tree"
        tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
        for name in tracked.stdout.split():
            (copy / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, copy / name)
        path = copy / file
        text = path.read_text()
        if text.count(line) != 1:
            raise SystemExit(f"{file}: the line {line!r} is not there once; update BUGS")
        path.write_text(text.replace(line, bug))
        run = subprocess.run(
            [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", *tests.split()],
            cwd=copy,
            capture_output=True,
            text=True,
            env={"PYTHONPATH": str(copy), "PATH": "/usr/bin:/bin", "MPLBACKEND": "Agg"},
        )
        last = run.stdout.strip().splitlines()[-1] if run.stdout.strip() else run.stderr[-200:]
        return run.returncode == 0, last


def main() -> int:
    print("| bug | tests | result |\n|---|---|---|")
    alive = 0
    for name, file, line, bug, tests in BUGS:
        passed, last = survives(file, line, bug, tests)
        alive += passed
        print(f"| {name} | {tests} | {'SURVIVES' if passed else 'caught'}: {last} |")
    return 1 if alive else 0


if __name__ == "__main__":
    sys.exit(main())
