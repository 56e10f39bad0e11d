"""The figure of docs/bodies.md: pressure around a ring on a meshed cylinder, facets vs smooth.

A capped cylinder mesh of 64 segments (r = 0.1 m), the example power net cut 20 % small,
96 x 8 nodes, sliding edges, relaxed by Newton with ``surface: mesh`` (the facets) and with
``surface: smooth`` (the fitted surface, the default); the pressure of every node of a middle
row against its angle, with Laplace's T / r. Run:

    .venv/bin/python benchmarks/figure_mesh_pressure.py [-o docs/mesh_pressure.png]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from cloth.io import atomic_output
from cloth.results.pressure import MMHG
from tests.conftest import capped_cylinder, write_obj
from tests.test_relax import hoop_tension, pressure, solve, tube

RADIUS, SEGMENTS, N, M = 0.1, 64, 96, 8


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).resolve().parents[1] / "docs" / "mesh_pressure.png"
    parser.add_argument("-o", "--output", type=Path, default=default)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="cloth-figure-"))
    os.environ.setdefault("CLOTH_CACHE_DIR", str(folder / "cache"))
    path = write_obj(folder / "cylinder.obj", *capped_cylinder(RADIUS, 0.5, SEGMENTS))
    fig, ax = plt.subplots(figsize=(7.5, 3.8), layout="constrained")
    row = M // 2
    for surface, style in (("mesh", "o-"), ("smooth", "s-")):
        state = tube({"mesh": str(path), "surface": surface}, 0.2, n=N, m=M)
        result = solve(state, iterations=100)
        _, p = pressure(state, result)
        x = result.final.x.reshape(M, N, 3)[row]
        angle = np.degrees(np.arctan2(x[:, 1], x[:, 0])) % 360
        order = np.argsort(angle)
        ax.plot(
            angle[order],
            p.reshape(M, N)[row][order] / MMHG,
            style,
            ms=3,
            lw=0.8,
            label=f"surface: {surface}",
        )
        laplace = float(hoop_tension(state, result)[row].mean()) / RADIUS / MMHG
    ax.axhline(laplace, color="k", lw=0.8, ls="--", label="T / r (Laplace)")
    for k in range(SEGMENTS):  # the mesh's edges (vertices of the 64-gon)
        ax.axvline(360 * k / SEGMENTS, color="0.85", lw=0.5, zorder=0)
    ax.set_xlim(0, 90)
    ax.set_xlabel("angle around the cylinder [deg] (grey: the mesh's edges)")
    ax.set_ylabel("pressure [mmHg]")
    ax.set_title(
        f"{SEGMENTS}-segment cylinder mesh, r = {RADIUS} m, 20 % reduction, {N} nodes around"
    )
    ax.legend(fontsize=8, loc="upper right")
    with atomic_output(args.output) as tmp:
        fig.savefig(tmp, format="png", dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
