"""The ``cloth`` command: thin argparse adapters over the library's functions.

Bad input (`cloth.errors.InputError`) is reported as one line on stderr with exit status 2, a
stage that could not finish (`cloth.errors.StageFailed`: a diverged relaxation) with its own;
nothing is written in that case, since every output is written atomically after the work is done.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
from collections.abc import Sequence

from cloth.cli.blocks import apply_block
from cloth.cli.parser import build_parser
from cloth.errors import EXIT_INPUT, InputError, StageFailed
from cloth.paths import output_path

__all__ = ["build_parser", "main"]


#: Options that name where a command writes (``-o`` and the extra figures and tables).
OUTPUTS = ("output", "plot", "csv", "summary", "curvature", "body_plot")


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse in one line an output that cannot be written where it is asked for, before any
    work (`cloth.paths.output_path`): ``-o`` of ``run`` and ``plot``, and of ``design`` with a
    case, is a folder, the others files."""
    for dest in OUTPUTS:
        value = getattr(args, dest, None)
        if value is not None:
            folder = dest == "output" and getattr(args, "output_folder", False)
            if args.command == "design":  # a case's design fills a folder, a sweep's a file
                folder = dest == "output" and args.input[0].suffix != ".nc"
            output_path(value, "--" + dest.replace("_", "-"), folder)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``cloth`` command; returns the exit status."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra and getattr(args, "handler", None) != "pipeline":
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if getattr(args, "handler", None) == "pipeline":  # Snakemake's own options pass through
        args.snakemake_args = [*extra, *args.snakemake_args]
    logging.basicConfig(
        level=getattr(logging, args.log_level),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
        stream=sys.stderr,
    )

    # --version, --help and a refused argument never load the numerical stack; a verb's
    # handler (cloth.cli.handlers, found by name) imports its own stage
    from cloth.io import set_command  # late: cloth.io imports xarray

    set_command(["cloth", *(sys.argv[1:] if argv is None else argv)])
    handler = getattr(importlib.import_module("cloth.cli.handlers"), args.handler)
    try:
        if getattr(args, "block", None) is not None and getattr(args, "verb", None) is not None:
            apply_block(args.verb, args, args.block_ignores)
        check_outputs(args)
        return handler(args)
    except InputError as exc:
        print(f"cloth: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except StageFailed as exc:
        print(f"cloth: error: {exc}", file=sys.stderr)
        return exc.status


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
