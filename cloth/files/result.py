"""The result file (``result.nc``) and ``summary.csv``: everything a user needs in one file.

Node fields (dims ``row``, ``col``): positions ``x``, ``y``, ``z`` (m), rest coordinates ``u``,
``v`` (m), ``stress_weft``, ``stress_warp`` (Pa), ``strain_weft``, ``strain_warp`` (1),
``tension_weft``, ``tension_warp`` (N m-1), ``pressure`` (Pa), ``pressure_mmHg``,
``p_laplace`` and ``p_laplace_difference`` (Pa), ``node_area`` (m2), ``edge_support_force``
(N), ``contact`` and ``constraint`` (flags), ``beyond_lab_range`` (flags). Spring fields (dim
``spring``): ``spring_stress`` (Pa, signed), ``spring_slack`` (flags),
``spring_strain`` (1), ``spring_family`` (flags), ``spring_node_a``/``_b``. Per iteration: the
solver history. Per landmark (dim ``landmark``): ``landmark_height`` (m), ``pressure_mean`` (the
body band's), ``pressure_max``, ``pressure_min`` (a probe's readings around the girth; Pa),
``tension_mean`` (N m-1) and the row diagnostics ``row_pressure_mean``, ``_max``, ``_min`` (Pa;
`cloth.results.landmarks`). Per sensor (dim ``sensor``) where the case places them: what each
reads. Totals: ``total_force`` and
``total_moment`` (dim ``xyz``; N, N m) of the fabric on the body, ``normal_force`` (N, sum of
the normal reactions), ``pressure_integral`` (N, sum of pressure x node area). Plus the fabric
curves, the case, body and provenance attributes. CF-1.11, written atomically.
"""

from __future__ import annotations

import csv
import io as _io
import json
import subprocess
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.case import Case
from cloth.case.judge import Judge
from cloth.case.pieces import BESIDE
from cloth.case.reading import Reading
from cloth.files.levels import estimate_columns
from cloth.files.material import fabric_variables
from cloth.files.pieces import pieces_attrs, pieces_variables, seam_variables
from cloth.files.state import CONSTRAINT_MEANINGS, CONTACT_MEANINGS
from cloth.garment.grid import WEFT
from cloth.garment.state import State
from cloth.io import atomic_output, flag_variable, global_attrs, node_variable, to_attr, variable
from cloth.results.fields import Fields
from cloth.results.judging import judged
from cloth.results.landmarks import LANDMARK_FIELDS, ROW_FIELDS, Landmark
from cloth.results.pressure import MMHG
from cloth.results.regions import Region, note

KIND = "result"
#: The solver history copied from relaxed.nc, per iteration.
HISTORY = (
    "residual",
    "energy",
    "penetration",
    "contacts",
    "step",
    "iteration_method",
    "turning_force",
)


#: A spring strained less than this (1) is slack (rounding leaves +-1e-16 on unstrained ones).
SLACK_STRAIN = 1e-9


