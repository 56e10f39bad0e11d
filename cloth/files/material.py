"""The material file (``material.nc``): a fabric's curves, the data behind them, and fit errors.

Layout (CF-1.11, one group of variables per direction D in weft, warp[, bias]):

====================================  ===========  ======  ===================================
variable                              dims         units   meaning
====================================  ===========  ======  ===================================
``D_knot_strain``                     (knot_D,)    1       knot strains of the curve
``D_knot_stress``                     (knot_D,)    Pa      knot stresses
``D_point_strain``                    (point_D,)   1       measured points the curve fits
``D_point_stress``                    (point_D,)   Pa
``D_fit_max_error``                   ()           Pa      max |curve - points|
``D_fit_rms_error``                   ()           Pa      RMS of curve - points
``D_fit_max_error_percent``           ()           %       max error / max measured stress
``D_fit_rms_error_percent``           ()           %
``D_compression_modulus``             ()           Pa      slope of sigma below zero strain
``D_residual_strain``                 ()           1       strain at zero load on the branch
``thickness``                         ()           m
``areal_density``                     ()           kg m-2  NaN when unknown
====================================  ===========  ======  ===================================

Global attributes: ``cloth_kind = "material"``, ``fabric_name``, ``provenance`` (JSON), CF
``Conventions``, ``history``.
"""

from __future__ import annotations

import json
from pathlib import Path

import xarray as xr

from cloth.case.locations import bundled_material
from cloth.errors import InputError
from cloth.io import global_attrs, read_netcdf, resolve, to_attr, variable
from cloth.materials.curves import DIRECTIONS, Fabric, StressStrainCurve
from cloth.materials.labtables import Material, ingest
from cloth.paths import input_file, path_form
from cloth.shipped import shipped

KIND = "material"
DATA_MATERIALS = shipped("materials")


def curve_variables(prefix: str, curve: StressStrainCurve) -> dict[str, xr.Variable]:
    """The knot and compression-modulus variables of one curve (also used in state files)."""
    dim = f"knot_{prefix}"
    return {
        f"{prefix}_knot_strain": variable(
            dim, curve.knot_strain, "1", f"{prefix} curve knot strain"
        ),
        f"{prefix}_knot_stress": variable(
            dim, curve.knot_stress, "Pa", f"{prefix} curve knot stress"
        ),
        f"{prefix}_compression_modulus": variable(
            (), curve.compression_modulus, "Pa", f"{prefix} stress slope below zero strain"
        ),
    }


def fabric_variables(fabric: Fabric) -> dict[str, xr.Variable]:
    """Curves of every direction, thickness and areal density of ``fabric``."""
    variables: dict[str, xr.Variable] = {}
    for direction in fabric.directions:
        variables.update(curve_variables(direction, fabric.curve(direction)))
    for direction, value in fabric.set_strain.items():
        variables[f"{direction}_set_strain"] = variable(
            (), value, "1", f"{direction} set strain of the last load/unload cycle"
        )
    variables["thickness"] = variable((), fabric.thickness, "m", "fabric thickness")
    variables["areal_density"] = variable(
        (), fabric.areal_density, "kg m-2", "fabric mass per area"
    )
    return variables


def fabric_from_dataset(ds: xr.Dataset) -> Fabric:
    """Rebuild the `Fabric` stored by `fabric_variables` (in a material or state file)."""
    curves = {}
    for direction in DIRECTIONS:
        if f"{direction}_knot_strain" in ds:
            curves[direction] = StressStrainCurve(
                ds[f"{direction}_knot_strain"].values,
                ds[f"{direction}_knot_stress"].values,
                compression_modulus=float(ds[f"{direction}_compression_modulus"]),
            )
    provenance = json.loads(ds.attrs.get("provenance", "{}"))
    return Fabric(
        name=str(ds.attrs.get("fabric_name", "fabric")),
        weft=curves["weft"],
        warp=curves["warp"],
        bias=curves.get("bias"),
        thickness=float(ds["thickness"]),
        areal_density=float(ds["areal_density"]),
        provenance={str(k): str(v) for k, v in provenance.items()},
        set_strain={d: float(ds[f"{d}_set_strain"]) for d in DIRECTIONS if f"{d}_set_strain" in ds},
    )


