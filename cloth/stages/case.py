"""The per-case stages before the results: a case file -> initial.nc (`predeform_file`),
initial.nc -> relaxed.nc (`relax_file`), and every stage into one folder (`run_case`).

Each checks first that the case fits the machine's free memory (`cloth.pipeline.guard`;
``force`` runs it anyway) and writes its files atomically.
"""

from __future__ import annotations

import importlib.util
import json
import logging
from dataclasses import replace
from pathlib import Path

import xarray as xr

from cloth.case import Case
from cloth.case.case import load_case, validate_case
from cloth.errors import EXIT_DIVERGED, InputError, StageFailed
from cloth.files.body import body_from_config, body_from_record
from cloth.files.levels import level_variables, mark_values
from cloth.files.material import case_fabric, piece_fabrics
from cloth.files.relaxed import relaxed_dataset
from cloth.files.state import read_state, state_dataset
from cloth.garment.cut import placement
from cloth.garment.mechanics import spring_state
from cloth.garment.predeform import predeform
from cloth.garment.state import State
from cloth.io import write_netcdf
from cloth.pipeline import guard
from cloth.results.landmarks import landmark_heights
from cloth.solvers import Diverged, relax
from cloth.solvers.problem import Problem
from cloth.solvers.relax import Result
from cloth.stages.cuts import case_cut
from cloth.stages.levels import LEVELS, Level, ladder, refine, relax_ladder, relax_levels

log = logging.getLogger("cloth")

#: Keys of a case's ``solver`` block that a command line may override.
SOLVER_KEYS = ("method", "tolerance", "max_iterations", "linear_solver", "log_every", "warm_start")


def check_fits(stages: tuple[str, ...], case: Case, base_dir: Path, source, force: bool):
    """Refuse (`InputError`) a case whose estimated memory in ``stages`` exceeds the free."""
    solved = {"relax", "aggregate"} & set(stages)  # where the backend matters
    cholesky = bool(solved) and guard.takes_cholesky(case, base_dir)
    guard.check_fits(stages, *guard.case_counts(case, base_dir), source, force, cholesky)


def _check_record_fits(stage: str, nodes: int, record: dict, source, force: bool) -> None:
    faces = guard.mesh_faces(record["path"]) if record.get("kind") == "mesh" else 0
    guard.check_fits((stage,), nodes, faces, source, force)


def initial_state(case: Case | dict, base_dir: str | Path = ".", source: str = "case") -> State:
    """The initial state of a case (a `Case`, or a mapping validated here): its fabric and
    body read from the files it names, relative to ``base_dir``, then
    `cloth.garment.predeform.predeform`."""
    case = validate_case(case, source)
    try:
        fabric = case_fabric(case, base_dir)
        garment = case.garment
        span = (garment.bottom, garment.top)
        body, record = body_from_config(case.body.block, base_dir, span, garment.loop_point)
        pattern, pattern_record = case_cut(case, base_dir, source)
        if pattern is not None:  # the wearer's surface over the rows where the pattern sits
            marks = {**record.get("landmarks", {}), **case.landmarks}
            shift = placement(garment.place, pattern.lines, marks, source)[1]
            if shift:
                span = (garment.bottom + shift, garment.top + shift)
                body, record = body_from_config(case.body.block, base_dir, span, garment.loop_point)
        fabrics = piece_fabrics(case, base_dir)
        state = predeform(case, fabric, body, record, source, pattern=pattern, fabrics=fabrics)
        if pattern_record is not None:
            state.attrs["pattern_body"] = json.dumps(pattern_record)
        return state
    except InputError as exc:  # what the case names or asks for: the case is where to fix it
        if exc.source is not None:
            raise
        raise InputError(exc.detail, source, exc.field) from None


def predeform_file(
    case_path: Path,
    output: Path,
    base_dir: Path | None = None,
    plot: Path | None = None,
    force: bool = False,
):
    """case.yaml -> initial.nc (and a 3D figure of the wrapped garment); returns the state.
    Relative paths in the case are relative to ``base_dir`` (default: the case's folder)."""
    case = load_case(case_path)
    base_dir = case_path.parent if base_dir is None else base_dir
    check_fits(("predeform",), case, base_dir, case_path, force)
    state = initial_state(case, base_dir, str(case_path))
    write_netcdf(state_dataset(state, "initial"), output)
    log.info("wrote %s", output)
    if plot:
        _plot_wrapped(state, plot, case_path.stem)
    return state


def _plot_wrapped(state, path: Path, name: str) -> None:
    # late: matplotlib takes ~0.4 s to import, which relax (same module) need not pay
    from cloth.figures.plots import plot_garment_3d  # late: matplotlib (above)

    grid = state.grid
    strain = spring_state(state.x, grid).strain[grid.family_slices[0]]
    body = body_from_record(state.body)
    plot_garment_3d(
        state.x,
        grid.n,
        grid.m,
        strain,
        "initial weft strain [1]",
        path,
        body,
        title=f"{name}: garment wrapped on the body (before relaxation)",
    )


