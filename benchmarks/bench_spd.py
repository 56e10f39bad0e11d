"""Positive-definite solvers (issue 41): cholespy's Cholesky, with conjugate gradients on the
kept factor, against SuperLU's LU on the same cases, side by side in one run.

Cases (power net, the pattern reduction ``--reduction`` (0.20), 0.86-1.22 m, no lengthwise
reduction, the tension field, the default path: continuation + reuse, to a relative residual
of 1e-8):

* ``torso``: the smooth parametric torso M;
* ``scan``: a scan stand-in, torso M written as a 128 x 120 triangle mesh with 1 mm of seeded
  noise along each vertex's normal (no real scan ships with cloth), read back as a ``mesh:``
  body through its fitted smooth surface;
* ``avatar``: avatar M (the body model fitted to size M's girths, a shipped mesh: a realistic
  body, read through its fitted smooth surface);

on each of ``--grids``, with each of ``--solvers`` (a backend name, with ``/fresh`` for no
reuse: a fresh factorisation per Newton system; ``amg`` is pyamg's smoothed aggregation as the
preconditioner of CG, set up afresh for each system), and with ``@REVISION`` the code of that
git revision (cloned to a temporary folder, run with this checkout's .venv and this file's
case): ``cholespy@76a0e56 cholespy@HEAD`` is a before-and-after in one run. A mesh body's
smooth surface is fitted once for all runs (one cache) and read before the clock starts, as
the pipeline's relax rule reads it from the cache predeform filled. Each run is its own
process, so its peak resident memory (VmHWM) is its own. Reported per run: relax time (s),
fine-grid Newton iterations, factorisations (all levels; cholespy's attempts on a matrix that
turned out not positive definite count too, and ``LU`` how many of them SuperLU then
factorised), solves with a factor (a Krylov iteration on a kept factor counts one), the peak
memory, and the largest difference of the positions from the first solver's (m).

Run:

    .venv/bin/python benchmarks/bench_spd.py [--cases torso scan avatar] [--grids 448x224]
        [--solvers superlu cholespy cholespy@REV] [--reduction 0.20] [--repeat 1]
        [--section spd] [--no-write]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _table import markdown_table, publish
from make_run_time import clone

HERE = Path(__file__).resolve().parent
NOISE = 1e-3  # m, along each vertex normal of the scan stand-in


def scan_mesh(folder: Path) -> Path:
    """The scan stand-in's OBJ file in ``folder`` (module docstring)."""
    import trimesh
    from validation_scans import write_obj

    from cloth.bodies.torso import chart_size, torso_mesh

    vertices, faces = torso_mesh(chart_size("M"), 128, 120)
    normals = trimesh.Trimesh(vertices, faces, process=False).vertex_normals
    noise = np.random.default_rng(41).normal(0.0, NOISE, len(vertices))
    return write_obj(folder / "scan.obj", vertices + noise[:, None] * normals, faces)


def case(kind: str, grid: str, folder: Path, reduction: float = 0.20) -> dict:
    n, m = (int(v) for v in grid.split("x"))
    if kind == "scan":
        body = {"mesh": str(scan_mesh(folder))}
    else:
        body = {kind: {"size": "M"}}
    return {
        "material": "powernet",
        "body": body,
        "garment": {"bottom": 0.86, "top": 1.22, "reduction": reduction, "grid": [n, m]},
    }


def one(kind: str, grid: str, solver: str, positions: Path, reduction: float = 0.20) -> dict:
    """Relax one case in this process; its facts, and its positions saved to ``positions``."""
    from dataclasses import replace

    from cloth.files.body import body_from_config
    from cloth.solvers import relax
    from cloth.solvers.linear import solves
    from cloth.solvers.relax import reset_peak_memory
    from cloth.stages.case import initial_state

    with tempfile.TemporaryDirectory() as tmp:  # the mesh kept, its fitted surface cached
        os.environ.setdefault("CLOTH_CACHE_DIR", str(Path(tmp) / "cache"))
        state = initial_state(case(kind, grid, Path(tmp), reduction))
        body, _ = body_from_config(state.case.body.block)
        getattr(body, "fit", None)  # a mesh's surface fitted (or read) before the clock
        name, _, fresh = solver.partition("@")[0].partition("/")
        settings = replace(
            state.case.solver,
            linear_solver=name,
            reuse=state.case.solver.reuse and fresh != "fresh",
            progress=False,
            log_every=0,
        )
        reset_peak_memory()
        solved = solves()
        start = time.perf_counter()
        result = relax(state, body, settings)
        seconds = time.perf_counter() - start
    np.save(positions, result.final.x)
    return {
        "seconds": seconds,
        "iterations": result.iterations,
        "converged": result.converged,
        "residual": float(result.final.residual),
        "factorisations": result.factorisations,
        "lu": result.lu_fallbacks,
        "solves": solves() - solved,
        "peak_mib": result.peak_memory / 2**20,
        "used": result.linear_solver,
        "code": str(Path(sys.modules["cloth"].__file__).parents[1]),
    }


