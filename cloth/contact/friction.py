"""Coulomb friction between fabric and skin: lagged and smoothed (after IPC, Li et al. 2020).

A node pressed on the body with the normal force lambda (N) slips when the tangential force on
it exceeds mu lambda. The skin's friction force on a node that has moved by the tangential
displacement u = T (x - x0) from where it was wrapped (x0, m; T = I - n n^T the tangent plane's
projector, n the skin's normal) is

    f = -mu lambda f1(|u|) u / |u|,
    f1(y) = 2 y / eps - y^2 / eps^2  (y < eps),  1  (y >= eps),

the derivative of the dissipation potential mu lambda f0(|u|), f0(y) = y^2 / eps - y^3 /
(3 eps^2) below eps and y - eps / 3 above. ``eps`` (the slip length, m) smooths stick into slip:
a node that moved less than eps sticks with a force growing with its move (stiffness
2 mu lambda / eps), one that moved more slides with the full Coulomb force. The model is exact
Coulomb as eps -> 0.

Lagging. lambda and n are frozen while Newton solves (so f has a potential and a symmetric
Hessian); then they are taken from the solution and Newton solves again, until the normal
forces stop changing (`cloth.solvers.lagged`). At the answer the residual counts a node as
balanced exactly when the friction carries its tangential force, |f_t| <= mu lambda.

Path. Friction makes the answer depend on the path: the one modelled is the relaxation from the
wrapped state (the reference x0), one quasi-static step. A garment pulled on differently sits
differently.

Arrays: per node (N,) or (N, 3); forces in N, lengths in m, stiffness in N m-1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, eq=False)
class Friction:
    """Lagged friction: coefficient ``mu`` (1), slip length ``eps`` (m), reference positions
    ``origin`` ((N, 3), m: the wrapped state), lagged normal forces ``normal_force`` ((N,), N)
    and normals ``normal`` ((N, 3), unit)."""

    mu: float | NDArray[np.float64]  # one coefficient, or one per node ((N,), a band's gripper)
    eps: float
    origin: NDArray[np.float64]
    normal_force: NDArray[np.float64]
    normal: NDArray[np.float64]

    def lagged(
        self, normal_force: NDArray[np.float64], normal: NDArray[np.float64]
    ) -> tuple[Friction, float]:
        """This friction with new lagged normal forces and normals, and the largest change of a
        normal force relative to the largest normal force."""
        scale = max(float(np.max(normal_force, initial=0.0)), 1e-300)
        change = float(np.max(np.abs(normal_force - self.normal_force), initial=0.0)) / scale
        return Friction(self.mu, self.eps, self.origin, normal_force, normal), change

    def _slip(self, x: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
        """Length ((N,), m) and direction ((N, 3)) of the tangential displacement."""
        move = x - self.origin
        n = self.normal
        u = move - np.einsum("ij,ij->i", move, n)[:, None] * n
        y = np.linalg.norm(u, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            direction = np.where(y[:, None] > 0, u / y[:, None], 0.0)
        return y, direction

    def response(self, x: NDArray[np.float64]) -> tuple[NDArray[np.float64], float]:
        """The friction force on every node ((N, 3), N) and the dissipation potential (J)."""
        y, direction = self._slip(x)
        s = y / self.eps
        stick = s < 1.0
        f1 = np.where(stick, 2.0 * s - s * s, 1.0)
        f0 = np.where(stick, self.eps * (s * s - s**3 / 3.0), y - self.eps / 3.0)
        bound = self.mu * self.normal_force
        return -(bound * f1)[:, None] * direction, float(bound @ f0)

    def sliding(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Nodes pressed on the skin that have slid past the slip length ((N,))."""
        y, _ = self._slip(x)
        return (self.normal_force > 0) & (y >= self.eps)

    def hessian_blocks(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """The potential's Hessian per node ((N, 3, 3), N m-1), positive semi-definite:
        mu lambda [f1'(y) d d^T + f1(y) / y (T - d d^T)], d the slip direction."""
        y, d = self._slip(x)
        s = y / self.eps
        stick = s < 1.0
        along = np.where(stick, 2.0 / self.eps * (1.0 - s), 0.0)
        with np.errstate(divide="ignore"):
            across = np.where(stick, (2.0 - s) / self.eps, 1.0 / np.maximum(y, 1e-300))
        n = self.normal
        tangent = np.eye(3) - n[:, :, None] * n[:, None, :]
        ddt = d[:, :, None] * d[:, None, :]
        bound = self.mu * self.normal_force
        return bound[:, None, None] * (
            along[:, None, None] * ddt + across[:, None, None] * (tangent - ddt)
        )
