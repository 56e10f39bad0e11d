"""How a girth line is read on the body: the case's ``girth_reading`` block and ``sensors``.

A girth line's value is read from a band of the body around the line's height, not from the
fabric's rows (rows move: they gather where the warp is slack and contact fronts cross them
where it is taut; the body does not move). `cloth.results.bands` computes the readings:

* ``half_width`` (m, default `HALF_WIDTH`, 2 cm): the band's half-width in height;
* ``kernel``: the band's weight over height, ``smooth`` (default: the biweight
  (1 - s^2)^2, s = (z - h) / half_width, whose slope is continuous, so the adjoint of a band
  value is exact wherever a node sits) or ``hat`` (1 - |s|);
* ``probe_diameter`` (m, default `PROBE_DIAMETER`, 5 cm as a PicoPress probe): the footprint
  of the pressure sensor whose largest and smallest reading around the girth are the line's
  max and min;
* ``angles`` (default `ANGLES`): how many equally spaced angles around the girth that probe is
  read at.

``sensors``: probes the case places by ``name``, ``height`` (m), ``angle`` (degrees about the
body's up axis from +x towards +y; the parametric bodies face +y, so 90 is the front) and
``diameter`` (m, default ``probe_diameter``). result.nc reports what each would read, to
compare point by point with measured values.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from cloth.errors import InputError

#: Default band half-width, m.
HALF_WIDTH = 0.02
#: Default probe footprint (diameter), m: a PicoPress probe is 5 cm across.
PROBE_DIAMETER = 0.05
#: Default number of probe angles around a girth line.
ANGLES = 36
#: The band kernels by name.
KERNELS = ("smooth", "hat")


@dataclass(frozen=True)
class Sensor:
    """A probe the case places: ``name``, ``height`` (m), ``angle`` (degrees, module
    docstring) and footprint ``diameter`` (m)."""

    name: str
    height: float
    angle: float
    diameter: float


def _positive(value: Any, where: str) -> float:
    number = float(value)
    if not (math.isfinite(number) and number > 0):
        raise InputError(f"must be a positive number of metres, got {value!r}", field=where)
    return number


@dataclass(frozen=True)
class Reading:
    """The ``girth_reading`` block and the ``sensors`` (module docstring); lengths in m."""

    half_width: float = HALF_WIDTH
    kernel: str = "smooth"
    probe_diameter: float = PROBE_DIAMETER
    angles: int = ANGLES
    sensors: tuple[Sensor, ...] = ()

    def __post_init__(self) -> None:
        if self.kernel not in KERNELS:
            raise InputError(
                f"unknown kernel {self.kernel!r}; use one of {', '.join(KERNELS)}",
                field="girth_reading.kernel",
            )
        if not (isinstance(self.angles, int) and self.angles >= 1):
            raise InputError(
                f"angles must be a whole number >= 1, got {self.angles!r}",
                field="girth_reading.angles",
            )

    @classmethod
    def from_blocks(
        cls, block: Mapping[str, Any] | None, sensors: Sequence[Mapping[str, Any]] | None
    ) -> Reading:
        """The typed block and sensors of a validated case; `InputError` naming the field."""
        block = dict(block or {})
        half = _positive(block.get("half_width", HALF_WIDTH), "girth_reading.half_width")
        probe = _positive(
            block.get("probe_diameter", PROBE_DIAMETER), "girth_reading.probe_diameter"
        )
        placed = []
        for k, item in enumerate(sensors or ()):
            where = f"sensors[{k}]"
            angle = float(item["angle"])
            height = float(item["height"])
            if not (math.isfinite(angle) and math.isfinite(height)):
                raise InputError(
                    f"height and angle must be finite numbers, got {height!r}, {angle!r}",
                    field=where,
                )
            diameter = _positive(item.get("diameter", probe), f"{where}.diameter")
            placed.append(Sensor(str(item["name"]), height, angle, diameter))
        names = [s.name for s in placed]
        if len(set(names)) != len(names):
            raise InputError("two sensors share a name; give each its own", field="sensors")
        kernel = str(block.get("kernel", "smooth"))
        return cls(half, kernel, probe, int(block.get("angles", ANGLES)), tuple(placed))
