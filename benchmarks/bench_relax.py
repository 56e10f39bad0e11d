"""Time to relative residual 1e-6 and 1e-8: Newton against the paper's explicit iteration.

Elliptic-cylinder tubes (a = 0.15 m, b = 0.10 m, reduction 0.2, sliding edges; on a circular
cylinder the symmetric start is already the answer up to one step) at ~2.5k, 10k and 40k nodes,
and the parametric torso at 96 x 48 and 384 x 192; Newton with each available linear solver and
the explicit method side by side, the explicit one within a time budget. One run each (these are
long); writes the table into docs/performance.md (section ``relax``). Run:

    .venv/bin/python benchmarks/bench_relax.py [--budget 120] [--sizes 50x50 100x100 200x200]
        [--torso 96x48 384x192] [--surfaces smooth mesh] [--newton-iterations 300]
        [--solvers superlu amg]
"""

from __future__ import annotations

import argparse
import os
import platform

from _table import markdown_table, replace_section

from cloth.files.body import body_from_config
from cloth.solvers import Settings, relax
from cloth.solvers.linear import available
from cloth.stages.case import initial_state


def seconds_to(result, level: float) -> str:
    """Wall time at which the history first reached ``level`` (linear in iterations)."""
    history = result.history.residual
    for index, value in enumerate(history):
        if value <= level:
            return f"{result.seconds * index / max(len(history) - 1, 1):.2f}"
    return f"> {result.seconds:.0f} (at {history[-1]:.1e})"


def run(case: dict, method: str, solver: str, iterations: int):
    state = initial_state(case)
    body, _ = body_from_config(state.case.body.block)
    settings = Settings(
        method=method,
        tolerance=1e-8,
        max_iterations=iterations,
        linear_solver=solver,
        progress=False,
        log_every=0,
        warm_start=100,
    )
    return relax(state, body, settings)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="*", default=["50x50", "100x100", "200x200"])
    parser.add_argument("--torso", nargs="*", default=["96x48", "384x192"])
    parser.add_argument("--budget", type=float, default=120.0, help="explicit time budget, s")
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument("--section", default="relax", help="docs/performance.md section")
    parser.add_argument("--newton-iterations", type=int, default=300)
    parser.add_argument("--solvers", nargs="*", help="linear solvers (default: all installed)")
    parser.add_argument(
        "--surfaces",
        nargs="*",
        default=["smooth"],
        choices=["smooth", "mesh"],
        help="torso contact surfaces (default: smooth; the mesh is slow on fine grids)",
    )
    args = parser.parse_args()
    names = args.solvers or ("superlu", "cholmod", "pardiso", "amg")
    solvers = [s for s in names if available(s)]
    rows = []
    cases = [
        (
            f"ellipse {size}",
            size,
            {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "top": 0.5}},
            (0.1, 0.4, 0.2),
        )
        for size in args.sizes
    ] + [
        (
            f"torso M {size} {surface}",
            size,
            {"torso": {"size": "M", "surface": surface}},
            (0.86, 1.22, 0.15),
        )
        for size in args.torso
        for surface in args.surfaces
    ]
    for label, size, body, (bottom, top, reduction) in cases:
        n, m = (int(v) for v in size.split("x"))
        case = {
            "material": "powernet",
            "body": body,
            "garment": {"bottom": bottom, "top": top, "reduction": reduction, "grid": [n, m]},
        }
        newton = {s: run(case, "newton", s, args.newton_iterations) for s in solvers}
        # a backend that fell back to superlu for some steps is still reported under its name
        warm = run(case, "explicit+newton", "superlu", args.newton_iterations)
        fastest = min(newton.values(), key=lambda r: r.seconds)
        # the explicit iteration: as many iterations as the budget allows (one step's cost x)
        probe = run(case, "explicit", "superlu", 5)
        per_step = probe.seconds / max(probe.iterations, 1)
        explicit = run(case, "explicit", "superlu", max(5, int(args.budget / per_step)))
        for name, result in newton.items():
            rows.append(
                [
                    label,
                    f"{n * m:,}",
                    f"newton/{name}",
                    str(result.iterations),
                    seconds_to(result, 1e-6),
                    seconds_to(result, 1e-8),
                ]
            )
        rows.append(
            [
                label,
                f"{n * m:,}",
                "explicit+newton/superlu",
                str(warm.iterations),
                seconds_to(warm, 1e-6),
                seconds_to(warm, 1e-8),
            ]
        )
        rows.append(
            [
                label,
                f"{n * m:,}",
                "explicit",
                str(explicit.iterations),
                seconds_to(explicit, 1e-6),
                seconds_to(explicit, 1e-8),
            ]
        )
        reached = explicit.history.residual[-1] <= 1e-6
        if reached:
            ratio = f"{explicit.seconds / fastest.seconds:.0f}x"
        elif args.budget >= fastest.seconds:
            ratio = f">= {args.budget / fastest.seconds:.0f}x (explicit not at 1e-6 in the budget)"
        else:
            ratio = "n/a (explicit not at 1e-6 in a budget shorter than Newton's run)"
        rows.append([label, "", "explicit / newton time", "", "", ratio])
        print(*rows[-4:], sep="\n", flush=True)
    table = markdown_table(
        ["case", "nodes", "method", "iterations", "to 1e-6 [s]", "to 1e-8 [s]"], rows
    )
    body = (
        f"One run each on {platform.machine()}, {os.cpu_count()} cores; explicit within a "
        f"{args.budget:.0f} s budget.\n\n{table}"
    )
    print(body)
    if not args.no_write:
        replace_section(args.section, body)


if __name__ == "__main__":
    main()
