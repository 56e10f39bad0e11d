"""Results: spring and node stresses (the paper's Figure 4), body pressure, landmarks, summaries.

Per spring k: strain eps_k and stress sigma_k = |S_k| / A_k (the paper's definition).
Per node (the paper's node stress): the average of sigma_k over the weft springs that meet the
node, and separately over the warp springs (`stress_weft`, `stress_warp`, Pa); likewise strains
and tensions T = sigma x thickness (N m-1).

Pressure: the body's normal reaction on each node over the node's deformed tributary area
(`cloth.results.pressure`). Generalised Laplace diagnostic: p_laplace = T_weft kappa_weft / (1 +
eps_warp) + T_warp kappa_warp / (1 + eps_weft), the tensions per unit deformed width (T is per
rest width), with kappa the normal curvature of the deformed weft and warp grid lines at the node
(the curvature vector of the circle through the node and its two neighbours, along the body's
inward normal).

Landmarks: girth lines (the parametric torso's bust, underbust, waist and hip from its size
chart, or heights given in the case) -> the grid row nearest each height: mean, max and min
pressure in Pa, kPa and mmHg with the RAL-GZ 387 compression class and the comfort group of
knitted garments they fall in, and the mean hoop tension.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.garment.grid import SLIDING, WARP, WEFT, Grid, node_area, spring_thickness
from cloth.garment.mechanics import SpringState
from cloth.results.pressure import contact_reaction

log = logging.getLogger(__name__)


def node_average(grid: Grid, values: NDArray[np.float64], family: int) -> NDArray[np.float64]:
    """(N,) mean of a per-spring quantity over the springs of ``family`` meeting each node."""
    sl = grid.family_slices[family]
    ends = grid.ends[sl]
    total = np.bincount(ends[:, 0], values[sl], grid.n_nodes)
    total += np.bincount(ends[:, 1], values[sl], grid.n_nodes)
    count = np.bincount(ends[:, 0], minlength=grid.n_nodes) + np.bincount(
        ends[:, 1], minlength=grid.n_nodes
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def line_curvature(
    x: NDArray[np.float64], normal: NDArray[np.float64], grid: Grid, along: str
) -> NDArray[np.float64]:
    """(N,) normal curvature (m-1, positive when the line bends around the body) of the weft
    ('weft': around) or warp ('warp': up) grid line through each node: its curvature vector's
    component along the inward body normal; NaN at open ends."""
    pts = x.reshape(grid.m, grid.n, 3)
    nrm = normal.reshape(grid.m, grid.n, 3)
    axis = 1 if along == "weft" else 0
    if axis == 1 and grid.closed:
        prev, nxt = np.roll(pts, 1, axis=1), np.roll(pts, -1, axis=1)
        valid = np.ones((grid.m, grid.n), bool)
    else:
        prev, nxt = np.roll(pts, 1, axis=axis), np.roll(pts, -1, axis=axis)
        valid = np.ones((grid.m, grid.n), bool)
        index = [slice(None), slice(None)]
        index[axis] = [0, -1]
        valid[tuple(index)] = False
    a, b = prev - pts, nxt - pts
    chord = nxt - prev
    cross = np.linalg.norm(np.cross(a, b), axis=2)
    denom = np.linalg.norm(a, axis=2) * np.linalg.norm(b, axis=2) * np.linalg.norm(chord, axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        kappa = 2.0 * cross / denom  # circle through three points
    bend = a + b  # points towards the centre of curvature
    length = np.linalg.norm(bend, axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        # the normal curvature: the curvature vector's component into the body (on a cone the
        # hoop circle's 1/r times the normal's radial share cos(alpha))
        into = np.where(length > 0, -np.einsum("ijk,ijk->ij", bend, nrm) / length, 0.0)
    out = np.where(valid, kappa * into, np.nan)
    return out.ravel()


@dataclass(frozen=True)
class Fields:
    """Per-node and per-spring results (see the module docstring); SI units."""

    spring_strain: NDArray[np.float64]
    spring_stress: NDArray[np.float64]
    stress_weft: NDArray[np.float64]
    stress_warp: NDArray[np.float64]
    strain_weft: NDArray[np.float64]
    strain_warp: NDArray[np.float64]
    tension_weft: NDArray[np.float64]
    tension_warp: NDArray[np.float64]
    pressure: NDArray[np.float64]
    p_laplace: NDArray[np.float64]
    area: NDArray[np.float64]
    reaction: NDArray[np.float64]
    edge_support: NDArray[np.float64]
    on_body: NDArray[np.int8]
    total_force: NDArray[np.float64]
    total_moment: NDArray[np.float64]
    normal_force: float
    pressure_integral: float


def node_fields(
    grid: Grid,
    x: NDArray[np.float64],
    springs: SpringState,
    thickness: float,
    forces: NDArray[np.float64] | None = None,
    unbalanced: NDArray[np.float64] | None = None,
    held: NDArray[np.bool_] | None = None,
    normal: NDArray[np.float64] | None = None,
    constraint: NDArray[np.int8] | None = None,
) -> Fields:
    """All per-node and per-spring results at positions x ((N, 3), m).

    ``forces``, ``unbalanced``, ``held`` and ``normal`` come from the relaxation's final
    evaluation (`cloth.solvers.problem.Evaluation`); without them (a fabric off any body) the
    pressure is zero.
    """
    stress = springs.stress  # sigma_k = S_k / A_k, signed: compression (slack fabric) < 0
    strain = springs.strain
    count = grid.n_nodes
    if held is None:
        held = np.zeros(count, bool)
        forces = unbalanced = np.zeros((count, 3))
        normal = np.zeros((count, 3))
    reaction = contact_reaction(forces, unbalanced, held)
    # a sliding edge node is balanced by the body (lambda n) and its edge's support (mu e_z):
    # R + lambda n + mu e_z = 0, so the support's share is mu = -(R_z + lambda n_z), N
    edge_support = np.zeros(count)
    if constraint is not None:
        sliding = constraint == SLIDING
        edge_support[sliding] = -(forces[sliding, 2] + reaction[sliding, 2])
    area = node_area(x, grid)
    magnitude = np.linalg.norm(reaction, axis=1)
    pressure = np.where(held, magnitude / area, 0.0)
    stress_weft = node_average(grid, stress, WEFT)
    stress_warp = node_average(grid, stress, WARP)
    if grid.materials is None:
        tension_weft, tension_warp = stress_weft * thickness, stress_warp * thickness
    else:  # each spring's tension in its own fabric's thickness
        tension = stress * spring_thickness(grid)
        tension_weft = node_average(grid, tension, WEFT)
        tension_warp = node_average(grid, tension, WARP)
    kappa_weft = line_curvature(x, normal, grid, "weft")
    kappa_warp = line_curvature(x, normal, grid, "warp")
    # Laplace needs force per unit DEFORMED width: the rest width of a weft line's strip is
    # stretched by 1 + the warp strain (and a warp line's by 1 + the weft strain)
    strain_weft, strain_warp = node_average(grid, strain, WEFT), node_average(grid, strain, WARP)
    p_laplace = tension_weft * kappa_weft / (1 + strain_warp) + tension_warp * np.nan_to_num(
        kappa_warp
    ) / (1 + strain_weft)
    return Fields(
        spring_strain=strain,
        spring_stress=stress,
        stress_weft=stress_weft,
        stress_warp=stress_warp,
        strain_weft=strain_weft,
        strain_warp=strain_warp,
        tension_weft=tension_weft,
        tension_warp=tension_warp,
        pressure=pressure,
        p_laplace=np.where(held, p_laplace, np.nan),
        area=area,
        reaction=reaction,
        edge_support=edge_support,
        on_body=held.astype(np.int8),
        total_force=reaction.sum(axis=0) * -1.0,  # the fabric's force on the body
        total_moment=-np.cross(x, reaction).sum(axis=0),
        normal_force=float(magnitude.sum()),
        pressure_integral=float(np.sum(pressure * area)),
    )


def lab_range_variables(state, strain: NDArray[np.float64]) -> dict:
    """Where the springs' strain passes the largest strain of the lab curve they follow (its last
    knot; beyond it the curve goes on with its last slope, extrapolated): a warning naming the
    fabric direction and the strains, a node flag ``beyond_lab_range`` (1 weft, 2 warp, 3 both)
    and per grid family the largest strain and the lab's, as 0-d variables."""
    import xarray as xr

    grid = state.grid
    flag = np.zeros(grid.n_nodes, np.int8)
    out = {}
    for family, label, bit in ((WEFT, "weft", 1), (WARP, "warp", 2)):
        sl = grid.family_slices[family]
        limit = float(grid.curves[family].knot_strain[-1])
        beyond = strain[sl] > limit
        largest = float(strain[sl].max()) if strain[sl].size else 0.0
        direction = label if state.around == "weft" else ("warp" if label == "weft" else "weft")
        log.info(
            "%s springs (the fabric's %s): largest strain %.4g, lab curve measured to %.4g",
            label,
            direction,
            largest,
            limit,
        )
        if np.any(beyond):
            ends = grid.ends[sl][beyond]
            flag[ends.ravel()] |= bit
            log.warning(
                "%s springs (the fabric's %s) strained up to %.4g, beyond the lab curve's last "
                "strain %.4g at %d springs: the curve is extrapolated there with its last slope",
                label,
                direction,
                largest,
                limit,
                int(beyond.sum()),
            )
        out[f"max_strain_{label}"] = xr.Variable(
            (), largest, {"units": "1", "long_name": f"largest {label} spring strain"}
        )
        out[f"lab_max_strain_{label}"] = xr.Variable(
            (), limit, {"units": "1", "long_name": f"last strain of the {label} lab curve"}
        )
    out["beyond_lab_range"] = xr.Variable(
        ("row", "col"),
        flag.reshape(grid.m, grid.n),
        {
            "units": "1",
            "long_name": "node with a spring strained beyond the lab curve",
            "flag_values": np.array([0, 1, 2, 3], np.int8),
            "flag_meanings": "within weft_beyond warp_beyond both_beyond",
        },
    )
    return out