def relax_state(state, overrides: dict, output: Path, previous: dict | None = None) -> None:
    """Relax ``state`` (its case's solver block, ``overrides`` on top) on the body its record
    names, with the coarser levels of its error estimate (`cloth.stages.levels`; with
    ``grid: auto``, the grids refined until the case's accuracy), and write relaxed.nc. A
    divergence writes the last finite state to ``*.diverged.nc`` and raises `StageFailed`."""
    settings = replace(state.case.solver, **overrides)
    body = body_from_record(state.body, output)
    garment = state.case.garment
    refined, solved = None, None
    try:
        if garment.auto:
            refined = refine(state, body, settings, garment.accuracy, garment.max_nodes)
            state, result = refined.state, refined.result
        elif garment.error_estimate and ladder(state, settings):
            result, solved = relax_ladder(state, body, settings, LEVELS)
        else:
            result = relax(state, body, settings)
    except Diverged as exc:
        failed = output.with_name(output.stem + ".diverged.nc")
        run = Result.diverged(exc, Problem.of(state, body).evaluate(exc.x), settings)
        write_netcdf(relaxed_dataset(state, run, settings, previous, stage="diverged"), failed)
        raise StageFailed(
            f"relaxation diverged ({exc}); the last finite state is in {failed}; try method "
            "explicit+newton or a smaller reduction",
            EXIT_DIVERGED,
        ) from None
    ds = relaxed_dataset(state, result, settings, previous)
    relaxed = state.with_positions(result.final.x)
    heights = landmark_heights(relaxed)
    if refined is not None:
        ds = ds.assign(levels_dataset(refined.levels, heights))
        ds.attrs.update(
            grid_auto=1,
            grid_accuracy=garment.accuracy,
            grid_max_nodes=garment.max_nodes,
            grid_met=refined.met,
            grid_worst_error=refined.worst,
        )
    elif solved is not None:
        levels = [level.level(heights, body) for level in solved]
        ds = ds.assign(levels_dataset(levels, heights))
    elif garment.error_estimate:
        levels = relax_levels(relaxed, body, settings, heights, LEVELS)
        ds = ds.assign(levels_dataset(levels, heights))
    write_netcdf(ds, output)
    log.info("wrote %s", output)


def levels_dataset(levels: list[Level], heights: dict[str, float]) -> xr.Dataset:
    """relaxed.nc's level variables (`cloth.files.levels`) of ``levels``, along the relaxed
    state's girth lines ``heights`` (name -> m; none without levels)."""
    if not levels:
        return xr.Dataset()
    names = sorted(heights, key=heights.__getitem__)
    values = mark_values([level.marks for level in levels], names)
    variables = level_variables([lv.grid for lv in levels], [lv.converged for lv in levels], values)
    return xr.Dataset(variables, coords={"landmark": ("landmark", names)})


def relax_file(initial: Path, output: Path, overrides: dict, force: bool = False) -> None:
    """initial.nc -> relaxed.nc, on the body the file records (no base directory needed); the
    memory check reads the case and body from the file's header before its arrays."""
    try:
        with xr.open_dataset(initial) as head:
            nodes = int(head.attrs["n"]) * int(head.attrs["m"])
            record = json.loads(head.attrs["body"])
    except Exception:  # read_state reports an unreadable file in one line
        record = None
    if record is not None:
        _check_record_fits("relax", nodes, record, initial, force)
    state, ds = read_state(initial)
    relax_state(state, overrides, output, dict(ds.attrs))


def run_case(
    case_path: Path,
    folder: Path,
    overrides: dict,
    base_dir: Path | None = None,
    stop_after: str | None = None,
    force: bool = False,
) -> None:
    """Every stage of one case into ``folder``: initial.nc, relaxed.nc, result.nc, summary.csv,
    figures/ and garment.html (where plotly is installed); ``stop_after`` one of predeform,
    relax, aggregate."""
    case = load_case(case_path)
    base_dir = case_path.parent if base_dir is None else base_dir
    check_fits(("predeform", "relax", "aggregate", "figures"), case, base_dir, case_path, force)
    state = initial_state(case, base_dir, str(case_path))
    initial = state_dataset(state, "initial")
    write_netcdf(initial, folder / "initial.nc")
    if stop_after == "predeform":
        return
    relax_state(state, overrides, folder / "relaxed.nc", dict(initial.attrs))
    if stop_after == "relax":
        return
    from cloth.stages.results import figures, view, write_result  # drawing: not for predeform

    result = write_result(folder / "relaxed.nc", folder / "result.nc", folder / "summary.csv")
    if stop_after == "aggregate":
        return
    figures(folder / "result.nc", folder / "figures")
    if importlib.util.find_spec("plotly") is not None:
        view(result, folder / "garment.html")
    else:
        log.warning("plotly is not installed: no garment.html (pip install 'cloth[view]')")