def material_dataset(material: Material) -> xr.Dataset:
    """The ``material.nc`` dataset of an ingested material."""
    fabric = material.fabric
    variables = fabric_variables(fabric)
    for direction, data in material.data.items():
        dim = f"point_{direction}"
        report = data.report
        variables.update(
            {
                f"{direction}_point_strain": variable(
                    dim, data.raw_strain, "1", f"{direction} measured strain"
                ),
                f"{direction}_point_stress": variable(
                    dim, data.raw_stress, "Pa", f"{direction} measured stress"
                ),
                f"{direction}_fit_max_error": variable(
                    (), report.max_error, "Pa", f"{direction} curve max abs error"
                ),
                f"{direction}_fit_rms_error": variable(
                    (), report.rms_error, "Pa", f"{direction} curve RMS error"
                ),
                f"{direction}_fit_max_error_percent": variable(
                    (), report.max_error_percent, "%", f"{direction} curve max error / max stress"
                ),
                f"{direction}_fit_rms_error_percent": variable(
                    (), report.rms_error_percent, "%", f"{direction} curve RMS error / max stress"
                ),
                f"{direction}_residual_strain": variable(
                    (), data.residual_strain, "1", f"{direction} strain at zero load (set)"
                ),
            }
        )
    attrs = global_attrs(f"cloth material: {fabric.name}")
    attrs.update(
        {
            "cloth_kind": KIND,
            "fabric_name": fabric.name,
            "provenance": str(to_attr(fabric.provenance)),
        }
    )
    return xr.Dataset(variables, attrs=attrs)


def fit_errors(ds: xr.Dataset) -> dict[str, dict[str, float]]:
    """Per direction: fit max/RMS error in Pa and % from a material dataset."""
    out = {}
    for direction in DIRECTIONS:
        if f"{direction}_fit_max_error" in ds:
            out[direction] = {
                key: float(ds[f"{direction}_fit_{key}"])
                for key in ("max_error", "rms_error", "max_error_percent", "rms_error_percent")
            }
    return out


__all__ = [
    "KIND",
    "case_fabric",
    "curve_variables",
    "fabric_from_dataset",
    "fabric_variables",
    "fit_errors",
    "load_fabric",
    "material_dataset",
    "piece_fabrics",
]


def case_fabric(case, base_dir: str | Path = ".") -> Fabric:
    """The fabric a case (`cloth.case.Case`) wears: its ``material`` (`load_fabric`) with the
    stresses scaled by its ``fabric_scale``."""
    return load_fabric(case.material, base_dir).scaled(case.fabric_scale)


def piece_fabrics(case, base_dir: str | Path = ".") -> dict[str, Fabric]:
    """The fabrics a case's bands, panels, layers and seams name (`cloth.case.pieces`), by
    name (`load_fabric`; the case's ``fabric_scale`` is its own material's only); `InputError`
    naming the key of the first that will not load."""
    pieces = case.garment.pieces
    out: dict[str, Fabric] = {}
    keys = [(f"garment.bands[{k}].material", b.material) for k, b in enumerate(pieces.bands)]
    keys += [(f"garment.panels[{k}].material", p.material) for k, p in enumerate(pieces.panels)]
    keys += [(f"garment.layers[{k}].material", x.material) for k, x in enumerate(pieces.layers)]
    if pieces.panels and pieces.seams.material is not None:
        keys.append(("garment.seams.material", pieces.seams.material))
    for key, name in keys:
        if name in out or name == case.material:
            continue
        try:
            out[name] = load_fabric(name, base_dir)
        except InputError as exc:
            raise InputError(exc.detail, exc.source, key) from None
    return out


def load_fabric(spec: str, base_dir: str | Path = ".") -> Fabric:
    """The fabric named by a case's ``material``: a lab table (CSV), a material.nc, or the name
    of a table in ``data/materials`` (e.g. ``powernet``)."""
    path = resolve(str(path_form(spec, None, "material")), base_dir)
    if bundled_material(spec):
        path = DATA_MATERIALS / f"{spec}.csv"
        if not path.is_file():
            names = sorted(p.stem for p in DATA_MATERIALS.glob("*.csv"))
            raise InputError(
                f"unknown material {spec!r}; give a lab table, a material.nc, or one of "
                f"{', '.join(names)}",
                field="material",
            )
    path = input_file(path, ".", None, "material", "material file")  # resolved above
    if path.suffix == ".nc":
        return fabric_from_dataset(read_netcdf(path, KIND))
    return ingest([path]).fabric
