"""The input stages: lab tables -> material.nc (`ingest_material`), a size chart -> the torso as
a mesh (`torso_file`), the leg (`leg_file`), an avatar fitted to it (`avatar_file`)."""

from __future__ import annotations

import logging
from collections.abc import Sequence
from pathlib import Path

from cloth.bodies.avatar import chart_targets, fit_avatar, fit_targets
from cloth.bodies.leg import DEFAULT_LEG_CHART, leg_mesh, leg_size
from cloth.bodies.torso import DEFAULT_CHART, chart_size, torso_mesh
from cloth.bodies.wearers import population_wearers, range_wearers
from cloth.errors import InputError
from cloth.figures.plots import plot_material
from cloth.files.avatar import avatar_output, sidecar, write_avatar
from cloth.files.material import material_dataset
from cloth.files.population import AGES, read_population
from cloth.files.wearers import default_population, index_record, write_index
from cloth.io import atomic_output, sha256, write_netcdf
from cloth.materials.labtables import ingest
from cloth.progress import progress

log = logging.getLogger("cloth")


def ingest_material(
    tables: Sequence[Path],
    directions: Sequence[str] | None,
    options,
    output: Path,
    plot: Path | None = None,
) -> None:
    """Read ``tables`` (one per direction in ``directions``, or directions from their columns)
    with `cloth.materials.labtables.IngestOptions` ``options`` into ``output``; log each
    curve's fit."""
    if directions and len(directions) != len(tables):
        raise InputError(
            f"give --direction once per table ({len(tables)}), got {len(directions)}",
            field="--direction",
        )
    material = ingest(tables, directions, options)
    ds = material_dataset(material)
    write_netcdf(ds, output)
    log.info("wrote %s", output)
    if plot:
        plot_material(ds, plot)
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


def torso_file(
    size: str,
    chart: Path | None,
    girths_cm: dict[str, float],
    around: int,
    rings: int,
    output: Path,
) -> None:
    """The parametric torso of ``size`` in ``chart`` (girths overridden in cm) as a mesh."""
    import dataclasses

    spec = chart_size(size, chart or DEFAULT_CHART)
    if girths_cm:
        spec = dataclasses.replace(
            spec, girth={**spec.girth, **{k: v / 100 for k, v in girths_cm.items()}}
        )
    _write_mesh(*torso_mesh(spec, around, rings), output, f"torso {spec.name}", spec.girth)


def leg_file(size: str, chart: Path | None, around: int, rings: int, output: Path) -> None:
    """The parametric leg of ``size`` in ``chart`` (`cloth.bodies.leg`) as a mesh."""
    spec = leg_size(size, chart or DEFAULT_LEG_CHART)
    _write_mesh(*leg_mesh(spec, around, rings), output, f"leg {spec.name}", spec.girth)


def avatar_file(chart: Path, size: str, output: Path, full: bool = False) -> None:
    """The avatar of ``size`` of the torso or leg chart ``chart`` (`cloth.bodies.avatar`) to
    ``output`` (PLY) and its provenance beside it (`cloth.files.avatar`); nothing is written
    where the fit fails. ``full``: the whole body in the model's A-pose, uncropped (a full-body
    scan as scanners export it). Needs the extra ``bodies``."""
    avatar_output(output)  # before seconds of fitting
    avatar = fit_avatar(chart, size, posed=not full)
    mesh, side = write_avatar(avatar, chart, output, full)
    log.info(
        "wrote %s and %s: avatar %s %s, %d evaluations in %.1f s, residuals (mm) %s",
        mesh,
        side,
        avatar.targets.kind,
        size,
        avatar.evaluations,
        avatar.seconds,
        ", ".join(f"{k} {v * 1e3:+.3f}" for k, v in avatar.residuals().items()),
    )


def wearers_folder(
    chart: Path,
    size: str,
    output: Path,
    population: Path | str | None = "default",
    ages: tuple[float, float] | None = AGES,
) -> dict:
    """The wearers of ``size`` of ``chart`` (`cloth.bodies.wearers`): from ``population`` (a
    file; ``default``: the shipped NHANES survey for a torso chart, ANSUR II for a leg chart;
    None: the chart's ranges), each fitted as an avatar into the folder ``output`` with the index
    (`cloth.files.wearers`), which is written last and returned. A wearer the body model
    cannot reach is recorded as refused, the others fitted. Needs the extra ``bodies``."""
    targets = chart_targets(chart, size)
    if population == "default":
        population = default_population(targets.kind)
    if population is not None:
        people = read_population(population, ages)
        wearers = population_wearers(
            targets, targets.ranges, people.measures, people.weight, str(population)
        )
        log.info(
            "size %s: %d people of %s (survey weight %.4g), wearers over %s cover %.1f %% of them",
            size,
            wearers.people,
            population,
            wearers.weight,
            ", ".join(wearers.measures),
            100 * wearers.coverage,
        )
    else:
        wearers = range_wearers(targets, targets.ranges)
    output.mkdir(parents=True, exist_ok=True)
    fitted: dict[str, str] = {}
    for wearer in progress(wearers.wearers, desc=f"wearers of {size}", unit="avatar"):
        if _fitted_before(output / f"{wearer.name}.ply", wearer.targets, chart):
            fitted[wearer.name] = f"{wearer.name}.ply"
            log.info("wearer %s of size %s: fitted before, kept", wearer.name, size)
            continue
        try:
            avatar = fit_targets(wearer.targets, chart)
        except InputError as exc:
            fitted[wearer.name] = f"refused: {exc.detail}"
            log.warning("wearer %s of size %s: %s", wearer.name, size, exc.detail)
            continue
        write_avatar(avatar, chart, output / f"{wearer.name}.ply")
        fitted[wearer.name] = f"{wearer.name}.ply"
    record = index_record(wearers, chart, size, population, ages, fitted)
    write_index(record, output)
    log.info("wrote %s: %d wearers of size %s", output, len(fitted), size)
    return record


def _fitted_before(mesh: Path, targets, chart: Path) -> bool:
    """Whether ``mesh`` is an avatar of this chart (sha256) fitted to ``targets`` (its size
    label, girths, stature and pinned shape), so that a folder regenerated after new wearers
    were added refits only those (a fit is deterministic: it would write the same bytes)."""
    record = sidecar(mesh) if mesh.is_file() else None
    if record is None or record.get("chart_sha256") != sha256(chart):
        return False
    girths = record.get("girths_m", {})
    same = record.get("size") == targets.size and all(
        girths.get(name, {}).get("chart") == (None if name in targets.free else value)
        for name, value in targets.girth.items()
    )
    pinned = all(record.get("parameters", {}).get(k) == v for k, v in targets.pinned.items())
    return same and pinned and record.get("stature_m", {}).get("chart") == targets.stature


def _write_mesh(vertices, faces, output: Path, what: str, girth: dict[str, float]) -> None:
    """A parametric body's mesh to ``output`` (format from its suffix, default PLY), logged."""
    import trimesh

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    suffix = output.suffix.lstrip(".").lower() or "ply"
    with atomic_output(output) as tmp:
        mesh.export(tmp, file_type=suffix)
    log.info(
        "wrote %s: %s, %d vertices, %d faces, girths (m) %s",
        output,
        what,
        len(vertices),
        len(faces),
        ", ".join(f"{k} {v:.4g}" for k, v in girth.items()),
    )
