"""Fitting a mesh's smooth contact surface, and querying it, against the mesh's face count.

Icospheres of radius 0.15 m (a torso's girth) at about 20k, 80k and 1.3M faces, with the default
options (sigma from the crease spacing, at least 5 mm; h = min(3 mm, 0.4 sigma)): the fit once
(wall time, the exact samples it computed), then the median over 5 runs of value+gradient
evaluations of 1M points near the surface (points per second) and of closest-point queries of
20k points (us per point), with the mesh's own exact query (libigl AABB) beside it. Writes the
table into docs/performance.md (section ``surface``). Run:

    .venv/bin/python benchmarks/bench_surface.py [--levels 5 6 8]
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time

import numpy as np
import trimesh
from _table import markdown_table, median_seconds, replace_section

from cloth.bodies.mesh import MeshBody
from cloth.bodies.smoothmesh import SmoothMeshBody
from cloth.bodies.surface import FitOptions, fit_surface

RADIUS = 0.15


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", nargs="*", type=int, default=[5, 6, 8])
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    os.environ.setdefault("CLOTH_CACHE_DIR", tempfile.mkdtemp(prefix="cloth-bench-"))
    rng = np.random.default_rng(0)
    rows = []
    for level in args.levels:
        sphere = trimesh.creation.icosphere(level, radius=RADIUS)
        mesh = MeshBody(np.asarray(sphere.vertices), np.asarray(sphere.faces))
        start = time.perf_counter()
        fit = fit_surface(mesh, FitOptions(), progress=False)
        fitted = time.perf_counter() - start
        body = SmoothMeshBody(mesh, lambda fit=fit: (fit, None))
        u = rng.normal(size=(1_000_000, 3))
        u /= np.linalg.norm(u, axis=1)[:, None]
        near = u * (RADIUS + rng.uniform(-0.005, 0.005, len(u)))[:, None]
        values = median_seconds(lambda: fit.field.evaluate(near, order=1), repeat=5)
        some = near[:20_000]
        closest = median_seconds(lambda: body.query(some), repeat=5)
        exact = median_seconds(lambda: mesh.query(some), repeat=5)
        rows.append(
            [
                f"{len(sphere.faces):,}",
                f"{fit.smoothing * 1e3:.3g} / {fit.spacing * 1e3:.3g}",
                f"{fitted:.1f}",
                f"{len(near) / values / 1e6:.2f}",
                f"{closest / len(some) * 1e6:.1f}",
                f"{exact / len(some) * 1e6:.1f}",
                f"{fit.deviation_max * 1e3:.3f}",
            ]
        )
        print(rows[-1], flush=True)
    header = [
        "faces",
        "sigma / h [mm]",
        "fit [s]",
        "value+gradient [M points/s]",
        "closest point [us/point]",
        "mesh AABB query [us/point]",
        "vertices off the surface [mm]",
    ]
    table = markdown_table(header, rows)
    table += f"\n\n{platform.machine()}, {os.cpu_count()} cores; fit once, queries median of 5."
    print(table)
    if not args.no_write:
        replace_section("surface", table)


if __name__ == "__main__":
    main()
