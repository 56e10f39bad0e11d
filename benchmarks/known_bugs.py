"""Plant, one at a time, the bugs that once passed every test (issue 34's reporting bugs and
issue 43's planted-bug audit), and bugs in the cutting room's files (issue 42), each on a copy
of the tree, and check that the tests now fail.

    .venv/bin/python benchmarks/known_bugs.py [--only NAME ...]

Prints one row per bug: the change, the tests run, and whether they failed (they must). Exit
status 1 if any bug survives; 2 if a line to change is no longer in its file (update BUGS).
"""

from __future__ import annotations

import argparse
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Bug:
    """``old`` (text found exactly once in ``file``) made ``new``; ``tests``: pytest's
    arguments (files, ``-k`` expressions) whose run must fail on the bug."""

    name: str
    file: str
    old: str
    new: str
    tests: str


BUGS = [
    Bug(
        "mmHg is 100 Pa",
        "cloth/results/pressure.py",
        "MMHG = 13.5951e3 * 9.80665 * 1e-3",
        "MMHG = 100.0",
        "tests/test_reporting.py",
    ),
    Bug(
        "compression class from the mean in Pa",
        "cloth/results/judging.py",
        'row["compression_class"] = judge.compression_class(mmhg) if name == point else ""',
        'row["compression_class"] = judge.compression_class(133.3 * mmhg) if name == point else ""',
        "tests/test_reporting.py",
    ),
    Bug(
        "girth-line mean is the probe's max",
        "cloth/results/landmarks.py",
        "                weighted_mean(force, fields.area, weight),\n",
        "                float(np.nanmax(probes)),\n",
        "tests/test_reporting.py",
    ),
    Bug(
        "kPa target x 100",
        "cloth/pipeline/sweep.py",
        'else target["pressure_kPa"] * 1e3',
        'else target["pressure_kPa"] * 1e2',
        "tests/test_reporting.py",
    ),
    Bug(
        "set strain doubled",
        "cloth/materials/labtables.py",
        "return zero_force_strain(strain[unloading], stress[unloading])",
        "return 2 * zero_force_strain(strain[unloading], stress[unloading])",
        "tests/test_ingest.py tests/test_worn.py",
    ),
    Bug(
        "graded design's confirmed value from the loop's last iterate",
        "cloth/stages/graded.py",
        '"confirmed_mmHg": value / MMHG,',
        '"confirmed_mmHg": result.achieved[k] / MMHG,',
        "tests/test_design.py -k confirm",
    ),
    Bug(
        "cloth design --tolerance ignored",
        "cloth/cli/handlers.py",
        "args.output, args.tolerance * MMHG, args.base_dir, **options)",
        "args.output, 0.5 * MMHG, args.base_dir, **options)",
        "tests/test_design.py -k tolerance",
    ),
    Bug(
        "shortfall checked at 10x the tolerance",
        "cloth/stages/design.py",
        "if not np.all(np.abs(sens.means - goal) <= tolerance):",
        "if not np.all(np.abs(sens.means - goal) <= 10 * tolerance):",
        "tests/test_design.py -k lab_range",
    ),
    Bug(
        "lab-range cap at the curve's second-to-last knot",
        "cloth/stages/design.py",
        "lab = float(grid.curves[WEFT].knot_strain[-1])",
        "lab = float(grid.curves[WEFT].knot_strain[-2])",
        "tests/test_design.py -k lab_range",
    ),
    Bug(
        "SVG pattern drawn upside down",
        "cloth/files/pattern.py",
        'return f"{x0 + x:.3f},{height - margin - y:.3f}"',
        'return f"{x0 + x:.3f},{margin + y:.3f}"',
        "tests/test_pattern.py",
    ),
    Bug(
        "SVG girth lines drawn at the bottom edge",
        "cloth/files/pattern.py",
        'left, right = at(-half, y).split(","), at(half, y).split(",")',
        'left, right = at(-half, 0.0).split(","), at(half, 0.0).split(",")',
        "tests/test_pattern.py",
    ),
    Bug(
        "graduation_met inverted",
        "cloth/results/judging.py",
        "int(limits[0] <= share <= limits[1])",
        "int(not limits[0] <= share <= limits[1])",
        "tests/test_reporting.py",
    ),
    Bug(
        "the mesh leg's lean pivots at G",
        "cloth/bodies/leg.py",
        '(vertices[:, 2] - chart.height["B"])',
        '(vertices[:, 2] - chart.height["G"])',
        "tests/test_leg.py",
    ),
    Bug(
        "the smooth leg's lean pivots at G",
        "cloth/bodies/leg.py",
        '            chart.height["B"],\n        )',
        '            chart.height["G"],\n        )',
        "tests/test_leg.py",
    ),
    Bug(
        "the case validator's finite check removed",
        "cloth/pipeline/config.py",
        "return number and (not isinstance(instance, float) or math.isfinite(instance))",
        "return number",
        "tests/test_fuzz.py -k 'finite or nul'",
    ),
    Bug(
        "a target's finite check removed",
        "cloth/results/targets.py",
        "if not match or not np.isfinite(value) or value <= 0:",
        "if not match or value <= 0:",
        "tests/test_design.py -k 'target and not profile'",
    ),
    Bug(
        "a leg chart's finite check removed",
        "cloth/bodies/leg.py",
        "if value is None or not np.isfinite(value) or value <= 0:",
        "if value is None or value <= 0:",
        "tests/test_leg.py -k bad_chart",
    ),
    Bug(
        "the NUL check on paths removed",
        "cloth/paths.py",
        'if "\\0" in value:',
        "if False:",
        "tests/test_fuzz.py -k 'finite or nul'",
    ),
    Bug(
        "summary.csv written without the atomic writer",
        "cloth/files/result.py",
        "    with atomic_output(path) as tmp:\n        tmp.write_text(buffer.getvalue())\n"
        "    return Path(path)",
        "    Path(path).write_text(buffer.getvalue())\n    return Path(path)",
        "tests/test_kill.py -k summary",
    ),
    # issue 42: the cutting room's files
    Bug(
        "seam allowance offset by half the allowance",
        "cloth/files/piece.py",
        "    grown = polygon + scale[:, None] * bisector",
        "    grown = polygon + 0.5 * scale[:, None] * bisector",
        "tests/test_piece.py tests/test_chart.py -k 'allowance or rectangle or trapezoid'",
    ),
    Bug(
        "notch cut outward",
        "cloth/files/piece.py",
        "np.array([left + depth, y])",
        "np.array([left - depth, y])",
        "tests/test_chart.py -k widths",
    ),
    Bug(
        "check square 99 mm",
        "cloth/files/printout.py",
        "SQUARE_MM = 100.0",
        "SQUARE_MM = 99.0",
        "tests/test_chart.py -k check_square",
    ),
    Bug(
        "knitting circumference read top to bottom",
        "cloth/files/knitting.py",
        "circumference = np.interp(at, pattern.height, pattern.circumference)",
        "circumference = np.interp(at, pattern.height, pattern.circumference[::-1])",
        "tests/test_chart.py -k knitting",
    ),
    Bug(
        "sizes not warm-started",
        "cloth/stages/chart.py",
        "            case = warm_case(case, previous, entry.source)",
        "            pass",
        "tests/test_chart.py -k warm",
    ),
    Bug(
        "relax reserves two cores again",
        "workflow/rules/relax.smk",
        "    threads: relax_threads",
        "    threads: 2",
        "tests/test_workflow.py -k threads_its_case_uses",
    ),
    Bug(
        "figures before the design's path",
        "workflow/rules/common.smk",
        "CRITICAL = 1",
        "CRITICAL = 0",
        "tests/test_workflow.py -k threads_its_case_uses",
    ),
    Bug(
        "a stale factor always tried",
        "cloth/solvers/linear.py",
        "        stale = bool(self.krylov) and self.krylov[-1] > KRYLOV_STALE",
        "        stale = False",
        "tests/test_linear.py -k stale",
    ),
]


