"""The worn garment: rest lengths longer by the fabric's set strain.

Stretch fabric does not return to its length after loading: a residual (set) strain s remains.
A garment cut to rest length L0 is, once worn, L0 (1 + s) long at rest, in each direction with
that direction's set. ``garment.worn: true`` builds that pattern: every weft rest length grows
by 1 + s_weft, every warp one by 1 + s_warp (the grid's families follow ``garment.around``).

Convention. From its set length the fabric follows the material's curve: a worn spring at
strain e' = l / (L0 (1 + s)) - 1 carries sigma(e'), the curve read as the unloading branch
measured from the set length, where a worn garment's stress starts. So a worn tube cut at
reduction r behaves as a new one cut at 1 - (1 - r)(1 + s).

Limit. A curve ingested from a cyclic table's unloading branch is measured from the specimen's
original length, so its stress already starts near the set; worn, that set would count twice
(in the longer rest length and in the curve's slack start). To compare new and worn with cyclic
data, give the material the first loading branch (``branch: load``, ``cycle: 1``) as the new
fabric's curve: the worn garment then takes the set measured on the last unloading branch and
that curve from its set length.

The set comes from ``garment.set_strain: {weft, warp}`` where given, else from the material's
load/unload cycles (`cloth.materials.curves.Fabric.set_strain`); a worn garment with neither is
refused.
"""

from __future__ import annotations

import math

from cloth.case import GarmentSpec
from cloth.errors import InputError
from cloth.materials.curves import Fabric

DIRECTIONS = ("weft", "warp")


def set_strains(garment: GarmentSpec, fabric: Fabric, source: str = "case") -> dict:
    """The set strain (1) per fabric direction of a worn garment (empty for a new one),
    checked: finite, >= 0 and < 1 (`InputError` naming the field)."""
    if not garment.worn:
        return {}
    given = garment.set_strain
    out = {}
    for direction in DIRECTIONS:
        value = given.get(direction, fabric.set_strain.get(direction))
        where = f"garment.set_strain.{direction}"
        if value is None:
            raise InputError(
                f"worn: true needs the {direction} set strain, and the material "
                f"{fabric.name!r} has no load/unload cycles to measure it; give "
                f"set_strain: {{{direction}: ...}} or set worn: false",
                source,
                where,
            )
        value = float(value)
        if not (math.isfinite(value) and 0.0 <= value < 1.0):
            raise InputError(f"a set strain must be a number in [0, 1), got {value}", source, where)
        out[direction] = value
    return out
