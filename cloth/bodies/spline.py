"""A tensor-product cubic B-spline field on a regular grid: value, gradient and Hessian.

phi(x) = sum_ijk c_ijk B((x - origin) / h - (i, j, k)), B the cubic B-spline in each axis: C2,
with exact derivatives. The smooth surfaces fitted to meshes (`cloth.bodies.surface`) are its
zero level set, with the smoothed signed-distance samples as the coefficients. Evaluation is
vectorised in batches of `BATCH` points (a (batch, 4, 4, 4) gather of coefficients, contracted
axis by axis): about 1.4 million value+gradient evaluations per second in numpy here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.bodies.base import as_points

#: Points evaluated per batch (bounds the (batch, 4, 4, 4) gather).
BATCH = 32768

#: Cubic B-spline basis on one cell, t in [0, 1): weights of coefficients i-1 .. i+2 and their
#: first and second derivatives (rows), as polynomial coefficients in t (columns t^0 .. t^3).
_BASIS = (
    np.array([[1, -3, 3, -1], [4, 0, -6, 3], [1, 3, 3, -3], [0, 0, 0, 1]], dtype=np.float64) / 6,
    np.array([[-3, 6, -3, 0], [0, -12, 9, 0], [3, 6, -9, 0], [0, 0, 3, 0]], dtype=np.float64) / 6,
    np.array([[6, -6, 0, 0], [-12, 18, 0, 0], [6, -18, 0, 0], [0, 6, 0, 0]], dtype=np.float64) / 6,
)


def _weights(t: NDArray, order: int) -> list[NDArray]:
    """[(P, 4)] B-spline weights and derivatives up to ``order`` at cell offsets t ((P,))."""
    powers = np.stack([np.ones_like(t), t, t * t, t * t * t], axis=1)
    return [powers @ _BASIS[k].T for k in range(order + 1)]


@dataclass(frozen=True, eq=False)
class SplineField:
    """phi(x) = sum_ijk c_ijk B((x - origin) / h - (i, j, k)), B the tensor cubic B-spline.

    Attributes
    ----------
    origin : (3,) float, m
        Position of coefficient (0, 0, 0).
    spacing : float, m
    coefficients : (nx, ny, nz) float, m
    """

    origin: NDArray[np.float64]
    spacing: float
    coefficients: NDArray[np.float64]
    _flat: NDArray[np.float64] = field(init=False, repr=False)
    _offsets: NDArray[np.intp] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        c = np.ascontiguousarray(self.coefficients, dtype=np.float64)
        object.__setattr__(self, "coefficients", c)
        object.__setattr__(self, "origin", np.asarray(self.origin, dtype=np.float64))
        object.__setattr__(self, "_flat", c.ravel())
        _, ny, nz = c.shape
        a = np.arange(4)
        offsets = (a[:, None, None] * ny + a[None, :, None]) * nz + a[None, None, :]
        object.__setattr__(self, "_offsets", offsets.ravel())

    def within(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """(P,) whether each point's 4 x 4 x 4 support lies inside the coefficient grid."""
        u = (points - self.origin) / self.spacing
        shape = np.asarray(self.coefficients.shape)
        return np.all((u >= 1.0) & (u < shape - 2.0), axis=1)

    def evaluate(self, points: ArrayLike, order: int = 2):
        """phi ((P,), m), and with ``order`` >= 1 its gradient ((P, 3)), with 2 its Hessian
        ((P, 3, 3), 1/m). Points outside `within` get the value of the nearest cell (their
        values mean nothing: check `within`); points that are not finite get NaN."""
        p = as_points(points)
        finite = np.all(np.isfinite(p), axis=1)
        if not np.all(finite):  # NaN in, NaN out (a folded line-search trial), no garbage cells
            p = np.where(finite[:, None], p, self.origin + 2 * self.spacing)
        value = np.empty(len(p))
        gradient = np.empty((len(p), 3)) if order >= 1 else None
        hessian = np.empty((len(p), 3, 3)) if order >= 2 else None
        for start in range(0, len(p), BATCH):
            part = slice(start, start + BATCH)
            out = self._batch(p[part], order)
            value[part] = out[0]
            if gradient is not None:
                gradient[part] = out[1]
            if hessian is not None:
                hessian[part] = out[2]
        if not np.all(finite):
            for out in (value, gradient, hessian):
                if out is not None:
                    out[~finite] = np.nan
        if order == 0:
            return value
        if order == 1:
            return value, gradient
        return value, gradient, hessian

    def _batch(self, p: NDArray, order: int):
        h = self.spacing
        shape = np.asarray(self.coefficients.shape)
        u = (p - self.origin) / h
        cell = np.floor(np.clip(u, 1.0, shape - 3.0)).astype(np.intp)  # far points: an edge cell
        t = u - cell
        _, ny, nz = self.coefficients.shape
        base = ((cell[:, 0] - 1) * ny + (cell[:, 1] - 1)) * nz + (cell[:, 2] - 1)
        c = self._flat[base[:, None] + self._offsets].reshape(-1, 4, 4, 4)
        wx, wy, wz = (_weights(t[:, a], order) for a in range(3))
        # contract z, then y, then x, keeping the derivative orders (i, j, k) with i+j+k <= order
        cz = [np.einsum("pabc,pc->pab", c, wz[k]) for k in range(order + 1)]
        cyz = {
            (j, k): np.einsum("pab,pb->pa", cz[k], wy[j])
            for j in range(order + 1)
            for k in range(order + 1 - j)
        }

        def d(i: int, j: int, k: int) -> NDArray:
            return np.einsum("pa,pa->p", cyz[j, k], wx[i]) / h ** (i + j + k)

        value = d(0, 0, 0)
        if order == 0:
            return (value,)
        gradient = np.stack([d(1, 0, 0), d(0, 1, 0), d(0, 0, 1)], axis=1)
        if order == 1:
            return value, gradient
        hessian = np.empty((len(p), 3, 3))
        hessian[:, 0, 0], hessian[:, 1, 1], hessian[:, 2, 2] = d(2, 0, 0), d(0, 2, 0), d(0, 0, 2)
        hessian[:, 0, 1] = hessian[:, 1, 0] = d(1, 1, 0)
        hessian[:, 0, 2] = hessian[:, 2, 0] = d(1, 0, 1)
        hessian[:, 1, 2] = hessian[:, 2, 1] = d(0, 1, 1)
        return value, gradient, hessian