def _copy(copy: Path) -> None:
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    for name in tracked.stdout.split():
        if (ROOT / name).is_file():
            (copy / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, copy / name)


def survives(bug: Bug) -> tuple[bool, str]:
    """Whether ``bug.tests`` pass on a copy of the tree with ``bug`` planted, and the run's
    last line."""
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / "tree"
        _copy(copy)
        path = copy / bug.file
        text = path.read_text()
        if text.count(bug.old) != 1:
            print(f"{bug.file}: the text {bug.old!r} is not there once; update BUGS")
            raise SystemExit(2)
        path.write_text(text.replace(bug.old, bug.new))
        env = {
            **os.environ,
            "PYTHONPATH": str(copy),
            "PATH": f"{Path(sys.executable).parent}:/usr/bin:/bin",
            "MPLBACKEND": "Agg",
        }
        pytest = [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider"]
        run = subprocess.run(
            [*pytest, *shlex.split(bug.tests)],
            cwd=copy,
            capture_output=True,
            text=True,
            env=env,
        )
        out = run.stdout.strip().splitlines()
        return run.returncode == 0, out[-1] if out else run.stderr[-200:]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", default=None, help="bugs whose name contains these")
    args = parser.parse_args(argv)
    bugs = [b for b in BUGS if not args.only or any(o in b.name for o in args.only)]
    print("| bug | tests | result |\n|---|---|---|", flush=True)
    alive = 0
    for bug in bugs:
        start = time.perf_counter()
        passed, last = survives(bug)
        alive += passed
        verdict = "SURVIVES" if passed else "caught"
        seconds = time.perf_counter() - start
        print(f"| {bug.name} | `{bug.tests}` | {verdict} ({seconds:.0f} s): {last} |", flush=True)
    print(f"\n{len(bugs) - alive} of {len(bugs)} planted bugs caught")
    return 1 if alive else 0


if __name__ == "__main__":
    sys.exit(main())
