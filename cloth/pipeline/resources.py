"""What a case's jobs ask a cluster for: memory (MB) and wall time (minutes), from its grid.

Snakemake passes ``mem_mb`` and ``runtime`` to its executor (SLURM: ``--mem`` and ``--time``);
a job that asks too little is killed, one that asks too much waits longer in the queue. The
per-case stages (``predeform``, ``relax``, ``aggregate``, ``figures``) grow with the grid's N
nodes. Peak resident memory and wall time were measured per stage as its own process
(`benchmarks/bench_resources.py`, table in docs/performance.md); each job asks `MARGIN` times
the model:

    mem_mb  = base + per_node x N           (+ `MESH_MB` on a mesh body: its fitted surface's
                                              coefficients and the mesh)
    runtime = 1 minute + seconds(N) / 60,   seconds(N) = reference x (N / reference_nodes)^p

Measured: relax 247 / 398 / 1173 MiB at 1k / 18k / 74k nodes (195 MiB + 13.1 MiB per 1000
nodes; 2026-12-01); predeform 250-290 MiB at any grid. Relax's time grows as N^1.3 (the sparse
factorisations; 147 s at 73,728 nodes with SuperLU, docs/performance.md); aggregate factorises
Newton's matrix once to count the equilibrium's unstable modes (`cloth.solvers.stability`):
461 / 1,554 MiB and 1.6 / 5.5 s at 18k / 74k nodes; the other stages take a few seconds.
The fit of a mesh body's surface (rule ``body_surface``) is bounded by the fit's own cap on
grid samples (`cloth.bodies.surface.MAX_SAMPLES`: about 3 GiB).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cloth.case import Case

#: Measured value x MARGIN is asked.
MARGIN = 2.0
#: A mesh body's extra memory in the per-case stages, MB (its spline coefficients, float64).
MESH_MB = 1500
#: Per stage: base MB, MB per node, seconds at REFERENCE_NODES, exponent p (module docstring).
MODEL = {
    "predeform": (270.0, 0.002, 5.0, 1.0),
    "relax": (215.0, 0.014, 147.0, 1.3),
    "aggregate": (260.0, 0.019, 5.5, 1.3),
    "figures": (300.0, 0.004, 10.0, 1.0),
}
#: Relax and aggregate where relax factorises by Cholesky (cholespy, auto's choice for the
#: tension field; `cloth.pipeline.guard.takes_cholesky`): the factor is half an LU's, and the
#: stability count a Cholesky factor. Measured 2026-12-03 (bench_resources.py, auto on the
#: torso): relax 272 / 477 / 844 MiB, aggregate 269 / 272 / 622 MiB at 4.6k / 18k / 74k nodes,
#: relax 1,793 MiB at 205k (bench_spd.py); fitted 279 MiB + 7.81 MiB per 1000 nodes, in MB.
CHOLESKY_MODEL = {
    "relax": (293.0, 0.0082, 147.0, 1.3),
    "aggregate": (168.0, 0.0067, 5.5, 1.3),
}
#: The grid the stage times were measured at (384 x 192 nodes).
REFERENCE_NODES = 73_728
#: What the body-fitting rule asks: the fit's sample cap x 5 float64 arrays, and its time.
SURFACE_MB = 4000
SURFACE_MINUTES = 30


def stage_model(stage: str, cholesky: bool = False) -> tuple[float, float, float, float]:
    """``stage``'s (base MB, MB per node, seconds at REFERENCE_NODES, exponent): MODEL's, or
    where relax factorises by Cholesky (``cholesky``) CHOLESKY_MODEL's for relax and aggregate."""
    return CHOLESKY_MODEL.get(stage, MODEL[stage]) if cholesky else MODEL[stage]


@dataclass(frozen=True)
class Resources:
    """``mem_mb``: memory, MB; ``runtime``: wall time, minutes (Snakemake's resource names)."""

    mem_mb: int
    runtime: int


def stage_resources(stage: str, case: Case) -> Resources:
    """What one per-case ``stage`` of ``case`` (its garment's grid and its body) asks: the LU
    model (MODEL) whatever the backend, so that a job is never killed for a material that turns
    out compressible (the rules do not read materials)."""
    base, per_node, seconds, power = MODEL[stage]
    nodes = case.garment.nodes
    memory = base + per_node * nodes + (MESH_MB if case.body.kind == "mesh" else 0.0)
    minutes = 1.0 + seconds * (nodes / REFERENCE_NODES) ** power / 60.0
    return Resources(mem_mb=math.ceil(MARGIN * memory), runtime=math.ceil(MARGIN * minutes))


def surface_resources() -> Resources:
    """What fitting a mesh body's smooth surface asks (module docstring)."""
    return Resources(mem_mb=SURFACE_MB, runtime=SURFACE_MINUTES)


#: Runs ``cloth`` with the given arguments and prints the process's own peak memory (bytes) as
#: the last line of stderr: ``python -c PEAK_SCRIPT ARGS...`` (`measure_stage`).
PEAK_SCRIPT = (
    "import sys\n"
    "from cloth.cli import main\n"
    "from cloth.solvers.relax import peak_memory\n"
    "code = main(sys.argv[1:])\n"
    "print(f'peak_memory_bytes {peak_memory():.0f}', file=sys.stderr)\n"
    "sys.exit(code)\n"
)


def measure_stage(python: str, *args: str) -> tuple[float, float]:
    """(wall seconds, peak resident MiB) of ``cloth ARGS`` run by ``python`` as its own process
    (what a Snakemake job is); raises RuntimeError with the tail of its stderr if it fails."""
    import subprocess
    import time

    start = time.perf_counter()
    done = subprocess.run([python, "-c", PEAK_SCRIPT, *args], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"cloth {' '.join(args)} failed: {done.stderr[-1000:]}")
    last = done.stderr.strip().splitlines()[-1].split()
    return seconds, float(last[1]) / 2**20
