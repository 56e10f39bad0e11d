"""Sweeps and the design answer: which pattern reduction gives the target pressure?

`collect` stacks the landmark summaries of a sweep's results into one dataset with dims
``material`` x ``body`` x ``reduction`` (x ``tissue_modulus`` x ``friction`` x ``worn``, those
the sweep varies: `cloth.pipeline.variants`) x ``landmark`` (pressure in Pa). `design` answers each
target (a girth line and a pressure) per material and body by linear interpolation of the mean
pressure on that line against the reduction; the pipeline then confirms each answer with an
extra relaxed case at the found reduction (`confirm`), reporting the confirmed pressure and its
error. A target no reduction in the swept range reaches gets a clear message instead.
"""

from __future__ import annotations

import csv
import io as _io
import itertools
import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.errors import InputError
from cloth.io import atomic_output, global_attrs, read_netcdf
from cloth.pipeline.variants import COORDINATES, KEYS, Variant, entry_keys
from cloth.results.landmarks import LANDMARK_FIELDS
from cloth.results.pressure import MMHG

FIELDS = {name: (units, long_name) for name, (_, units, long_name) in LANDMARK_FIELDS.items()}
#: Each value's stated discretisation error (`cloth.files.levels`), NaN where not estimated.
ERRORS = {
    f"{name}_error": (units, f"estimated discretisation error of the {long_name}")
    for name, (units, long_name) in FIELDS.items()
}


def _dims(index: list[dict]) -> tuple[str, ...]:
    return ("material", "body", "reduction", *entry_keys(index))


def _pair(items: list, paths: list[str | Path], what: str) -> list[tuple]:
    """``items`` with their result files, one each in order (`InputError` if the counts differ)."""
    if len(items) != len(paths):
        raise InputError(
            f"give one result.nc per {what} ({len(items)}), got {len(paths)}", field="results"
        )
    return list(zip(items, paths, strict=True))


def collect(index: list[dict], results: list[str | Path]) -> xr.Dataset:
    """Stack the ``results`` (a result.nc per index entry, in its order) of the index entries
    (case, material, body, reduction, and the variant keys the sweep varies:
    `cloth.pipeline.variants`) into the sweep dataset, a dimension per key and the ``landmark``."""
    dims = _dims(index)
    values = {
        dim: sorted({e[dim] if dim in ("material", "body") else float(e[dim]) for e in index})
        for dim in dims
    }
    datasets = {}
    landmarks: list[str] = []
    for entry, path in _pair(index, results, "sweep case"):
        ds = read_netcdf(path, "result", ("pressure_mean",))
        datasets[entry["case"]] = ds
        for name in ds["landmark"].values.tolist():
            if name not in landmarks:
                landmarks.append(name)
    shape = (*(len(values[dim]) for dim in dims), len(landmarks))
    data = {name: np.full(shape, np.nan) for name in {**FIELDS, **ERRORS}}
    converged = np.zeros(shape[:-1], dtype=np.int8)
    for entry in index:
        ds = datasets[entry["case"]]
        i = tuple(
            values[dim].index(entry[dim] if dim in ("material", "body") else float(entry[dim]))
            for dim in dims
        )
        converged[i] = int(ds.attrs.get("converged", 0))
        for k, name in enumerate(ds["landmark"].values.tolist()):
            for field in data:
                if field in ds:
                    data[field][(*i, landmarks.index(name))] = float(ds[field][k])
    all_dims = (*dims, "landmark")
    described = {**FIELDS, **ERRORS}
    variables = {
        field: xr.Variable(
            all_dims, array, {"units": described[field][0], "long_name": described[field][1]}
        )
        for field, array in data.items()
    }
    flags = {"flag_values": np.array([0, 1], np.int8), "flag_meanings": "no yes"}
    variables["converged"] = xr.Variable(
        dims, converged, {"units": "1", "long_name": "relaxation converged", **flags}
    )
    coords = {
        "material": xr.Variable("material", values["material"], {"long_name": "fabric"}),
        "body": xr.Variable("body", values["body"], {"long_name": "body"}),
        "reduction": xr.Variable(
            "reduction",
            np.asarray(values["reduction"]),
            {"units": "1", "long_name": "pattern reduction"},
        ),
        "landmark": xr.Variable("landmark", landmarks, {"long_name": "girth line"}),
    }
    for key in entry_keys(index):
        array = np.asarray(values[key], np.int8 if key == "worn" else np.float64)
        attrs = dict(COORDINATES[key])
        if "flag_values" in attrs:
            attrs["flag_values"] = np.asarray(attrs["flag_values"], np.int8)
        coords[key] = xr.Variable(key, array, attrs)
    attrs = global_attrs("cloth sweep")
    attrs.update({"cloth_kind": "sweep", "cases": json.dumps(index, sort_keys=True)})
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def combinations(ds: xr.Dataset, dims: tuple[str, ...]) -> list[dict]:
    """Every combination of the coordinates of ``dims`` (a selection each)."""
    return [
        dict(zip(dims, combo, strict=True))
        for combo in itertools.product(*(ds[dim].values.tolist() for dim in dims))
    ]


