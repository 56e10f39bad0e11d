"""Guardrails before long work: estimate a case's peak memory and time from its counts, before
anything is allocated, and refuse in one line a case that would not fit in the machine's free
memory (``--force``, or ``CLOTH_FORCE=1`` in the environment, runs it anyway).

The estimate is `cloth.pipeline.resources`' per-stage model, measured as its own process (docs/
performance.md, "What a job asks for"), without its cluster margin, for relax and aggregate
the Cholesky backend's where relax will take it (`takes_cholesky`: about half an LU's memory):

    memory = base + per_node x N + BYTES_PER_FACE x F       (N garment nodes, F mesh faces)
    time   = reference x (N / reference_nodes)^p

A mesh's face count is read from its header (PLY, binary STL) or, for other formats, bounded
from the file's size (`BYTES_PER_FACE_ON_DISK`), so even a huge file costs nothing to check.
Free memory is the kernel's MemAvailable, or the cgroup's limit less its use where that is
smaller (a SLURM job's allocation).
"""

from __future__ import annotations

import logging
import os
import re
from dataclasses import dataclass
from pathlib import Path

from cloth.case import Case
from cloth.errors import InputError
from cloth.io import resolve
from cloth.pipeline.resources import REFERENCE_NODES, stage_model
from cloth.solvers.linear import SPD, choose

log = logging.getLogger(__name__)

#: Peak bytes per mesh face while a stage holds a mesh body: 560 B measured loading a 1.3M-face
#: mesh (vertices, faces, trimesh's checks), twice that for the sections and proximity.
BYTES_PER_FACE = 1100
#: The fewest bytes a face takes in a mesh file without a face count in its header (an OBJ
#: face line and its share of the vertex lines), so that size / this bounds the faces.
BYTES_PER_FACE_ON_DISK = 24
#: The environment variable that has the same effect as ``--force``.
FORCE_VARIABLE = "CLOTH_FORCE"


@dataclass(frozen=True)
class Estimate:
    """A stage's estimated peak memory (``memory_mb``, MB) and wall time (``seconds``, s)."""

    stage: str
    nodes: int
    faces: int
    memory_mb: float
    seconds: float


def estimate(stage: str, nodes: int, faces: int = 0, cholesky: bool = False) -> Estimate:
    """The estimate of ``stage`` (predeform, relax, aggregate, figures) for a garment of
    ``nodes`` nodes on a body of ``faces`` mesh faces (0: a closed-form body or the torso),
    relaxed by Cholesky where ``cholesky`` (`takes_cholesky`), else by LU."""
    base, per_node, seconds, power = stage_model(stage, cholesky)
    memory = base + per_node * nodes + BYTES_PER_FACE * faces / 1e6
    return Estimate(stage, nodes, faces, memory, seconds * (nodes / REFERENCE_NODES) ** power)


def mesh_faces(path: str | Path) -> int:
    """The number of faces of a mesh file, from its header (PLY, binary STL), else an upper
    bound from its size; 0 when the file is missing (the body's own check reports that)."""
    path = Path(path)
    if not path.is_file():
        return 0
    size = path.stat().st_size
    with open(path, "rb") as handle:
        head = handle.read(4096)
    if head.startswith(b"ply"):
        found = re.search(rb"element\s+face\s+(\d+)", head)
        if found:
            return int(found[1])
    if path.suffix.lower() == ".stl" and not head[:5].lower() == b"solid" and size >= 84:
        return int.from_bytes(head[80:84], "little")
    return size // BYTES_PER_FACE_ON_DISK


def free_memory_mb() -> float | None:
    """Memory this process can still take, MB: MemAvailable, or the cgroup's limit less its
    use where smaller; None where neither can be read (then nothing is refused)."""
    free = None
    try:
        text = Path("/proc/meminfo").read_text()
        found = re.search(r"MemAvailable:\s+(\d+) kB", text)
        free = int(found[1]) * 1024 / 1e6 if found else None
    except OSError:
        pass
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        used = int(Path("/sys/fs/cgroup/memory.current").read_text())
        if limit != "max":
            room = (int(limit) - used) / 1e6
            free = room if free is None else min(free, room)
    except (OSError, ValueError):
        pass
    return free


def case_counts(case: Case, base_dir: str | Path = ".") -> tuple[int, int]:
    """(garment nodes, body mesh faces) of a case."""
    mesh = case.body.option("mesh")
    faces = mesh_faces(resolve(mesh, base_dir)) if mesh is not None else 0
    return case.garment.nodes, faces


def takes_cholesky(case: Case, base_dir: str | Path = ".") -> bool:
    """Whether relax will factorise ``case``'s Newton systems by Cholesky: the backend
    `cloth.solvers.linear.choose` takes for it is one of `cloth.solvers.linear.SPD`, with the
    case positive definite by construction as `cloth.solvers.relax.positive_definite` has it
    (read here from the case: every curve of its fabric tension-only, no shear or bending
    springs, no skin model). False where its material cannot be read, or its backend is not
    installed (predeform and relax say why)."""
    solver = case.solver
    if solver.method == "explicit":
        return False
    garment = case.garment
    springs = garment.shear_modulus is None and garment.bend_modulus is None
    convex = springs and not case.skin.present
    if convex:
        from cloth.files.material import load_fabric  # xarray, only where relax is estimated

        try:
            convex = load_fabric(case.material, base_dir).tension_only
        except (InputError, OSError):
            return False
    try:
        return choose(solver.linear_solver, convex) in SPD
    except InputError:
        return False


def check_fits(
    stages: tuple[str, ...],
    nodes: int,
    faces: int,
    source: str | Path,
    force: bool = False,
    cholesky: bool = False,
) -> list[Estimate]:
    """Estimate ``stages`` (relaxed by Cholesky where ``cholesky``) and log them; raise
    `InputError` (one line: the estimate, the free memory, the fixes) when the largest exceeds
    the free memory, unless ``force`` or the environment's `FORCE_VARIABLE` is set."""
    estimates = [estimate(stage, nodes, faces, cholesky) for stage in stages]
    worst = max(estimates, key=lambda e: e.memory_mb)
    log.info(
        "estimated: %s nodes%s, peak memory %.0f MB (%s), time %s",
        f"{nodes:,}",
        f" on {faces:,} mesh faces" if faces else "",
        worst.memory_mb,
        worst.stage,
        ", ".join(f"{e.stage} {_duration(e.seconds)}" for e in estimates),
    )
    free = free_memory_mb()
    if free is None or worst.memory_mb <= free:
        return estimates
    if force or os.environ.get(FORCE_VARIABLE, "") not in ("", "0"):
        log.warning("%.0f MB estimated, %.0f MB free: going on as forced", worst.memory_mb, free)
        return estimates
    what = f"{nodes:,} garment nodes" + (f" on a mesh of {faces:,} faces" if faces else "")
    mesh_heavy = BYTES_PER_FACE * faces / 1e6 > worst.memory_mb / 2
    raise InputError(
        f"{what} need an estimated {worst.memory_mb:,.0f} MB in {worst.stage} (and about "
        f"{_duration(worst.seconds)}), but {free:,.0f} MB are free; use a coarser garment.grid "
        f"or a decimated mesh, or --force (or {FORCE_VARIABLE}=1) to run anyway",
        source,
        "body.mesh" if mesh_heavy else "garment.grid",
    )


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.0f} h"
    return f"{seconds / 86400:.2g} days"
