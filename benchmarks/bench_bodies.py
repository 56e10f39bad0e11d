"""Mesh proximity backends side by side, and pre-deformation time on the torso (medians).

Proximity: 10k and 100k points within +-5 mm of the surface (where garment nodes are) of a
20k-face and a 100k-face torso mesh, for libigl (default), the numpy/scipy fallback
(cloth.bodies.proximity) and trimesh's closest_point (on a 1k-point sample: it is slow). Writes the
tables into docs/performance.md (sections ``proximity`` and ``predeform``). Run:

    .venv/bin/python benchmarks/bench_bodies.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import platform

import numpy as np
import trimesh
from _table import markdown_table, median_seconds, replace_section

from cloth.bodies import MeshBody
from cloth.bodies.torso import chart_size, torso_mesh
from cloth.stages.case import initial_state


def near_surface(body: MeshBody, count: int, rng) -> np.ndarray:
    faces = rng.integers(0, len(body.faces), count)
    w = rng.dirichlet([1, 1, 1], count)
    on = np.einsum("pk,pkd->pd", w, body.vertices[body.faces[faces]])
    _, _, n = body.query(on)
    return on + n * rng.uniform(-0.005, 0.005, (count, 1))


def proximity_rows(repeat: int) -> list[list[str]]:
    rng = np.random.default_rng(0)
    rows = []
    for around, rings in ((128, 78), (256, 194)):
        vertices, faces = torso_mesh(chart_size("M"), around=around, rings=rings)
        igl_body = MeshBody(vertices, faces, backend="igl")
        numpy_body = MeshBody(vertices, faces, backend="numpy")
        mesh = trimesh.Trimesh(vertices, faces, process=False)
        sample = near_surface(igl_body, 1000, rng)
        try:
            import rtree  # noqa: F401 - trimesh's closest_point needs it (the bench extra)

            t_tri = median_seconds(lambda: trimesh.proximity.closest_point(mesh, sample), 1, 0)
            t_tri /= 1000
        except ImportError:
            t_tri = float("nan")
        for count in (10_000, 100_000):
            p = near_surface(igl_body, count, rng)
            t_igl = median_seconds(lambda: igl_body.query(p), repeat)
            t_np = median_seconds(lambda: numpy_body.query(p), max(1, repeat // 2))
            assert np.allclose(igl_body.query(p)[0], numpy_body.query(p)[0], atol=1e-12)
            rows.append(
                [
                    f"{len(faces):,}",
                    f"{count:,}",
                    f"{t_igl:.3f} ({1e6 * t_igl / count:.1f} us/pt)",
                    f"{t_np:.3f} ({1e6 * t_np / count:.1f} us/pt, {t_np / t_igl:.0f}x)",
                    f"{1e6 * t_tri:.0f} us/pt ({1e6 * t_tri / (1e6 * t_igl / count):.0f}x)",
                ]
            )
            print(rows[-1], flush=True)
    return rows


def predeform_rows(repeat: int) -> list[list[str]]:
    rows = []
    for n, m in ((96, 48), (384, 192)):
        case = {
            "material": "powernet",
            "body": {"torso": {"size": "M"}},
            "garment": {"bottom": 0.86, "top": 1.22, "reduction": 0.15, "grid": [n, m]},
        }
        t = median_seconds(lambda: initial_state(case), repeat)
        rows.append([f"{n} x {m}", f"{n * m:,}", f"{t:.2f}"])
        print(rows[-1], flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    machine = f"{platform.machine()}, {os.cpu_count()} cores"
    prox = markdown_table(
        ["faces", "points", "libigl [s]", "numpy/scipy [s] (vs libigl)", "trimesh (vs libigl)"],
        proximity_rows(args.repeat),
    )
    pre = markdown_table(["grid", "nodes", "predeform [s]"], predeform_rows(args.repeat))
    head = f"Medians of {args.repeat} runs on {machine}."
    print(prox, pre, sep="\n\n")
    if not args.no_write:
        replace_section("proximity", f"{head} Points within 5 mm of the torso surface.\n\n{prox}")
        replace_section(
            "predeform",
            f"{head} Parametric torso M (31k faces), reduction 0.15, material ingested from the "
            f"lab table each time (~0.5 s of it).\n\n{pre}",
        )


if __name__ == "__main__":
    main()
