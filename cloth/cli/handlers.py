"""The ``cloth`` command's handlers: each turns parsed arguments into one call of a stage
(`cloth.stages`) or of the library, and returns the exit status.

Each handler imports its stage when it runs, not at the module's top: ``cloth --version``,
``--help`` and a refused argument import none of them (measured in
tests/test_cli_startup.py; the numerical stack costs about 1.5 s to import)."""

from __future__ import annotations

import argparse
import logging
from collections.abc import Callable
from pathlib import Path

from cloth.errors import InputError

log = logging.getLogger("cloth")

Handler = Callable[[argparse.Namespace], int]


def _required(args: argparse.Namespace, dest: str, what: str) -> None:
    """Refuse a missing input that may come from the line or from ``--json``."""
    if getattr(args, dest) in (None, []):
        raise InputError(f"give {what}", field=dest)


def material_ingest(args: argparse.Namespace) -> int:
    from cloth.materials.labtables import IngestOptions
    from cloth.stages.inputs import ingest_material

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


def body_torso(args: argparse.Namespace) -> int:
    from cloth.stages.inputs import torso_file

    _required(args, "size", "--size, or --json with a torso block")
    girths = {
        k: getattr(args, k)
        for k in ("bust", "underbust", "waist", "hip")
        if getattr(args, k) is not None
    }
    torso_file(args.size, args.chart, girths, args.around, args.rings, args.output)
    return 0


def body_leg(args: argparse.Namespace) -> int:
    from cloth.stages.inputs import leg_file

    leg_file(args.size, args.chart, args.around, args.rings, args.output)
    return 0


def _fit_options(args: argparse.Namespace):  # -> FitOptions, imported when used
    from cloth.bodies.surface import FitOptions

    region = None if args.region is None else tuple(args.region)
    return FitOptions(args.smoothing, args.spacing, args.refine, args.denoise, region)


def body_check(args: argparse.Namespace) -> int:
    from cloth.stages.bodycheck import describe

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


def body_fit(args: argparse.Namespace) -> int:
    from cloth.files.avatar import load_mesh
    from cloth.files.surface import load_or_fit

    _required(args, "mesh", "the mesh file, or --json with a mesh body block")
    mesh, _ = load_mesh(args.mesh, args.units, args.up, args.repair, allow_holes=True)
    _, place = load_or_fit(mesh, _fit_options(args), args.output)
    if args.output is not None and Path(place).resolve() != Path(args.output).resolve():
        import shutil

        from cloth.io import atomic_output

        with atomic_output(args.output) as tmp:  # the fit was in the cache: -o gets it too
            shutil.copyfile(place, tmp)
        log.info("wrote %s (the fit from %s)", args.output, place)
    return 0


def body_avatar(args: argparse.Namespace) -> int:
    from cloth.stages.inputs import avatar_file

    avatar_file(args.chart, args.size, args.output, args.full)
    return 0


def body_wearers(args: argparse.Namespace) -> int:
    from cloth.files.population import AGES
    from cloth.stages.inputs import wearers_folder

    population = {"default": "default", "none": None}.get(args.population, args.population)
    if population not in ("default", None):
        population = Path(population)
    ages = AGES if args.ages is None else tuple(args.ages)
    wearers_folder(args.chart, args.size, args.output, population, ages)
    return 0


def wearers(args: argparse.Namespace) -> int:
    from cloth.stages.wearers import run_wearers

    run_wearers(args.case, args.output, _overrides(args), args.wearers, args.base_dir)
    return 0


def sizes(args: argparse.Namespace) -> int:
    from cloth.files.population import AGES
    from cloth.results.pressure import MMHG
    from cloth.results.targets import Target
    from cloth.stages.sizerequest import Request, bands_of, population_of, sizing_names
    from cloth.stages.sizes import design_sizes
    from cloth.stages.sizetables import write_sizes

    bands = bands_of([Target.parse(t) for t in args.target])
    by = sizing_names(args.by) if args.by is not None else (bands[0].line,)
    request = Request(
        population=population_of(args.case, args.population),
        bands=bands,
        by=by,
        coverage=args.coverage,
        max_sizes=args.max_sizes,
        variants=args.max_variants,
        ages=AGES if args.ages is None else tuple(args.ages),
        margin=None if args.margin is None else args.margin * MMHG,
        rounds=args.rounds,
    )
    outcome = design_sizes(args.case, request, args.output, _overrides(args))
    write_sizes(outcome, args.output, fail=not args.report_unmet)
    return 0


