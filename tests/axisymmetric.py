"""An independent reference for a tube on a body of revolution: rings and meridian segments
(issue 40, item 8). Not the grid solver: its own model, minimised by scipy.

The garment is K rings cut at heights Z_k (equally spaced from the bottom edge to the top),
each of rest circumference C_k = (1 - reduction) x the body's girth there, joined by meridian
segments of rest length L_k = (1 - lengthwise) (Z_{k+1} - Z_k). Ring k at radius rho_k and
height z_k stores the hoop energy t Lw_k C_k psi_weft(2 pi rho_k / C_k - 1) (t the thickness,
Lw_k the rest meridian length it stands for: half of each segment beside it), segment s the
meridian energy t Cw_s L_s psi_warp(l_s / L_s - 1) (Cw_s the mean rest circumference of its
rings, l_s its length in the (rho, z) plane); psi is the lab curve's energy density, so compressed
fabric stores nothing in a tension field. The body of radius R(z) keeps every ring outside:
rho_k = R(z_k) + g_k with g_k >= 0, and the edge rings are held at their heights (sliding
edges). The energy is minimised over (z, g) by L-BFGS-B with the exact gradient.

At the minimum a ring on the body (g_k = 0) is pressed by mu_k = dE/drho_k, the multiplier of
its contact, along the normal (1, -R') of the profile: its contact force is mu_k sqrt(1 + R'^2)
(N, the whole ring). Its area is half of each frustum beside it, pi (rho_a + rho_b) l / 2. A
girth line's value is read as cloth reads it on the body (docs/outputs.md): the biweight of
half-width b averaged over each ring's span of height (half-way to its neighbours),
sum F_k w_k / sum a_k w_k.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from cloth.materials.curves import Fabric


@dataclass(frozen=True)
class Rings:
    """The minimum: ring radii ``rho`` and heights ``z`` ((K,), m), contact forces ``force``
    ((K,), N, whole rings), areas ``area`` ((K,), m2), and the minimiser's report."""

    rho: np.ndarray
    z: np.ndarray
    force: np.ndarray
    area: np.ndarray
    gradient_norm: float
    message: str


def solve(
    radius: Callable[[np.ndarray], np.ndarray],
    slope: Callable[[np.ndarray], np.ndarray],
    fabric: Fabric,
    bottom: float,
    top: float,
    reduction: float,
    lengthwise: float,
    rings: int = 400,
) -> Rings:
    """The tube of ``rings`` rings from ``bottom`` to ``top`` (m) on the body of ``radius``
    R(z) (m; ``slope`` R'(z)) at its energy minimum (module docstring)."""
    cut = np.linspace(bottom, top, rings)
    rest_c = (1 - reduction) * 2 * np.pi * radius(cut)
    rest_l = (1 - lengthwise) * np.diff(cut)
    ring_l = np.zeros(rings)
    ring_l[:-1] += 0.5 * rest_l
    ring_l[1:] += 0.5 * rest_l
    seg_c = 0.5 * (rest_c[:-1] + rest_c[1:])
    t = fabric.thickness
    weft, warp = fabric.weft, fabric.warp

    def unpack(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        z = np.concatenate([[bottom], v[: rings - 2], [top]])
        return z, v[rings - 2 :]

    def parts(z: np.ndarray, gap: np.ndarray):
        rho = radius(z) + gap
        hoop = 2 * np.pi * rho / rest_c - 1
        d_rho, d_z = np.diff(rho), np.diff(z)
        length = np.hypot(d_rho, d_z)
        meridian = length / rest_l - 1
        energy = np.sum(t * ring_l * rest_c * weft.energy_density(hoop))
        energy += np.sum(t * seg_c * rest_l * warp.energy_density(meridian))
        # dE/drho and the explicit dE/dz
        e_rho = 2 * np.pi * t * ring_l * weft.stress(hoop)
        pull = t * seg_c * warp.stress(meridian) / np.where(length > 0, length, 1.0)
        e_rho[:-1] -= pull * d_rho
        e_rho[1:] += pull * d_rho
        e_z = np.zeros(rings)
        e_z[:-1] -= pull * d_z
        e_z[1:] += pull * d_z
        return energy, rho, e_rho, e_z

    def objective(v: np.ndarray) -> tuple[float, np.ndarray]:
        z, gap = unpack(v)
        energy, _, e_rho, e_z = parts(z, gap)
        d_z = e_z + e_rho * slope(z)  # rho = R(z) + g moves with z
        return energy, np.concatenate([d_z[1:-1], e_rho])

    start = np.concatenate([cut[1:-1], np.full(rings, 1e-4)])
    bounds = [(bottom, top)] * (rings - 2) + [(0.0, None)] * rings
    found = minimize(
        objective,
        start,
        jac=True,
        method="L-BFGS-B",
        bounds=bounds,
        options={"maxiter": 200000, "maxfun": 400000, "ftol": 1e-16, "gtol": 1e-13, "maxcor": 50},
    )
    z, gap = unpack(found.x)
    _, rho, e_rho, _ = parts(z, gap)
    on = gap <= 1e-9
    force = np.where(on, np.maximum(e_rho, 0.0), 0.0) * np.sqrt(1 + slope(z) ** 2)
    frustum = np.pi * (rho[:-1] + rho[1:]) * np.hypot(np.diff(rho), np.diff(z))
    area = np.zeros(rings)
    area[:-1] += 0.5 * frustum
    area[1:] += 0.5 * frustum
    free = np.concatenate([objective(found.x)[1][: rings - 2], np.where(on, 0.0, e_rho)])
    return Rings(rho, z, force, area, float(np.abs(free).max()), str(found.message))


def band_mean(rings: Rings, height: float, half_width: float = 0.02) -> float:
    """A girth line's mean pressure (Pa) read on the rings (module docstring), the biweight
    averaged over each ring's span by quadrature."""
    z = rings.z
    top = np.concatenate([0.5 * (z[:-1] + z[1:]), [z[-1]]])
    bottom = np.concatenate([[z[0]], 0.5 * (z[:-1] + z[1:])])
    weight = np.empty(len(z))
    for k, (low, high) in enumerate(zip(bottom, top, strict=True)):
        if high - low <= 1e-12:
            s = (z[k] - height) / half_width
            weight[k] = max(0.0, 1 - s * s) ** 2
            continue
        u = np.linspace(low, high, 65)
        s = np.clip((u - height) / half_width, -1.0, 1.0)
        weight[k] = np.trapezoid((1 - s * s) ** 2, u) / (high - low)
    return float(np.sum(rings.force * weight) / np.sum(rings.area * weight))
