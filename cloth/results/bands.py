"""Girth lines read on the body: a band of the body around the line's height, and probes.

The body does not move; the fabric's rows do (they gather where the warp is slack, and contact
fronts cross them where it is taut), so a girth line's value is read from the body around the
line, whatever rows lie there. With f_i = p_i a_i the contact force on node i (N; 0 off the
body), a_i its deformed area (m2) and w_i the band's weight of the node,

    mean = sum_i f_i w_i / sum_i a_i w_i,

the contact force in the band over the band's area (Pa). The weight is the kernel
K((z - h) / b) averaged over the node's span of height: from half-way to the node below in its
warp line to half-way to the one above (the node's own height at an edge row), the span its
tributary area covers. h is the line's height and b the band's half-width
(`cloth.case.reading.Reading`: 2 cm by default); K the ``smooth`` biweight (1 - s^2)^2 or the
``hat`` 1 - |s| (0 for |s| >= 1). Averaged over the span, the weights integrate the kernel
exactly whatever the row spacing: a coarse grid's rows farther apart than the band still read
it, and the value moves smoothly as rows move through the band (sampled at the nodes' heights
alone it would wobble with the rows' phase). Every node of the garment counts in the area, on
the body or not (a bridging node presses with 0 Pa); at an edge line the band is clipped to the
garment, which ends there. The band's mean weft tension is weighted the same, sum T_i a_i w_i /
sum a_i w_i (N m-1).

A probe (`probe_readings`) is a pressure sensor's footprint of diameter D centred on the girth
at height h and angle phi: the same quotient with w_i = K(r_i / r), r_i the node's distance
from the centre measured on the body, sqrt(dz^2 + ds^2), ds = rho_i wrap(theta_i - phi) the arc
around the girth (rho_i, theta_i the node's horizontal radius and angle about the band's
centre, the area-weighted centroid of the band's nodes), r = D / 2 or the grid's cell size where
that is larger (a footprint smaller than a cell would hold no node). A line's max and min are
the largest and smallest readings of a probe at ``angles`` equally spaced angles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.case.reading import Reading


def kernel(s: NDArray[np.float64], name: str) -> tuple[NDArray, NDArray]:
    """The band kernel K(s) and its slope dK/ds at ``s`` (any shape, 1): ``smooth`` (biweight)
    or ``hat``; both 0 for |s| >= 1."""
    inside = np.abs(s) < 1.0
    if name == "hat":
        value = np.where(inside, 1.0 - np.abs(s), 0.0)
        slope = np.where(inside, -np.sign(s), 0.0)
    else:
        u = 1.0 - s * s
        value = np.where(inside, u * u, 0.0)
        slope = np.where(inside, -4.0 * s * u, 0.0)
    return value, slope


def _integral(s: NDArray[np.float64], name: str) -> NDArray[np.float64]:
    """The kernel's antiderivative from 0 to ``s``, held beyond |s| = 1."""
    t = np.clip(s, -1.0, 1.0)
    if name == "hat":
        return t - 0.5 * t * np.abs(t)
    return t - 2.0 * t**3 / 3.0 + t**5 / 5.0


@dataclass(frozen=True)
class BandWeights:
    """The band's weights ``value`` ((N,), 1; module docstring) of a grid's nodes, and what
    their derivatives in the nodes' heights need (`chain`)."""

    value: NDArray[np.float64]
    upper: NDArray[np.float64]  # (N,) dw_i / d(top of i's span)
    lower: NDArray[np.float64]  # (N,) dw_i / d(bottom of i's span)
    shape: tuple[int, int]  # (m, n)

    def chain(self, g: NDArray[np.float64]) -> NDArray[np.float64]:
        """(N,) sum_i g_i dw_i/dz_k for each node k: the heights' part of the gradient of
        sum_i g_i w_i (``g`` (N,) held fixed)."""
        m, n = self.shape
        up = (g * self.upper).reshape(m, n)
        low = (g * self.lower).reshape(m, n)
        out = np.zeros((m, n))
        # the span's top is half-way to the node above (the node itself on the top row)
        out[:-1] += 0.5 * up[:-1]
        out[1:] += 0.5 * up[:-1]
        out[-1] += up[-1]
        # its bottom half-way to the node below (the node itself on the bottom row)
        out[1:] += 0.5 * low[1:]
        out[:-1] += 0.5 * low[1:]
        out[0] += low[0]
        return out.ravel()


