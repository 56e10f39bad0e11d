"""The ``cloth`` command: thin argparse adapters over the library's functions.

Bad input (`cloth.errors.InputError`) is reported as one line on stderr with exit status 2;
nothing is written in that case, since every output is written atomically after the work is done.
"""

from __future__ import annotations

import argparse
import importlib.util
import logging
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from cloth import __version__
from cloth.errors import EXIT_INPUT, InputError

#: Exit status of a relaxation that diverged (its last finite state is written beside).
EXIT_DIVERGED = 3

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


def _body_torso(args: argparse.Namespace) -> int:
    import dataclasses

    import trimesh

    from cloth.bodies.torso import DEFAULT_CHART, chart_size, torso_mesh
    from cloth.io import atomic_output

    chart = chart_size(args.size, args.chart or DEFAULT_CHART)
    overrides = {k: getattr(args, k) / 100 for k in ("bust", "underbust", "waist", "hip")
                 if getattr(args, k) is not None}  # fmt: skip
    if overrides:
        chart = dataclasses.replace(chart, girth={**chart.girth, **overrides})
    vertices, faces = torso_mesh(chart, args.around, args.rings)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    suffix = args.output.suffix.lstrip(".").lower() or "ply"
    with atomic_output(args.output) as tmp:
        mesh.export(tmp, file_type=suffix)
    log.info(
        "wrote %s: torso %s, %d vertices, %d faces, girths (m) %s",
        args.output, chart.name, len(vertices), len(faces),
        ", ".join(f"{k} {v:.4g}" for k, v in chart.girth.items()),
    )  # fmt: skip
    return 0


def _fit_options(args: argparse.Namespace):  # -> FitOptions (imported late: startup time)
    from cloth.bodies.surface import FitOptions

    return FitOptions(args.smoothing, args.spacing, args.refine, args.denoise)


def _body_check(args: argparse.Namespace) -> int:
    from cloth.bodies.check import describe

    lines = describe(
        args.mesh, args.units, args.up, args.repair, args.levels, args.surface,
        _fit_options(args), args.curvature, args.surface_file,
    )  # fmt: skip
    print("\n".join(lines))
    return 0


def _body_fit(args: argparse.Namespace) -> int:
    from cloth.bodies.mesh import MeshBody
    from cloth.bodies.surfacefile import load_or_fit

    mesh = MeshBody.load(args.mesh, args.units, args.up, args.repair, allow_holes=True)
    load_or_fit(mesh, _fit_options(args), args.output)
    return 0


def _predeform(args: argparse.Namespace) -> int:
    from cloth.bodies import body_from_config
    from cloth.config import load_case
    from cloth.io import write_netcdf
    from cloth.mechanics import spring_state
    from cloth.plots import plot_garment_3d
    from cloth.predeform import predeform
    from cloth.state import state_dataset

    case = load_case(args.case)
    base_dir = args.base_dir if args.base_dir is not None else args.case.parent
    _guard(("predeform",), case, base_dir, args)
    state = predeform(case, base_dir, str(args.case))
    write_netcdf(state_dataset(state, "initial"), args.output)
    log.info("wrote %s", args.output)
    if args.plot:
        import numpy as np

        grid = state.grid
        strain = spring_state(state.x, grid).strain[grid.family_slices[0]]
        body, _ = body_from_config(state.case["body"], base_dir)
        plot_garment_3d(
            state.x, grid.n, grid.m, np.repeat(strain.reshape(grid.m, grid.n), 1, axis=1).ravel(),
            "initial weft strain [1]", args.plot, body,
            title=f"{args.case.stem}: garment wrapped on the body (before relaxation)",
        )  # fmt: skip
    return 0


def _case_write(args: argparse.Namespace) -> int:
    import json

    import yaml

    from cloth.config import validate_case
    from cloth.io import atomic_output

    try:
        case = json.loads(args.json)
    except json.JSONDecodeError as exc:
        raise InputError(f"not valid JSON ({exc.msg})", field="--json") from None
    case = validate_case(case, args.output)
    with atomic_output(args.output) as tmp:
        tmp.write_text(yaml.safe_dump(case, sort_keys=False))
    log.info("wrote %s", args.output)
    return 0


def _case_check(args: argparse.Namespace) -> int:
    import yaml

    from cloth.config import load_case

    print(yaml.safe_dump(load_case(args.case), sort_keys=False), end="")
    return 0


def _settings(args: argparse.Namespace, case: dict):
    from cloth.solvers import Settings

    block = dict(case.get("solver", {}))
    for key in (
        "method",
        "tolerance",
        "max_iterations",
        "linear_solver",
        "log_every",
        "warm_start",
    ):
        value = getattr(args, key, None)
        if value is not None:
            block[key] = value
    return Settings(**block)


