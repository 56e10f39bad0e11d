"""The sweep stages: every case's result -> sweep.nc, sweep.csv and the figures of the sweep
(`sweep_files`), sweep.nc -> design.csv (`design_file`), the confirmation runs -> their errors
(`confirm_file`). The logic is `cloth.pipeline.sweep`'s; these join it to the files."""

from __future__ import annotations

import logging
from pathlib import Path

from cloth.figures.onbody import plot_sweep_on_body
from cloth.io import read_netcdf, write_netcdf
from cloth.pipeline.designplots import plot_design
from cloth.pipeline.sweep import (
    collect,
    confirm,
    design,
    design_header,
    read_design,
    sweep_rows,
    write_rows,
)
from cloth.pipeline.variants import Variant
from cloth.stages.secant import iterate_row

log = logging.getLogger("cloth")


def sweep_files(
    index: list[dict],
    results: list[Path],
    targets: list[dict],
    output: Path,
    csv: Path,
    plot: Path,
    body_plot: Path | None = None,
) -> None:
    """The ``results`` (a result.nc each) of the cases in ``index`` (case, material, body,
    reduction, variant keys; in its order) -> sweep.nc, sweep.csv, the design plot and the small
    multiples on the body."""
    ds = collect(index, results)
    write_netcdf(ds, output)
    rows = sweep_rows(ds)
    write_rows(rows, csv, list(rows[0]) if rows else ["material"])
    plot_design(ds, targets, plot)
    if body_plot:
        several = len({entry["material"] for entry in index}) > 1

        def label(e: dict) -> str:
            parts = [e["material"], e["body"]] if several else [e["body"]]
            return ", ".join(part for part in (*parts, Variant.of(e).label()) if part)

        cases = [
            (label(e), float(e["reduction"]), read_netcdf(path, "result"))
            for e, path in zip(index, results, strict=True)
        ]
        plot_sweep_on_body(cases, body_plot)


def design_file(sweep: Path, targets: list[dict], output: Path) -> None:
    """sweep.nc -> design.csv: the reduction that meets each target, interpolated (logged)."""
    rows = design(read_netcdf(sweep, "sweep", ("pressure_mean",)), targets)
    for row in rows:
        variant = Variant.of(row).label()
        where = f"{row['material']} on {row['body']}" + (f" ({variant})" if variant else "")
        if row["status"] == "ok":
            log.info(
                "%s: %.4g mmHg at the %s needs a reduction of %.4g +- %.2g (the girth line's "
                "discretisation error; to be confirmed)",
                where,
                row["target_mmHg"],
                row["landmark"],
                row["reduction"],
                row["reduction_error"],
            )
        else:
            log.warning("%s: %s", where, row["message"])
    write_rows(rows, output, design_header(rows))


def confirm_file(
    design: Path, results: list[Path], output: Path, iterate: Path | None = None
) -> None:
    """design.csv and the confirmation cases' ``results`` (a result.nc per answered row, in its
    order) -> the confirmed CSV; with ``iterate`` (a folder), each answer missing its target by
    more than its stated error is confirmed again by a secant into it (`cloth.stages.secant`)."""
    design_rows = read_design(design)
    rows = confirm(design_rows, results)
    if iterate is not None:
        iterate.mkdir(parents=True, exist_ok=True)
        answered = iter(results)
        for source, row in zip(design_rows, rows, strict=True):
            if source["status"] == "ok":
                row.update(iterate_row(source, Path(next(answered)), iterate))
    header = list(dict.fromkeys(k for row in rows for k in row))
    write_rows(rows, output, header or ["material"])
    for row in rows:
        if "confirmed_mmHg" in row:
            log.info(
                "%s on %s, %s: reduction %.4f gives %.4g +- %.2g mmHg (target %.4g, "
                "off by %+.2f %%)",
                row["material"],
                row["body"],
                row["landmark"],
                float(row["reduction"]),
                row["confirmed_mmHg"],
                row["confirmed_error_mmHg"],
                float(row["target_mmHg"]),
                row["error_percent"],
            )
