"""The command line's wearers commands (issue 52): ``cloth body wearers`` (fit a size's
wearers), ``cloth wearers`` (a case's garment on every wearer of its size) and ``cloth
wearers-report`` (the pipeline's gathering of their results). `cloth.cli.parser` adds them."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any


def ages_option(command: argparse.ArgumentParser) -> None:
    """``--ages LOW HIGH``: the ages kept from a population (`cloth.files.population.AGES`)."""
    command.add_argument(
        "--ages",
        nargs=2,
        type=float,
        metavar=("LOW", "HIGH"),
        default=None,
        help="ages kept from the population, years (default 18 45)",
    )


def add_wearers_commands(
    commands: Any,
    body_commands: Any,
    path: Callable[[str], Path],
    solver_options: Callable[[argparse.ArgumentParser], None],
) -> None:
    """Add the wearers commands to the top-level ``commands`` and the ``body`` group's
    ``body_commands`` (argparse's sub-parser actions); ``path`` and ``solver_options`` are the
    parser's own argument type and solver options."""
    _path = path
    wearers = body_commands.add_parser(
        "wearers",
        help="fit the wearers of a size -> DIR of avatars and wearers.json (bodies extra)",
        description="The few bodies that span everyone a size fits (docs/bodies.md, 'The "
        "wearers of a size'): from a population of measured people (the size's people at the "
        "5th, 50th and 95th percentile of each measure the chart and the file share), or from "
        "the chart's girth ranges (their corners and centre); each fitted as an avatar. "
        "Needs the extra: pip install 'cloth[bodies]'.",
    )
    wearers.add_argument("chart", type=_path, help="torso or leg size chart (CSV, cm)")
    wearers.add_argument("--size", required=True, help="size name in the chart (e.g. S, M, L)")
    wearers.add_argument(
        "--population",
        default="default",
        help="CSV of measured people (docs/bodies.md); 'none': the chart's ranges only "
        "(default: the shipped NHANES survey for a torso chart, ANSUR II for a leg chart)",
    )
    ages_option(wearers)
    wearers.add_argument("-o", "--output", type=_path, required=True, help="output folder")
    wearers.set_defaults(handler="body_wearers", output_folder=True)

    wr = commands.add_parser(
        "wearers",
        help="case.yaml -> its garment on every wearer of its size: wearers.csv, .nc, .png",
        description="Cut the case's garment once for its body (or take its garment.pattern) "
        "and run it on every wearer of the size (docs/outputs.md, 'Every wearer of a size'): "
        "one case and run per wearer in DIR/{wearer}/, and per girth line the lowest, centre "
        "and highest pressure over them, which wearer gives each, and the stated "
        "discretisation error kept apart.",
    )
    wr.add_argument("case", type=_path, help="case YAML file (a body with a size)")
    wr.add_argument("-o", "--output", type=_path, required=True, help="output folder")
    wr.add_argument(
        "--wearers",
        type=_path,
        help="a folder cloth body wearers wrote (default: the shipped wearers of the body's "
        "chart and size)",
    )
    wr.add_argument(
        "--base-dir",
        type=_path,
        help="folder relative paths in the case are relative to (default: the case file's folder)",
    )
    solver_options(wr)
    wr.set_defaults(handler="wearers", output_folder=True)

    wrr = commands.add_parser(
        "wearers-report",
        help="each wearer's result.nc -> wearers.csv, .nc, .png (the pipeline's rule wearers)",
    )
    wrr.add_argument(
        "results",
        nargs="+",
        metavar="NAME=RESULT",
        help="a wearer's name and her result.nc (size=... the body the garment is cut for)",
    )
    wrr.add_argument("--index", type=_path, required=True, help="the wearers' wearers.json")
    wrr.add_argument("-o", "--output", type=_path, required=True, help="output folder")
    wrr.set_defaults(handler="wearers_report", output_folder=True)
