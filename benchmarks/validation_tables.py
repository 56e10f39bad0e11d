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

from cloth.bodies import EllipticCylinder
from cloth.files.body import body_from_config
from cloth.garment.grid import node_area
from cloth.results.pressure import MMHG, contact_reaction
from cloth.solvers import Settings, relax
from cloth.stages.case import initial_state

DOC = Path(__file__).resolve().parents[1] / "docs" / "validation.md"


def solve(body: dict, reduction: float, n: int, around: str = "weft"):
    case = {
        "material": "powernet",
        "body": body,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": reduction,
            "grid": [n, 6],
            "edges": "sliding",
            "around": around,
        },
    }
    state = initial_state(case)
    solid, _ = body_from_config(state.case.body.block)
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
            grid = state.grid
            rest = grid.rest_length[grid.family_slices[0]]
            chord = 2 * radius * np.sin(np.pi / grid.n) / rest - 1
            reference = state.fabric.weft.stress(chord) * state.fabric.thickness / radius
            chord_error = np.max(np.abs(p / reference - 1))
            rows.append(
                [
                    f"{radius:.2f}",
                    f"{reduction:.1f}",
                    f"{expected:.1f}",
                    f"{expected / MMHG:.2f}",
                    f"{p.mean():.1f}",
                    f"{100 * error:.3f}",
                    f"{chord_error:.1e}",
                    f"{100 * spread:.2e}",
                    f"{result.history.residual[-1]:.1e}",
                ]
            )
    laplace = markdown_table(
        [
            "radius [m]",
            "reduction",
            "T/r [Pa]",
            "T/r [mmHg]",
            "mean pressure [Pa]",
            "max error vs arc [%]",
            "max error vs chord [1]",
            "tension spread [%]",
            "residual",
        ],
        rows,
    )
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
        [
            [
                "128 x 6",
                f"{100 * (t.max() / t.min() - 1):.3f}",
                f"{100 * err.max():.3f}",
                f"{100 * err.mean():.3f}",
            ]
        ],
    )
    cone = cone_table()
    replace_section("cone", cone, DOC)
    replace_section("laplace", laplace, DOC)
    replace_section("orthotropy", ortho, DOC)
    replace_section("ellipse", ell, DOC)
    print(laplace, ortho, ell, sep="\n\n")


def cone_table() -> str:
    """Cone r 0.15 -> 0.07 m over 0.3 m, sliding edges, 64 x 8, 15 % reduction; a cylinder with
    the warp stretched too: the Laplace diagnostic and the edge rows' shares."""
    import tempfile

    from cloth.files.relaxed import relaxed_dataset
    from cloth.io import write_netcdf
    from cloth.stages.results import aggregate

    rows = []
    folder = Path(tempfile.mkdtemp(prefix="cloth-validation-"))
    for body, name in (
        ({"cone": {"radius_bottom": 0.15, "radius_top": 0.07, "top": 0.3}}, "cone"),
        ({"cylinder": {"radius": 0.1, "top": 0.5}}, "cylinder"),
    ):
        for lengthwise in (0.0, 0.1):
            bottom, top = (0.05, 0.25) if name == "cone" else (0.1, 0.4)
            case = {
                "material": "powernet",
                "body": body,
                "garment": {
                    "bottom": bottom,
                    "top": top,
                    "reduction": 0.15,
                    "grid": [64, 8],
                    "edges": "sliding",
                    "lengthwise_reduction": lengthwise,
                },
            }
            state = initial_state(case)
            solid, _ = body_from_config(state.case.body.block)
            settings = Settings(tolerance=1e-10, max_iterations=60, progress=False)
            result = relax(state, solid, settings)
            ds = relaxed_dataset(state, result, settings)
            out, _ = aggregate(write_netcdf(ds, folder / f"{name}{lengthwise}.nc"))
            p = out["pressure"].values
            inner = out["contact"].values[1:-1].astype(bool)
            ratio = out["p_laplace"].values[1:-1][inner] / p[1:-1][inner]
            ev = result.final
            push = -np.einsum("ij,ij->i", ev.forces, ev.normal)  # -R . n
            edges = np.concatenate([np.arange(64), np.arange(7 * 64, 8 * 64)])
            held = out["contact"].values.ravel()[edges].astype(bool)
            lam = (p.ravel() * out["node_area"].values.ravel())[edges][held]
            rows.append(
                [
                    name,
                    f"{lengthwise:.1f}",
                    f"{ratio.min():.4f}-{ratio.max():.4f}",
                    f"{100 * np.max(np.abs(push[edges][held] / lam - 1)):.1f}",
                    f"{held.sum()} of {edges.size}",
                    f"{np.abs(out['edge_support_force'].values).max():.3g}",
                ]
            )
    return markdown_table(
        [
            "body",
            "lengthwise reduction",
            "p_laplace / pressure (interior contact)",
            "-R.n vs lambda at edge nodes, max [%]",
            "edge nodes on the body",
            "max edge support force [N]",
        ],
        rows,
    )


if __name__ == "__main__":
    main()
