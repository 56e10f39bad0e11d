"""A garment of several fabrics in state and result files (issue 69; `cloth.garment.pieces`).

Written only where the garment has bands, panels or layers; a garment of one fabric's files are
as they were. Variables (``W`` weft and warp springs, the rest -1):

=============================  =================  =====  =======================================
variable                       dims               units  meaning
=============================  =================  =====  =======================================
``spring_curve``               (spring,)          1      the spring's composite curve, -1 none
``curve_knot_strain``          (curve, knot)      1      each composite's knots (NaN padded)
``curve_knot_stress``          (curve, knot)      Pa     stress over the spring's own thickness
``curve_compression_modulus``  (curve,)           Pa     slope below zero strain
``spring_fabric``              (spring,)          1      the fabric at the spring's middle
``node_fabric``                (row, col)         1      the fabric at the node
``fabricK_*``                  as a material's    -      fabric K's curves (`cloth.files.material`)
=============================  =================  =====  =======================================

The fabrics' names are the attribute ``fabrics`` (JSON, in the order the indices count), their
thicknesses ``fabric_thickness`` (m), the seams' places ``seam_share`` (JSON: shares of the rest
circumference from the centre back), and ``row_split`` the share of each cell between two rows
that the lower row stands for (`cloth.garment.pieces.SpringMaterials`).
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping

import numpy as np
import xarray as xr

from cloth.files.material import fabric_from_dataset, fabric_variables
from cloth.garment.grid import Grid
from cloth.garment.pieces import SpringMaterials
from cloth.io import node_variable, variable
from cloth.materials.curves import Fabric, StressStrainCurve


def flag_words(names: tuple[str, ...]) -> str:
    """CF flag meanings for fabric names: each a word of letters, digits and underscores."""
    return " ".join(re.sub(r"\W+", "_", name).strip("_") or "fabric" for name in names)


def pieces_variables(grid: Grid, fabrics: Mapping[str, Fabric]) -> dict[str, xr.Variable]:
    """The variables of ``grid``'s fabrics (module docstring); none for one fabric."""
    materials = grid.materials
    if materials is None:
        return {}
    woven = materials.index.size
    curve = np.full(grid.n_springs, -1, dtype=np.int32)
    curve[:woven] = materials.index
    fabric = np.full(grid.n_springs, -1, dtype=np.int16)
    fabric[:woven] = materials.fabric
    knots = max(c.n_knots for c in materials.curves)
    strain = np.full((len(materials.curves), knots), np.nan)
    stress = np.full((len(materials.curves), knots), np.nan)
    for k, c in enumerate(materials.curves):
        strain[k, : c.n_knots] = c.knot_strain
        stress[k, : c.n_knots] = c.knot_stress
    count = len(materials.names)
    flags = {
        "flag_values": np.arange(count, dtype=np.int16),
        "flag_meanings": flag_words(materials.names),
    }
    out = {
        "spring_curve": variable("spring", curve, "1", "composite curve of the spring (-1 none)"),
        "curve_knot_strain": variable(("curve", "curve_knot"), strain, "1", "composite knots"),
        "curve_knot_stress": variable(
            ("curve", "curve_knot"), stress, "Pa", "composite knot stress (own thickness)"
        ),
        "curve_compression_modulus": variable(
            "curve",
            np.array([c.compression_modulus for c in materials.curves]),
            "Pa",
            "composite stress slope below zero strain",
        ),
        "spring_fabric": variable(
            "spring", fabric, "1", "fabric at the spring's middle (-1 none)", **flags
        ),
        "node_fabric": node_variable(
            (grid.m, grid.n), materials.node_fabric, "1", "fabric at the node", **flags
        ),
    }
    for k, name in enumerate(materials.names):
        if name not in fabrics:
            continue
        for key, var in fabric_variables(fabrics[name]).items():
            dims = tuple(f"fabric{k}_{d}" for d in var.dims)
            out[f"fabric{k}_{key}"] = xr.Variable(dims, var.values, var.attrs)
    return out


