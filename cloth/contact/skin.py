"""The skin models a garment meets: the tissue layer under each node and the friction.

`skin_models` builds them from a state's `cloth.case.Skin` (the case's ``body.tissue`` and
``contact``, checked where the case was built), before any is lagged
(`cloth.solvers.lagged.start` takes them at the relaxation's first evaluation).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cloth.case import Skin
from cloth.contact.friction import Friction
from cloth.contact.tissue import Layer
from cloth.garment.grid import Grid, node_area


def skin_models(
    skin: Skin, grid: Grid, x: NDArray[np.float64]
) -> tuple[Layer | None, Friction | None]:
    """The tissue layer under each node and the friction ``skin`` asks for, for a garment on
    ``grid`` wrapped at ``x`` ((N, 3), m); None where it asks for none. Not yet lagged
    (`cloth.solvers.lagged.start` takes them at the relaxation's first evaluation)."""
    layer = None
    if skin.tissue is not None:
        thickness, modulus = skin.tissue.layers(x[:, 2])
        layer = Layer(thickness, modulus, node_area(x, grid))
    friction = None
    if skin.friction:
        eps = skin.contact.slip(float(grid.rest_length.min()))
        zeros = np.zeros(grid.n_nodes)
        friction = Friction(node_friction(skin, grid), eps, x.copy(), zeros, np.zeros_like(x))
    return layer, friction


def node_friction(skin: Skin, grid: Grid) -> float | NDArray[np.float64]:
    """The friction coefficient at each node ((N,), 1): the case's contact friction, a band's
    own on its rows (a gripper, `cloth.case.pieces.Band.friction`); one number where every
    node has the case's."""
    mu = float(skin.contact.friction)
    rows = getattr(grid.materials, "row_friction", None)
    if rows is None or not np.isfinite(rows).any():
        return mu
    return np.repeat(np.where(np.isfinite(rows), rows, mu), grid.n)
