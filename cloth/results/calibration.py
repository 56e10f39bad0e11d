"""What a set of readings can tell of a case's parameters, and how well: the linear algebra of
``cloth calibrate`` (`cloth.stages.calibrate` runs the equilibria).

The fit is in internal coordinates u, one per parameter (`Parameter`): friction mu as itself,
the tissue modulus as ln E (a modulus is positive and known to a factor, so its interval is one
of factors), the fabric scale as itself. J (R x p) is the readings' (Pa) derivative in u.

Which parameters the readings determine (`determined`): the columns of J, each times its
parameter's plausible range (`Parameter.span`: how far it could be, a priori) over the
readings' noise sigma (Pa), are ordered by QR with column pivoting (the most informative
first, each next one's information the part of its column the earlier ones do not explain,
|R_kk|). The k-th is determined where that information holds it to within its range at 95 %:
`Z` / |R_kk| < 1, i.e. the interval a fit of it with the earlier ones would give is narrower
than what is plausible anyway. A parameter the readings do not move (friction on a body where
the garment does not slide) or that more readings than there are would be needed to separate
(one reading, two parameters: the second's R_kk is 0) is not determined; the fit holds it at
its start value and fits the others.

The interval of a fitted parameter (`intervals`): the covariance sigma^2 (J_d^T J_d)^-1 of the
determined columns J_d at the fit's end, sigma the fit's own residual standard deviation
sqrt(RSS / (R - q)) with Student's t quantile for R - q degrees of freedom where there are more
readings than fitted parameters q, else the noise given and the normal quantile; the 95 %
interval u +- t sd, mapped back to the parameter (ln E to E: an interval of factors).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import qr
from scipy.stats import t as student

#: The normal quantile of a two-sided 95 % interval.
Z = 1.959963984540054
#: The confidence of every interval.
CONFIDENCE = 0.95


@dataclass(frozen=True)
class Parameter:
    """A parameter ``cloth calibrate`` fits: ``name``, ``units``, its plausible range ``span``
    in u (module docstring), the finite-difference step ``step`` in u, u's lower ``bound``,
    and whether u is the parameter's logarithm (``log``)."""

    name: str
    units: str
    span: float
    step: float
    bound: float
    log: bool = False

    def to_u(self, value: float) -> float:
        """The internal coordinate of ``value``."""
        return math.log(value) if self.log else value

    def of_u(self, u: float) -> float:
        """The parameter's value at internal coordinate ``u``."""
        return math.exp(u) if self.log else u


#: The parameters, by name: friction (0-1 covers cloth on skin), the tissue modulus (a decade
#: either way, 1e3-1e5 Pa from fat to muscle) and the fabric's scale (a lot within +-30 %).
PARAMETERS = {
    "friction": Parameter("friction", "1", 1.0, 0.02, 0.0),
    "tissue_modulus": Parameter("tissue_modulus", "Pa", math.log(10.0), 0.05, -math.inf, True),
    "fabric_scale": Parameter("fabric_scale", "1", 0.3, 0.01, 0.05),
}


def determined(
    jacobian: NDArray[np.float64], spans: NDArray[np.float64], noise: float
) -> NDArray[np.bool_]:
    """(p,) whether each column of ``jacobian`` ((R, p), Pa per unit of u) is determined by
    readings of noise ``noise`` (Pa) given plausible ranges ``spans`` (p,) (module docstring)."""
    rows, p = jacobian.shape
    scaled = jacobian * spans[None, :] / noise
    _, r, order = qr(scaled, mode="economic", pivoting=True)
    out = np.zeros(p, dtype=bool)
    for k in range(min(rows, p)):
        info = abs(float(r[k, k]))
        if info <= 0 or Z / info >= 1.0:
            break
        out[order[k]] = True
    return out


@dataclass(frozen=True)
class Interval:
    """A fitted parameter's 95 % interval ``low``-``high`` (the parameter's units) and the
    standard deviation ``sd`` of u."""

    low: float
    high: float
    sd: float


def intervals(
    jacobian: NDArray[np.float64],
    residual: NDArray[np.float64],
    u: NDArray[np.float64],
    parameters: list[Parameter],
    noise: float,
) -> tuple[list[Interval], float]:
    """The intervals of ``parameters`` (module docstring) at ``u`` (q,), the fit's ``jacobian``
    ((R, q), Pa per u) and ``residual`` ((R,), Pa); ``noise`` (Pa) where R <= q. Returns them
    and the sigma used (Pa)."""
    rows, q = jacobian.shape
    if rows > q:
        sigma = math.sqrt(float(residual @ residual) / (rows - q))
        quantile = float(student.ppf(0.5 + CONFIDENCE / 2, rows - q))
    else:
        sigma, quantile = noise, Z
    normal = jacobian.T @ jacobian
    try:
        covariance = sigma**2 * np.linalg.inv(normal)
    except np.linalg.LinAlgError:
        covariance = np.full((q, q), np.inf)
    out = []
    for k, parameter in enumerate(parameters):
        sd = math.sqrt(max(float(covariance[k, k]), 0.0))
        low = max(u[k] - quantile * sd, parameter.bound)
        high = u[k] + quantile * sd
        out.append(Interval(parameter.of_u(low), parameter.of_u(high), sd))
    return out, sigma
