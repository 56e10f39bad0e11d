"""``cloth wearers CASE -o DIR``: one garment on every wearer of its size (issue 52, item 4).

The case's garment is cut once for the case's body (its size's body: a chart's torso or leg,
an avatar), or is the pattern the case gives (``garment.pattern``), and worn unchanged by each
wearer of the size (`cloth.bodies.wearers`; their avatars from ``--wearers DIR``, else the
shipped ones of the body's chart and size, `cloth.files.wearers`), placed by a girth line
(`cloth.garment.cut`). Into ``DIR``:

- ``{wearer}/case.yaml`` and its run (``result.nc``, ``summary.csv``): one case per wearer,
  ``size/`` the body the garment is cut for. A wearer's pressures are a plain ``cloth run`` of
  its case.yaml, bit for bit.
- ``wearers.nc``: per wearer and girth line the mean pressure (Pa) and its stated
  discretisation error (Pa, NaN where none), the wearers' girths and stature (m).
- ``wearers.csv``: per girth line the minimum, centre and maximum mean pressure over the
  wearers (mmHg), which wearer gives each extreme, the size's body's value, and beside them,
  kept apart, the largest stated discretisation error of a wearer there (mmHg); at the case's
  class point (``judge.class_point``, B) the compression class of the lowest and the highest
  wearer (the class holds for every wearer where they agree), and with ``judge.bands`` the
  bands that hold every wearer.
- ``wearers.png``: each line's range over the wearers, the centre wearer and the size's body
  marked, against the case's pressure bands or compression classes.

With the case's ``variation`` (friction, tissue moduli, worn; docs/config.md) each value is
also run on the centre wearer, one at a time (``centre~mu0.4``, ``centre~tissue20000``,
``centre~worn``): the ranges and their extremes take them in, named so.

A wearer at a girth line her garment does not reach (a line outside the placed pattern) has
no value there (NaN; blank in the CSV).
"""

from __future__ import annotations

import copy
import csv
import logging
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from cloth.bodies.wearers import SIZE
from cloth.case import Case
from cloth.case.case import load_case
from cloth.case.judge import Judge
from cloth.case.locations import relocated
from cloth.files.wearers import body_wearers, read_index
from cloth.io import atomic_output, global_attrs, variable, write_netcdf
from cloth.pipeline.wearers import wearer_blocks
from cloth.progress import progress
from cloth.results.pressure import MMHG
from cloth.stages.case import run_case

log = logging.getLogger("cloth")


def wearers_of(case: Case, base_dir: Path, wearers: Path | None) -> tuple[Path, dict]:
    """The wearers folder of ``case`` (``wearers``, else the shipped one of its body's chart and
    size) and its index; one line where the body has no size or none ship."""
    if wearers is not None:
        return wearers, read_index(wearers)
    return body_wearers(
        case.body.block,
        lambda chart: base_dir / Path(chart).expanduser(),
        "body",
        "--wearers DIR (cloth body wearers)",
    )


def wearer_cases(case: Case, folder: Path, index: dict) -> dict[str, dict]:
    """Name -> case mapping of the size's body (`SIZE`) and of every fitted wearer in the
    wearers ``folder`` with ``index``: the case's garment as a pattern cut for its body."""
    data = case.to_dict()
    garment = data["garment"]
    if "pattern" not in garment:
        garment["pattern"] = {"body": copy.deepcopy(data["body"])}
    return wearer_blocks(data, folder, index)


def run_wearers(
    case_path: Path,
    output: Path,
    overrides: dict,
    wearers: Path | None = None,
    base_dir: Path | None = None,
) -> xr.Dataset:
    """Every stage of the case on every wearer into ``output`` (module docstring); returns
    wearers.nc's dataset."""
    case = load_case(case_path)
    base_dir = case_path.parent if base_dir is None else base_dir
    folder, index = wearers_of(case, base_dir, wearers)
    cases = wearer_cases(case, folder, index)
    output.mkdir(parents=True, exist_ok=True)
    for name, data in progress(list(cases.items()), desc="wearers", unit="case"):
        target = output / name
        target.mkdir(parents=True, exist_ok=True)
        path = target / "case.yaml"
        with atomic_output(path) as tmp:
            tmp.write_text(yaml.safe_dump(relocated(data, base_dir, target), sort_keys=False))
        run_case(path, target, overrides, stop_after="aggregate")
    results = {name: output / name / "result.nc" for name in cases}
    return report_files(results, index, output, case.judge)


def report_files(results: dict[str, Path], index: dict, output: Path, judge: Judge) -> xr.Dataset:
    """wearers.nc, wearers.csv and wearers.png in ``output`` from each wearer's ``results``
    (name -> result.nc, `SIZE` the body the garment is cut for) and the wearers' ``index``,
    judged by ``judge``; returns wearers.nc's dataset."""
    from cloth.figures.wearers import plot_wearers  # late: matplotlib (~0.4 s)

    output.mkdir(parents=True, exist_ok=True)
    ds = collect(results, index)
    write_netcdf(ds, output / "wearers.nc")
    write_table(ds, output / "wearers.csv", judge)
    plot_wearers(ds, judge, output / "wearers.png")
    log.info("wrote %s: %d wearers", output, len([n for n in results if n != SIZE]))
    return ds


