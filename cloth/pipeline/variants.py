"""The sweep's variants: tissue modulus, skin friction, new or worn, lengthwise reduction.

A sweep varies materials, bodies and reductions, and optionally (config ``sweep``):

* ``tissue_moduli``: Young's moduli of the soft tissue, Pa (``.inf`` or null: a rigid body),
  with ``tissue_thickness`` (m) for the layer;
* ``frictions``: Coulomb friction coefficients between fabric and skin (0: frictionless);
* ``worn``: ``[false, true]`` for the new and the worn garment (`cloth.garment.worn`);
* ``lengthwise_reductions``: the warp's reduction (1), replacing the sweep garment's
  ``lengthwise_reduction``: first order on the pressure (the taut warp lifts the fabric off the
  body's hollows; docs/model.md), so a design question is answered per value.

Each combination is a `Variant`; its case is the sweep case's block with the variant applied
(`Variant.apply`) and its name the sweep name plus `Variant.tag` (empty for the default
variant: a rigid body, no friction, new, the garment's own lengthwise reduction or none, so a
sweep that varies none of them keeps its names).
The index entry of a case carries each varied key (`entry_keys`), and ``sweep.nc`` a dimension
per varied key (`cloth.pipeline.sweep.collect`).
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from cloth.case.case import following_skin
from cloth.errors import InputError

#: The variant keys, as index entries, design rows and sweep.nc dimensions name them.
KEYS = ("tissue_modulus", "friction", "worn", "lengthwise_reduction")
#: The sweep config's list of each key.
CONFIG_KEYS = {
    "tissue_modulus": "tissue_moduli",
    "friction": "frictions",
    "worn": "worn",
    "lengthwise_reduction": "lengthwise_reductions",
}
#: Coordinate attributes of each key in sweep.nc.
COORDINATES = {
    "tissue_modulus": {"units": "Pa", "long_name": "soft tissue Young's modulus (inf: rigid)"},
    "friction": {"units": "1", "long_name": "fabric-skin friction coefficient"},
    "worn": {
        "units": "1",
        "long_name": "garment worn",
        "flag_values": [0, 1],
        "flag_meanings": "new worn",
    },
    "lengthwise_reduction": {"units": "1", "long_name": "lengthwise (warp) pattern reduction"},
}


def _number(value: Any) -> float:
    if value is None or (isinstance(value, str) and value.lower() in ("", "inf", "rigid")):
        return math.inf
    return float(value)


def _optional(value: Any) -> float | None:
    if value is None or (isinstance(value, str) and value.strip() == ""):
        return None
    number = float(value)
    return None if math.isnan(number) else number


def _flag(value: Any) -> bool:
    if isinstance(value, str):
        return value.strip().lower() in ("1", "true", "yes", "worn")
    return bool(value)


@dataclass(frozen=True)
class Variant:
    """Tissue modulus (Pa, inf: rigid), friction coefficient (1), worn (bool), lengthwise
    reduction (1; None: the sweep garment's own)."""

    tissue_modulus: float = math.inf
    friction: float = 0.0
    worn: bool = False
    lengthwise_reduction: float | None = None

    @classmethod
    def of(cls, entry: Mapping[str, Any]) -> Variant:
        """The variant of an index entry or a design row (strings allowed; absent keys take the
        default)."""
        return cls(
            _number(entry.get("tissue_modulus")),
            float(entry.get("friction", 0.0) or 0.0),
            _flag(entry.get("worn", False)),
            _optional(entry.get("lengthwise_reduction")),
        )

    def tag(self) -> str:
        """The case-name suffix: ``__tissue20000``, ``__mu040``, ``__worn``; empty by default."""
        parts = []
        if math.isfinite(self.tissue_modulus):
            parts.append(f"__tissue{self.tissue_modulus:g}".replace("+", ""))
        if self.friction:
            parts.append(f"__mu{round(100 * self.friction):03d}")
        if self.worn:
            parts.append("__worn")
        if self.lengthwise_reduction:
            parts.append(f"__lw{round(1000 * self.lengthwise_reduction):03d}")
        return "".join(parts)

    def label(self) -> str:
        """For figures: 'tissue 20 kPa, mu 0.4, worn' (empty by default)."""
        parts = []
        if math.isfinite(self.tissue_modulus):
            parts.append(f"tissue {self.tissue_modulus / 1e3:g} kPa")
        if self.friction:
            parts.append(f"mu {self.friction:g}")
        if self.worn:
            parts.append("worn")
        if self.lengthwise_reduction is not None:
            parts.append(f"lengthwise {self.lengthwise_reduction:g}")
        return ", ".join(parts)

    def apply(self, block: dict, tissue_thickness: float | None) -> dict:
        """The case block with this variant: body.tissue, contact.friction, garment.worn and
        garment.lengthwise_reduction."""
        block = dict(block)
        if math.isfinite(self.tissue_modulus):
            tissue = {"thickness": tissue_thickness, "modulus": self.tissue_modulus}
            block["body"] = {**block["body"], "tissue": tissue}
        if self.friction:
            block["contact"] = {**block.get("contact", {}), "friction": self.friction}
        if self.worn:
            block["garment"] = {**block["garment"], "worn": True}
        if self.lengthwise_reduction is not None:
            garment = {**block["garment"], "lengthwise_reduction": self.lengthwise_reduction}
            block["garment"] = garment
        return block


def sweep_variants(sweep: Mapping[str, Any]) -> list[tuple[dict, Variant]]:
    """Every variant of a sweep config, each with its index-entry keys (only the varied ones)."""
    lists = {key: list(sweep[CONFIG_KEYS[key]]) for key in KEYS if CONFIG_KEYS[key] in sweep}
    out = []
    for values in itertools.product(*lists.values()):
        entry = dict(zip(lists, values, strict=True))
        variant = Variant.of(entry)
        keys = {key: getattr(variant, key) for key in lists}
        if "worn" in keys:
            keys["worn"] = int(keys["worn"])
        out.append((keys, variant))
    return out or [({}, Variant())]


def entry_keys(index: list[dict]) -> list[str]:
    """The variant keys the entries of a sweep index carry."""
    return [key for key in KEYS if index and key in index[0]]


def variation_cases(data: dict, block: dict, wearer: str) -> dict[str, dict]:
    """Name -> case mapping of each value of the case's ``variation`` (friction, tissue
    modulus, worn) run on ``wearer``'s case ``block``, one at a time: ``{wearer}~mu0.4``,
    ``{wearer}~tissue20000``, ``{wearer}~worn``; a value the case has already is left out."""
    spec = data.get("variation") or {}
    thickness = spec.get("tissue_thickness")
    if spec.get("tissue_modulus") and thickness is None:
        raise InputError(
            "variation.tissue_modulus needs variation.tissue_thickness (m), the layer's thickness",
            None,
            "variation.tissue_thickness",
        )
    friction = float((data.get("contact") or {}).get("friction", 0.0))
    tissue = (data["body"].get("tissue") or {}).get("modulus")
    worn = bool(data["garment"].get("worn", False))
    runs = [
        *(
            (f"mu{v:g}", Variant(friction=float(v)))
            for v in spec.get("friction", [])
            if v != friction
        ),
        *(
            (f"tissue{v:g}", Variant(tissue_modulus=float(v)))
            for v in spec.get("tissue_modulus", [])
            if v != tissue
        ),
        *(("worn", Variant(worn=True)) for v in spec.get("worn", []) if v and not worn),
        *(("new", None) for v in spec.get("worn", []) if not v and worn),
    ]
    out = {}
    for tag, variant in runs:
        varied = copy.deepcopy(block)
        if variant is None:  # the new garment of a worn case
            varied["garment"]["worn"] = False
        else:
            varied = variant.apply(varied, thickness)
        if variant is not None and variant.friction == 0.0 and "contact" in varied:
            varied["contact"] = {**varied["contact"], "friction": 0.0}
        out[f"{wearer}~{tag}"] = following_skin(varied)
    return out