def git_revision() -> str:
    """The source tree's git revision, or 'unknown'."""
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            timeout=5,
            cwd=Path(__file__).resolve().parent,
        )
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def result_dataset(
    state: State, fields: Fields, marks: list[Landmark], relaxed: xr.Dataset
) -> xr.Dataset:
    grid = state.grid
    converged = int(relaxed.attrs.get("solver_converged", 0))
    note = "" if converged else " (NOT CONVERGED)"
    shape = (grid.m, grid.n)
    variables = {
        "x": node_variable(shape, state.x[:, 0], "m", "node x position"),
        "y": node_variable(shape, state.x[:, 1], "m", "node y position"),
        "z": node_variable(shape, state.x[:, 2], "m", "node height", positive="up"),
        "u": node_variable(shape, grid.rest_uv[:, 0], "m", "rest coordinate along the weft"),
        "v": node_variable(shape, grid.rest_uv[:, 1], "m", "rest coordinate along the warp"),
        "stress_weft": node_variable(shape, fields.stress_weft, "Pa", "weft stress" + note),
        "stress_warp": node_variable(shape, fields.stress_warp, "Pa", "warp stress" + note),
        "strain_weft": node_variable(shape, fields.strain_weft, "1", "weft strain"),
        "strain_warp": node_variable(shape, fields.strain_warp, "1", "warp strain"),
        "tension_weft": node_variable(shape, fields.tension_weft, "N m-1", "weft tension"),
        "tension_warp": node_variable(shape, fields.tension_warp, "N m-1", "warp tension"),
        "pressure": node_variable(shape, fields.pressure, "Pa", "pressure on the body" + note),
        "pressure_mmHg": node_variable(
            shape, fields.pressure / MMHG, "mmHg", "pressure on the body"
        ),
        "p_laplace": node_variable(shape, fields.p_laplace, "Pa", "generalised Laplace pressure"),
        "p_laplace_difference": node_variable(
            shape, fields.p_laplace - fields.pressure, "Pa", "p_laplace minus pressure"
        ),
        "node_area": node_variable(shape, fields.area, "m2", "deformed tributary area of the node"),
        "edge_support_force": node_variable(
            shape,
            fields.edge_support,
            "N",
            "vertical force of the edge support on a sliding edge node (0 elsewhere)",
        ),
        "contact": flag_variable(shape, fields.on_body, "node on the body", CONTACT_MEANINGS),
        "constraint": flag_variable(
            shape, state.constraint, "node movement kind", CONSTRAINT_MEANINGS
        ),
        "spring_stress": xr.Variable(
            "spring",
            fields.spring_stress,
            {"units": "Pa", "long_name": "spring stress S/A (negative: compressed)"},
        ),
        "spring_slack": xr.Variable(
            "spring",
            (fields.spring_strain <= SLACK_STRAIN).astype(np.int8),
            {
                "units": "1",
                "long_name": "spring slack or compressed (strain <= 1e-9)",
                "flag_values": np.array([0, 1], np.int8),
                "flag_meanings": "stretched slack_or_compressed",
            },
        ),
        "spring_strain": xr.Variable(
            "spring", fields.spring_strain, {"units": "1", "long_name": "spring strain"}
        ),
        "total_force": xr.Variable(
            "xyz",
            fields.total_force,
            {"units": "N", "long_name": "force of the fabric on the body"},
        ),
        "total_moment": xr.Variable(
            "xyz",
            fields.total_moment,
            {"units": "N m", "long_name": "moment of the fabric on the body about the origin"},
        ),
        "normal_force": xr.Variable(
            (), fields.normal_force, {"units": "N", "long_name": "sum of the normal reactions"}
        ),
        "pressure_integral": xr.Variable(
            (),
            fields.pressure_integral,
            {"units": "N", "long_name": "pressure integrated over the contact area"},
        ),
        "landmark_height": xr.Variable(
            "landmark", [m.height for m in marks], {"units": "m", "long_name": "landmark height"}
        ),
    }
    variables.update(pattern_variables(state))
    for name, (attribute, units, long_name) in (LANDMARK_FIELDS | ROW_FIELDS).items():
        variables[name] = xr.Variable(
            "landmark",
            [getattr(m, attribute) for m in marks],
            {"units": units, "long_name": long_name},
        )
    for name in ("spring_family", "spring_node_a", "spring_node_b", "rest_length", "area"):
        variables[name] = relaxed[name].variable
    for name in HISTORY:
        if name in relaxed:
            variables[name] = relaxed[name].variable
    variables.update(fabric_variables(state.fabric))
    variables.update(pieces_variables(grid, state.fabrics))
    variables.update(seam_variables(grid, state.x))
    variables.update(band_ratio_variables(state, marks))
    coords = {
        "row": relaxed["row"].variable,
        "col": relaxed["col"].variable,
        "landmark": xr.Variable("landmark", [m.name for m in marks], {"long_name": "girth line"}),
        "xyz": xr.Variable("xyz", ["x", "y", "z"], {"long_name": "component"}),
    }
    attrs = global_attrs(f"cloth result: {state.fabric.name}", dict(relaxed.attrs))
    keep = ("case", "body", "provenance", "fabric_name", "around", "n", "m", "closed")
    attrs.update({k: relaxed.attrs[k] for k in keep if k in relaxed.attrs})
    attrs.update({k: v for k, v in relaxed.attrs.items() if k.startswith(("solver_", "grid_"))})
    attrs.update(pieces_attrs(grid, state.fabrics))
    attrs.update(
        {
            "cloth_kind": KIND,
            "git_revision": git_revision(),
            "converged": converged,
            "comment": ""
            if converged
            else "the relaxation did NOT converge: results are approximate",
        }
    )
    return xr.Dataset(variables, coords=coords, attrs={k: to_attr(v) for k, v in attrs.items()})


