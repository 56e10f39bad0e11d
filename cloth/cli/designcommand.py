"""The command line's ``cloth design`` (a sweep's uniform reductions, a case's graded pattern,
a chart's sizes, a robust design over the wearers, a panel's width, a band at most as hard as
the fabric beside it). `cloth.cli.parser` adds it."""

from __future__ import annotations

from typing import Any

from cloth.cli.argtypes import path_argument, pattern_options, size_names


def add_design_command(commands: Any) -> None:
    """Add ``cloth design`` to the subcommands ``commands``."""
    de = commands.add_parser(
        "design",
        help="sweep.nc -> design.csv: the uniform reduction per target; or case.yaml -> a "
        "graded pattern meeting a pressure on every target line (docs/outputs.md)",
    )
    de.add_argument(
        "input",
        type=path_argument,
        nargs="+",
        help="sweep.nc from cloth sweep, or a case YAML; or one case YAML per size (each size "
        "named by its file's stem)",
    )
    de.add_argument("--targets", help="with sweep.nc: JSON list of {landmark, pressure_mmHg}")
    de.add_argument(
        "--target",
        action="append",
        default=[],
        metavar="LINE=PRESSURE",
        help="with a case: a girth line's mean pressure, in mmHg (default), kPa or Pa, e.g. "
        "waist=20 or hip=2.0kPa, or a band LINE=LOW:HIGH (B=23:32; with --wearers); repeat "
        "per line",
    )
    de.add_argument(
        "--base-dir",
        type=path_argument,
        help="with a case: folder relative paths in the case are "
        "relative to (default: the case file's folder)",
    )
    de.add_argument(
        "--tolerance",
        type=float,
        default=0.5,
        help="with a case: how near every line must come to its target, mmHg (default 0.5)",
    )
    de.add_argument(
        "--sizes",
        type=size_names,
        help="with a case on a parametric torso or leg: design these sizes of its chart at "
        "once, e.g. S,M,L, each warm-started from the one before it",
    )
    de.add_argument(
        "--wearers",
        nargs="?",
        const="shipped",
        metavar="DIR",
        help="with a case: a robust design for every wearer of the case's size (the shipped "
        "wearers of its chart, or DIR from cloth body wearers): one profile that puts each "
        "wearer inside every band, --target LINE=LOW:HIGH (docs/outputs.md, 'Robust design')",
    )
    de.add_argument(
        "--band-ratio-max",
        type=float,
        metavar="R",
        help="with a case of bands: every band presses at most R times the line beside it (1: "
        "a stocking's top band no harder than the leg below); a band over it has its reduction "
        "designed to R x that line (docs/how-to/pieces.md)",
    )
    de.add_argument(
        "--panel",
        type=int,
        metavar="K",
        help="with a case of panels: meet the one --target by panel K's width (0: the first "
        "listed), about its centre, its neighbours' fabrics held (docs/how-to/pieces.md)",
    )
    de.add_argument(
        "--report-unmet",
        action="store_true",
        help="with --wearers: a band not met is reported in robust.csv only, exit status 0 "
        "(the pipeline's robust designs)",
    )
    de.add_argument(
        "--cold",
        action="store_true",
        help="with several sizes: start each size from the case, not from the size before it",
    )
    de.add_argument(
        "--cut",
        choices=("auto", "two-panel", "tube"),
        default="auto",
        help="with a case: the pattern's cut (default auto: a tube on a leg, two panels elsewhere)",
    )
    pattern_options(de)
    de.add_argument(
        "-o",
        "--output",
        type=path_argument,
        required=True,
        help="design.csv to write (sweep.nc), or the folder of the design (a case)",
    )
    de.set_defaults(handler="design")