def compare(args: argparse.Namespace) -> int:
    from cloth.errors import InputError

    inputs = args.inputs
    if len(inputs) == 1 and inputs[0].suffix in (".yaml", ".yml"):
        from cloth.stages.study import run_study

        run_study(inputs[0], args.output, _overrides(args))
        return 0
    if len(inputs) != 2:
        raise InputError(
            f"got {len(inputs)} files; give RESULT.nc MEASURED.csv, or one STUDY.yaml",
            field="compare",
        )
    from cloth.stages.compare import compare as compare_files

    compare_files(inputs[0], inputs[1], args.output)
    return 0


def calibrate(args: argparse.Namespace) -> int:
    from cloth.errors import InputError
    from cloth.results.pressure import MMHG
    from cloth.stages.calibrate import NOISE, fit, parameter_names, write_calibration

    if args.noise is not None and args.noise <= 0:
        raise InputError(f"the noise must be above 0 mmHg, got {args.noise:g}", field="--noise")
    noise = NOISE if args.noise is None else args.noise * MMHG
    names = parameter_names(args.fit)
    found = fit(args.case, args.measured, names, args.base_dir, _overrides(args), noise)
    base_dir = args.case.parent if args.base_dir is None else args.base_dir
    write_calibration(found, args.measured, args.output, base_dir)
    return 0


def wearers_report(args: argparse.Namespace) -> int:
    import json

    from cloth.case.judge import Judge
    from cloth.files.wearers import read_index
    from cloth.stages.wearers import report_files

    results = {}
    for text in args.results:
        name, sep, path = text.partition("=")
        if not sep or not name or not path:
            raise InputError(f"{text!r}: give NAME=RESULT.nc", field="results")
        results[name] = Path(path)
        if not results[name].is_file():
            raise InputError("result file not found; check the path", path, "results")
    import xarray as xr

    with xr.open_dataset(next(iter(results.values()))) as first:
        case = json.loads(str(first.attrs.get("case", "{}")))
    report_files(
        results, read_index(args.index.parent), args.output, Judge.from_block(case.get("judge"))
    )
    return 0


def predeform(args: argparse.Namespace) -> int:
    from cloth.stages.case import predeform_file

    predeform_file(args.case, args.output, args.base_dir, args.plot, args.force)
    return 0


def case_write(args: argparse.Namespace) -> int:
    import json

    from cloth.case.case import validate_case
    from cloth.files.casefile import write_case

    try:
        case = json.loads(args.json)
    except json.JSONDecodeError as exc:
        raise InputError(f"not valid JSON ({exc.msg})", field="--json") from None
    write_case(validate_case(case, args.output), args.output, args.base_dir)
    return 0


def case_check(args: argparse.Namespace) -> int:
    import yaml

    from cloth.case.case import load_case

    print(yaml.safe_dump(load_case(args.case).to_dict(), sort_keys=False), end="")
    return 0


def _overrides(args: argparse.Namespace) -> dict:
    """The solver keys given on the command line (on top of the case's solver block)."""
    from cloth.stages.case import SOLVER_KEYS

    return {k: getattr(args, k) for k in SOLVER_KEYS if getattr(args, k, None) is not None}


def relax(args: argparse.Namespace) -> int:
    from cloth.stages.case import relax_file

    relax_file(args.initial, args.output, _overrides(args), args.force)
    return 0


def run(args: argparse.Namespace) -> int:
    from cloth.stages.case import run_case

    run_case(args.case, args.output, _overrides(args), args.base_dir, args.stop_after, args.force)
    return 0


def aggregate(args: argparse.Namespace) -> int:
    from cloth.stages.results import write_result

    write_result(args.relaxed, args.output, args.summary)
    return 0


def plot(args: argparse.Namespace) -> int:
    from cloth.stages.results import figures

    figures(
        args.result, args.output, args.peers, args.stress_range, args.pressure_range, args.ranges
    )
    return 0


def ranges(args: argparse.Namespace) -> int:
    from cloth.figures.ranges import write_ranges

    stress, pressure = write_ranges(args.results, args.output)
    log.info(
        "colour ranges of %d results: stress %.4g-%.4g Pa, pressure %.4g-%.4g mmHg -> %s",
        len(args.results),
        *stress,
        *pressure,
        args.output,
    )
    return 0


def view(args: argparse.Namespace) -> int:
    from cloth.stages.results import view

    view(args.result, args.output)
    return 0


