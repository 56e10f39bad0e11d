"""Tables of docs/validation.md for mesh bodies: the torso's own mesh against the smooth torso.

1. ``scan_refinement``: the parametric torso M written as a triangle mesh at several
   resolutions (around x rings) and read back as a ``mesh:`` body, contacted through its fitted
   smooth surface (the default), against the smooth parametric torso itself: iterations, the
   final residual and the girth-line mean pressures.
2. ``scan_smoothing``: one mesh (128 x 120) at several smoothing widths sigma: girth-line means,
   the peak pressure, and how far the garment enters the original mesh (the smoothed surface
   lies up to a few tenths of a millimetre inside or outside it).
3. ``scan_profile`` (``--profile 32x30``, with ``--grid 384x192``): how sharply the smooth
   torso's own row-mean pressure changes around each girth line, against one mesh's ring
   spacing there: the range of the smooth torso's row means within half a ring spacing of the
   line, beside the mesh's value on the line. A mesh cannot be expected to match the line
   closer than that range: its rings sample the body no finer.

Garment: power net, 15 % reduction, 0.80-1.25 m (every girth line inside it, none on an edge
row), sliding edges, Newton to 1e-8 (at most 150 iterations). Run (several minutes; one
relaxation per row):

    .venv/bin/python benchmarks/validation_scans.py [--grid 96x48] [--meshes 32x30 64x60 128x120]
        [--smoothing 0.004 0.006 0.010] [--profile 32x30 [--grid 384x192]]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from _table import markdown_table, replace_section

from cloth.bodies.torso import LANDMARKS, chart_size, torso_mesh
from cloth.files.body import body_from_config
from cloth.results.fields import node_fields
from cloth.results.landmarks import landmarks
from cloth.results.pressure import MMHG
from cloth.solvers import Settings, relax
from cloth.stages.case import initial_state

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
    case = {
        "material": "powernet",
        "body": body,
        "landmarks": heights,
        "garment": {**GARMENT, "grid": list(grid)},
    }
    start = time.perf_counter()
    state = initial_state(case)
    solid, _ = body_from_config(state.case.body.block)
    settings = Settings(tolerance=1e-8, max_iterations=150, progress=False, log_every=0)
    result = relax(state, solid, settings)
    ev = result.final
    fields = node_fields(
        state.grid,
        ev.x,
        ev.springs,
        state.fabric.thickness,
        ev.forces,
        ev.unbalanced,
        ev.on_body,
        ev.normal,
    )
    marks = {m.name: m.mean for m in landmarks(heights, ev.x, fields, state.grid)}
    out = {
        "iterations": result.iterations,
        "converged": result.converged,
        "residual": result.history.residual[-1],
        "seconds": time.perf_counter() - start,
        "marks": marks,
        "peak": float(fields.pressure.max()),
        "surface": state.body.get("surface", {}),
        # (m,) mean height (m) and mean pressure (Pa) of every grid row
        "rows": (
            ev.x[:, 2].reshape(grid[1], grid[0]).mean(axis=1),
            fields.pressure.reshape(grid[1], grid[0]).mean(axis=1),
        ),
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
    parser.add_argument("--profile", help="only the scan_profile table, of this mesh (32x30)")
    args = parser.parse_args()
    grid = tuple(int(v) for v in args.grid.split("x"))
    folder = Path(tempfile.mkdtemp(prefix="cloth-scans-"))
    os.environ.setdefault("CLOTH_CACHE_DIR", str(folder / "cache"))
    chart = chart_size("M")
    reference = run({"torso": {"size": "M"}}, grid)
    if args.profile:
        profile_table(args.profile, grid, reference, folder)
        return
    header = [
        "body",
        "refined",
        "sigma [mm]",
        "iterations",
        "residual",
        *(f"{n} [mmHg]" for n in LANDMARKS),
    ]
    rows = [
        [
            "smooth parametric torso",
            "-",
            "-",
            str(reference["iterations"]),
            f"{reference['residual']:.1e}",
            *pressures(reference["marks"]),
        ]
    ]
    for spec in args.meshes:
        around, rings = (int(v) for v in spec.split("x"))
        path = write_obj(folder / f"torso_{spec}.obj", *torso_mesh(chart, around, rings))
        got = run({"mesh": str(path)}, grid)
        rows.append(
            [
                f"its mesh, {around} around x {rings} rings",
                str(got["surface"].get("refine_levels", 0)),
                f"{got['surface']['smoothing_m'] * 1e3:.3g}",
                str(got["iterations"]) + ("" if got["converged"] else " (not converged)"),
                f"{got['residual']:.1e}",
                *pressures(got["marks"], reference["marks"]),
            ]
        )
        print(rows[-1], flush=True)
    replace_section("scan_refinement", markdown_table(header, rows), DOC)

    from cloth.bodies.mesh import MeshBody

    vertices, faces = torso_mesh(chart, 128, 120)
    path = write_obj(folder / "torso_smoothing.obj", vertices, faces)
    mesh = MeshBody(vertices, faces)
    header = [
        "sigma [mm]",
        "vertices off the surface, max / RMS [mm]",
        "iterations",
        *(f"{n} [mmHg]" for n in LANDMARKS),
        "peak [mmHg]",
        "enters the mesh [mm]",
    ]
    rows = [
        [
            "smooth torso",
            "-",
            str(reference["iterations"]),
            *pressures(reference["marks"]),
            f"{reference['peak'] / MMHG:.1f}",
            "-",
        ]
    ]
    for sigma in args.smoothing:
        got = run({"mesh": str(path), "smoothing": sigma}, grid, mesh)
        s = got["surface"]
        rows.append(
            [
                f"{sigma * 1e3:.3g}",
                f"{s['deviation_max_m'] * 1e3:.2f} / {s['deviation_rms_m'] * 1e3:.2f}",
                str(got["iterations"]) + ("" if got["converged"] else " (not converged)"),
                *pressures(got["marks"], reference["marks"]),
                f"{got['peak'] / MMHG:.1f}",
                f"{got['enters'] * 1e3:.2f}",
            ]
        )
        print(rows[-1], flush=True)
    replace_section("scan_smoothing", markdown_table(header, rows), DOC)


def profile_table(spec: str, grid: tuple[int, int], reference: dict, folder: Path) -> None:
    """The ``scan_profile`` table (module docstring, 3.)."""
    chart = chart_size("M")
    around, rings = (int(v) for v in spec.split("x"))
    vertices, faces = torso_mesh(chart, around, rings)
    got = run({"mesh": str(write_obj(folder / f"torso_{spec}.obj", vertices, faces))}, grid)
    ring_z = np.unique(np.round(vertices[:, 2], 9))
    z, smooth = reference["rows"]
    header = [
        "girth line",
        "mesh ring spacing [mm]",
        "smooth torso [mmHg]",
        "smooth torso within half a ring spacing [%]",
        f"mesh {spec} [mmHg]",
        f"mesh {spec}, within half a ring spacing [%]",
    ]
    rows = []
    for name in LANDMARKS:
        height = chart.height[name]
        at = int(np.argmin(np.abs(ring_z - height)))
        spacing = float(np.diff(ring_z[max(at - 1, 0) : at + 2]).mean())
        band = np.abs(z - height) <= spacing / 2
        line = reference["marks"][name]
        mesh_z, mesh_p = got["rows"]
        mesh_band = np.abs(mesh_z - height) <= spacing / 2
        rows.append(
            [
                name,
                f"{spacing * 1e3:.1f}",
                f"{line / MMHG:.2f}",
                _spread(smooth[band], line),
                f"{got['marks'][name] / MMHG:.2f} ({100 * (got['marks'][name] / line - 1):+.1f} %)",
                _spread(mesh_p[mesh_band], line),
            ]
        )
        print(rows[-1], flush=True)
    surface = got["surface"]
    note = (
        f"Garment grid {grid[0]} x {grid[1]}; the mesh {around} around x {rings} rings "
        f"(refined {surface.get('refine_levels', 0)} times, sigma "
        f"{surface['smoothing_m'] * 1e3:.3g} mm), {got['iterations']} iterations."
        "\n\n"
    )
    replace_section("scan_profile", note + markdown_table(header, rows), DOC)


def _spread(values: np.ndarray, line: float) -> str:
    """The range of row means ``values`` (Pa) against the line's ``line`` (Pa), in %."""
    return f"{100 * (values.min() / line - 1):+.1f} .. {100 * (values.max() / line - 1):+.1f}"


if __name__ == "__main__":
    main()
