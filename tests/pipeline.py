"""Running the Snakemake pipeline from the tests: a private copy of its files, and the command."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")


def workspace(tmp_path: Path) -> Path:
    """A copy of the pipeline's files, so runs never touch the checkout's results/."""
    for name in ("Snakefile", "workflow", "config", "data"):
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, tmp_path / name)
        else:
            shutil.copy(source, tmp_path / name)
    return tmp_path


def from_checkout(where: Path, config: str = "config/ci.yaml") -> tuple[str, ...]:
    """Snakemake arguments that run the checkout's workflow with ``where`` as the working
    directory (``--directory``), as a deployed workflow runs: nothing copied beside it."""
    return (
        "-s",
        str(ROOT / "Snakefile"),
        "--directory",
        str(where),
        "--configfile",
        str(ROOT / config),
    )


def environment(base: dict[str, str] | None = None) -> dict[str, str]:
    """``base`` (default: this process's environment) with the venv first on PATH, for the
    rules' ``cloth`` commands."""
    base = dict(os.environ if base is None else base)
    return {
        **base,
        "PATH": f"{Path(sys.executable).parent}:{base.get('PATH', '')}",
        "MPLBACKEND": "Agg",
    }


def snakemake(
    where: Path, *args: str, env: dict[str, str] | None = None, timeout: float = 600
) -> subprocess.CompletedProcess:
    """Run Snakemake on 2 cores in ``where`` (its output captured)."""
    return subprocess.run(
        [str(SNAKEMAKE), "--cores", "2", *args],
        cwd=where,
        capture_output=True,
        text=True,
        env=environment(env),
        timeout=timeout,
    )
