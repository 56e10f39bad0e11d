"""State files (``initial.nc``, ``relaxed.nc``): everything needed to rebuild the model.

A state holds the grid topology, rest geometry, spring areas, the fabric curves, the movement
kind of every node, the positions, a reference to the body (kind, path, sha256) and the case, so
any stage can continue from the file alone.

Variables (dims ``row`` = j (warp, bottom to top), ``col`` = i (weft, around), ``spring``):

=====================  ==============  =======  ==========================================
variable               dims            units    meaning
=====================  ==============  =======  ==========================================
``x``, ``y``, ``z``    (row, col)      m        node positions (body frame, z up)
``u``, ``v``           (row, col)      m        rest coordinates in the flat pattern
``constraint``         (row, col)      -        0 free, 1 sliding (height held), 2 fixed
``contact``            (row, col)      -        0 off the body, 1 on the body surface
``spring_node_a/b``    (spring,)       -        node index k = row * n + col of each end
``rest_length``        (spring,)       m
``area``               (spring,)       m2       thickness x tributary width
``spring_family``      (spring,)       -        0 weft, 1 warp, 2 shear, 3 bend
fabric curves          see cloth.files.material
=====================  ==============  =======  ==========================================
"""

from __future__ import annotations

import json
import re
from dataclasses import replace
from typing import Any

import numpy as np
import xarray as xr

from cloth import __version__
from cloth.case import Case
from cloth.errors import InputError
from cloth.files.material import fabric_from_dataset, fabric_variables
from cloth.files.pieces import pieces_attrs, pieces_from_dataset, pieces_variables
from cloth.garment.grid import FAMILIES, Grid, StressStrainCurve
from cloth.garment.layout import Layout
from cloth.garment.state import State, grid_fabric
from cloth.io import flag_variable, global_attrs, node_variable, read_netcdf, to_attr, variable

KIND = "state"
FORMAT_VERSION = 1

CONSTRAINT_MEANINGS = "free sliding fixed"
CONTACT_MEANINGS = "off_body on_body"
REQUIRED = (
    "x",
    "y",
    "z",
    "u",
    "v",
    "constraint",
    "contact",
    "spring_node_a",
    "spring_node_b",
    "rest_length",
    "area",
    "spring_family",
    "weft_knot_strain",
    "warp_knot_strain",
    "thickness",
)


