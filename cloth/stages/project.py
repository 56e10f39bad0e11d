"""Your own folder (issue 70, item 2): ``cloth init DIR`` writes a starter project that runs as
written with the installed package alone, and ``cloth pipeline`` runs the package's Snakemake
workflow (`cloth.shipped.workflow_dir`, the file the repository's Snakefile includes) from the
working folder, on its ``config.yaml``, its results landing there.

The starter (`STARTER`): ``config.yaml`` (a sweep of the example fabric on the parametric
torso M at two reductions, a small grid, and the design question at the waist), ``case.yaml``
(one case, for ``cloth run case.yaml -o out``) and ``powernet.csv`` (the example lab table,
copied: replace it by your tensile tester's export). Each file says what it is in its comments.
"""

from __future__ import annotations

import logging
import os
import shutil
import subprocess
import sys
from pathlib import Path

from cloth.errors import InputError
from cloth.io import atomic_output
from cloth.shipped import shipped, workflow_dir

log = logging.getLogger(__name__)

CONFIG = """\
# A cloth project (`cloth init`): run it from this folder with
#     cloth pipeline --cores 2
# which writes results/ here (sweep.csv, design_confirmed.csv, each case's result.nc and
# figures). Every key is in cloth's configuration page (docs/config.md) and its schema.

# Fabrics by name: a tensile tester's export (here the shipped example power net, copied beside
# this file: illustrative, not measured) and how its curves are fitted.
materials:
  myfabric:
    table: powernet.csv
    knots: 6
    branch: unload # the branch a worn garment follows

# Bodies by name: the parametric torso of the shipped size chart (size M); a scan would be
# {mesh: scans/me.obj, units: mm, up: y, kind: torso}.
bodies:
  torso_M:
    torso: {size: M}

# Every material x body x reduction is a case; 48 x 16 nodes answers in seconds (a report's
# grid is finer: every girth line states its error).
sweep:
  materials: [myfabric]
  bodies: [torso_M]
  reductions: [0.15, 0.20]
  garment: {bottom: 0.9, top: 1.15, grid: [48, 16], edges: sliding}
  solver: {method: newton, tolerance: 1.0e-8, max_iterations: 100}
  lengthwise_reductions: [0.0]

# The design question: which reduction gives 15 mmHg at the waist? (answered and confirmed)
targets:
  - {landmark: waist, pressure_mmHg: 15}

cases: {}
"""

CASE = """\
# One case (`cloth run case.yaml -o out`): the example fabric on the parametric torso M, cut
# 15 % smaller than the body's girths. Every key is in cloth's docs/config.md.
material: powernet.csv # a lab table beside this file; or a shipped name: powernet
body:
  torso: {size: M}
garment:
  bottom: 0.9 # m, along the body's up axis
  top: 1.15
  reduction: 0.15
  grid: [48, 16] # nodes around x nodes up
"""

#: The starter's files: name -> text, or the shipped file copied.
STARTER = {"config.yaml": CONFIG, "case.yaml": CASE, "powernet.csv": ("materials", "powernet.csv")}


def init_project(folder: str | Path) -> list[Path]:
    """Write the starter project (module docstring) into ``folder`` (new, or empty); the files
    written. `InputError` where ``folder`` holds a file of the starter's already."""
    folder = Path(folder)
    taken = [name for name in STARTER if (folder / name).exists()]
    if taken:
        raise InputError(
            f"{taken[0]} is there already; give a new or empty folder", folder, "folder"
        )
    if folder.exists() and not folder.is_dir():
        raise InputError("not a folder", folder, "folder")
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, source in STARTER.items():
        with atomic_output(folder / name) as tmp:
            if isinstance(source, str):
                tmp.write_text(source)
            else:
                shutil.copyfile(shipped(*source), tmp)
        written.append(folder / name)
        log.info("wrote %s", folder / name)
    return written


def pipeline(configfile: str | Path = "config.yaml", args: list[str] | None = None) -> int:
    """Run the package's workflow (module docstring) in the working folder on ``configfile``,
    Snakemake's own options ``args`` passed through (``--cores``, ``-n``, ``--profile``, a
    target, ...); its exit status. ``--cores all`` where no cores, jobs or profile is given; a
    ``--profile`` by name is the package's (``--profile slurm``, docs/cluster.md) unless this
    folder has one of that name."""
    args = list(args or [])
    config = Path(configfile)
    if not config.is_file():
        raise InputError(
            "no config here; run `cloth init DIR` for a starter, or give --configfile",
            config,
            "--configfile",
        )
    if not any(a.split("=")[0] in ("--cores", "-c", "--jobs", "-j", "--profile") for a in args):
        args = ["--cores", "all", *args]
    args = [_profile(a, args[k - 1] if k else "") for k, a in enumerate(args)]
    bin_dir = Path(sys.executable).parent
    here = shutil.which("snakemake", path=str(bin_dir))
    command = [here] if here else [sys.executable, "-m", "snakemake"]
    command += ["-s", str(workflow_dir() / "Snakefile"), "--directory", ".", *args]
    command += ["--configfile", str(config)]  # last: it takes one or more values
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}"}
    log.info("running %s", " ".join(command))
    return subprocess.call(command, env=env)


def _profile(value: str, before: str) -> str:
    """``value`` after ``--profile``: a folder of that name here, else the package's own
    profile of that name (``default``, ``slurm``: ``workflow/profiles/``), else as given."""
    if before != "--profile" or Path(value).exists():
        return value
    packaged = workflow_dir() / "profiles" / value
    return str(packaged) if packaged.is_dir() else value


__all__ = ["CASE", "CONFIG", "STARTER", "init_project", "pipeline"]