def band_weights(
    z: NDArray[np.float64], shape: tuple[int, int], height: float, reading: Reading
) -> BandWeights:
    """The band's weights of the nodes of a grid of ``shape`` (m rows, n columns) at heights
    ``z`` ((m * n,), m) for the line at ``height`` (m; module docstring)."""
    m, n = shape
    b = reading.half_width
    rows = np.asarray(z, float).reshape(m, n)
    top, bottom = rows.copy(), rows.copy()
    top[:-1] = 0.5 * (rows[:-1] + rows[1:])
    bottom[1:] = 0.5 * (rows[:-1] + rows[1:])
    top, bottom, here = top.ravel(), bottom.ravel(), rows.ravel()
    span = top - bottom
    s_top, s_bottom, s_here = (top - height) / b, (bottom - height) / b, (here - height) / b
    k_top, _ = kernel(s_top, reading.kernel)
    k_bottom, _ = kernel(s_bottom, reading.kernel)
    point, slope = kernel(s_here, reading.kernel)
    wide = np.abs(span) > 1e-9 * b
    safe = np.where(wide, span, 1.0)
    averaged = b * (_integral(s_top, reading.kernel) - _integral(s_bottom, reading.kernel)) / safe
    value = np.where(wide, averaged, point)
    # a span too short to average over: the kernel at the node, its slope split over the ends
    upper = np.where(wide, (k_top - value) / safe, 0.5 * slope / b)
    lower = np.where(wide, (value - k_bottom) / safe, 0.5 * slope / b)
    return BandWeights(value, upper, lower, (m, n))


def weighted_mean(
    numerator: NDArray[np.float64], area: NDArray[np.float64], weight: NDArray[np.float64]
) -> float:
    """sum(numerator w) / sum(area w), NaN where no node has weight."""
    denominator = float(np.sum(area * weight))
    return float(np.sum(numerator * weight)) / denominator if denominator > 0 else float("nan")


def band_centre(x: NDArray[np.float64], area: NDArray[np.float64], weight: NDArray) -> NDArray:
    """(2,) m: the area-weighted centroid (x, y) of the nodes in a band (weights ``weight``)."""
    total = float(np.sum(area * weight))
    if total <= 0:
        return np.zeros(2)
    return (area * weight) @ x[:, :2] / total


def probe_readings(
    x: NDArray[np.float64],
    force: NDArray[np.float64],
    area: NDArray[np.float64],
    height: float,
    angles_deg: NDArray[np.float64],
    diameter: float,
    reading: Reading,
) -> NDArray[np.float64]:
    """(K,) Pa: what a probe of footprint ``diameter`` (m) centred at ``height`` (m) reads at
    each of ``angles_deg`` ((K,), degrees from +x towards +y), from the nodes' positions ``x``
    ((N, 3), m), contact forces ``force`` ((N,), N) and areas ``area`` ((N,), m2); NaN where
    the footprint holds no garment. The footprint's radius is at least the grid's cell size
    (module docstring)."""
    radius = max(0.5 * diameter, float(np.sqrt(np.median(area))) if area.size else 0.0)
    dz = x[:, 2] - height
    near = np.flatnonzero(np.abs(dz) < radius)
    out = np.full(len(angles_deg), np.nan)
    if near.size == 0:
        return out
    band, _ = kernel(dz[near] / radius, reading.kernel)
    centre = band_centre(x[near], area[near], band)
    offset = x[near, :2] - centre
    rho = np.hypot(offset[:, 0], offset[:, 1])
    theta = np.arctan2(offset[:, 1], offset[:, 0])
    for k, phi in enumerate(np.radians(np.asarray(angles_deg, float))):
        turn = np.angle(np.exp(1j * (theta - phi)))  # wrapped to (-pi, pi]
        distance = np.hypot(dz[near], rho * turn)
        weight, _ = kernel(distance / radius, reading.kernel)
        out[k] = weighted_mean(force[near], area[near], weight)
    return out


def around(reading: Reading) -> NDArray[np.float64]:
    """(angles,) degrees: the probe's equally spaced angles around a girth, from 0."""
    return 360.0 * np.arange(reading.angles) / reading.angles