def collect(paths: dict[str, Path], index: dict) -> xr.Dataset:
    """wearers.nc's dataset from each wearer's result.nc (``paths``: name -> file)."""
    names = list(paths)
    results = {}
    for name, path in paths.items():
        with xr.open_dataset(path) as ds:
            results[name] = ds.load()
    lines: list[str] = []
    for ds in results.values():
        lines += [str(n) for n in ds["landmark"].values if str(n) not in lines]
    shape = (len(names), len(lines))
    mean = np.full(shape, np.nan)
    error = np.full(shape, np.nan)
    for i, name in enumerate(names):
        ds = results[name]
        for j, line in enumerate(lines):
            if line in ds["landmark"].values:
                at = ds.sel(landmark=line)
                mean[i, j] = float(at["pressure_mean"])
                if "pressure_mean_error" in ds:
                    error[i, j] = float(at["pressure_mean_error"])
    info = {w["name"]: w for w in index["wearers"]}
    stature = np.array([info.get(n, {}).get("stature_m", np.nan) for n in names], dtype=float)
    attrs = global_attrs("cloth wearers: one garment on every wearer of its size")
    attrs.update(
        size=str(index.get("size")),
        chart=str(index.get("chart")),
        source=str(index.get("source")),
        population=str(index.get("population")),
        people=int(index.get("people", 0)),
        coverage=float(index.get("coverage", 1.0)),
    )
    return xr.Dataset(
        {
            "pressure_mean": variable(
                ("wearer", "landmark"), mean, "Pa", "band-mean pressure on the girth line"
            ),
            "pressure_mean_error": variable(
                ("wearer", "landmark"),
                error,
                "Pa",
                "stated discretisation error of pressure_mean (NaN: none)",
            ),
            "stature": variable("wearer", stature, "m", "wearer's stature (NaN: the size's body)"),
        },
        coords={"wearer": ("wearer", names), "landmark": ("landmark", lines)},
        attrs=attrs,
    )


def table_rows(ds: xr.Dataset, judge: Judge | None = None) -> list[dict[str, object]]:
    """wearers.csv's rows (module docstring), one per girth line; with ``judge``, at its class
    point the class of the lowest and the highest wearer, and on every line the bands that
    hold every wearer."""
    names = [str(n) for n in ds["wearer"].values]
    wearers = [k for k, n in enumerate(names) if n != SIZE]
    rows = []
    for j, line in enumerate(ds["landmark"].values):
        values = ds["pressure_mean"].values[wearers, j] / MMHG
        errors = ds["pressure_mean_error"].values[wearers, j] / MMHG
        known = np.isfinite(values)
        row: dict[str, object] = {"landmark": str(line), "wearers": int(known.sum())}
        if known.any():
            low, high = int(np.nanargmin(values)), int(np.nanargmax(values))
            centre = names.index("centre") if "centre" in names else None
            row.update(
                pressure_min_mmHg=round(float(values[low]), 4),
                min_wearer=names[wearers[low]],
                pressure_centre_mmHg=""
                if centre is None
                else round(float(ds["pressure_mean"].values[centre, j] / MMHG), 4),
                pressure_max_mmHg=round(float(values[high]), 4),
                max_wearer=names[wearers[high]],
                spread_mmHg=round(float(values[high] - values[low]), 4),
                discretisation_error_mmHg=""
                if not np.isfinite(errors[known]).any()
                else round(float(np.nanmax(errors[known])), 4),
            )
        if judge is not None and known.any():
            if str(line) == judge.class_point:
                row["class_min"] = judge.compression_class(float(np.nanmin(values)))
                row["class_max"] = judge.compression_class(float(np.nanmax(values)))
            if judge.bands:
                held = [
                    name
                    for name, low, high in judge.bands
                    if np.all((values[known] >= low) & (values[known] <= high))
                ]
                row["bands_every_wearer"] = " ".join(held) or "-"
        size = names.index(SIZE) if SIZE in names else None
        if size is not None and np.isfinite(ds["pressure_mean"].values[size, j]):
            row["size_body_mmHg"] = round(float(ds["pressure_mean"].values[size, j] / MMHG), 4)
        rows.append(row)
    return rows


#: wearers.csv's columns, in order.
COLUMNS = (
    "landmark",
    "wearers",
    "pressure_min_mmHg",
    "min_wearer",
    "pressure_centre_mmHg",
    "pressure_max_mmHg",
    "max_wearer",
    "spread_mmHg",
    "size_body_mmHg",
    "discretisation_error_mmHg",
    "class_min",
    "class_max",
    "bands_every_wearer",
)


def write_table(ds: xr.Dataset, path: Path, judge: Judge | None = None) -> Path:
    with atomic_output(path) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(COLUMNS), restval="")
        writer.writeheader()
        writer.writerows(table_rows(ds, judge))
    return path


__all__ = [
    "COLUMNS",
    "SIZE",
    "collect",
    "report_files",
    "run_wearers",
    "table_rows",
    "wearer_cases",
    "wearers_of",
]