def region_variables(
    found: Sequence[Region], marks: list[Landmark], shape: tuple[int, int]
) -> dict[str, xr.Variable]:
    """Per region (`cloth.results.regions`: ``slack_warp``, ``off_body``) of a grid of
    ``shape`` (m, n): its node flag ``{name}`` (``slack_warp`` only: ``off_body`` is the
    complement of ``contact``), ``{name}_share`` (1, of the garment's area), ``{name}_ranges``
    ((R, 2) m, dims ``{name}_range`` and ``bound``: bottom, top) and ``landmark_{name}`` (flag:
    the region meets the line's band)."""
    flags = {"flag_values": np.array([0, 1], np.int8), "flag_meanings": "no yes"}
    out: dict[str, xr.Variable] = {}
    for item in found:
        label = item.name.replace("_", " ")
        if item.name != "off_body":
            out[item.name] = node_variable(
                shape, item.flag.astype(np.int8), "1", f"node in the {label} region", **flags
            )
        out[f"{item.name}_share"] = variable(
            (), item.share, "1", f"share of the garment's area in the {label} region"
        )
        out[f"{item.name}_ranges"] = variable(
            (f"{item.name}_range", "bound"),
            item.ranges,
            "m",
            f"height ranges of the {label} region (bottom, top)",
        )
        out[f"landmark_{item.name}"] = variable(
            "landmark",
            np.array([m.name in item.lines for m in marks], np.int8),
            "1",
            f"the {label} region meets the girth line's band",
            **flags,
        )
    return out


def sensor_variables(reading: Reading, values: np.ndarray) -> dict[str, xr.Variable]:
    """The case's sensors (dim ``sensor``; `cloth.case.reading`): ``sensor_height`` (m),
    ``sensor_angle`` (degree), ``sensor_diameter`` (m) and ``sensor_pressure`` ((S,) Pa, what
    each reads); none where the case places no sensor."""
    if not reading.sensors:
        return {}
    sensors = reading.sensors
    return {
        "sensor": xr.Variable("sensor", [s.name for s in sensors], {"long_name": "sensor"}),
        "sensor_height": variable("sensor", [s.height for s in sensors], "m", "sensor height"),
        "sensor_angle": variable(
            "sensor",
            [s.angle for s in sensors],
            "degree",
            "sensor angle about the up axis from +x towards +y",
        ),
        "sensor_diameter": variable(
            "sensor", [s.diameter for s in sensors], "m", "sensor footprint diameter"
        ),
        "sensor_pressure": variable(
            "sensor", values, "Pa", "pressure the sensor reads (contact force over area)"
        ),
    }


def pattern_variables(state: State) -> dict[str, xr.Variable]:
    """The cut pattern per row (dim ``row``): ``rest_circumference`` (m, the sum of the row's
    weft rest lengths), ``pattern_height`` (m, the rest warp coordinate v), and where predeform
    recorded them ``cut_height`` (m, the body height the row was cut for) and
    ``row_reduction`` (1, the reduction profile there); `cloth pattern` reads them."""
    grid = state.grid
    weft = grid.rest_length[grid.family_slices[WEFT]]
    per_row = weft.reshape(grid.m, -1).sum(axis=1)  # n springs round a tube, n - 1 across
    out = {
        "rest_circumference": variable(
            "row", per_row, "m", "rest circumference of the row (flat width of an open piece)"
        ),
        "pattern_height": variable(
            "row", grid.rest_uv[:: grid.n, 1], "m", "rest warp coordinate of the row"
        ),
    }
    cut = state.row_values("cut_height")
    if cut is not None:
        out["cut_height"] = variable(
            "row",
            cut,
            "m",
            "body height the row was cut for",
            shift=float(state.attrs.get("cut_shift", 0.0)),
            comment="the row's height on the wearer is cut_height + shift (a pattern placed "
            "by a girth line on a body it was not cut for; 0 on its own body)",
        )
    reduction = state.row_values("row_reduction")
    if reduction is not None:
        profile = state.case.garment.reduction_profile
        out["row_reduction"] = variable(
            "row",
            reduction,
            "1",
            "reduction of the row's rest circumference from the hull girth",
            profile=json.dumps(profile.to_block() if profile is not None else None),
            interpolation="monotone cubic (PCHIP) through the knots, held beyond the end knots",
        )
    return out


