"""The command line's ``cloth init`` and ``cloth pipeline``: a project in your own folder, and
the package's workflow run there (`cloth.stages.project`). `cloth.cli.parser` adds them."""

from __future__ import annotations

import argparse
from typing import Any

from cloth.cli.argtypes import path_argument


def add_project_commands(commands: Any) -> None:
    """Add ``cloth init`` and ``cloth pipeline`` to the subcommands ``commands``."""
    init = commands.add_parser(
        "init",
        help="DIR -> a starter project that runs as written: config.yaml, case.yaml and the "
        "example lab table",
    )
    init.add_argument("folder", type=path_argument, help="the project's folder (new or empty)")
    init.set_defaults(handler="init")
    run = commands.add_parser(
        "pipeline",
        help="run the package's Snakemake workflow here, on config.yaml; Snakemake's options "
        "pass through (--cores, -n, --profile slurm, a target)",
    )
    run.add_argument(
        "--configfile",
        type=path_argument,
        default="config.yaml",
        help="the pipeline config (default config.yaml in this folder)",
    )
    run.add_argument(
        "snakemake_args",
        nargs=argparse.REMAINDER,
        help="Snakemake's own options, passed as they are",
    )
    run.set_defaults(handler="pipeline")
