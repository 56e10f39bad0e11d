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
layer of the band its undeformed height falls in, the base layer elsewhere (`cloth.case.Tissue`,
the case's ``body.tissue``, checked where the case is built).

Arrays: per node (N,); heights z in m, the body's frame (z up).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


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