def variant_dims(ds: xr.Dataset) -> tuple[str, ...]:
    """The variant dimensions of a sweep dataset (`cloth.pipeline.variants.KEYS` it has)."""
    return tuple(key for key in KEYS if key in ds.dims)


def sweep_rows(ds: xr.Dataset) -> list[dict[str, object]]:
    """One row per case and girth line; where the sweep has new and worn garments, one row
    per new case with the worn pressure beside it (``pressure_mean_mmHg_worn``, and the change
    in %)."""
    rows = []
    both = "worn" in ds.dims and ds.sizes["worn"] == 2
    dims = tuple(
        d
        for d in ("material", "body", "reduction", *variant_dims(ds))
        if not (both and d == "worn")
    )
    for where in combinations(ds, (*dims, "landmark")):
        at = ds.sel(where | ({"worn": 0} if both else {}))
        if not np.isfinite(float(at["pressure_mean"])):
            continue
        row = {
            **where,
            "pressure_mean_Pa": float(at["pressure_mean"]),
            "pressure_mean_mmHg": float(at["pressure_mean"]) / MMHG,
            "pressure_mean_error_mmHg": float(mean_error(at)) / MMHG,
            "pressure_max_mmHg": float(at["pressure_max"]) / MMHG,
            "tension_mean_N_per_m": float(at["tension_mean"]),
            "converged": int(at["converged"]),
        }
        if both:
            worn = float(ds.sel(where | {"worn": 1})["pressure_mean"])
            row["pressure_mean_mmHg_worn"] = worn / MMHG
            row["worn_change_percent"] = 100 * (worn / float(at["pressure_mean"]) - 1)
        rows.append(row)
    return rows


def mean_error(ds: xr.Dataset) -> xr.DataArray:
    """The stated error of the mean pressure of a sweep or result dataset (Pa): its
    ``pressure_mean_error``, or NaN shaped like ``pressure_mean`` in a file written without
    error estimates."""
    if "pressure_mean_error" in ds:
        return ds["pressure_mean_error"]
    return xr.full_like(ds["pressure_mean"], np.nan, dtype=float)


def write_rows(rows: list[dict[str, object]], path: str | Path, header: list[str]) -> Path:
    buffer = _io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=header)
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
    with atomic_output(path) as tmp:
        tmp.write_text(buffer.getvalue())
    return Path(path)


def target_pa(target: dict) -> float:
    return (
        target["pressure_mmHg"] * MMHG
        if "pressure_mmHg" in target
        else target["pressure_kPa"] * 1e3
    )