def band_ratio_variables(state: State, marks: list[Landmark]) -> dict[str, xr.Variable]:
    """``band_ratio`` ((band,), 1): each band's mean pressure over the line's beside it
    (`cloth.case.pieces.BESIDE`): above 1 a band presses harder than the fabric next to it (a
    stocking's top band as a tourniquet); NaN where the line beside is off the garment."""
    bands = state.case.garment.pieces.bands
    if not bands:
        return {}
    mean = {m.name: m.mean for m in marks}
    ratio = [
        mean.get(b.name, np.nan) / mean.get(b.name + BESIDE, np.nan)
        if mean.get(b.name + BESIDE)
        else np.nan
        for b in bands
    ]
    return {
        "band_ratio": variable(
            "band", np.asarray(ratio, dtype=float), "1", "band mean pressure over the line beside's"
        ),
        "band": variable("band", np.array([b.name for b in bands]), None, "garment band"),
    }


def summary_rows(ds: xr.Dataset, case_name: str) -> list[dict[str, object]]:
    """summary.csv's rows: per girth line its pressures, tension, error estimate and the case's
    judging (`cloth.results.judging`; the default judge for a result without its case)."""
    rows = []
    for index, name in enumerate(ds["landmark"].values.tolist()):
        mark = Landmark(
            str(name),
            float(ds["landmark_height"][index]),
            -1,
            float(ds["pressure_mean"][index]),
            float(ds["pressure_max"][index]),
            float(ds["pressure_min"][index]),
            float(ds["tension_mean"][index]),
            float(ds["row_pressure_mean"][index]) if "row_pressure_mean" in ds else np.nan,
        )
        record = mark.record()
        record.pop("row")
        extra = {
            name: float(ds[name])
            for name in (
                "max_strain_weft",
                "lab_max_strain_weft",
                "max_strain_warp",
                "lab_max_strain_warp",
            )
            if name in ds
        }
        if "band_ratio" in ds:  # a garment's bands: each band's line over the line beside
            bands = [str(b) for b in ds["band"].values]
            extra["band_ratio"] = (
                float(ds["band_ratio"].values[bands.index(str(name))]) if str(name) in bands else ""
            )
        rows.append(
            {
                "case": case_name,
                **record,
                **estimate_columns(ds, index),
                **extra,
                **_region_columns(ds, index),
                "converged": int(ds.attrs.get("converged", 0)),
            }
        )
    case = ds.attrs.get("case")
    judge = Case.from_dict(json.loads(case)).judge if case else Judge()
    return judged(rows, judge)


def _region_columns(ds: xr.Dataset, index: int) -> dict[str, object]:
    """summary.csv's region columns of the ``index``-th girth line (`cloth.results.regions`):
    whether the slack warp and the lifted garment meet its band (0/1), and the words."""
    if "landmark_slack_warp" not in ds:
        return {}
    slack = int(ds["landmark_slack_warp"][index])
    off = int(ds["landmark_off_body"][index])
    case = json.loads(ds.attrs.get("case", "{}"))
    friction = float((case.get("contact") or {}).get("friction", 0.0))
    return {
        "warp_slack": slack,
        "off_body": off,
        "friction_note": note(bool(slack), bool(off), friction),
    }


def write_summary(rows: list[dict[str, object]], path: str | Path) -> Path:
    buffer = _io.StringIO()
    if rows:
        writer = csv.DictWriter(buffer, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow(
                {k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()}
            )
    else:
        buffer.write("case,landmark\n")
    with atomic_output(path) as tmp:
        tmp.write_text(buffer.getvalue())
    return Path(path)
