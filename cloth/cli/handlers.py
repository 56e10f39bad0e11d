"""The ``cloth`` command's handlers: each turns parsed arguments into one call of a stage
(`cloth.stages`) or of the library, and returns the exit status."""

from __future__ import annotations

import argparse
import logging
from collections.abc import Callable

from cloth.bodies.mesh import MeshBody
from cloth.bodies.surface import FitOptions
from cloth.errors import InputError
from cloth.figures.export import export
from cloth.files.pattern import write_pattern
from cloth.files.surface import load_or_fit
from cloth.io import atomic_output, read_netcdf
from cloth.materials.labtables import IngestOptions
from cloth.pipeline.config import load_case, validate_case
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.stages import figures, view, write_result
from cloth.stages.bodycheck import describe
from cloth.stages.case import SOLVER_KEYS, predeform_file, relax_file, run_case
from cloth.stages.graded import design_files
from cloth.stages.inputs import ingest_material, leg_file, torso_file
from cloth.stages.sweep import confirm_file, design_file, sweep_files

log = logging.getLogger("cloth")

Handler = Callable[[argparse.Namespace], int]


def _required(args: argparse.Namespace, dest: str, what: str) -> None:
    """Refuse a missing input that may come from the line or from ``--json``."""
    if getattr(args, dest) in (None, []):
        raise InputError(f"give {what}", field=dest)


def _material_ingest(args: argparse.Namespace) -> int:
    _required(args, "tables", "the lab table(s), or --json with a table")
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
    ingest_material(args.tables, args.direction, options, args.output, args.plot)
    return 0


def _body_torso(args: argparse.Namespace) -> int:
    _required(args, "size", "--size, or --json with a torso block")
    girths = {
        k: getattr(args, k)
        for k in ("bust", "underbust", "waist", "hip")
        if getattr(args, k) is not None
    }
    torso_file(args.size, args.chart, girths, args.around, args.rings, args.output)
    return 0


def _body_leg(args: argparse.Namespace) -> int:
    leg_file(args.size, args.chart, args.around, args.rings, args.output)
    return 0


def _fit_options(args: argparse.Namespace):  # -> FitOptions (imported late: startup time)

    return FitOptions(args.smoothing, args.spacing, args.refine, args.denoise)


def _body_check(args: argparse.Namespace) -> int:
    _required(args, "mesh", "the mesh file, or --json with a mesh body block")
    lines = describe(
        args.mesh,
        args.units,
        args.up,
        args.repair,
        args.levels,
        args.surface,
        _fit_options(args),
        args.curvature,
        args.surface_file,
    )
    print("\n".join(lines))
    return 0


def _body_fit(args: argparse.Namespace) -> int:
    _required(args, "mesh", "the mesh file, or --json with a mesh body block")
    mesh = MeshBody.load(args.mesh, args.units, args.up, args.repair, allow_holes=True)
    load_or_fit(mesh, _fit_options(args), args.output)
    return 0


def _predeform(args: argparse.Namespace) -> int:
    predeform_file(args.case, args.output, args.base_dir, args.plot, args.force)
    return 0


def _case_write(args: argparse.Namespace) -> int:
    import json

    import yaml

    try:
        case = json.loads(args.json)
    except json.JSONDecodeError as exc:
        raise InputError(f"not valid JSON ({exc.msg})", field="--json") from None
    case = validate_case(case, args.output)
    with atomic_output(args.output) as tmp:
        tmp.write_text(yaml.safe_dump(case.to_dict(), sort_keys=False))
    log.info("wrote %s", args.output)
    return 0


def _case_check(args: argparse.Namespace) -> int:
    import yaml

    print(yaml.safe_dump(load_case(args.case).to_dict(), sort_keys=False), end="")
    return 0


def _overrides(args: argparse.Namespace) -> dict:
    """The solver keys given on the command line (on top of the case's solver block)."""
    return {k: getattr(args, k) for k in SOLVER_KEYS if getattr(args, k, None) is not None}


def _relax(args: argparse.Namespace) -> int:
    relax_file(args.initial, args.output, _overrides(args), args.force)
    return 0


def _run(args: argparse.Namespace) -> int:
    run_case(args.case, args.output, _overrides(args), args.base_dir, args.stop_after, args.force)
    return 0


def _aggregate(args: argparse.Namespace) -> int:
    write_result(args.relaxed, args.output, args.summary)
    return 0


def _plot(args: argparse.Namespace) -> int:
    figures(args.result, args.output, args.peers, args.stress_range, args.pressure_range)
    return 0


def _view(args: argparse.Namespace) -> int:
    view(args.result, args.output)
    return 0


def _export(args: argparse.Namespace) -> int:
    export(read_netcdf(args.result, "result", ("x", "y", "z")), args.output, args.field)
    log.info("wrote %s", args.output)
    return 0


def _pattern(args: argparse.Namespace) -> int:
    write_pattern(args.result, args.output, args.cut, args.formats)
    return 0


def _sweep(args: argparse.Namespace) -> int:
    import json

    sweep_files(
        json.loads(args.index),
        args.results,
        json.loads(args.targets),
        args.output,
        args.csv,
        args.plot,
        args.body_plot,
    )
    return 0


def _design(args: argparse.Namespace) -> int:
    import json

    if args.input.suffix == ".nc":
        if args.target or args.targets is None:
            raise InputError(
                "a sweep's design takes --targets JSON, not --target; --target designs a case",
                args.input,
                "--targets",
            )
        design_file(args.input, json.loads(args.targets), args.output)
        return 0
    if args.targets is not None:
        raise InputError(
            "a case's design takes --target LINE=PRESSURE (repeat per line), not --targets",
            args.input,
            "--target",
        )
    if not (args.tolerance > 0 and args.tolerance < float("inf")):
        raise InputError(
            f"must be a positive number of mmHg, got {args.tolerance}", field="--tolerance"
        )
    targets = [Target.parse(text) for text in args.target]
    design_files(args.input, targets, args.output, args.tolerance * MMHG, args.base_dir)
    return 0


def _confirm(args: argparse.Namespace) -> int:
    confirm_file(args.design, args.results, args.output)
    return 0
