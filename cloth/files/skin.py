"""The skin models' variables in relaxed.nc and result.nc (only where the case asks for them).

relaxed.nc, with friction: ``friction_force_x``, ``_y``, ``_z`` (row, col; N), the skin's
friction force on each node at equilibrium, and ``friction_state`` (flags: 0 off the skin,
1 sticking, 2 slipping). result.nc copies them and adds ``friction_force`` (N, its magnitude).
With tissue, result.nc has ``skin_distance`` (m, signed distance of each node from the
undeformed skin, negative inside) and ``indentation`` (m, how far the node presses the tissue
in: max(0, -skin_distance)), and the layer under each node, ``tissue_thickness`` (m) and
``tissue_modulus`` (Pa).
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from cloth.garment.grid import Grid
from cloth.io import flag_variable, node_variable

FRICTION_MEANINGS = "off_skin stick slip"


def friction_variables(grid: Grid, friction: dict[str, NDArray]) -> dict[str, xr.Variable]:
    """relaxed.nc's friction variables from `cloth.solvers.relax.Result.friction` (none when
    it is empty)."""
    if not friction:
        return {}
    force, shape = friction["force"], (grid.m, grid.n)
    out = {
        f"friction_force_{axis}": node_variable(
            shape, force[:, k], "N", f"skin friction force {axis}"
        )
        for k, axis in enumerate("xyz")
    }
    out["friction_state"] = flag_variable(
        shape, friction["state"], "friction state of the node", FRICTION_MEANINGS
    )
    return out


def result_skin_variables(grid: Grid, ev, relaxed: xr.Dataset, layer=None) -> dict:
    """result.nc's skin variables: friction copied from ``relaxed`` with its magnitude; the
    tissue's from the final evaluation ``ev`` and the ``layer`` (`cloth.contact.tissue.Layer`)."""
    out: dict[str, xr.Variable] = {}
    shape = (grid.m, grid.n)
    if "friction_force_x" in relaxed:
        parts = [relaxed[f"friction_force_{axis}"] for axis in "xyz"]
        out.update({part.name: part.variable for part in parts})
        out["friction_state"] = relaxed["friction_state"].variable
        magnitude = np.sqrt(sum(part.values**2 for part in parts))
        out["friction_force"] = node_variable(
            shape, magnitude, "N", "skin friction force magnitude"
        )
    if layer is not None and ev.indentation is not None:
        out["skin_distance"] = node_variable(
            shape,
            ev.distance,
            "m",
            "signed distance from the undeformed skin (inside < 0)",
        )
        out["indentation"] = node_variable(
            shape, ev.indentation, "m", "indentation of the soft tissue"
        )
        out["tissue_thickness"] = node_variable(
            shape, layer.thickness, "m", "soft tissue thickness"
        )
        out["tissue_modulus"] = node_variable(
            shape, layer.modulus, "Pa", "soft tissue Young's modulus"
        )
    return out
