"""Time nodal forces and the stiffness refill at 10k, 40k and 160k nodes (medians).

Compares, in one run, the library's sparse-incidence force product against an np.bincount
scatter, and the in-place stiffness refill against a fresh COO -> CSR assembly; writes the table
into docs/performance.md (section ``mechanics``). Run: ``make bench`` or

    .venv/bin/python benchmarks/bench_mechanics.py [--sizes 100x100 200x200 400x400]
"""

from __future__ import annotations

import argparse
import os
import platform

import numpy as np
import scipy.sparse as sp
from _table import markdown_table, median_seconds, replace_section

from cloth.garment.grid import build_grid
from cloth.garment.mechanics import forces, spring_forces, spring_state, stiffness
from cloth.materials.curves import Fabric, StressStrainCurve


def fabric() -> Fabric:
    curve = StressStrainCurve([0.0, 0.2, 0.5, 1.0], [0.0, 1e5, 5e5, 2e6])
    return Fabric("bench", curve, curve, thickness=5e-4)


def forces_bincount(x, grid):
    state = spring_state(x, grid)
    f = spring_forces(state, grid)
    a, b = grid.ends[:, 0], grid.ends[:, 1]
    out = np.empty_like(x)
    for c in range(3):
        out[:, c] = np.bincount(a, f[:, c], minlength=grid.n_nodes) - np.bincount(
            b, f[:, c], minlength=grid.n_nodes
        )
    return out


def stiffness_coo(x, grid):
    state = spring_state(x, grid)
    d = state.direction
    axial = grid.area * state.tangent / grid.rest_length
    lateral = grid.area * state.stress / state.length
    blocks = (axial - lateral)[:, None, None] * d[:, :, None] * d[:, None, :]
    blocks[:, [0, 1, 2], [0, 1, 2]] += lateral[:, None]
    a, b = grid.ends[:, 0], grid.ends[:, 1]
    p, q = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
    rows, cols, vals = [], [], []
    for r, c, s in ((a, a, 1), (b, b, 1), (a, b, -1), (b, a, -1)):
        rows.append((3 * r[:, None, None] + p).ravel())
        cols.append((3 * c[:, None, None] + q).ravel())
        vals.append(s * blocks.ravel())
    n = 3 * grid.n_nodes
    return sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()


def measure(grid, repeat: int, label: str) -> list[str]:
    """One table row: medians of the force and stiffness kernels on ``grid``."""
    rng = np.random.default_rng(0)
    u, v = grid.rest_uv.T
    x = np.stack([1.3 * u, 1.2 * v, np.zeros_like(u)], axis=1)
    x += rng.normal(scale=1e-4, size=(grid.n_nodes, 3))
    stiffness(x, grid)  # builds the pattern once (not timed)
    np.testing.assert_allclose(forces(x, grid), forces_bincount(x, grid), atol=1e-9)
    t_forces = median_seconds(lambda: forces(x, grid), repeat)
    t_bincount = median_seconds(lambda: forces_bincount(x, grid), repeat)
    t_refill = median_seconds(lambda: stiffness(x, grid, project=True), repeat)
    t_coo = median_seconds(lambda: stiffness_coo(x, grid), max(3, repeat // 2))
    return [
        f"{grid.n_nodes:,}{label}",
        f"{grid.n_springs:,}",
        f"{1e3 * t_forces:.1f}",
        f"{1e3 * t_bincount:.1f} ({t_bincount / t_forces:.2f}x)",
        f"{1e3 * t_refill:.1f}",
        f"{1e3 * t_coo:.1f} ({t_coo / t_refill:.2f}x)",
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--sizes",
        nargs="+",
        default=["100x100", "200x200", "400x400", "400x400+sb"],
        help="NxM grids; a '+sb' suffix adds shear and bend springs",
    )
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args()
    rows = []
    for size in args.sizes:
        shape, _, extra = size.partition("+")
        n, m = (int(v) for v in shape.split("x"))
        moduli = {"shear_modulus": 1e4, "bend_modulus": 1e3} if extra == "sb" else {}
        grid = build_grid(n, m, 1.0, np.linspace(0, 1.0, m), fabric(), closed=True, **moduli)
        rows.append(measure(grid, args.repeat, " (+shear, bend)" if extra else ""))
        print(rows[-1], flush=True)
    table = markdown_table(
        [
            "nodes",
            "springs",
            "forces: incidence product [ms]",
            "forces: bincount [ms] (ratio)",
            "stiffness refill [ms]",
            "stiffness COO->CSR [ms] (ratio)",
        ],
        rows,
    )
    machine = f"{platform.machine()}, {os.cpu_count()} cores, numpy {np.__version__}"
    body = (
        f"Medians of {args.repeat} runs on {machine}; tube grids, the paper's weft and warp "
        f"springs unless marked.\n\n{table}"
    )
    print(body)
    if not args.no_write:
        replace_section("mechanics", body)


if __name__ == "__main__":
    main()
