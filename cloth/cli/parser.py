"""The ``cloth`` command's argument parser: every verb and its options, declared once."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, NoReturn

from cloth import __version__
from cloth.cli.argtypes import path_argument, pattern_options, size_names
from cloth.cli.designcommand import add_design_command
from cloth.cli.measurecommands import add_measure_commands
from cloth.cli.projectcommands import add_project_commands
from cloth.cli.sizecommands import add_sizes_command
from cloth.cli.wearercommands import add_wearers_commands
from cloth.errors import EXIT_INPUT


class Parser(argparse.ArgumentParser):
    """argparse's parser whose errors are one line (the argument, what is wrong, where to look)
    with exit status 2, like every other refusal of the command."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_INPUT, f"cloth: error: {message}; see {self.prog} --help\n")

    def add_subparsers(self, **kwargs: Any) -> Any:
        """argparse's, its commands kept in `commands` (name -> parser, in the order added) for
        the generated reference (docs/reference/cli.md)."""
        action = super().add_subparsers(**kwargs)
        self.commands: dict[str, argparse.ArgumentParser] = action.choices
        return action


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 2:
        raise argparse.ArgumentTypeError(f"must be >= 2, got {value}")
    return value


def _force_option(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--force",
        action="store_true",
        help="run even when the estimated peak memory exceeds the free memory (also "
        "CLOTH_FORCE=1; docs/performance.md, 'Guardrails')",
    )


def _json_option(command: argparse.ArgumentParser, block: str, ignore: tuple[str, ...] = ()):
    """``--json BLOCK``: the options as a JSON block (`cloth.cli.blocks`)."""
    command.add_argument(
        "--json",
        dest="block",
        metavar="BLOCK",
        help=f"the options as {block} in JSON, each key an option's name (e.g. "
        "'{\"thickness_mm\": 0.5}' for --thickness-mm 0.5); the workflow passes its blocks so",
    )
    command.set_defaults(verb=command, block_ignores=frozenset(ignore))


