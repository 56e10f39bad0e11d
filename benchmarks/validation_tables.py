"""Regenerate the tables of docs/validation.md from the solver (the same cases the tests check).

Laplace's law on circular cylinders (radius x reduction), orthotropy (warp around), and the
elliptic cylinder (pressure against T kappa). Run (about a minute):

    .venv/bin/python benchmarks/validation_tables.py

The tables are written between the markers of docs/validation.md.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from _table import markdown_table, replace_section

from cloth.aggregate import MMHG
from cloth.bodies import EllipticCylinder, body_from_config
from cloth.predeform import predeform
from cloth.pressure import contact_reaction, node_area
from cloth.solvers import Settings, relax

DOC = Path(__file__).resolve().parents[1] / "docs" / "validation.md"


def solve(body: dict, reduction: float, n: int, around: str = "weft"):
    case = {
        "material": "powernet", "body": body,
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": reduction, "grid": [n, 6],
                    "edges": "sliding", "around": around},
    }  # fmt: skip
    state = predeform(case)
    solid, _ = body_from_config(state.case["body"])
    result = relax(state, solid, Settings(tolerance=1e-10, max_iterations=60, progress=False))
    ev = result.final
    reaction = contact_reaction(ev.forces, ev.unbalanced, ev.on_body)
    pressure = np.linalg.norm(reaction, axis=1) / node_area(ev.x, state.grid)
    weft = state.grid.family_slices[0]
    tension = np.abs(ev.springs.stress[weft]) * state.fabric.thickness
    return state, result, pressure, tension


def main() -> None:
    rows = []
    for radius in (0.05, 0.10, 0.15):
        for reduction in (0.1, 0.2, 0.3):
            state, result, p, t = solve({"cylinder": {"radius": radius, "top": 0.5}}, reduction, 64)
            eps = 1 / (1 - reduction) - 1
            expected = float(state.fabric.weft.stress(eps)) * state.fabric.thickness / radius
            error = np.max(np.abs(p / expected - 1))
            spread = t.max() / t.min() - 1
            rows.append([f"{radius:.2f}", f"{reduction:.1f}", f"{expected:.1f}",
                         f"{expected / MMHG:.2f}", f"{p.mean():.1f}", f"{100 * error:.3f}",
                         f"{100 * spread:.2e}", f"{result.history.residual[-1]:.1e}"])  # fmt: skip
    laplace = markdown_table(
        ["radius [m]", "reduction", "T/r [Pa]", "T/r [mmHg]", "mean pressure [Pa]",
         "max error [%]", "tension spread [%]", "residual"],
        rows,
    )  # fmt: skip
    weft = solve({"cylinder": {"radius": 0.1, "top": 0.5}}, 0.2, 64)
    warp = solve({"cylinder": {"radius": 0.1, "top": 0.5}}, 0.2, 64, around="warp")
    eps = 1 / 0.8 - 1
    ratio = float(weft[0].fabric.warp.stress(eps) / weft[0].fabric.weft.stress(eps))
    measured = warp[2].mean() / weft[2].mean()
    ortho = markdown_table(
        ["sigma_warp/sigma_weft at eps", "pressure ratio warp/weft around", "error [%]"],
        [[f"{ratio:.5f}", f"{measured:.5f}", f"{100 * abs(measured / ratio - 1):.3f}"]],
    )
    state, result, p, t = solve({"elliptic_cylinder": {"a": 0.15, "b": 0.10, "top": 0.5}}, 0.2, 128)
    ellipse = EllipticCylinder(0.15, 0.10)
    kappa = ellipse.curvature(result.final.closest[:, :2])
    t_ring = t.reshape(6, 128)
    t_node = (0.5 * (t_ring + np.roll(t_ring, 1, axis=1))).ravel()
    err = np.abs(p / (t_node * kappa) - 1)
    ell = markdown_table(
        ["grid", "tension spread [%]", "pressure vs T kappa: max error [%]", "mean error [%]"],
        [["128 x 6", f"{100 * (t.max() / t.min() - 1):.3f}", f"{100 * err.max():.3f}",
          f"{100 * err.mean():.3f}"]],
    )  # fmt: skip
    replace_section("laplace", laplace, DOC)
    replace_section("orthotropy", ortho, DOC)
    replace_section("ellipse", ell, DOC)
    print(laplace, ortho, ell, sep="\n\n")


if __name__ == "__main__":
    main()
