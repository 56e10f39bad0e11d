"""Argument types and options the command's parsers share (`cloth.cli.parser`,
`cloth.cli.sizecommands`, `cloth.cli.designcommand`)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path


def amount(quantity: str, unit: str) -> Callable[[str], float]:
    """An argument type: a finite number >= 0 of ``quantity`` (``length``) in ``unit``
    (``mm``), refused in argparse's one line otherwise."""

    def read(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"give a {quantity} in {unit}, got {text!r}") from None
        if not 0 <= value < float("inf"):
            raise argparse.ArgumentTypeError(f"must be a {quantity} >= 0 in {unit}, got {text}")
        return value

    return read


#: A length in mm, >= 0 and finite.
MILLIMETRES = amount("length", "mm")


def path_argument(text: str) -> Path:
    """A path argument: not empty (``Path("")`` would be the working directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("give a path, not an empty string")
    return Path(text)


def size_names(text: str) -> list[str]:
    """A comma-separated list of size names: ``S,M,L``."""
    names = [name.strip() for name in text.split(",")]
    if not all(names):
        raise argparse.ArgumentTypeError(
            f"give size names separated by commas, e.g. S,M,L; got {text!r}"
        )
    return names


def pattern_options(command: argparse.ArgumentParser) -> None:
    """The pattern pieces' options (`cloth.files.piece`, `cloth.files.printout`)."""
    command.add_argument(
        "--seam-allowance",
        type=MILLIMETRES,
        default=6.0,
        metavar="MM",
        help="seam allowance of the cut line around the sew line, mm (default 6, a flatlock "
        "seam's; 0: the net pattern)",
    )
    command.add_argument(
        "--paper",
        choices=("A4", "letter"),
        default="A4",
        help="paper of the 1:1 PDF, tiled where the piece does not fit (default A4)",
    )