def _relax_state(state, base_dir, args, output: Path, previous: dict | None) -> int:
    from cloth.bodies import body_from_config
    from cloth.io import write_netcdf
    from cloth.relaxfile import relaxed_dataset
    from cloth.solvers import Diverged, relax

    settings = _settings(args, state.case)
    body, _ = body_from_config(state.case["body"], base_dir)
    try:
        result = relax(state, body, settings)
    except Diverged as exc:
        failed = output.with_name(output.stem + ".diverged.nc")
        contact = state.contact
        write_netcdf(
            relaxed_dataset(state, exc.x, contact, exc.history, settings, False,
                            len(exc.history) - 1, settings.linear_solver, 0.0, previous,
                            stage="diverged"),
            failed,
        )  # fmt: skip
        print(
            f"cloth: error: relaxation diverged ({exc}); the last finite state is in {failed}; "
            "try method explicit+newton or a smaller reduction",
            file=sys.stderr,
        )
        return EXIT_DIVERGED
    final = result.final
    write_netcdf(
        relaxed_dataset(state, final.x, final.on_body, result.history, settings,
                        result.converged, result.iterations, result.linear_solver,
                        result.seconds, previous, factorisations=result.factorisations,
                        peak_memory=result.peak_memory),
        output,
    )  # fmt: skip
    log.info("wrote %s", output)
    return 0


def _guard(stages: tuple[str, ...], case: dict, base_dir: Path, args: argparse.Namespace):
    """Refuse (InputError) a case whose estimated memory exceeds the free memory."""
    from cloth.guard import case_counts, check_fits

    source = getattr(args, "case", None) or getattr(args, "initial", None)
    check_fits(stages, *case_counts(case, base_dir), source, args.force)


def _relax(args: argparse.Namespace) -> int:
    import json

    import xarray as xr

    from cloth.state import read_state

    base_dir = args.base_dir if args.base_dir is not None else Path(".")
    try:  # the case from the header alone, before the arrays are read
        with xr.open_dataset(args.initial) as head:
            case = json.loads(head.attrs["case"])
    except Exception:  # read_state reports an unreadable file in one line
        case = None
    if case is not None:
        _guard(("relax",), case, base_dir, args)
    state, ds = read_state(args.initial)
    return _relax_state(state, base_dir, args, args.output, dict(ds.attrs))


def _run(args: argparse.Namespace) -> int:
    from cloth.config import load_case
    from cloth.io import write_netcdf
    from cloth.predeform import predeform
    from cloth.state import state_dataset

    case = load_case(args.case)
    base_dir = args.base_dir if args.base_dir is not None else args.case.parent
    _guard(("predeform", "relax", "aggregate", "figures"), case, base_dir, args)
    state = predeform(case, base_dir, str(args.case))
    initial = state_dataset(state, "initial")
    write_netcdf(initial, args.output / "initial.nc")
    if args.stop_after == "predeform":
        return 0
    relaxed = args.output / "relaxed.nc"
    code = _relax_state(state, base_dir, args, relaxed, dict(initial.attrs))
    if code or args.stop_after == "relax":
        return code
    from cloth.resultfile import write_summary
    from cloth.stages import aggregate, figures

    result, rows = aggregate(relaxed, base_dir)
    write_netcdf(result, args.output / "result.nc")
    write_summary(rows, args.output / "summary.csv")
    if args.stop_after == "aggregate":
        return 0
    figures(args.output / "result.nc", args.output / "figures")
    if importlib.util.find_spec("plotly") is not None:
        from cloth.onbody import body_band
        from cloth.view import write_view

        write_view(result, args.output / "garment.html", body_band(result))
    else:
        log.warning("plotly is not installed: no garment.html (pip install 'cloth[view]')")
    return 0


def _aggregate(args: argparse.Namespace) -> int:
    from cloth.io import write_netcdf
    from cloth.resultfile import write_summary
    from cloth.stages import aggregate

    base_dir = args.base_dir if args.base_dir is not None else Path(".")
    ds, rows = aggregate(args.relaxed, base_dir)
    write_netcdf(ds, args.output)
    if args.summary:
        write_summary(rows, args.summary)
    if not int(ds.attrs["converged"]):
        log.warning("%s: the relaxation did not converge; results are marked so", args.relaxed)
    for row in rows:
        log.info(
            "%s: pressure mean %.4g Pa (%.3g mmHg, RAL %s), max %.3g mmHg",
            row["landmark"], row["pressure_mean_Pa"], row["pressure_mean_mmHg"],
            row["ral_gz_387_class"], row["pressure_max_mmHg"],
        )  # fmt: skip
    return 0


