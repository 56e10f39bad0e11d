"""The result stages: relaxed.nc -> result.nc and summary.csv (`aggregate`, `write_result`),
result.nc -> figures (`figures`) and the interactive view (`view`). `cloth.results.fields` computes,
`cloth.files.result` lays out the result file; the stages join them to the files.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.figures.drawing import body_band  # no matplotlib: a view draws with plotly
from cloth.figures.ranges import RANGE_FIELDS, read_ranges, shared_ranges
from cloth.files import levels
from cloth.files.body import body_from_record
from cloth.files.result import (
    region_variables,
    result_dataset,
    sensor_variables,
    summary_rows,
    write_summary,
)
from cloth.files.skin import result_skin_variables
from cloth.files.state import read_state
from cloth.garment.grid import WEFT
from cloth.garment.mechanics import spring_state
from cloth.io import read_fields, read_netcdf, write_netcdf
from cloth.results.fields import lab_range_variables, node_average, node_fields
from cloth.results.landmarks import (
    band_half_widths,
    landmark_heights,
    landmarks,
    sensor_readings,
)
from cloth.results.regions import Region, regions
from cloth.results.resolution import mesh_spacing, row_spacing
from cloth.solvers.problem import Evaluation, Problem
from cloth.solvers.stability import unstable_modes

log = logging.getLogger(__name__)


def aggregate(relaxed_path: str | Path) -> tuple[xr.Dataset, list]:
    """relaxed.nc -> (result dataset, summary rows): the stage's function.

    Rebuilds the model and body from the state file, evaluates the final positions (forces,
    contact, normals) and computes every field, landmark and total.
    """
    state, ds = read_state(relaxed_path, "relaxed")
    body = body_from_record(state.body, relaxed_path)
    problem = Problem.of(state, body)
    ev = problem.evaluate(state.x)
    fields = node_fields(
        state.grid,
        state.x,
        ev.springs,
        state.fabric.thickness,
        ev.forces,
        ev.unbalanced,
        ev.on_body,
        ev.normal,
        state.constraint,
    )
    reading = state.case.reading
    widths = band_half_widths(state)
    marks = landmarks(landmark_heights(state), state.x, fields, state.grid, reading, widths)
    result = result_dataset(state, fields, marks, ds)
    result = result.assign(sensor_variables(reading, sensor_readings(reading, state.x, fields)))
    found = regions(
        fields.strain_warp,
        fields.on_body,
        state.x,
        fields.area,
        state.grid.m,
        {mark.name: mark.height for mark in marks},
        reading.half_width,
    )
    result = result.assign(region_variables(found, marks, (state.grid.m, state.grid.n)))
    _log_regions(found, state.case.contact.friction)
    result = result.assign(_estimates(state, marks, ds))
    result = result.assign(_resolution(state, body, marks))
    if "x_initial" in ds:
        start = np.stack([ds[f"{a}_initial"].values.ravel() for a in "xyz"], axis=1)
        before = node_average(state.grid, spring_state(start, state.grid).stress, WEFT)
        result = result.assign(
            {f"{a}_initial": ds[f"{a}_initial"].variable for a in "xyz"}
            | {
                "stress_weft_initial": (
                    ("row", "col"),
                    before.reshape(state.grid.m, state.grid.n),
                    {"units": "Pa", "long_name": "weft stress before relaxation"},
                )
            }
        )
    result = result.assign(lab_range_variables(state, ev.springs.strain))
    result = result.assign(result_skin_variables(state.grid, ev, ds, problem.tissue))
    result.attrs["unstable_modes"] = stability(problem, ev, ds.attrs.get("solver_unstable_modes"))
    name = Path(relaxed_path).parent.name
    return result, summary_rows(result, name)


def _log_regions(found: tuple[Region, ...], friction: float) -> None:
    """One log line per region that meets a girth line (`cloth.results.regions`)."""
    words = {
        "slack_warp": "the warp is slack (the fabric gathers)",
        "off_body": "the garment lifts off the body (it bridges)",
    }
    for item in found:
        if not item.share:
            continue
        spans = ", ".join(f"{1e3 * low:.0f}-{1e3 * high:.0f} mm" for low, high in item.ranges)
        log.info(
            "%s on %.1f %% of the garment's area, at heights %s",
            words[item.name],
            100 * item.share,
            spans,
        )
        if item.lines and not friction:
            log.warning(
                "%s at the girth line%s %s: the pressure there depends on the skin's friction, "
                "which this frictionless model leaves out (contact.friction)",
                words[item.name],
                "" if len(item.lines) == 1 else "s",
                ", ".join(item.lines),
            )


def _estimates(state, marks: list, relaxed: xr.Dataset) -> dict[str, xr.Variable]:
    """The error estimate of every girth-line value from the levels relaxed.nc holds, and the
    levels with the reported grid first (`cloth.files.levels`); logged per line."""
    names = [mark.name for mark in marks]
    grid = (state.grid.n, state.grid.m)
    grids, converged, values = levels.read_levels(relaxed, names)
    found = levels.estimates(marks, grid, grids, values)
    if grids:
        levels.log_estimates(names, found)
    else:
        log.info("no coarser levels in %s: the girth lines have no error estimate", grid)
    fine = levels.mark_values([marks], names)
    stacked = {f: np.concatenate([fine[f], values[f]]) if values else fine[f] for f in fine}
    converged = [bool(int(relaxed.attrs.get("solver_converged", 0))), *converged]
    return levels.estimate_variables(found) | levels.level_variables(
        [grid, *grids], converged, stacked
    )


def _resolution(state, body, marks: list) -> dict[str, xr.Variable]:
    """The garment's row spacing at each girth line and, on a mesh body, the mesh's vertical
    sampling there (`cloth.results.resolution`), logged where the mesh is the coarser."""
    heights = np.array([mark.height for mark in marks])
    rows_z = state.x.reshape(state.grid.m, state.grid.n, 3)[..., 2].mean(axis=1)
    rows = row_spacing(rows_z, heights) if len(marks) and state.grid.m > 1 else heights * np.nan
    faces = getattr(body, "faces", None)
    mesh = None if faces is None else mesh_spacing(np.asarray(body.vertices), faces, heights)
    if mesh is not None:
        for mark, row, step in zip(marks, rows, mesh, strict=True):
            if step > row:
                log.info(
                    "%s: the mesh's vertices are %.3g mm apart in height there, the garment's "
                    "rows %.3g mm: between them the body is the fitted surface's interpolation, "
                    "which the error estimate (the garment's grid on a fixed surface) does not "
                    "include",
                    mark.name,
                    1e3 * step,
                    1e3 * row,
                )
    return levels.resolution_variables(rows, mesh)


def stability(problem: Problem, ev: Evaluation, counted: int | None = None) -> int:
    """The equilibrium's unstable modes: ``counted`` by relax from its last factor where it
    did (relaxed.nc's ``solver_unstable_modes``), else `cloth.solvers.stability.unstable_modes`
    (one factorisation; -1 where they are not defined: faceted contact, tissue, friction; or
    not found: a matrix SuperLU had to pivot or found singular). A saddle is warned of with
    what it means for the numbers (docs/model.md, "Compressed fabric")."""
    if counted is not None:
        modes = int(counted)
    else:
        try:
            modes = unstable_modes(problem, ev)
        except (ValueError, RuntimeError) as exc:
            log.debug("unstable modes not counted: %s", exc)
            return -1
    if modes:
        log.warning(
            "the equilibrium is a saddle: %d unstable mode%s. The garment is balanced there but "
            "would not stay: a nearby state of lower energy exists, and another solver path may "
            "end on it, so the reported pressures are those of one balanced state, not the "
            "garment's settled one (docs/model.md, Compressed fabric)",
            modes,
            "" if modes == 1 else "s",
        )
    return modes


def figures(
    result_path: str | Path,
    folder: str | Path,
    peers: list[str | Path] | tuple = (),
    stress_range: tuple[float, float] | None = None,
    pressure_range: tuple[float, float] | None = None,
    ranges: str | Path | None = None,
) -> list[Path]:
    """result.nc -> every figure of `cloth.figures.plots.FIGURES` in ``folder``: the flat maps, the
    profiles and the garment on the body. Colour ranges: ``stress_range`` (Pa) and
    ``pressure_range`` (mmHg) where given, else those of the colour-range file ``ranges`` (its
    sweep's, `cloth.figures.ranges`: the pipeline's), else the range over ``peers`` (the result
    files of the case's sweep, so that its figures compare) and the result itself."""
    # matplotlib takes ~0.4 s to import, which relax and aggregate need not pay: imported here
    from cloth.figures import onbody  # late: matplotlib (above)
    from cloth.figures.plots import plot_result  # late: matplotlib (above)

    ds = read_netcdf(result_path, "result", ("stress_weft", "pressure", "u", "v"))
    if ranges is not None:
        shared_stress, shared_pressure = read_ranges(ranges)
    else:
        others = [read_fields(p, "result", RANGE_FIELDS) for p in peers]
        shared_stress, shared_pressure = shared_ranges([ds, *others])
    stress_range = stress_range or shared_stress
    pressure_range = pressure_range or shared_pressure
    paths = plot_result(ds, folder, stress_range, pressure_range)
    body = body_band(ds)
    for name, (variable, scale, _) in onbody.FIELDS.items():
        low, high = pressure_range if variable == "pressure_mmHg" else stress_range
        scale = 1.0 if variable == "pressure_mmHg" else scale
        shown = (low * scale, high * scale)
        paths.append(onbody.plot_on_body(ds, name, Path(folder) / f"{name}.png", shown, body))
    return paths


def write_result(
    relaxed_path: str | Path, output: str | Path, summary: str | Path | None = None
) -> xr.Dataset:
    """relaxed.nc -> result.nc (and the landmark summary CSV): the aggregate stage's files;
    logs each girth line's pressure, and warns if the relaxation did not converge."""
    import logging

    log = logging.getLogger("cloth")
    ds, rows = aggregate(relaxed_path)
    write_netcdf(ds, output)
    if summary:
        write_summary(rows, summary)
    if not int(ds.attrs["converged"]):
        log.warning("%s: the relaxation did not converge; results are marked so", relaxed_path)
    for row in rows:
        judged = "".join(
            f", {label} {text(row[key])}"
            for key, label, text in (
                ("compression_class", "class", str),
                ("share_of_class_point", "share", lambda v: f"{float(v):.3g} of the class point's"),
                ("pressure_band", "band", str),
            )
            if row.get(key) not in (None, "")
        )
        log.info(
            "%s: pressure mean %.4g Pa (%.3g mmHg%s), max %.3g mmHg",
            row["landmark"],
            row["pressure_mean_Pa"],
            row["pressure_mean_mmHg"],
            judged,
            row["pressure_max_mmHg"],
        )
    return ds


def view(result: str | Path | xr.Dataset, output: str | Path) -> Path:
    """result.nc (or its dataset) -> the interactive HTML view over its body
    (`cloth.figures.view`)."""
    from cloth.figures.view import write_view  # as in `figures`

    ds = (
        result
        if isinstance(result, xr.Dataset)
        else (read_netcdf(result, "result", ("x", "y", "z", "pressure_mmHg")))
    )
    return write_view(ds, output, body_band(ds))