def seam_variables(grid: Grid, x: np.ndarray) -> dict[str, xr.Variable]:
    """Where each seam sits on the body at positions ``x`` ((N, 3), m): ``seam_x``, ``seam_y``,
    ``seam_z`` ((seam, row), m), each row's point at the seam's share of its rest
    circumference, linear between the two nodes around it; none without seams."""
    materials = grid.materials
    if materials is None or materials.seams.size == 0:
        return {}
    pts = x.reshape(grid.m, grid.n, 3)
    place = materials.seams * grid.n
    below = np.floor(place).astype(int) % grid.n
    t = (place - np.floor(place))[:, None, None]
    at = (1 - t) * pts[:, below].transpose(1, 0, 2) + t * pts[:, (below + 1) % grid.n].transpose(
        1, 0, 2
    )  # (seam, row, 3)
    angle = np.mod(360.0 * materials.seams - 180.0 + 180.0, 360.0) - 180.0
    return {
        f"seam_{axis}": variable(("seam", "row"), at[..., k], "m", f"seam {axis} position")
        for k, axis in enumerate("xyz")
    } | {
        "seam_angle": variable(
            "seam", angle, "degree", "seam's share of the cut circumference from the centre front"
        )
    }


def pieces_attrs(grid: Grid, fabrics: Mapping[str, Fabric]) -> dict[str, str]:
    """The attributes of ``grid``'s fabrics (module docstring); none for one fabric."""
    materials = grid.materials
    if materials is None:
        return {}
    attrs = {
        "fabrics": json.dumps(list(materials.names)),
        "fabric_thickness": json.dumps(list(materials.fabric_thickness)),
        "seam_share": json.dumps(materials.seams.tolist()),
        "row_split": json.dumps(materials.split.tolist()),
        "row_friction": json.dumps(
            [None if not np.isfinite(f) else float(f) for f in materials.row_friction]
        ),
    }
    for k, name in enumerate(materials.names):
        if name in fabrics:
            attrs[f"fabric{k}_name"] = fabrics[name].name
            attrs[f"fabric{k}_provenance"] = json.dumps(fabrics[name].provenance)
    return attrs


def pieces_from_dataset(ds: xr.Dataset) -> tuple[SpringMaterials | None, dict[str, Fabric]]:
    """The springs' fabrics and the pieces' fabrics by name, as `pieces_variables` and
    `pieces_attrs` wrote them; (None, {}) for a garment of one fabric."""
    if "spring_curve" not in ds:
        return None, {}
    names = tuple(json.loads(ds.attrs["fabrics"]))
    strain, stress = ds["curve_knot_strain"].values, ds["curve_knot_stress"].values
    moduli = ds["curve_compression_modulus"].values
    curves = []
    for k in range(strain.shape[0]):
        keep = np.isfinite(strain[k])
        curves.append(StressStrainCurve(strain[k, keep], stress[k, keep], float(moduli[k])))
    curve = ds["spring_curve"].values
    woven = int(np.count_nonzero(curve >= 0))
    materials = SpringMaterials(
        tuple(curves),
        curve[:woven].astype(np.intp),
        ds["spring_fabric"].values[:woven].astype(np.int16),
        ds["node_fabric"].values.ravel().astype(np.int16),
        names,
        np.asarray(json.loads(ds.attrs.get("seam_share", "[]")), dtype=float),
        tuple(json.loads(ds.attrs["fabric_thickness"])),
        np.asarray(json.loads(ds.attrs["row_split"]), dtype=float),
        np.asarray(
            [np.nan if f is None else f for f in json.loads(ds.attrs.get("row_friction", "[]"))]
            or np.full(int(ds.attrs["m"]), np.nan),
            dtype=float,
        ),
    )
    fabrics = {}
    for k, name in enumerate(names):
        prefix = f"fabric{k}_"
        keys = [key for key in ds.variables if str(key).startswith(prefix)]
        if not keys:
            continue
        sub = xr.Dataset(
            {
                str(key)[len(prefix) :]: xr.Variable(
                    tuple(str(d)[len(prefix) :] for d in ds[key].dims),
                    ds[key].values,
                    ds[key].attrs,
                )
                for key in keys
            },
            attrs={
                "fabric_name": ds.attrs.get(f"{prefix}name", name),
                "provenance": ds.attrs.get(f"{prefix}provenance", "{}"),
            },
        )
        fabrics[name] = fabric_from_dataset(sub)
    return materials, fabrics


__all__ = [
    "flag_words",
    "pieces_attrs",
    "pieces_from_dataset",
    "pieces_variables",
    "seam_variables",
]