def _plot(args: argparse.Namespace) -> int:
    from cloth.stages import figures

    figures(args.result, args.output, args.peers, args.stress_range, args.pressure_range)
    return 0


def _view(args: argparse.Namespace) -> int:
    from cloth.io import read_netcdf
    from cloth.onbody import body_band
    from cloth.view import write_view

    ds = read_netcdf(args.result, "result", ("x", "y", "z", "pressure_mmHg"))
    write_view(ds, args.output, body_band(ds))
    return 0


def _export(args: argparse.Namespace) -> int:
    from cloth.export import export
    from cloth.io import read_netcdf

    export(read_netcdf(args.result, "result", ("x", "y", "z")), args.output, args.field)
    log.info("wrote %s", args.output)
    return 0


def _sweep(args: argparse.Namespace) -> int:
    import json

    from cloth.io import write_netcdf
    from cloth.sweep import collect, plot_design, sweep_rows, write_rows

    index = json.loads(args.index)
    targets = json.loads(args.targets)
    ds = collect(index, args.root)
    write_netcdf(ds, args.output)
    rows = sweep_rows(ds)
    write_rows(rows, args.csv, list(rows[0]) if rows else ["material"])
    plot_design(ds, targets, args.plot)
    if args.body_plot:
        from cloth.io import read_netcdf
        from cloth.onbody import plot_sweep_on_body

        several = len({entry["material"] for entry in index}) > 1
        cases = [
            (
                f"{e['material']}, {e['body']}" if several else e["body"], float(e["reduction"]),
                read_netcdf(args.root / "results" / "cases" / e["case"] / "result.nc", "result"),
            )
            for e in index
        ]  # fmt: skip
        plot_sweep_on_body(cases, args.body_plot)
    return 0


def _design(args: argparse.Namespace) -> int:
    import json

    from cloth.io import read_netcdf
    from cloth.sweep import DESIGN_HEADER, design, write_rows

    rows = design(read_netcdf(args.sweep, "sweep", ("pressure_mean",)), json.loads(args.targets))
    for row in rows:
        if row["status"] == "ok":
            log.info(
                "%s on %s: %.4g mmHg at the %s needs a reduction of %.4g (to be confirmed)",
                row["material"], row["body"], row["target_mmHg"], row["landmark"],
                row["reduction"],
            )  # fmt: skip
        else:
            log.warning("%s on %s: %s", row["material"], row["body"], row["message"])
    write_rows(rows, args.output, DESIGN_HEADER)
    return 0


def _confirm(args: argparse.Namespace) -> int:
    from cloth.sweep import confirm, read_design, write_rows

    rows = confirm(read_design(args.design), args.root)
    header = list(dict.fromkeys(k for row in rows for k in row))
    write_rows(rows, args.output, header or ["material"])
    for row in rows:
        if "confirmed_mmHg" in row:
            log.info(
                "%s on %s, %s: reduction %s gives %.4g mmHg (target %s, error %+.2f %%)",
                row["material"], row["body"], row["landmark"], row["reduction"],
                row["confirmed_mmHg"], row["target_mmHg"], row["error_percent"],
            )  # fmt: skip
    return 0


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 2:
        raise argparse.ArgumentTypeError(f"must be >= 2, got {value}")
    return value


def _force_option(command: argparse.ArgumentParser) -> None:
    command.add_argument(
        "--force", action="store_true",
        help="run even when the estimated peak memory exceeds the free memory (also "
        "CLOTH_FORCE=1; docs/performance.md, 'Guardrails')",
    )  # fmt: skip


