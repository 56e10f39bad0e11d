"""What ``cloth compare`` writes: compare.csv, agreement.csv and compare.nc.

compare.csv, one row per place (readings averaged over repeats; `cloth.results.agreement`):
``subject``, ``point`` (the girth line the reading named, or empty), ``height_m``,
``angle_deg``, ``probe_mm``, ``repeats``, ``measured_mmHg`` (the repeats' mean),
``repeat_sd_mmHg`` (their sample standard deviation; empty for one reading), ``model_mmHg``
(the model's probe reading there), ``model_error_mmHg`` (its stated discretisation error,
`cloth.results.sensing`), ``error_line`` (the girth line that error is taken from) and
``difference_mmHg`` (model - measured).

agreement.csv, one row per subject and a last row ``all`` pooling every place: ``subject``,
``places``, ``bias_mmHg``, ``sd_mmHg``, ``loa_low_mmHg``, ``loa_high_mmHg``, ``rmse_mmHg``,
``r`` and ``repeat_sd_mmHg`` (the repeats' pooled standard deviation, the measurement's own
noise).

compare.nc (CF-1.11, ``cloth_kind = "compare"``) holds the same in SI along the dims ``place``
(``subject``, ``point``, ``height`` m, ``angle`` degree, ``probe_diameter`` m, ``repeats``,
``measured_pressure``, ``repeat_sd``, ``model_pressure``, ``model_pressure_error``,
``difference``, Pa) and ``group`` (the subjects and ``all``: ``places``, ``bias``, ``sd``,
``loa_low``, ``loa_high``, ``rmse``, ``repeat_sd`` Pa and ``r`` 1), with the files compared as
global attributes (``result_file`` and ``measurements_file``, or ``study_file``), relative to
compare.nc's own folder.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from cloth.io import global_attrs, variable
from cloth.results.agreement import Agreement, Compared, pooled_sd
from cloth.results.pressure import MMHG

#: compare.csv's columns.
COMPARE_COLUMNS = [
    "subject",
    "point",
    "height_m",
    "angle_deg",
    "probe_mm",
    "repeats",
    "measured_mmHg",
    "repeat_sd_mmHg",
    "model_mmHg",
    "model_error_mmHg",
    "error_line",
    "difference_mmHg",
]
#: agreement.csv's columns.
AGREEMENT_COLUMNS = [
    "subject",
    "places",
    "bias_mmHg",
    "sd_mmHg",
    "loa_low_mmHg",
    "loa_high_mmHg",
    "rmse_mmHg",
    "r",
    "repeat_sd_mmHg",
]
#: The pooled group's name in agreement.csv and compare.nc.
POOLED = "all"


def _mmhg(value: float) -> float | str:
    return "" if not math.isfinite(value) else value / MMHG


def groups(table: Compared) -> list[tuple[str, Agreement, float]]:
    """Per subject (in order) and pooled (`POOLED`): the agreement and the repeats' pooled
    standard deviation (Pa)."""
    out = []
    names = list(dict.fromkeys(table.subject))
    for name in [*names, POOLED] if len(names) > 1 else [POOLED]:
        part = table if name == POOLED else table.of_subject(name)
        noise = pooled_sd(part.repeats, part.repeat_sd)
        out.append((name, Agreement.of(part.model, part.measured), noise))
    return out


def compare_rows(table: Compared) -> list[dict[str, object]]:
    """compare.csv's rows (module docstring)."""
    rows = []
    for k in range(len(table.subject)):
        rows.append(
            {
                "subject": table.subject[k],
                "point": table.point[k],
                "height_m": float(table.height[k]),
                "angle_deg": float(table.angle[k]),
                "probe_mm": float(1e3 * table.probe[k]),
                "repeats": int(table.repeats[k]),
                "measured_mmHg": _mmhg(float(table.measured[k])),
                "repeat_sd_mmHg": _mmhg(float(table.repeat_sd[k])),
                "model_mmHg": _mmhg(float(table.model[k])),
                "model_error_mmHg": _mmhg(float(table.model_error[k])),
                "error_line": table.error_line[k],
                "difference_mmHg": _mmhg(float(table.difference[k])),
            }
        )
    return rows


def agreement_rows(table: Compared) -> list[dict[str, object]]:
    """agreement.csv's rows (module docstring)."""
    rows = []
    for name, stats, noise in groups(table):
        rows.append(
            {
                "subject": name,
                "places": stats.n,
                "bias_mmHg": _mmhg(stats.bias),
                "sd_mmHg": _mmhg(stats.sd),
                "loa_low_mmHg": _mmhg(stats.loa_low),
                "loa_high_mmHg": _mmhg(stats.loa_high),
                "rmse_mmHg": _mmhg(stats.rmse),
                "r": "" if not math.isfinite(stats.r) else stats.r,
                "repeat_sd_mmHg": _mmhg(noise),
            }
        )
    return rows


def compare_dataset(table: Compared, sources: dict[str, str]) -> xr.Dataset:
    """compare.nc's dataset (module docstring); ``sources`` name the files compared."""
    place = "place"
    found = groups(table)
    pa = "Pa"
    data = {
        "subject": variable(place, np.array(table.subject, dtype=str), None, "subject"),
        "point": variable(place, np.array(table.point, dtype=str), None, "girth line named"),
        "height": variable(place, table.height, "m", "probe centre height"),
        "angle": variable(
            place, table.angle, "degree", "probe centre angle about the up axis from +x to +y"
        ),
        "probe_diameter": variable(place, table.probe, "m", "probe footprint diameter"),
        "repeats": variable(place, table.repeats, "1", "readings averaged"),
        "measured_pressure": variable(place, table.measured, pa, "measured pressure"),
        "repeat_sd": variable(place, table.repeat_sd, pa, "standard deviation of the repeats"),
        "model_pressure": variable(place, table.model, pa, "model probe reading"),
        "model_pressure_error": variable(
            place, table.model_error, pa, "stated discretisation error of the model reading"
        ),
        "difference": variable(place, table.difference, pa, "model minus measured pressure"),
        "group": variable("group", np.array([g[0] for g in found], dtype=str), None, "subject"),
        "places": variable("group", [g[1].n for g in found], "1", "places compared"),
        "r": variable("group", [g[1].r for g in found], "1", "Pearson r of model and measured"),
        "repeat_sd_pooled": variable(
            "group", [g[2] for g in found], pa, "pooled standard deviation of the repeats"
        ),
    }
    for name, long_name in (
        ("bias", "mean of model minus measured"),
        ("sd", "standard deviation of model minus measured"),
        ("loa_low", "lower limit of agreement (bias - 1.96 sd)"),
        ("loa_high", "upper limit of agreement (bias + 1.96 sd)"),
        ("rmse", "root mean square of model minus measured"),
    ):
        data[name] = variable("group", [getattr(g[1], name) for g in found], pa, long_name)
    attrs = global_attrs("cloth compare: model against measured pressures")
    attrs.update(cloth_kind="compare", **{f"{k}_file": v for k, v in sources.items()})
    return xr.Dataset(data, attrs=attrs)
