"""The skin models a case asks for: the tissue layer (the case's ``body.tissue``) and the
friction (its ``contact``), checked as they are built."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError

#: The friction law's slip length as a fraction of the shortest rest spring, where the case
#: gives none (`cloth.contact.friction`).
SLIP_FRACTION = 1e-3


@dataclass(frozen=True)
class Band:
    """A layer between two heights (m): its thickness (m) and modulus (Pa)."""

    bottom: float
    top: float
    thickness: float
    modulus: float


@dataclass(frozen=True)
class Tissue:
    """The case's ``body.tissue``: the base layer and its bands (`cloth.contact.tissue`)."""

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

    @classmethod
    def from_block(
        cls, block: Mapping[str, Any], bottom: float = -math.inf, top: float = math.inf
    ) -> Tissue:
        """The tissue of a ``body.tissue`` block, checked: positive finite thickness and
        modulus, bands inside the garment's heights ``bottom``-``top`` (m) and not overlapping
        (`InputError` naming the field)."""
        thickness = _positive(block, "thickness", "body.tissue", "m")
        modulus = _positive(block, "modulus", "body.tissue", "Pa")
        bands: list[Band] = []
        for index, raw in enumerate(block.get("bands", [])):
            where = f"body.tissue.bands[{index}]"
            low, high = float(raw["bottom"]), float(raw["top"])
            if not (math.isfinite(low) and math.isfinite(high) and low < high):
                raise InputError(
                    f"bottom ({raw['bottom']}) must be below top ({raw['top']}), both in m",
                    field=where,
                )
            if low < bottom or high > top:
                raise InputError(
                    f"the band {low:g}-{high:g} m lies outside the garment ({bottom:g}-{top:g} "
                    "m); move it within the garment's bottom and top",
                    field=where,
                )
            band = Band(
                low,
                high,
                _positive(raw, "thickness", where, "m"),
                _positive(raw, "modulus", where, "Pa"),
            )
            for other, previous in enumerate(bands):
                if band.bottom < previous.top and previous.bottom < band.top:
                    raise InputError(
                        f"the band {low:g}-{high:g} m overlaps band {other} "
                        f"({previous.bottom:g}-{previous.top:g} m); bands must not overlap",
                        field=where,
                    )
            bands.append(band)
        return cls(thickness, modulus, tuple(bands))


def _positive(block: Mapping[str, Any], key: str, where: str, unit: str) -> float:
    value = block.get(key)
    if value is None:
        raise InputError(f"{key} is missing; give it in {unit}", field=f"{where}.{key}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0):
        raise InputError(
            f"{key} must be a positive number in {unit}, got {value!r}", field=f"{where}.{key}"
        )
    return number


@dataclass(frozen=True)
class Contact:
    """The case's ``contact`` block: the Coulomb friction coefficient mu (1; 0 frictionless)
    and the smoothed law's slip length (m; None: `SLIP_FRACTION` x the shortest rest spring)."""

    friction: float = 0.0
    slip_length: float | None = None

    def __post_init__(self) -> None:
        try:
            mu = float(self.friction)
        except (TypeError, ValueError):
            mu = math.nan
        if not (math.isfinite(mu) and mu >= 0):
            raise InputError(
                f"friction must be a coefficient >= 0 (cotton on skin: 0.3-0.9), got "
                f"{self.friction!r}",
                field="contact.friction",
            )
        eps = self.slip_length
        if eps is not None and not (math.isfinite(float(eps)) and float(eps) > 0):
            raise InputError(
                f"slip_length must be a positive length in m, got {eps!r}",
                field="contact.slip_length",
            )

    def slip(self, shortest_rest: float) -> float:
        """The slip length, m, for a grid whose shortest rest spring is ``shortest_rest`` (m)."""
        if self.slip_length is None:
            return SLIP_FRACTION * shortest_rest
        return float(self.slip_length)


@dataclass(frozen=True)
class Skin:
    """The skin models under the garment: the tissue layer (None: a rigid body) and the
    friction (`cloth.contact.skin.skin_models` builds them for a grid)."""

    tissue: Tissue | None = None
    contact: Contact = field(default_factory=Contact)
    #: The largest friction coefficient a garment's band gives its rows (a gripper; 0: none;
    #: `cloth.case.pieces.Band.friction`).
    grip: float = 0.0

    @property
    def friction(self) -> bool:
        return float(self.contact.friction) != 0.0 or self.grip != 0.0

    @property
    def present(self) -> bool:
        """Whether any skin model is under the garment (a tissue layer, friction)."""
        return self.tissue is not None or self.friction

    def check_solver(self, method: str, continuation: bool) -> None:
        """Tissue and friction are solved by Newton only, and friction never from a coarse
        grid's answer (it depends on the path: the relaxation from the wrap); else
        `InputError`."""
        if self.present and method != "newton":
            raise InputError(
                f"tissue and friction are solved by method newton only, got {method}; "
                "set solver.method: newton",
                field="solver.method",
            )
        if self.friction and continuation:
            raise InputError(
                "friction depends on the path from the wrapped state, which continuation "
                "replaces; set solver.continuation: false",
                field="solver.continuation",
            )
