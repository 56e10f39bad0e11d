"""The ``cloth`` command: thin argparse adapters over the library's functions.

Bad input (`cloth.errors.InputError`) is reported as one line on stderr with exit status 2;
nothing is written in that case, since every output is written atomically after the work is done.
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from cloth import __version__
from cloth.errors import EXIT_INPUT, InputError

log = logging.getLogger("cloth")

Handler = Callable[[argparse.Namespace], int]


def _material_ingest(args: argparse.Namespace) -> int:
    from cloth.io import write_netcdf
    from cloth.labtables import IngestOptions, ingest
    from cloth.materialfile import material_dataset
    from cloth.plots import plot_material

    options = IngestOptions(
        n_knots=args.knots,
        branch=args.branch,
        cycle=args.cycle,
        thickness_mm=args.thickness_mm,
        specimen_width_mm=args.specimen_width_mm,
        gauge_length_mm=args.gauge_length_mm,
        compression_ratio=args.compression_ratio,
        name=args.name,
    )
    if args.direction and len(args.direction) != len(args.tables):
        raise InputError(
            f"give --direction once per table ({len(args.tables)}), got {len(args.direction)}",
            field="--direction",
        )
    material = ingest(args.tables, args.direction, options)
    ds = material_dataset(material)
    write_netcdf(ds, args.output)
    log.info("wrote %s", args.output)
    if args.plot:
        plot_material(ds, args.plot)
    for direction, data in material.data.items():
        report = data.report
        log.info(
            "%s: %d knots, fit error max %.4g Pa (%.3g %%), rms %.4g Pa (%.3g %%)",
            direction,
            material.fabric.curve(direction).n_knots,
            report.max_error,
            report.max_error_percent,
            report.rms_error,
            report.rms_error_percent,
        )
    return 0


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 2:
        raise argparse.ArgumentTypeError(f"must be >= 2, got {value}")
    return value


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``cloth`` command."""
    parser = argparse.ArgumentParser(
        prog="cloth",
        description="Stress and body pressure of stretch fabric worn on a body "
        "(spring-particle model).",
    )
    parser.add_argument("--version", action="version", version=f"cloth {__version__}")
    parser.add_argument(
        "--log-level",
        default="INFO",
        choices=["DEBUG", "INFO", "WARNING", "ERROR"],
        help="logging verbosity (default INFO)",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    material = commands.add_parser("material", help="fabric lab tables")
    material_commands = material.add_subparsers(dest="material_command", required=True)
    ingest = material_commands.add_parser(
        "ingest",
        help="lab table(s) -> material.nc (curves, data, fit error)",
        description="Read lab tables (see docs/materials.md) into a material netCDF file.",
    )
    ingest.add_argument("tables", nargs="+", type=Path, help="CSV lab table(s)")
    ingest.add_argument("-o", "--output", type=Path, required=True, help="material.nc to write")
    ingest.add_argument("--plot", type=Path, help="also write a figure of data and curves")
    ingest.add_argument(
        "--direction",
        action="append",
        choices=["weft", "warp", "bias"],
        help="direction of each table without a direction column (repeat per table)",
    )
    ingest.add_argument(
        "--knots",
        type=_positive_int,
        help="knots of the fitted curve (default: clean tables keep their points, raw exports "
        "get 8)",
    )
    ingest.add_argument(
        "--branch",
        default="unload",
        choices=["unload", "load", "all"],
        help="branch of cyclic data to fit (default unload: what a worn garment follows)",
    )
    ingest.add_argument("--cycle", type=int, help="cycle to fit (default: the last)")
    ingest.add_argument("--thickness-mm", type=float, help="fabric thickness, mm")
    ingest.add_argument("--specimen-width-mm", type=float, help="tested strip width, mm")
    ingest.add_argument("--gauge-length-mm", type=float, help="clamp distance, mm")
    ingest.add_argument(
        "--compression-ratio",
        type=float,
        help="compression modulus / initial slope (default 0.01)",
    )
    ingest.add_argument("--name", help="fabric name (default: header name or file stem)")
    ingest.set_defaults(handler=_material_ingest)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``cloth`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=getattr(logging, args.log_level),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
        stream=sys.stderr,
    )
    handler: Handler = args.handler
    try:
        return handler(args)
    except InputError as exc:
        print(f"cloth: error: {exc}", file=sys.stderr)
        return EXIT_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
