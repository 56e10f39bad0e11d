"""The case's ``judge`` block: how its girth-line pressures are judged in the summary.

* ``classes``: compression classes by name, each [low, high] mmHg (inclusive), judged at the
  point ``class_point`` only (default B, the ankle, where RAL-GZ 387/1 defines them). Default
  the RAL-GZ 387/1 classes: I 18-21, II 23-32, III 34-46, IV at least 49 mmHg (the classes as
  the Guetezeichen's quality assurance RAL-GZ 387/1 and EN 17430 list them).
* ``graduation``: per measuring point, the [low, high] share of the class point's pressure its
  pressure must have. Default `GRADUATION`: ILLUSTRATIVE shares falling from the ankle to the
  thigh, not the standard's table; set your standard's.
* ``bands``: named pressure bands (mmHg, [low, high)), judged on every line; default none.

A garment whose lines do not include the class point (a torso's) gets no class and no
graduation: only its bands.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from cloth.errors import InputError

#: RAL-GZ 387/1 compression classes at B, mmHg (inclusive).
CLASSES = MappingProxyType(
    {"I": (18.0, 21.0), "II": (23.0, 32.0), "III": (34.0, 46.0), "IV": (49.0, math.inf)}
)
#: ILLUSTRATIVE graduation: each point's pressure as a share of B's (not the standard's table).
GRADUATION = MappingProxyType(
    {
        "B1": (0.7, 1.0),
        "C": (0.5, 0.9),
        "D": (0.4, 0.8),
        "E": (0.3, 0.8),
        "F": (0.2, 0.6),
        "G": (0.1, 0.5),
    }
)


def _pairs(block: Mapping[str, Any], what: str) -> Mapping[str, tuple[float, float]]:
    out = {}
    for name, pair in block.items():
        low, high = (float(v) for v in pair)
        if not (low >= 0 and high >= low):
            raise InputError(
                f"{name}: give [low, high] with 0 <= low <= high, got {list(pair)}",
                field=f"judge.{what}.{name}",
            )
        out[str(name)] = (low, high)
    return MappingProxyType(out)


@dataclass(frozen=True)
class Judge:
    """The ``judge`` block (module docstring); pressures in mmHg, shares 1."""

    class_point: str = "B"
    classes: Mapping[str, tuple[float, float]] = field(default_factory=lambda: CLASSES)
    graduation: Mapping[str, tuple[float, float]] = field(default_factory=lambda: GRADUATION)
    bands: tuple[tuple[str, float, float], ...] = ()

    @classmethod
    def from_block(cls, block: Mapping[str, Any] | None) -> Judge:
        block = block or {}
        bands = []
        for number, band in enumerate(block.get("bands", [])):
            low, high = float(band["low_mmHg"]), float(band["high_mmHg"])
            if not 0 <= low < high:
                raise InputError("give 0 <= low_mmHg < high_mmHg", field=f"judge.bands.{number}")
            bands.append((str(band["name"]), low, high))
        return cls(
            class_point=str(block.get("class_point", "B")),
            classes=_pairs(block["classes"], "classes") if "classes" in block else CLASSES,
            graduation=(
                _pairs(block["graduation"], "graduation") if "graduation" in block else GRADUATION
            ),
            bands=tuple(bands),
        )

    def compression_class(self, mmhg: float) -> str:
        """The class a pressure (mmHg) at the class point falls in, '-' for none."""
        for name, (low, high) in self.classes.items():
            if low <= mmhg <= high:
                return name
        return "-"

    def band(self, mmhg: float) -> str:
        """The bands a pressure (mmHg) falls in, joined by '+'; '-' for none."""
        names = [name for name, low, high in self.bands if low <= mmhg < high]
        return "+".join(names) or "-"
