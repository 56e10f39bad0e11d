"""Argument types the command's parsers share (`cloth.cli.parser`, `cloth.cli.sizecommands`)."""

from __future__ import annotations

import argparse
from collections.abc import Callable


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