def _mesh_options(parser: argparse.ArgumentParser) -> None:
    """A mesh file as a case reads it, and the options of its smooth surface."""
    parser.add_argument(
        "mesh",
        type=path_argument,
        nargs="?",
        help="mesh file (OBJ, STL, PLY, GLB, ...; or --json's mesh)",
    )
    parser.add_argument("--units", default="m", help="length unit of the file: m, cm or mm")
    parser.add_argument("--up", default="z", help="axis of the file that points up: x, y or z")
    parser.add_argument("--repair", action="store_true", help="let trimesh repair defects")
    parser.add_argument(
        "--smoothing", type=float, help="smoothing width sigma, m (default: from the mesh)"
    )
    parser.add_argument("--spacing", type=float, help="grid spacing h, m (default: sigma / 2.5)")
    parser.add_argument(
        "--refine",
        type=int,
        help="times each triangle is split along curved patches before the fit (default: "
        "until the facets are 8 mm wide, at most 3; 0: never)",
    )
    parser.add_argument(
        "--denoise",
        action=argparse.BooleanOptionalAction,
        help="filter the vertices along their normals before the fit (default: where they "
        "scatter like noise)",
    )
    parser.add_argument(
        "--region",
        type=float,
        nargs=2,
        metavar=("BOTTOM", "TOP"),
        help="fit only the part of the body a garment between these heights (m) wraps, plus "
        "3 cm (a full-body scan as given; default: the whole mesh)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``cloth`` command."""
    parser = Parser(
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
    ingest.add_argument(
        "tables", nargs="*", type=path_argument, help="CSV lab table(s) (or --json's table)"
    )
    ingest.add_argument(
        "-o", "--output", type=path_argument, required=True, help="material.nc to write"
    )
    ingest.add_argument("--plot", type=path_argument, help="also write a figure of data and curves")
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
        help="compression modulus / initial slope (default 0: a pure tension field)",
    )
    ingest.add_argument("--name", help="fabric name (default: header name or file stem)")
    _json_option(ingest, "a config's material block (docs/config.md)")
    ingest.set_defaults(handler="material_ingest")

    body = commands.add_parser("body", help="bodies: parametric torso and leg, mesh checks")
    body_commands = body.add_subparsers(dest="body_command", required=True)
    torso = body_commands.add_parser(
        "torso",
        help="write the parametric torso of a size chart as a mesh",
        description="Build the smooth, watertight parametric torso of a size (m, z up).",
    )
    torso.add_argument("--size", help="size name in the chart (e.g. S, M); required")
    torso.add_argument("--chart", type=path_argument, help="size chart CSV (default data/bodies)")
    for key in ("bust", "underbust", "waist", "hip"):
        torso.add_argument(f"--{key}", type=float, help=f"override the {key} girth, cm")
    torso.add_argument("--around", type=int, default=128, help="mesh points per ring")
    torso.add_argument("--rings", type=int, default=120, help="mesh rings")
    torso.add_argument(
        "-o", "--output", type=path_argument, required=True, help="mesh file (.ply, .stl)"
    )
    _json_option(torso, "a case's torso body block (docs/config.md)", ("surface", "tissue"))
    torso.set_defaults(handler="body_torso")
    leg = body_commands.add_parser(
        "leg", help="write the parametric leg of a stocking size chart as a mesh (m, z up)"
    )
    leg.add_argument("--size", required=True, help="size name in the leg chart (e.g. S, M, L)")
    leg.add_argument("--chart", type=path_argument, help="leg chart CSV (default data/bodies)")
    leg.add_argument("--around", type=int, default=96, help="mesh points per ring")
    leg.add_argument("--rings", type=int, default=160, help="mesh rings")
    leg.add_argument(
        "-o", "--output", type=path_argument, required=True, help="mesh file (.ply, .stl)"
    )
    leg.set_defaults(handler="body_leg")
    check = body_commands.add_parser(
        "check",
        help="check a mesh and print its bounds, height and girth profile",
        description="Load a body mesh as cloth would (units, up axis, checks) and describe it.",
    )
    _mesh_options(check)
    check.add_argument("--levels", type=int, default=10, help="heights in the girth profile")
    check.add_argument(
        "--surface",
        choices=("smooth", "mesh"),
        default="smooth",
        help="contact surface: smooth (fit it and report its deviation) or mesh (the facets)",
    )
    check.add_argument(
        "--curvature",
        type=path_argument,
        help="write the smooth surface's mean curvature figure (PNG)",
    )
    check.add_argument(
        "--surface-file",
        type=path_argument,
        help="a fitted surface (cloth body fit) to use if it fits",
    )
    _json_option(check, "a case's mesh body block (docs/config.md)", ("tissue",))
    check.set_defaults(handler="body_check")
    fit = body_commands.add_parser(
        "fit",
        help="fit the smooth contact surface of a mesh -> surface.nc",
        description="Fit (or reuse) the smooth contact surface of a mesh body (docs/bodies.md).",
    )
    _mesh_options(fit)
    fit.add_argument("-o", "--output", type=path_argument, required=True, help="surface file (.nc)")
    _json_option(
        fit, "a case's mesh body block (docs/config.md)", ("surface", "surface_file", "tissue")
    )
    fit.set_defaults(handler="body_fit")
    avatar = body_commands.add_parser(
        "avatar",
        help="fit a realistic body to a size chart -> FILE.ply and FILE.json (bodies extra)",
        description="Fit the body model Anny to one size of a torso or leg chart: its stature "
        "and its tape girths at the chart's heights (docs/bodies.md, 'Avatars'). Writes the "
        "posed, cropped, watertight mesh (m, z up, floor at 0) and its provenance beside it. "
        "Needs the extra: pip install 'cloth[bodies]'.",
    )
    avatar.add_argument("chart", type=path_argument, help="torso or leg size chart (CSV, cm)")
    avatar.add_argument("--size", required=True, help="size name in the chart (e.g. S, M, L)")
    avatar.add_argument(
        "-o", "--output", type=path_argument, required=True, help="mesh file (.ply)"
    )
    avatar.add_argument(
        "--full",
        action="store_true",
        help="the whole body in the model's own A-pose, arms hanging, uncropped (a full-body "
        "scan as scanners export it; for tests and benchmarks of scans used as given)",
    )
    avatar.set_defaults(handler="body_avatar")

    pre = commands.add_parser(
        "predeform",
        help="case.yaml -> initial.nc (the garment wrapped on the body)",
        description="Cut the pattern of a case and wrap it around the body (docs/config.md).",
    )
    pre.add_argument("case", type=path_argument, help="case YAML file")
    pre.add_argument(
        "-o", "--output", type=path_argument, required=True, help="initial.nc to write"
    )
    pre.add_argument(
        "--base-dir",
        type=path_argument,
        help="folder relative paths in the case are relative to (default: the case file's folder)",
    )
    pre.add_argument(
        "--plot", type=path_argument, help="also write a 3D figure of the wrapped garment"
    )
    _force_option(pre)
    pre.set_defaults(handler="predeform")

    def solver_options(command: argparse.ArgumentParser) -> None:
        command.add_argument(
            "--method",
            choices=["explicit", "newton", "explicit+newton"],
            help="relaxation method (default: the case's solver block, else newton)",
        )
        command.add_argument("--tolerance", type=float, help="relative residual to stop at")
        command.add_argument("--max-iterations", type=int, help="iteration limit")
        command.add_argument(
            "--linear-solver",
            choices=["auto", "superlu", "cholespy", "cholmod", "pardiso", "amg"],
            help="Newton's sparse solver (default auto: cholespy where the matrix is positive "
            "definite, docs/solvers.md)",
        )
        command.add_argument("--log-every", type=int, help="log a line every N iterations")
        command.add_argument(
            "--warm-start", type=int, help="explicit iterations before Newton (explicit+newton)"
        )
        _force_option(command)

    rel = commands.add_parser(
        "relax",
        help="initial.nc -> relaxed.nc (equilibrium on the body)",
        description="Relax a wrapped garment to equilibrium (docs/solvers.md).",
    )
    rel.add_argument("initial", type=path_argument, help="initial.nc from cloth predeform")
    rel.add_argument(
        "-o", "--output", type=path_argument, required=True, help="relaxed.nc to write"
    )
    solver_options(rel)
    rel.set_defaults(handler="relax")

    run = commands.add_parser(
        "run",
        help="case.yaml -> every stage into a folder: initial.nc, relaxed.nc, "
        "result.nc, summary.csv, figures/ and garment.html",
    )
    run.add_argument("case", type=path_argument, help="case YAML file")
    run.add_argument("-o", "--output", type=path_argument, required=True, help="output folder")
    run.add_argument(
        "--stop-after",
        choices=("predeform", "relax", "aggregate"),
        help="stop after this stage (default: run them all)",
    )
    run.add_argument(
        "--base-dir",
        type=path_argument,
        help="folder relative paths in the case are relative to (default: the case file's folder)",
    )
    solver_options(run)
    run.set_defaults(handler="run", output_folder=True)

    add_wearers_commands(commands, body_commands, path_argument, solver_options)
    add_sizes_command(commands, path_argument, solver_options)
    add_project_commands(commands)
    add_measure_commands(commands, path_argument, solver_options)

    agg = commands.add_parser(
        "aggregate",
        help="relaxed.nc -> result.nc (+ summary.csv): stresses, pressure, landmarks",
        description="Compute node and spring stresses, body pressure and summaries "
        "(docs/outputs.md).",
    )
    agg.add_argument("relaxed", type=path_argument, help="relaxed.nc from cloth relax")
    agg.add_argument("-o", "--output", type=path_argument, required=True, help="result.nc to write")
    agg.add_argument("--summary", type=path_argument, help="also write the landmark summary CSV")
    agg.set_defaults(handler="aggregate")

    plot = commands.add_parser("plot", help="result.nc -> figures (PNG) in a folder")
    plot.add_argument("result", type=path_argument, help="result.nc from cloth aggregate")
    plot.add_argument(
        "-o", "--output", type=path_argument, required=True, help="folder for the figures"
    )
    plot.add_argument(
        "--stress-range",
        type=float,
        nargs=2,
        metavar=("LOW", "HIGH"),
        help="fixed colour range of the stress maps, Pa (to compare runs)",
    )
    plot.add_argument(
        "--pressure-range",
        type=float,
        nargs=2,
        metavar=("LOW", "HIGH"),
        help="fixed colour range of the pressure map, mmHg",
    )
    plot.add_argument(
        "--peers",
        type=path_argument,
        nargs="*",
        default=[],
        metavar="RESULT",
        help="result.nc files (a sweep's) whose values set the colour ranges not given, so "
        "that the figures of a sweep compare (default: this result's own range)",
    )
    plot.add_argument(
        "--ranges",
        type=path_argument,
        metavar="JSON",
        help="colour-range file from cloth ranges (a sweep's): its ranges for those not "
        "given, in place of --peers",
    )
    plot.set_defaults(handler="plot", output_folder=True)

    ranges = commands.add_parser(
        "ranges",
        help="result.nc files -> the colour ranges their figures share (JSON)",
        description="The stress (Pa) and pressure (mmHg) colour ranges shared by a sweep's "
        "results, read once for cloth plot --ranges (docs/outputs.md).",
    )
    ranges.add_argument("results", type=path_argument, nargs="+", help="result.nc files of a sweep")
    ranges.add_argument(
        "-o", "--output", type=path_argument, required=True, help="JSON file to write"
    )
    ranges.set_defaults(handler="ranges")

    view = commands.add_parser(
        "view", help="result.nc -> one self-contained HTML page: body and garment in 3D"
    )
    view.add_argument("result", type=path_argument, help="result.nc from cloth aggregate")
    view.add_argument(
        "-o", "--output", type=path_argument, required=True, help="HTML file to write"
    )
    view.set_defaults(handler="view")

    exp = commands.add_parser("export", help="result.nc -> .ply, .vtu or .csv")
    exp.add_argument("result", type=path_argument, help="result.nc from cloth aggregate")
    exp.add_argument(
        "-o", "--output", type=path_argument, required=True, help="file: .ply, .vtu, .csv"
    )
    exp.add_argument("--field", default="stress_weft", help="field coloured in the PLY")
    exp.set_defaults(handler="export")

    pat = commands.add_parser(
        "pattern",
        help="result.nc (one per size) -> the cut pattern: CSV table, SVG and DXF outline, the "
        "graded nest in AAMA/ASTM DXF, a 1:1 PDF, a tube's knitting table (mm; docs/outputs.md)",
    )
    pat.add_argument(
        "result", type=path_argument, nargs="+", help="result.nc from cloth aggregate, one per size"
    )
    pat.add_argument(
        "-o",
        "--output",
        type=path_argument,
        required=True,
        help="pattern.csv to write; the other files get its name with their suffixes "
        "(pattern_astm.dxf, pattern_knitting.csv; with several sizes pattern_{size}.csv ...)",
    )
    pat.add_argument(
        "--cut",
        choices=("two-panel", "tube"),
        default="two-panel",
        help="two-panel: the flat width is half the circumference (front and back panels); "
        "tube: all of it (default: two-panel)",
    )
    pat.add_argument(
        "--formats",
        nargs="+",
        choices=("csv", "svg", "dxf", "astm", "pdf", "knitting"),
        help="files to write (default: every one that applies: knitting for a tube only; the "
        "DXF files need the extra pattern: ezdxf)",
    )
    pat.add_argument(
        "--sizes",
        type=size_names,
        help="the results' size names, in order, e.g. S,M,L (default: each result's chart size)",
    )
    pattern_options(pat)
    pat.add_argument(
        "--course-step",
        type=float,
        default=5.0,
        metavar="MM",
        help="course step of the knitting table, mm of the tube's rest height (default 5)",
    )
    pat.add_argument(
        "--note",
        action="append",
        default=[],
        help="a note for every piece's annotation (e.g. the pressure targets); repeatable",
    )
    pat.set_defaults(handler="pattern")

    sw = commands.add_parser("sweep", help="results of a sweep -> sweep.nc, sweep.csv, design plot")
    sw.add_argument(
        "results",
        nargs="+",
        type=path_argument,
        help="result.nc of each case of the index, in its order",
    )
    sw.add_argument(
        "--index",
        required=True,
        help="JSON list of {case, material, body, reduction, and the variant keys}",
    )
    sw.add_argument("--targets", default="[]", help="JSON list of design targets (for the plot)")
    sw.add_argument("-o", "--output", type=path_argument, required=True, help="sweep.nc to write")
    sw.add_argument("--csv", type=path_argument, required=True, help="sweep.csv to write")
    sw.add_argument("--plot", type=path_argument, required=True, help="design plot to write")
    sw.add_argument(
        "--body-plot",
        type=path_argument,
        help="small multiples to write: the pressure on the body per body and reduction",
    )
    sw.set_defaults(handler="sweep")

    add_design_command(commands)

    co = commands.add_parser("confirm", help="design.csv + confirmation results -> errors")
    co.add_argument("design", type=path_argument, help="design.csv from cloth design")
    co.add_argument(
        "results",
        nargs="*",
        type=path_argument,
        help="result.nc of each answered target's confirmation case, in design.csv's order",
    )
    co.add_argument(
        "-o", "--output", type=path_argument, required=True, help="confirmed CSV to write"
    )
    co.add_argument(
        "--iterate",
        type=path_argument,
        metavar="DIR",
        help="confirm each answer that misses its target by more than its stated error again, "
        "by a secant on the confirmed cases (at most 3 runs each, into DIR; docs/outputs.md)",
    )
    co.set_defaults(handler="confirm")

    case = commands.add_parser("case", help="case files: check, write")
    case_commands = case.add_subparsers(dest="case_command", required=True)
    case_check = case_commands.add_parser(
        "check", help="validate a case file and print it with defaults filled"
    )
    case_check.add_argument("case", type=path_argument, help="case YAML file")
    case_check.set_defaults(handler="case_check")
    case_write = case_commands.add_parser(
        "write", help="validate a case given as JSON and write it as YAML (used by the pipeline)"
    )
    case_write.add_argument("--json", required=True, help="the case as a JSON object")
    case_write.add_argument(
        "-o", "--output", type=path_argument, required=True, help="case YAML to write"
    )
    case_write.add_argument(
        "--base-dir",
        type=path_argument,
        default=Path("."),
        help="folder the JSON's relative paths are relative to (default: the working "
        "directory); the written case stores them relative to its own folder, so it runs as "
        "written from anywhere",
    )
    case_write.set_defaults(handler="case_write")
    return parser
