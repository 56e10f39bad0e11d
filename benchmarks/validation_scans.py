"""Tables of docs/validation.md for mesh bodies: the torso's own mesh against the smooth torso.

1. ``scan_refinement``: the parametric torso M written as a triangle mesh at several
   resolutions (around x rings) and read back as a ``mesh:`` body, contacted through its fitted
   smooth surface (the default), against the smooth parametric torso itself: iterations, the
   final residual and the girth-line mean pressures.
2. ``scan_smoothing``: one mesh (128 x 120) at several smoothing widths sigma: girth-line means,
   the peak pressure, and how far the garment enters the original mesh (the smoothed surface
   lies up to a few tenths of a millimetre inside or outside it).

Garment: power net, 15 % reduction, 0.80-1.25 m (every girth line inside it, none on an edge
row), sliding edges, Newton to 1e-8 (at most 150 iterations). Run (several minutes; one
relaxation per row):

    .venv/bin/python benchmarks/validation_scans.py [--grid 96x48] [--meshes 32x30 64x60 128x120]
        [--smoothing 0.004 0.006 0.010]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from _table import markdown_table, replace_section

from cloth.aggregate import node_fields
from cloth.bodies import body_from_config
from cloth.bodies.torso import LANDMARKS, chart_size, torso_mesh
from cloth.landmarks import landmarks
from cloth.predeform import predeform
from cloth.pressure import MMHG
from cloth.solvers import Settings, relax

DOC = Path(__file__).resolve().parents[1] / "docs" / "validation.md"
GARMENT = {"bottom": 0.80, "top": 1.25, "reduction": 0.15, "edges": "sliding"}


def write_obj(path: Path, vertices: np.ndarray, faces: np.ndarray) -> Path:
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def run(body: dict, grid: tuple[int, int], mesh=None) -> dict:
    chart = chart_size("M")
    heights = {name: chart.height[name] for name in LANDMARKS}
    case = {"material": "powernet", "body": body, "landmarks": heights,
            "garment": {**GARMENT, "grid": list(grid)}}  # fmt: skip
    start = time.perf_counter()
    state = predeform(case)
    solid, _ = body_from_config(state.case["body"])
    settings = Settings(tolerance=1e-8, max_iterations=150, progress=False, log_every=0)
    result = relax(state, solid, settings)
    ev = result.final
    fields = node_fields(
        state.grid, ev.x, ev.springs, state.fabric.thickness, ev.forces, ev.unbalanced,
        ev.on_body, ev.normal,
    )  # fmt: skip
    marks = {m.name: m.mean for m in landmarks(heights, ev.x, fields, state.grid)}
    out = {
        "iterations": result.iterations,
        "converged": result.converged,
        "residual": result.history.residual[-1],
        "seconds": time.perf_counter() - start,
        "marks": marks,
        "peak": float(fields.pressure.max()),
        "surface": state.body.get("surface", {}),
    }
    if mesh is not None:  # how far the garment lies inside the original mesh
        out["enters"] = float(max(0.0, -mesh.query(ev.x)[0].min()))
    return out


def pressures(marks: dict, reference: dict | None = None) -> list[str]:
    cells = []
    for name in LANDMARKS:
        value = marks[name] / MMHG
        cell = f"{value:.2f}"
        if reference is not None:
            cell += f" ({100 * (marks[name] / reference[name] - 1):+.1f} %)"
        cells.append(cell)
    return cells


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", default="96x48")
    parser.add_argument("--meshes", nargs="*", default=["32x30", "64x60", "128x120"])
    parser.add_argument("--smoothing", nargs="*", type=float, default=[0.004, 0.006, 0.010])
    args = parser.parse_args()
    grid = tuple(int(v) for v in args.grid.split("x"))
    folder = Path(tempfile.mkdtemp(prefix="cloth-scans-"))
    os.environ.setdefault("CLOTH_CACHE_DIR", str(folder / "cache"))
    chart = chart_size("M")
    reference = run({"torso": {"size": "M"}}, grid)
    header = ["body", "refined", "sigma [mm]", "iterations", "residual",
              *(f"{n} [mmHg]" for n in LANDMARKS)]  # fmt: skip
    rows = [["smooth parametric torso", "-", "-", str(reference["iterations"]),
             f"{reference['residual']:.1e}", *pressures(reference["marks"])]]  # fmt: skip
    for spec in args.meshes:
        around, rings = (int(v) for v in spec.split("x"))
        path = write_obj(folder / f"torso_{spec}.obj", *torso_mesh(chart, around, rings))
        got = run({"mesh": str(path)}, grid)
        rows.append([
            f"its mesh, {around} around x {rings} rings",
            str(got["surface"].get("refine_levels", 0)),
            f"{got['surface']['smoothing_m'] * 1e3:.3g}",
            str(got["iterations"]) + ("" if got["converged"] else " (not converged)"),
            f"{got['residual']:.1e}", *pressures(got["marks"], reference["marks"]),
        ])  # fmt: skip
        print(rows[-1], flush=True)
    replace_section("scan_refinement", markdown_table(header, rows), DOC)

    from cloth.bodies.mesh import MeshBody

    vertices, faces = torso_mesh(chart, 128, 120)
    path = write_obj(folder / "torso_smoothing.obj", vertices, faces)
    mesh = MeshBody(vertices, faces)
    header = ["sigma [mm]", "vertices off the surface, max / RMS [mm]", "iterations",
              *(f"{n} [mmHg]" for n in LANDMARKS), "peak [mmHg]",
              "enters the mesh [mm]"]  # fmt: skip
    rows = [["smooth torso", "-", str(reference["iterations"]), *pressures(reference["marks"]),
             f"{reference['peak'] / MMHG:.1f}", "-"]]  # fmt: skip
    for sigma in args.smoothing:
        got = run({"mesh": str(path), "smoothing": sigma}, grid, mesh)
        s = got["surface"]
        rows.append([
            f"{sigma * 1e3:.3g}",
            f"{s['deviation_max_m'] * 1e3:.2f} / {s['deviation_rms_m'] * 1e3:.2f}",
            str(got["iterations"]) + ("" if got["converged"] else " (not converged)"),
            *pressures(got["marks"], reference["marks"]), f"{got['peak'] / MMHG:.1f}",
            f"{got['enters'] * 1e3:.2f}",
        ])  # fmt: skip
        print(rows[-1], flush=True)
    replace_section("scan_smoothing", markdown_table(header, rows), DOC)


if __name__ == "__main__":
    main()
