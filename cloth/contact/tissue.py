"""Soft tissue under the skin: a compliant (Winkler) layer over a rigid core.

The body's surface is the skin. Under it lies a layer of thickness h (m) and Young's modulus E
(Pa) over a rigid core; under a pressure p the skin moves inward along its normal by

    u = p h / E

(a Winkler foundation: each point of the layer is an independent spring, no shear between
neighbours). A garment node at signed distance d < 0 from the undeformed skin indents the layer
by u = -d and the layer pushes it out along the skin's normal n with the force

    lambda = k u,  k = E A / h  (N m-1),

A the node's tributary area (`cloth.garment.grid.node_area`), so that p = lambda / A = E u / h.
The layer's energy is p^2 h / (2 E) per area, k u^2 / 2 per node, its force -k d n and its
Hessian k (n n^T + d grad^2 d) (grad^2 d the Hessian of the signed distance: the skin's
curvature). A is lagged: frozen while Newton solves, updated from the solution, until it stops
changing (`cloth.solvers.lagged`), so at equilibrium p = E u / h holds with the deformed areas.

Limits: the layer is linear and local, so it knows nothing of the tissue's incompressibility or
its spreading of a load sideways; u must stay below h (beyond, the node would be in the core:
the run warns). Bands give different layers by height (bust, waist, hip): a node takes the
layer of the band its undeformed height falls in, the base layer elsewhere.

Arrays: per node (N,); heights z in m, the body's frame (z up).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError


@dataclass(frozen=True)
class Band:
    """A layer between two heights (m): its thickness (m) and modulus (Pa)."""

    bottom: float
    top: float
    thickness: float
    modulus: float


@dataclass(frozen=True)
class Tissue:
    """The case's ``body.tissue``: the base layer and its bands."""

    thickness: float
    modulus: float
    bands: tuple[Band, ...] = ()

    def layers(self, z: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Thickness (m) and modulus (Pa) of the layer under nodes at heights ``z`` ((N,), m)."""
        thickness = np.full(len(z), self.thickness)
        modulus = np.full(len(z), self.modulus)
        for band in self.bands:
            inside = (z >= band.bottom) & (z <= band.top)
            thickness[inside], modulus[inside] = band.thickness, band.modulus
        return thickness, modulus


def _positive(block: Mapping[str, Any], key: str, where: str, unit: str, source) -> float:
    value = block.get(key)
    if value is None:
        raise InputError(f"{key} is missing; give it in {unit}", source, f"{where}.{key}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0):
        raise InputError(
            f"{key} must be a positive number in {unit}, got {value!r}", source, f"{where}.{key}"
        )
    return number


def tissue_from_case(case: Mapping[str, Any], source: str = "case") -> Tissue | None:
    """The case's tissue layer (None: a rigid body), checked: positive finite thickness and
    modulus, bands inside the garment's height span and not overlapping (`InputError`)."""
    block = case.get("body", {}).get("tissue")
    if block is None:
        return None
    base = Tissue(
        _positive(block, "thickness", "body.tissue", "m", source),
        _positive(block, "modulus", "body.tissue", "Pa", source),
    )
    garment = case.get("garment", {})
    low, high = float(garment.get("bottom", -math.inf)), float(garment.get("top", math.inf))
    bands = []
    for index, raw in enumerate(block.get("bands", [])):
        where = f"body.tissue.bands[{index}]"
        bottom, top = float(raw["bottom"]), float(raw["top"])
        if not (math.isfinite(bottom) and math.isfinite(top) and bottom < top):
            raise InputError(
                f"bottom ({raw['bottom']}) must be below top ({raw['top']}), both in m",
                source, where,
            )  # fmt: skip
        if bottom < low or top > high:
            raise InputError(
                f"the band {bottom:g}-{top:g} m lies outside the garment ({low:g}-{high:g} m); "
                "move it within the garment's bottom and top",
                source, where,
            )  # fmt: skip
        band = Band(bottom, top, _positive(raw, "thickness", where, "m", source),
                    _positive(raw, "modulus", where, "Pa", source))  # fmt: skip
        for other, previous in enumerate(bands):
            if band.bottom < previous.top and previous.bottom < band.top:
                raise InputError(
                    f"the band {bottom:g}-{top:g} m overlaps band {other} "
                    f"({previous.bottom:g}-{previous.top:g} m); bands must not overlap",
                    source, where,
                )  # fmt: skip
        bands.append(band)
    return Tissue(base.thickness, base.modulus, tuple(bands))


@dataclass(frozen=True, eq=False)
class Layer:
    """The tissue under each node, with its lagged stiffness.

    thickness (N,) m; modulus (N,) Pa; area (N,) m2: the tributary areas the stiffness
    k = E A / h (N,) N m-1 was taken at.
    """

    thickness: NDArray[np.float64]
    modulus: NDArray[np.float64]
    area: NDArray[np.float64]

    @property
    def stiffness(self) -> NDArray[np.float64]:
        return self.modulus * self.area / self.thickness

    def at_area(self, area: NDArray[np.float64]) -> tuple[Layer, float]:
        """This layer with its stiffness taken at ``area`` ((N,), m2), and the largest relative
        change of an area."""
        change = float(np.max(np.abs(area - self.area) / np.maximum(self.area, 1e-300)))
        return Layer(self.thickness, self.modulus, area), change

    def response(
        self, distance: NDArray[np.float64], normal: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
        """At signed distances from the skin ((N,), m) with its normals ((N, 3)): each node's
        indentation u ((N,), m), the layer's force on it ((N, 3), N) and the energy (J)."""
        indentation = np.maximum(-distance, 0.0)
        push = self.stiffness * indentation
        return indentation, push[:, None] * normal, float(0.5 * push @ indentation)

    def hessian_blocks(
        self,
        distance: NDArray[np.float64],
        normal: NDArray[np.float64],
        curvature: NDArray[np.float64] | None,
        project: bool,
    ) -> NDArray[np.float64]:
        """The layer's Hessian per node ((N, 3, 3), N m-1): k (n n^T + d grad^2 d) where the
        node indents it (``curvature``: grad^2 d, (N, 3, 3) m-1, or None for flat facets);
        ``project`` keeps only k n n^T (positive semi-definite)."""
        k = np.where(distance < 0.0, self.stiffness, 0.0)
        blocks = k[:, None, None] * normal[:, :, None] * normal[:, None, :]
        if curvature is not None and not project:
            blocks += (k * distance)[:, None, None] * curvature
        return blocks
