"""A garment on a meshed body: the fitted smooth surface against the mesh's facets, side by side.

The parametric torso M written as its 128 x 120 triangle mesh and read back as a ``mesh:`` body
(a scan stand-in we can ship), power net at 15 % reduction between the hip and bust lines,
sliding edges, Newton with SuperLU to 1e-8: ``surface: smooth`` (the default; the time includes
fitting the surface, which is then cached) against ``surface: mesh`` (the facets, capped at
``--mesh-iterations``). With ``--variants plain continuation+reuse`` the smooth surface is
also relaxed with coarse-to-fine continuation and factor reuse (issue 12's headline on a meshed
body); ``--surfaces`` picks the surfaces. One run each; writes docs/performance.md (section
``--section``, default ``relax_scan``). Run:

    .venv/bin/python benchmarks/bench_scan.py [--grids 96x48 384x192] [--mesh-iterations 40]
        [--surfaces smooth mesh] [--variants plain] [--section relax_scan] [--no-write]
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time
from pathlib import Path

from _table import markdown_table, replace_section
from _torso import VARIANTS
from bench_relax import seconds_to
from validation_scans import write_obj

from cloth.bodies.torso import chart_size, torso_mesh
from cloth.files.body import body_from_config
from cloth.solvers import Settings, relax
from cloth.stages.case import initial_state


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="*", default=["96x48", "384x192"])
    parser.add_argument("--mesh-iterations", type=int, default=40)
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument(
        "--surfaces", nargs="+", default=["smooth", "mesh"], choices=["smooth", "mesh"]
    )
    parser.add_argument("--variants", nargs="+", default=["plain"], choices=list(VARIANTS))
    parser.add_argument("--section", default="relax_scan")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="cloth-scan-"))
    os.environ["CLOTH_CACHE_DIR"] = str(folder / "cache")  # the first fit is timed
    path = write_obj(folder / "torso.obj", *torso_mesh(chart_size("M"), 128, 120))
    rows = []
    for grid in args.grids:
        n, m = (int(v) for v in grid.split("x"))
        runs = [("smooth", 150, v) for v in args.variants if "smooth" in args.surfaces]
        runs += [("mesh", args.mesh_iterations, "plain")] if "mesh" in args.surfaces else []
        for surface, iterations, variant in runs:
            continued, reuse = VARIANTS[variant]
            case = {
                "material": "powernet",
                "body": {"mesh": str(path), "surface": surface},
                "garment": {
                    "bottom": 0.86,
                    "top": 1.22,
                    "reduction": 0.15,
                    "grid": [n, m],
                    "edges": "sliding",
                },
            }
            start = time.perf_counter()
            state = initial_state(case)
            body, _ = body_from_config(state.case.body.block)
            prepared = time.perf_counter() - start
            settings = Settings(
                tolerance=1e-8,
                max_iterations=iterations,
                linear_solver="superlu",
                progress=False,
                log_every=0,
                continuation=continued,
                reuse=reuse,
            )
            result = relax(state, body, settings)
            # with continuation the history is the fine grid's, after the coarse levels
            reached = (
                seconds_to(result, 1e-8)
                if variant == "plain"
                else (f"{result.seconds:.2f}" if result.converged else f"> {result.seconds:.0f}")
            )
            rows.append(
                [
                    f"{n} x {m}",
                    f"{n * m:,}",
                    surface,
                    variant,
                    f"{prepared:.1f}",
                    str(result.iterations) + ("" if result.converged else " (cap)"),
                    str(result.factorisations),
                    seconds_to(result, 1e-6) if variant == "plain" else "",
                    reached,
                ]
            )
            print(rows[-1], flush=True)
    header = [
        "grid",
        "nodes",
        "surface",
        "variant",
        "predeform (+ fit) [s]",
        "(fine) iterations",
        "factorisations",
        "relax to 1e-6 [s]",
        "relax to 1e-8 [s]",
    ]
    body = (
        f"One run each on {platform.machine()}, {os.cpu_count()} cores, Newton with SuperLU; "
        f"the faceted runs capped at {args.mesh_iterations} iterations.\n\n"
        + markdown_table(header, rows)
    )
    print(body)
    if not args.no_write:
        replace_section(args.section, body)


if __name__ == "__main__":
    main()
