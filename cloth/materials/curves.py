"""Stress-strain curves of a fabric and the fabric itself.

A `StressStrainCurve` is the paper's piecewise-linear approximation of a lab curve sigma(eps):
knots (eps_i, sigma_i) with eps_0 = 0 and sigma_0 = 0, linear between knots, linear beyond the
last knot with the last slope. Fabric buckles rather than carrying compression, so below zero
strain the stress follows a compression modulus ``E_c`` (default ``COMPRESSION_RATIO`` times the
initial slope: 0, a pure tension field; a user option) instead of the tensile slope. With
E_c = 0 and a curve that never falls, each spring's energy is a convex, non-decreasing function
of its length, hence convex in the node positions: the fabric has no saddle equilibria, and
every solver path ends on the same one (docs/model.md, "Compressed fabric").

The strain-energy density psi(eps) = int_0^eps sigma is exact for such curves (piecewise
quadratic), so a spring network built from them has a true total energy: equilibrium is its
minimum and Newton's method has an objective for its line search.

Units: strain is dimensionless (1), stress and moduli in Pa, energy density in J m-3.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cloth.errors import InputError

#: Default compression modulus as a fraction of the curve's initial (tensile) slope: a pure
#: tension field (docs/model.md, "Compressed fabric").
COMPRESSION_RATIO = 0.0

Direction = Literal["weft", "warp", "bias"]
DIRECTIONS: tuple[str, ...] = ("weft", "warp", "bias")


def _readonly(values: ArrayLike) -> NDArray[np.float64]:
    array = np.array(values, dtype=np.float64)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class StressStrainCurve:
    """Piecewise-linear stress-strain curve sigma(eps).

    Parameters
    ----------
    knot_strain : (K,) float, 1
        Knot strains, strictly increasing, starting at 0.
    knot_stress : (K,) float, Pa
        Knot stresses, with stress[0] = 0.
    compression_modulus : float, Pa, optional
        Slope of sigma for eps < 0 (buckling fabric carries no compression). Default
        ``COMPRESSION_RATIO`` (0) x the slope of the first rising segment.

    Examples
    --------
    >>> curve = StressStrainCurve([0.0, 0.5, 1.0], [0.0, 1.0e5, 4.0e5])
    >>> float(curve.stress(0.75))
    250000.0
    >>> float(curve.energy_density(0.5))  # 0.5 * 0.5 * 1e5
    25000.0
    """

    knot_strain: NDArray[np.float64]
    knot_stress: NDArray[np.float64]
    compression_modulus: float | None = None
    _slope: NDArray[np.float64] = field(init=False, repr=False)
    _energy: NDArray[np.float64] = field(init=False, repr=False)
    _interp_x: NDArray[np.float64] = field(init=False, repr=False)
    _interp_y: NDArray[np.float64] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        strain = _readonly(self.knot_strain)
        stress = _readonly(self.knot_stress)
        if strain.ndim != 1 or stress.shape != strain.shape:
            raise InputError(
                f"strain and stress must be 1-D arrays of one length, got shapes {strain.shape} "
                f"and {stress.shape}",
                field="knots",
            )
        if strain.size < 2:
            raise InputError(
                f"a curve needs at least 2 knots, got {strain.size}; give more points",
                field="knots",
            )
        if not (np.all(np.isfinite(strain)) and np.all(np.isfinite(stress))):
            bad = int(np.flatnonzero(~(np.isfinite(strain) & np.isfinite(stress)))[0])
            raise InputError(
                f"knot {bad} is not finite (strain {strain[bad]}, stress {stress[bad]}); "
                "remove NaN/inf values",
                field="knots",
            )
        steps = np.diff(strain)
        if np.any(steps <= 0):
            bad = int(np.flatnonzero(steps <= 0)[0]) + 1
            raise InputError(
                f"knot strains must be strictly increasing; knot {bad} (strain {strain[bad]}) "
                f"does not exceed knot {bad - 1} (strain {strain[bad - 1]}): sort the table and "
                "remove duplicate strains",
                field="strain",
            )
        if strain[0] != 0.0 or stress[0] != 0.0:
            raise InputError(
                f"a curve must start at sigma(0) = 0, got first knot ({strain[0]}, {stress[0]}); "
                "add the knot (0, 0)",
                field="knots",
            )
        slope = np.diff(stress) / steps
        if np.any(slope < 0):
            bad = int(np.flatnonzero(slope < 0)[0]) + 1
            raise InputError(
                f"the stress falls from knot {bad - 1} to knot {bad} ({stress[bad - 1]:g} to "
                f"{stress[bad]:g} Pa), so beyond them a stretched spring would push; give a "
                "curve whose stress never falls, or the raw test data for a monotone fit "
                "(--knots K)",
                field="stress",
            )
        modulus = self.compression_modulus
        if modulus is None:
            positive = slope[slope > 0]  # the first rising segment (a toe may be flat)
            modulus = COMPRESSION_RATIO * (float(positive[0]) if positive.size else 0.0)
        modulus = float(modulus)
        if not np.isfinite(modulus) or modulus < 0:
            raise InputError(
                f"compression modulus must be finite and >= 0 Pa, got {modulus}",
                field="compression_modulus",
            )
        energy = np.concatenate(([0.0], np.cumsum(0.5 * (stress[1:] + stress[:-1]) * steps)))
        object.__setattr__(self, "knot_strain", strain)
        object.__setattr__(self, "knot_stress", stress)
        object.__setattr__(self, "compression_modulus", modulus)
        object.__setattr__(self, "_slope", _readonly(slope))
        object.__setattr__(self, "_energy", _readonly(energy))
        # knots padded for np.interp: strain -1 (a spring of zero length) and a far strain on
        # the extension of the last segment; outside that range `stress` uses the segments
        far = strain[-1] + 1.0e3
        object.__setattr__(self, "_interp_x", _readonly(np.concatenate(([-1.0], strain, [far]))))
        pad_y = [-modulus, *stress, stress[-1] + slope[-1] * (far - strain[-1])]
        object.__setattr__(self, "_interp_y", _readonly(pad_y))

    @classmethod
    def linear(cls, modulus: float, compression_modulus: float | None = None) -> StressStrainCurve:
        """A linear curve sigma = E eps (E in Pa), by default equally stiff in compression."""
        modulus = float(modulus)
        return cls(
            [0.0, 1.0],
            [0.0, modulus],
            compression_modulus=modulus if compression_modulus is None else compression_modulus,
        )

    @property
    def n_knots(self) -> int:
        return int(self.knot_strain.size)

    @property
    def tension_only(self) -> bool:
        """Whether a spring of this curve carries no compression (compression modulus 0): its
        energy is then convex and non-decreasing in its length (the stress never falls), hence
        convex in its ends' positions, and its Hessian positive semi-definite everywhere."""
        return self.compression_modulus == 0.0

    @property
    def slopes(self) -> NDArray[np.float64]:
        """(K-1,) float, Pa: slope of each segment."""
        return self._slope

    def _segment(self, eps: NDArray[np.float64]) -> NDArray[np.intp]:
        index = np.searchsorted(self.knot_strain, eps, side="right") - 1
        return np.clip(index, 0, self.knot_strain.size - 2)

    def stress_tangent(self, eps: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Stress (Pa) and tangent modulus dsigma/deps (Pa) at strains ``eps`` in one pass."""
        eps = np.asarray(eps, dtype=np.float64)
        k = self._segment(eps)
        tangent = self._slope[k]
        sigma = self.knot_stress[k] + tangent * (eps - self.knot_strain[k])
        compressed = eps < 0.0
        sigma = np.where(compressed, self.compression_modulus * eps, sigma)
        tangent = np.where(compressed, self.compression_modulus, tangent)
        return sigma, tangent

    def stress(self, eps: ArrayLike) -> NDArray[np.float64]:
        """sigma(eps), Pa, elementwise over any array of strains."""
        eps = np.asarray(eps, dtype=np.float64)
        if eps.size == 0 or eps.min() < -1.0 or eps.max() > self._interp_x[-1]:
            return self.stress_tangent(eps)[0]
        return np.interp(eps, self._interp_x, self._interp_y)  # ~3x faster than the segments

    def tangent(self, eps: ArrayLike) -> NDArray[np.float64]:
        """dsigma/deps, Pa; at a knot, the slope of the segment to its right."""
        return self.stress_tangent(eps)[1]

    def energy_density(self, eps: ArrayLike) -> NDArray[np.float64]:
        """psi(eps) = int_0^eps sigma(e) de, J m-3, exact (piecewise quadratic)."""
        eps = np.asarray(eps, dtype=np.float64)
        k = self._segment(eps)
        d = eps - self.knot_strain[k]
        psi = self._energy[k] + self.knot_stress[k] * d + 0.5 * self._slope[k] * d * d
        return np.where(eps < 0.0, 0.5 * self.compression_modulus * eps * eps, psi)

    __call__ = stress


@dataclass(frozen=True, eq=False)
class Fabric:
    """A stretch fabric: a curve per direction and the sheet's properties.

    Parameters
    ----------
    name : str
        Human-readable name, e.g. ``"power net 80/20"``.
    weft, warp : StressStrainCurve
        Curves along the weft (course, x) and warp (wale, y) directions.
    thickness : float, m
        Sheet thickness; a spring's area is thickness x its tributary width.
    areal_density : float, kg m-2
        Mass per area (NaN when unknown); not needed for statics.
    bias : StressStrainCurve, optional
        Curve at 45 degrees, stored with the material and plotted; the simulation does not use
        it: the optional shear springs are linear with the garment's ``shear_modulus``
        (`cloth.garment.grid.build_grid`).
    provenance : dict of str to str
        Where the numbers came from (files, sha256, fit settings).
    set_strain : dict of str to float, 1
        Set (residual) strain per direction measured in the lab table's load/unload cycles:
        where the last cycle's unloading branch reaches zero force. Empty when not measured.
        A worn garment's rest lengths grow by it (`cloth.garment.worn`).
    """

    name: str
    weft: StressStrainCurve
    warp: StressStrainCurve
    thickness: float
    areal_density: float = float("nan")
    bias: StressStrainCurve | None = None
    provenance: dict[str, str] = field(default_factory=dict)
    set_strain: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        thickness = float(self.thickness)
        if not np.isfinite(thickness) or thickness <= 0:
            raise InputError(
                f"thickness must be a positive length in m, got {self.thickness!r}; "
                "give thickness_mm in the table header or the config",
                field="thickness",
            )
        object.__setattr__(self, "thickness", thickness)

    def curve(self, direction: str) -> StressStrainCurve:
        """The curve of ``direction`` ('weft', 'warp' or 'bias')."""
        if direction not in DIRECTIONS:
            raise InputError(
                f"unknown direction {direction!r}; use one of {', '.join(DIRECTIONS)}",
                field="direction",
            )
        curve = getattr(self, direction)
        if curve is None:
            raise InputError(f"fabric {self.name!r} has no {direction} curve", field="direction")
        return curve

    @property
    def directions(self) -> tuple[str, ...]:
        return tuple(d for d in DIRECTIONS if getattr(self, d) is not None)

    @property
    def tension_only(self) -> bool:
        """Whether every curve of the fabric carries no compression
        (`StressStrainCurve.tension_only`)."""
        return all(self.curve(d).tension_only for d in self.directions)

    def scaled(self, factor: float) -> Fabric:
        """The fabric with every curve's stresses (and compression modulus) times
        ``factor`` (1, > 0): a stiffer or softer lot of it (a case's ``fabric_scale``)."""
        if factor == 1.0:
            return self

        def scale(curve: StressStrainCurve | None) -> StressStrainCurve | None:
            if curve is None:
                return None
            modulus = curve.compression_modulus
            return StressStrainCurve(
                curve.knot_strain,
                curve.knot_stress * factor,
                None if modulus is None else modulus * factor,
            )

        return replace(
            self,
            weft=scale(self.weft),
            warp=scale(self.warp),
            bias=scale(self.bias),
            provenance={**self.provenance, "fabric_scale": f"{factor:.6g}"},
        )