def run(
    kind: str, grid: str, solver: str, positions: Path, reduction: float, clones: dict[str, Path]
) -> dict:
    """One run in its own process; a ``solver@REVISION`` with that revision's code."""
    command = [sys.executable, __file__, "--one", kind, grid, solver, str(positions)]
    command += ["--reduction", str(reduction)]
    folder = clones.get(solver.partition("@")[2], HERE.parent)
    env = {**os.environ, "PYTHONPATH": str(folder)}
    done = subprocess.run(command, capture_output=True, text=True, cwd=folder, env=env)
    if done.returncode:
        sys.exit(f"{kind} {grid} {solver} failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def _file_name(solver: str) -> str:
    return solver.replace("/", "-").replace("@", "-")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=["torso", "scan"])
    parser.add_argument("--grids", nargs="+", default=["448x224"])
    parser.add_argument("--solvers", nargs="+", default=["superlu", "cholespy"])
    parser.add_argument("--reduction", type=float, default=0.20, help="the pattern's, 0-1")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--section", default="spd")
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    parser.add_argument("--one", nargs=4, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        kind, grid, solver, positions = args.one
        print(json.dumps(one(kind, grid, solver, Path(positions), args.reduction)))
        return
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        revisions = {s.partition("@")[2] for s in args.solvers} - {""}
        clones = {r: clone(r, Path(tmp)) for r in sorted(revisions)}
        # one cache for every run: a mesh body's surface is fitted once, before any clock
        os.environ["CLOTH_CACHE_DIR"] = str(Path(tmp) / "cache")
        for kind in args.cases:
            for grid in args.grids:
                runs: dict[str, list[dict]] = {s: [] for s in args.solvers}
                for _ in range(args.repeat):  # the solvers alternate
                    for solver in args.solvers:
                        saved = Path(tmp) / f"{_file_name(solver)}.npy"
                        runs[solver].append(run(kind, grid, solver, saved, args.reduction, clones))
                first = np.load(Path(tmp) / f"{_file_name(args.solvers[0])}.npy")
                base = statistics.median(r["seconds"] for r in runs[args.solvers[0]])
                for solver in args.solvers:
                    facts = runs[solver][-1]
                    seconds = statistics.median(r["seconds"] for r in runs[solver])
                    saved = Path(tmp) / f"{_file_name(solver)}.npy"
                    gap = float(np.abs(np.load(saved) - first).max())
                    rows.append(
                        [
                            kind,
                            grid,
                            f"{int(np.prod([int(v) for v in grid.split('x')])):,}",
                            solver,
                            f"{seconds:.1f}",
                            f"{seconds / base:.2f}",
                            str(facts["iterations"]) + ("" if facts["converged"] else " (not)"),
                            f"{facts['factorisations']} ({facts['lu']} LU)",
                            str(facts["solves"]),
                            f"{facts['residual']:.1e}",
                            f"{facts['peak_mib']:.0f}",
                            f"{gap:.1e}",
                        ]
                    )
                    print(rows[-1], flush=True)
    header = [
        "case",
        "grid",
        "nodes",
        "solver",
        "relax [s]",
        "/ first",
        "fine iterations",
        "factorisations",
        "solves",
        "residual",
        "peak memory [MiB]",
        "max position gap [m]",
    ]
    note = (
        f"{args.repeat} run(s) each, medians, solvers alternating, each run its own process, on "
        f"{platform.machine()}, {os.cpu_count()} cores; reduction {args.reduction:.2f}, "
        "continuation + reuse, to 1e-8."
    )
    publish(f"{note}\n\n{markdown_table(header, rows)}", args.section, not args.no_write)


if __name__ == "__main__":
    main()