def design(ds: xr.Dataset, targets: list[dict]) -> list[dict[str, object]]:
    """The reduction reaching each target per material, body and variant (linear
    interpolation)."""
    rows = []
    reductions = ds["reduction"].values
    for target in targets:
        landmark = target["landmark"]
        if landmark not in ds["landmark"].values.tolist():
            raise InputError(
                f"unknown landmark {landmark!r}; the sweep has "
                f"{', '.join(ds['landmark'].values.tolist())}",
                "config",
                "targets",
            )
        goal = target_pa(target)
        for where in combinations(ds, ("material", "body", *variant_dims(ds))):
            p = ds["pressure_mean"].sel(where | {"landmark": landmark}).values
            ok = np.isfinite(p)
            row = {
                **where,
                "landmark": landmark,
                "target_Pa": goal,
                "target_mmHg": goal / MMHG,
                "reduction": math.nan,
                "slope_Pa": math.nan,
                "reduction_error": math.nan,
                "reduction_low": math.nan,
                "reduction_high": math.nan,
                "status": "",
                "message": "",
            }
            if np.count_nonzero(ok) < 2:
                row.update(status="no_data", message="fewer than two swept reductions")
            elif not (p[ok].min() <= goal <= p[ok].max()):
                row.update(
                    status="out_of_range",
                    message=(
                        f"no reduction in {reductions[ok].min():.3g}-{reductions[ok].max():.3g}"
                        f" reaches {goal / MMHG:.3g} mmHg at the {landmark}: the sweep gives "
                        f"{p[ok].min() / MMHG:.3g}-{p[ok].max() / MMHG:.3g} mmHg; widen the "
                        "reductions or choose another fabric"
                    ),
                )
            else:
                order = np.argsort(p[ok])
                reduction = float(np.interp(goal, p[ok][order], reductions[ok][order]))
                errors = mean_error(ds).sel(where | {"landmark": landmark}).values[ok]
                row.update(reduction=reduction, status="ok")
                row.update(reduction_interval(reductions[ok], p[ok], errors, reduction))
            rows.append(row)
    return rows


def reduction_interval(
    reductions: np.ndarray, pressures: np.ndarray, errors: np.ndarray, reduction: float
) -> dict[str, float]:
    """The design answer's interval: ``reduction`` (1) +- the stated pressure error at it (Pa,
    interpolated between the two swept cases around it, ``errors``) over the slope of the mean
    pressure between them (Pa per unit reduction, ``slope_Pa``): ``reduction_error``,
    ``reduction_low`` and ``reduction_high`` (1); NaN where a case around it has no error
    estimate. The interval holds the discretisation error only: the interpolation's is measured
    by the confirmation (`cloth.stages.secant`)."""
    order = np.argsort(reductions)
    r, p, e = reductions[order], pressures[order], errors[order]
    k = int(np.clip(np.searchsorted(r, reduction, side="right") - 1, 0, len(r) - 2))
    t = (reduction - r[k]) / (r[k + 1] - r[k])
    slope = (p[k + 1] - p[k]) / (r[k + 1] - r[k])
    half = ((1 - t) * e[k] + t * e[k + 1]) / abs(slope) if slope else math.inf
    return {
        "slope_Pa": slope,
        "reduction_error": half,
        "reduction_low": reduction - half,
        "reduction_high": reduction + half,
    }


DESIGN_HEADER = [
    "material",
    "body",
    "landmark",
    "target_Pa",
    "target_mmHg",
    "reduction",
    "slope_Pa",
    "reduction_error",
    "reduction_low",
    "reduction_high",
    "status",
    "message",
]


def design_header(rows: list[dict]) -> list[str]:
    """`DESIGN_HEADER` with the variant keys the rows carry, after the body."""
    keys = [key for key in KEYS if rows and key in rows[0]]
    return [*DESIGN_HEADER[:2], *keys, *DESIGN_HEADER[2:]]


def read_design(path: str | Path) -> list[dict[str, str]]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def confirm_name(row: dict) -> str:
    """The confirmation case of a design row (with its variant's tag, `cloth.pipeline.variants`)."""
    tag = Variant.of(row).tag()
    return f"design__{row['material']}__{row['body']}__{row['landmark']}{tag}"


def confirm(
    design_rows: list[dict[str, str]], results: list[str | Path]
) -> list[dict[str, object]]:
    """The confirmed pressure of every answered target (``results``: the result.nc of each
    answered row's confirmation case, in the rows' order), and its error against the target."""
    answered = [row for row in design_rows if row["status"] == "ok"]
    paths = iter(path for _, path in _pair(answered, results, "answered target"))
    out = []
    for row in design_rows:
        record: dict[str, object] = dict(row)
        if row["status"] == "ok":
            ds = read_netcdf(next(paths), "result", ("pressure_mean",))
            confirmed = float(ds["pressure_mean"].sel(landmark=row["landmark"]))
            goal = float(row["target_Pa"])
            stated = float(mean_error(ds).sel(landmark=row["landmark"]))
            record.update(
                confirmed_Pa=confirmed,
                confirmed_mmHg=confirmed / MMHG,
                confirmed_error_Pa=stated,
                confirmed_error_mmHg=stated / MMHG,
                error_percent=100 * (confirmed - goal) / goal,
                converged=int(ds.attrs.get("converged", 0)),
            )
        out.append(record)
    return out
