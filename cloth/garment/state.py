"""The `State` every stage hands on: a garment on a body at one stage, and the fabric as its
grid sees it. Read from and written to ``initial.nc`` and ``relaxed.nc`` by
`cloth.files.state`."""

from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cloth.case import Case, Skin
from cloth.garment.grid import Grid
from cloth.materials.curves import Fabric


@dataclass(frozen=True, eq=False)
class State:
    """A garment on a body at one stage.

    Attributes
    ----------
    grid : Grid
    x : (N, 3) float, m
        Node positions, N = n*m, node k = j*n + i.
    constraint : (N,) int8
        FREE, SLIDING or FIXED.
    on_body : (N,) int8
        1 where the node is on the body surface (the file's ``contact`` flag).
    fabric : Fabric
        The fabric as ingested (weft and warp as in the lab table).
    around : {'weft', 'warp'}
        The fabric direction along the grid's weft (around the body).
    case : Case
        The case.
    body : dict
        Body reference: kind, parameters, path and sha256 of any file.
    skin : Skin
        The skin models under the garment (tissue, friction), the case's; the solvers read
        these, never the case.
    attrs : dict
        Stage attributes (solver results, history, ...).
    fabrics : dict of str to Fabric
        The fabrics of the garment's bands, panels, layers and seams by the names the case
        gives them (`cloth.garment.pieces`); empty for a garment of one fabric.
    layout : Layout or None
        Where those pieces lie (`cloth.garment.layout`), for the solvers.
    """

    grid: Grid
    x: NDArray[np.float64]
    constraint: NDArray[np.int8]
    on_body: NDArray[np.int8]
    fabric: Fabric
    around: str
    case: Case
    body: dict[str, Any]
    moduli: dict[str, float] = field(default_factory=dict)
    skin: Skin = field(default_factory=Skin)
    attrs: dict[str, Any] = field(default_factory=dict)
    fabrics: dict[str, Fabric] = field(default_factory=dict)
    #: Where the garment's pieces lie (`cloth.garment.layout.Layout`), copied from the case by
    #: predeform as the skin is, for the solvers (which never read the case); None for one fabric.
    layout: Any = None

    def with_positions(self, x: NDArray[np.float64], **changes: Any) -> State:
        return replace(self, x=x, **changes)

    def row_values(self, key: str) -> NDArray[np.float64] | None:
        """A per-row list predeform kept in ``attrs`` (``cut_height`` m, ``row_reduction`` 1,
        ``hull_girth`` m; JSON text once read from a file) as (m,) float, or None."""
        raw = self.attrs.get(key)
        if raw is None:
            return None
        values = np.asarray(json.loads(raw) if isinstance(raw, str) else raw, dtype=float)
        return values if values.shape == (self.grid.m,) else None


def grid_fabric(fabric: Fabric, around: str) -> Fabric:
    """The fabric as the grid sees it: its weft family runs around the body."""
    if around == "warp":
        return replace(fabric, weft=fabric.warp, warp=fabric.weft)
    return fabric