def state_dataset(state: State, stage: str, previous: dict[str, Any] | None = None) -> xr.Dataset:
    """The netCDF dataset of ``state`` at ``stage`` ('initial', 'relaxed', ...)."""
    grid = state.grid
    shape = (grid.m, grid.n)
    x = state.x.reshape(grid.m, grid.n, 3)
    uv = grid.rest_uv.reshape(grid.m, grid.n, 2)
    variables = {
        "x": node_variable(shape, x[..., 0], "m", "node x position", axis="X"),
        "y": node_variable(shape, x[..., 1], "m", "node y position"),
        "z": node_variable(shape, x[..., 2], "m", "node height", positive="up"),
        "u": node_variable(shape, uv[..., 0], "m", "rest coordinate along the weft"),
        "v": node_variable(shape, uv[..., 1], "m", "rest coordinate along the warp"),
        "constraint": flag_variable(
            shape, state.constraint.astype(np.int8), "node movement kind", CONSTRAINT_MEANINGS
        ),
        "contact": flag_variable(
            shape, state.on_body.astype(np.int8), "node on the body", CONTACT_MEANINGS
        ),
        "spring_node_a": variable("spring", grid.ends[:, 0].astype(np.int32), "1", "first node"),
        "spring_node_b": variable("spring", grid.ends[:, 1].astype(np.int32), "1", "second node"),
        "rest_length": variable("spring", grid.rest_length, "m", "spring rest length"),
        "area": variable("spring", grid.area, "m2", "spring area (thickness x tributary width)"),
        "spring_family": xr.Variable(
            "spring",
            grid.family.astype(np.int8),
            {
                "long_name": "spring family",
                "units": "1",
                "flag_values": np.arange(len(FAMILIES), dtype=np.int8),
                "flag_meanings": " ".join(FAMILIES),
            },
        ),
    }
    variables.update(fabric_variables(state.fabric))
    variables.update(pieces_variables(grid, state.fabrics))
    coords = {
        "row": variable(
            "row", np.arange(grid.m, dtype=np.int32), "1", "warp index j (bottom to top)"
        ),
        "col": variable("col", np.arange(grid.n, dtype=np.int32), "1", "weft index i (around)"),
    }
    attrs = global_attrs(f"cloth {stage} state: {state.fabric.name}", previous)
    attrs.update(
        {
            "cloth_kind": KIND,
            "format_version": FORMAT_VERSION,
            "stage": stage,
            "n": grid.n,
            "m": grid.m,
            "closed": int(grid.closed),
            "around": state.around,
            "fabric_name": state.fabric.name,
            "provenance": str(to_attr(state.fabric.provenance)),
            "case": json.dumps(state.case.to_dict(), sort_keys=True),
            "body": json.dumps(state.body, sort_keys=True),
            "moduli": json.dumps(state.moduli, sort_keys=True),
        }
    )
    attrs.update({key: to_attr(value) for key, value in state.attrs.items()})
    attrs.update(pieces_attrs(grid, state.fabrics))
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def state_from_dataset(ds: xr.Dataset, source: str = "state") -> State:
    """Rebuild a `State` from its dataset."""
    version = int(ds.attrs.get("format_version", -1))
    if version != FORMAT_VERSION:
        raise InputError(
            f"state format version {version} is not {FORMAT_VERSION} (written by cloth "
            f"{ds.attrs.get('cloth_version', '?')}, this is {__version__}); re-run the stage "
            "that made it",
            source,
            "format_version",
        )
    n, m = int(ds.attrs["n"]), int(ds.attrs["m"])
    fabric = fabric_from_dataset(ds)
    around = str(ds.attrs.get("around", "weft"))
    moduli = json.loads(ds.attrs.get("moduli", "{}"))
    seen = grid_fabric(fabric, around)
    family = ds["spring_family"].values.astype(np.int8)
    counts = np.bincount(family, minlength=len(FAMILIES))
    starts = np.concatenate(([0], np.cumsum(counts)))
    curves: list[StressStrainCurve | None] = [seen.weft, seen.warp, None, None]
    if counts[2]:
        curves[2] = StressStrainCurve.linear(moduli["shear_modulus"])
    if counts[3]:
        curves[3] = StressStrainCurve.linear(moduli["bend_modulus"])
    grid = Grid(
        n=n,
        m=m,
        closed=bool(int(ds.attrs["closed"])),
        rest_uv=np.stack([ds["u"].values.ravel(), ds["v"].values.ravel()], axis=1),
        ends=np.stack([ds["spring_node_a"].values, ds["spring_node_b"].values], axis=1).astype(
            np.intp
        ),
        rest_length=ds["rest_length"].values.astype(np.float64),
        area=ds["area"].values.astype(np.float64),
        family=family,
        family_slices=tuple(
            slice(int(starts[f]), int(starts[f + 1])) for f in range(len(FAMILIES))
        ),
        curves=tuple(curves),
        thickness=fabric.thickness,
    )
    materials, fabrics = pieces_from_dataset(ds)
    if materials is not None:
        grid = replace(grid, materials=materials)
    layout = None
    x = np.stack([ds[c].values.ravel() for c in ("x", "y", "z")], axis=1).astype(np.float64)
    if "case" not in ds.attrs:
        raise InputError("the file has no case; re-run the stage that made it", source, "case")
    case = Case.from_dict(json.loads(ds.attrs["case"]), source)
    if materials is not None:
        layout = Layout.of(case)
    skip = {
        "Conventions",
        "title",
        "institution",
        "source",
        "cloth_version",
        "history",
        "cloth_kind",
        "format_version",
        "n",
        "m",
        "closed",
        "around",
        "fabric_name",
        "provenance",
        "case",
        "body",
        "moduli",
        "stage",
        "fabrics",
        "fabric_thickness",
        "seam_share",
        "row_split",
        "row_friction",
    }
    return State(
        grid=grid,
        x=x,
        constraint=ds["constraint"].values.ravel().astype(np.int8),
        on_body=ds["contact"].values.ravel().astype(np.int8),
        fabric=fabric,
        around=around,
        case=case,
        body=json.loads(ds.attrs.get("body", "{}")),
        moduli=moduli,
        skin=case.skin,
        attrs={
            k: v for k, v in ds.attrs.items() if k not in skip and not re.match(r"fabric\d+_", k)
        },
        fabrics=fabrics,
        layout=layout,
    )


def read_state(path, stage: str | None = None) -> tuple[State, xr.Dataset]:
    """Read a state file (checking its kind and variables); return the state and dataset."""
    ds = read_netcdf(path, KIND, REQUIRED)
    if stage is not None and ds.attrs.get("stage") != stage:
        raise InputError(
            f"expected a {stage} state, found stage {ds.attrs.get('stage')!r}; pass the right file",
            path,
            "stage",
        )
    return state_from_dataset(ds, str(path)), ds