def export(args: argparse.Namespace) -> int:
    from cloth.figures.export import export
    from cloth.io import read_netcdf

    export(read_netcdf(args.result, "result", ("x", "y", "z")), args.output, args.field)
    log.info("wrote %s", args.output)
    return 0


def pattern(args: argparse.Namespace) -> int:
    from cloth.stages.patterns import write_patterns

    write_patterns(
        args.result,
        args.output,
        args.cut,
        args.formats,
        args.sizes,
        args.seam_allowance,
        args.paper,
        args.note,
        args.course_step,
    )
    return 0


def sweep(args: argparse.Namespace) -> int:
    import json

    from cloth.stages.sweep import sweep_files

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


def design(args: argparse.Namespace) -> int:
    import json

    from cloth.results.pressure import MMHG
    from cloth.results.targets import Target
    from cloth.stages.chart import chart_sizes, design_chart, file_sizes
    from cloth.stages.graded import design_files
    from cloth.stages.sweep import design_file

    first = args.input[0]
    if first.suffix == ".nc":
        if len(args.input) > 1:
            raise InputError("a sweep's design takes one sweep.nc", args.input[1], "input")
        if args.target or args.targets is None:
            raise InputError(
                "a sweep's design takes --targets JSON, not --target; --target designs a case",
                first,
                "--targets",
            )
        design_file(first, json.loads(args.targets), args.output)
        return 0
    if args.targets is not None:
        raise InputError(
            "a case's design takes --target LINE=PRESSURE (repeat per line), not --targets",
            first,
            "--target",
        )
    if not (args.tolerance > 0 and args.tolerance < float("inf")):
        raise InputError(
            f"must be a positive number of mmHg, got {args.tolerance}", field="--tolerance"
        )
    targets = [Target.parse(text) for text in args.target]
    if args.panel is not None:
        from cloth.stages.paneldesign import panel_files

        if len(args.input) > 1 or args.sizes is not None or args.wearers is not None:
            raise InputError("--panel designs one case's panel", field="--panel")
        if len(targets) != 1 or targets[0].band is not None:
            raise InputError(
                "--panel meets one target, LINE=PRESSURE (a panel's width is one control)",
                field="--target",
            )
        panel_files(
            first, targets[0], args.panel, args.output, args.tolerance * MMHG, args.base_dir
        )
        return 0
    if args.wearers is not None:
        from cloth.stages.wearerdesign import robust_files

        if len(args.input) > 1 or args.sizes is not None:
            raise InputError("--wearers designs one case's size", field="--wearers")
        folder = None if args.wearers == "shipped" else Path(args.wearers)
        robust_files(first, targets, args.output, folder, args.base_dir, fail=not args.report_unmet)
        return 0
    bands = [t.line for t in targets if t.band is not None]
    if bands:
        raise InputError(
            f"a band ({bands[0]}=LOW:HIGH) is for a robust design over the wearers; add "
            "--wearers, or give one pressure",
            field="--target",
        )
    options = {"cut": args.cut, "allowance": args.seam_allowance, "paper": args.paper}
    if args.band_ratio_max is not None:
        if not (args.band_ratio_max > 0 and args.band_ratio_max < float("inf")):
            raise InputError(
                f"must be a positive ratio, got {args.band_ratio_max}", field="--band-ratio-max"
            )
        if args.sizes is not None or len(args.input) > 1:
            raise InputError("--band-ratio-max designs one case", field="--band-ratio-max")
        options["band_ratio"] = args.band_ratio_max
    if args.sizes is not None and len(args.input) > 1:
        raise InputError(
            "--sizes takes one case on a chart's body; several case files are one size each",
            field="--sizes",
        )
    if args.sizes is None and len(args.input) == 1:
        design_files(first, targets, args.output, args.tolerance * MMHG, args.base_dir, **options)
        return 0
    sizes = (
        chart_sizes(first, args.sizes, args.base_dir)
        if args.sizes is not None
        else file_sizes(args.input, args.base_dir)
    )
    design_chart(sizes, targets, args.output, args.tolerance * MMHG, cold=args.cold, **options)
    return 0


def confirm(args: argparse.Namespace) -> int:
    from cloth.stages.sweep import confirm_file

    confirm_file(args.design, args.results, args.output, args.iterate)
    return 0


def init(args: argparse.Namespace) -> int:
    from cloth.stages.project import init_project

    init_project(args.folder)
    return 0


def pipeline(args: argparse.Namespace) -> int:
    from cloth.stages.project import pipeline as run_pipeline

    return run_pipeline(args.configfile, args.snakemake_args)
