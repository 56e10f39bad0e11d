"""The command line's ``cloth sizes`` (issue 62): a size chart designed for a measured
population. `cloth.cli.parser` adds it."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cloth.cli.argtypes import amount
from cloth.cli.wearercommands import ages_option


def _share(text: str) -> float:
    """A share in (0, 1]."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"give a share between 0 and 1, got {text!r}") from None
    if not 0 < value <= 1:
        raise argparse.ArgumentTypeError(f"must be in (0, 1], e.g. 0.95; got {text}")
    return value


def _count(text: str) -> int:
    """A whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"give a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def add_sizes_command(
    commands: Any,
    path: Callable[[str], Path],
    solver_options: Callable[[argparse.ArgumentParser], None],
) -> None:
    """Add ``cloth sizes`` to the top-level ``commands`` (argparse's sub-parser action);
    ``path`` and ``solver_options`` are the parser's own argument type and solver options."""
    sizes = commands.add_parser(
        "sizes",
        help="case.yaml + a population -> a size chart, one garment per size, confirmed",
        description="Design the fewest sizes that put the asked share of a measured "
        "population inside every target band, one pattern per size, searched with Laplace's "
        "law calibrated on full equilibria and confirmed from scratch on each size's extreme "
        "wearers (docs/outputs.md, 'Designing a size chart'). The case gives the fabric, the "
        "garment, the solver, and the body (a leg or torso chart's size) every wearer is "
        "built from.",
    )
    sizes.add_argument("case", type=path, help="case YAML file (a leg or torso body with a size)")
    sizes.add_argument(
        "--population",
        default="default",
        help="CSV of measured people, girths in cm (docs/bodies.md); default: the shipped "
        "ANSUR II women for a leg, NHANES for a torso",
    )
    sizes.add_argument(
        "--target",
        action="append",
        required=True,
        metavar="LINE=LOW:HIGH",
        help="a girth line's band, mmHg by default (B=23:32); repeat for more lines",
    )
    sizes.add_argument(
        "--by",
        default=None,
        metavar="MEASURE[,MEASURE]",
        help="the sizing measure, and a second one for variants (ankle or ankle,calf; the "
        "chart's names B, C work too); each needs a --target at its line (default: the "
        "first target's line)",
    )
    sizes.add_argument(
        "--coverage",
        type=_share,
        default=0.95,
        help="the share of the population that must fit a size (default 0.95)",
    )
    sizes.add_argument("--max-sizes", type=_count, default=8, help="the most sizes (default 8)")
    sizes.add_argument(
        "--max-variants",
        type=_count,
        default=3,
        help="the most variants of a size by the second measure (default 3)",
    )
    sizes.add_argument(
        "--margin",
        type=amount("pressure", "mmHg"),
        default=None,
        help="how far inside every band the search keeps the fast model, mmHg (default: twice "
        "its rms error on the equilibria it was calibrated on, at least 0.5)",
    )
    sizes.add_argument(
        "--rounds",
        type=_count,
        default=2,
        help="the most rounds of confirmation: the searched chart's, then each of its sizes not "
        "confirmed recut from what its equilibria read (default 2)",
    )
    sizes.add_argument(
        "--report-unmet",
        action="store_true",
        help="a size not confirmed after the rounds is reported in sizes.csv (confirmed 0) and "
        "the log only, exit status 0 (the pipeline's size charts)",
    )
    ages_option(sizes)
    sizes.add_argument("-o", "--output", type=path, required=True, help="output folder")
    solver_options(sizes)
    sizes.set_defaults(handler="sizes", output_folder=True)