def _mesh_options(parser: argparse.ArgumentParser) -> None:
    """A mesh file as a case reads it, and the options of its smooth surface."""
    parser.add_argument("mesh", type=Path, help="mesh file (OBJ, STL, PLY, GLB, ...)")
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

    body = commands.add_parser("body", help="bodies: parametric torso, mesh checks")
    body_commands = body.add_subparsers(dest="body_command", required=True)
    torso = body_commands.add_parser(
        "torso",
        help="write the parametric torso of a size chart as a mesh",
        description="Build the smooth, watertight parametric torso of a size (m, z up).",
    )
    torso.add_argument("--size", required=True, help="size name in the chart (e.g. S, M)")
    torso.add_argument("--chart", type=Path, help="size chart CSV (default data/bodies)")
    for key in ("bust", "underbust", "waist", "hip"):
        torso.add_argument(f"--{key}", type=float, help=f"override the {key} girth, cm")
    torso.add_argument("--around", type=int, default=128, help="mesh points per ring")
    torso.add_argument("--rings", type=int, default=120, help="mesh rings")
    torso.add_argument("-o", "--output", type=Path, required=True, help="mesh file (.ply, .stl)")
    torso.set_defaults(handler=_body_torso)
    check = body_commands.add_parser(
        "check",
        help="check a mesh and print its bounds, height and girth profile",
        description="Load a body mesh as cloth would (units, up axis, checks) and describe it.",
    )
    _mesh_options(check)
    check.add_argument("--levels", type=int, default=10, help="heights in the girth profile")
    check.add_argument(
        "--surface", choices=("smooth", "mesh"), default="smooth",
        help="contact surface: smooth (fit it and report its deviation) or mesh (the facets)",
    )  # fmt: skip
    check.add_argument(
        "--curvature", type=Path, help="write the smooth surface's mean curvature figure (PNG)"
    )
    check.add_argument(
        "--surface-file", type=Path, help="a fitted surface (cloth body fit) to use if it fits"
    )
    check.set_defaults(handler=_body_check)
    fit = body_commands.add_parser(
        "fit",
        help="fit the smooth contact surface of a mesh -> surface.nc",
        description="Fit (or reuse) the smooth contact surface of a mesh body (docs/bodies.md).",
    )
    _mesh_options(fit)
    fit.add_argument("-o", "--output", type=Path, required=True, help="surface file (.nc)")
    fit.set_defaults(handler=_body_fit)

    pre = commands.add_parser(
        "predeform",
        help="case.yaml -> initial.nc (the garment wrapped on the body)",
        description="Cut the pattern of a case and wrap it around the body (docs/config.md).",
    )
    pre.add_argument("case", type=Path, help="case YAML file")
    pre.add_argument("-o", "--output", type=Path, required=True, help="initial.nc to write")
    pre.add_argument(
        "--base-dir", type=Path, help="folder relative paths in the case are relative to "
        "(default: the case file's folder)",
    )  # fmt: skip
    pre.add_argument("--plot", type=Path, help="also write a 3D figure of the wrapped garment")
    _force_option(pre)
    pre.set_defaults(handler=_predeform)

    def solver_options(command: argparse.ArgumentParser) -> None:
        command.add_argument(
            "--method", choices=["explicit", "newton", "explicit+newton"],
            help="relaxation method (default: the case's solver block, else newton)",
        )  # fmt: skip
        command.add_argument("--tolerance", type=float, help="relative residual to stop at")
        command.add_argument("--max-iterations", type=int, help="iteration limit")
        command.add_argument(
            "--linear-solver", choices=["auto", "superlu", "cholmod", "pardiso", "amg"],
            help="Newton's sparse solver (default auto)",
        )  # fmt: skip
        command.add_argument("--log-every", type=int, help="log a line every N iterations")
        command.add_argument(
            "--warm-start", type=int, help="explicit iterations before Newton (explicit+newton)"
        )
        command.add_argument(
            "--base-dir", type=Path, help="folder the case's relative paths are relative to"
        )
        _force_option(command)

    rel = commands.add_parser(
        "relax",
        help="initial.nc -> relaxed.nc (equilibrium on the body)",
        description="Relax a wrapped garment to equilibrium (docs/solvers.md).",
    )
    rel.add_argument("initial", type=Path, help="initial.nc from cloth predeform")
    rel.add_argument("-o", "--output", type=Path, required=True, help="relaxed.nc to write")
    solver_options(rel)
    rel.set_defaults(handler=_relax)

    run = commands.add_parser(
        "run", help="case.yaml -> every stage into a folder: initial.nc, relaxed.nc, "
        "result.nc, summary.csv, figures/ and garment.html",
    )  # fmt: skip
    run.add_argument("case", type=Path, help="case YAML file")
    run.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    run.add_argument(
        "--stop-after", choices=("predeform", "relax", "aggregate"),
        help="stop after this stage (default: run them all)",
    )  # fmt: skip
    solver_options(run)
    run.set_defaults(handler=_run)

    agg = commands.add_parser(
        "aggregate",
        help="relaxed.nc -> result.nc (+ summary.csv): stresses, pressure, landmarks",
        description="Compute node and spring stresses, body pressure and summaries "
        "(docs/outputs.md).",
    )
    agg.add_argument("relaxed", type=Path, help="relaxed.nc from cloth relax")
    agg.add_argument("-o", "--output", type=Path, required=True, help="result.nc to write")
    agg.add_argument("--summary", type=Path, help="also write the landmark summary CSV")
    agg.add_argument(
        "--base-dir", type=Path, help="folder the case's relative paths are relative to"
    )
    agg.set_defaults(handler=_aggregate)

    plot = commands.add_parser("plot", help="result.nc -> figures (PNG) in a folder")
    plot.add_argument("result", type=Path, help="result.nc from cloth aggregate")
    plot.add_argument("-o", "--output", type=Path, required=True, help="folder for the figures")
    plot.add_argument(
        "--stress-range", type=float, nargs=2, metavar=("LOW", "HIGH"),
        help="fixed colour range of the stress maps, Pa (to compare runs)",
    )  # fmt: skip
    plot.add_argument(
        "--pressure-range", type=float, nargs=2, metavar=("LOW", "HIGH"),
        help="fixed colour range of the pressure map, mmHg",
    )  # fmt: skip
    plot.add_argument(
        "--peers", type=Path, nargs="*", default=[], metavar="RESULT",
        help="result.nc files (a sweep's) whose values set the colour ranges not given, so "
        "that the figures of a sweep compare (default: this result's own range)",
    )  # fmt: skip
    plot.set_defaults(handler=_plot)

    view = commands.add_parser(
        "view", help="result.nc -> one self-contained HTML page: body and garment in 3D"
    )
    view.add_argument("result", type=Path, help="result.nc from cloth aggregate")
    view.add_argument("-o", "--output", type=Path, required=True, help="HTML file to write")
    view.set_defaults(handler=_view)

    exp = commands.add_parser("export", help="result.nc -> .ply, .vtu or .csv")
    exp.add_argument("result", type=Path, help="result.nc from cloth aggregate")
    exp.add_argument("-o", "--output", type=Path, required=True, help="file: .ply, .vtu, .csv")
    exp.add_argument("--field", default="stress_weft", help="field coloured in the PLY")
    exp.set_defaults(handler=_export)

    sw = commands.add_parser("sweep", help="results of a sweep -> sweep.nc, sweep.csv, design plot")
    sw.add_argument("--index", required=True, help="JSON list of {case, material, body, reduction}")
    sw.add_argument("--targets", default="[]", help="JSON list of design targets (for the plot)")
    sw.add_argument("--root", type=Path, default=Path("."), help="folder holding results/")
    sw.add_argument("-o", "--output", type=Path, required=True, help="sweep.nc to write")
    sw.add_argument("--csv", type=Path, required=True, help="sweep.csv to write")
    sw.add_argument("--plot", type=Path, required=True, help="design plot to write")
    sw.add_argument(
        "--body-plot", type=Path,
        help="small multiples to write: the pressure on the body per body and reduction",
    )  # fmt: skip
    sw.set_defaults(handler=_sweep)

    de = commands.add_parser("design", help="sweep.nc -> design.csv: the reduction per target")
    de.add_argument("sweep", type=Path, help="sweep.nc from cloth sweep")
    de.add_argument("--targets", required=True, help="JSON list of {landmark, pressure_mmHg}")
    de.add_argument("-o", "--output", type=Path, required=True, help="design.csv to write")
    de.set_defaults(handler=_design)

    co = commands.add_parser("confirm", help="design.csv + confirmation results -> errors")
    co.add_argument("design", type=Path, help="design.csv from cloth design")
    co.add_argument("--root", type=Path, default=Path("."), help="folder holding results/")
    co.add_argument("-o", "--output", type=Path, required=True, help="confirmed CSV to write")
    co.set_defaults(handler=_confirm)

    case = commands.add_parser("case", help="case files: check, write")
    case_commands = case.add_subparsers(dest="case_command", required=True)
    case_check = case_commands.add_parser(
        "check", help="validate a case file and print it with defaults filled"
    )
    case_check.add_argument("case", type=Path, help="case YAML file")
    case_check.set_defaults(handler=_case_check)
    case_write = case_commands.add_parser(
        "write", help="validate a case given as JSON and write it as YAML (used by the pipeline)"
    )
    case_write.add_argument("--json", required=True, help="the case as a JSON object")
    case_write.add_argument("-o", "--output", type=Path, required=True, help="case YAML to write")
    case_write.set_defaults(handler=_case_write)
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
    from cloth.io import set_command

    set_command(["cloth", *(sys.argv[1:] if argv is None else argv)])
    handler: Handler = args.handler
    try:
        return handler(args)
    except InputError as exc:
        print(f"cloth: error: {exc}", file=sys.stderr)
        return EXIT_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
