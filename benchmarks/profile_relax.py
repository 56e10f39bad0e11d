"""Where a relaxation's time goes: cProfile of Newton on the torso case (docs/performance.md,
section ``profile``), plain and with continuation and reuse, side by side.

Rows are the parts issue 12 names, each the cumulative time of the functions that do it (a
part that calls another includes it, so the column does not sum to 100 %): the Newton step as a
whole; evaluations (spring state, forces, contact); the contact queries wherever called (in
evaluations and in projections onto the body); assembly
(the stiffness and the Newton matrix); factorisation (SuperLU), and within it the
nested-dissection ordering (computed once per grid); solves with a factor (direct,
and inside GMRES); GMRES itself; the line search (its trial evaluations included). Run:

    .venv/bin/python benchmarks/profile_relax.py [--grid 448x224] [--no-write]
"""

from __future__ import annotations

import argparse
import cProfile
import platform
import pstats

from _table import markdown_table, replace_section
from _torso import torso_case

from cloth.solvers import Settings, relax

#: Part -> (file suffix, function name) of the functions whose cumulative time it is.
PARTS = {
    "Newton step (all of it)": [("solvers/newton.py", "newton_step")],
    "evaluations (springs, forces, contact)": [("solvers/problem.py", "evaluate")],
    "contact queries (wherever called)": [("bodies/implicit.py", "query")],
    "stiffness (springs' Hessian blocks)": [("cloth/garment/mechanics.py", "stiffness")],
    "the Newton matrix (projection, contact)": [("solvers/newton.py", "newton_matrix")],
    "factorisation (SuperLU)": [("solvers/linear.py", "lu_factor")],
    "of which the ordering (once per grid)": [("solvers/ordering.py", "dof_permutation")],
    "solves with a factor": [("~", "<method 'solve' of 'SuperLU' objects>")],
    "GMRES (reuse)": [("_isolve/iterative.py", "gmres")],
    "line search (its evaluations included)": [("solvers/newton.py", "_line_search")],
}


def profile(state, body, settings) -> tuple[dict[str, float], float, object]:
    profiler = cProfile.Profile()
    result = profiler.runcall(relax, state, body, settings)
    stats = pstats.Stats(profiler).stats  # (file, line, name) -> (cc, nc, tt, ct, callers)
    total = max(ct for (_, _, name), (_, _, _, ct, _) in stats.items() if name == "relax")
    times = {}
    for part, functions in PARTS.items():
        times[part] = sum(
            ct
            for (file, _, name), (_, _, _, ct, _) in stats.items()
            if any(name == n and (f == "~" or file.endswith(f)) for f, n in functions)
        )
    return times, total, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", default="448x224")
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    n, m, state, body = torso_case(args.grid)
    runs = {}
    for name, continued, reuse in (("plain", False, False), ("continuation+reuse", True, True)):
        settings = Settings(
            tolerance=1e-8,
            max_iterations=100,
            progress=False,
            log_every=0,
            linear_solver="superlu",
            continuation=continued,
            reuse=reuse,
        )
        runs[name] = profile(state, body, settings)
        print(name, runs[name][1], flush=True)
    header = ["part"]
    for name in runs:
        header += [f"{name} [s]", f"{name} [%]"]
    rows = []
    for part in PARTS:
        row = [part]
        for times, total, _ in runs.values():
            row += [f"{times[part]:.1f}", f"{100 * times[part] / total:.0f}"]
        rows.append(row)
    rows.append(["relax, total", *[v for _, t, _ in runs.values() for v in (f"{t:.1f}", "100")]])
    facts = ", ".join(
        f"{name}: {r.iterations} fine iterations, {r.factorisations} factorisations"
        for name, (_, _, r) in runs.items()
    )
    note = (
        f"cProfile, one run each, on {platform.machine()}, 2 cores: torso M at {args.grid} "
        f"({n * m:,} nodes) to 1e-8, SuperLU ({facts}). Times under cProfile are longer than "
        "without it."
    )
    table = markdown_table(header, rows)
    print(table)
    if not args.no_write:
        replace_section("profile", note + "\n\n" + table)


if __name__ == "__main__":
    main()
