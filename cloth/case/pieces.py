"""A garment of several fabrics, as a case gives it: bands, panels, layers and seams (issue 69;
docs/config.md, "A garment of several pieces").

* a **band** (`Band`) is a ring of rows of another fabric at the garment's top or bottom edge
  or at a height: a waistband, a leg band, a stocking's top band or welt. It has its own
  reduction (or cut circumference) and may be folded double (``layers: 2``); it reads as a
  girth line of its own, named after it, and the line just beside it reads too
  (``NAME_beside``, `BESIDE`);
* **panels** (`Panel`) divide the tube around: sectors between two angles, sewn edge to edge,
  each of its own fabric; their angles cover the circle exactly once;
* a **layer** (`Layer`) is a second fabric over a region (a sector between two heights), on
  top of the garment and stretched with it (in parallel): a tummy-control panel;
* **seams** (`Seams`) join the panels: a strip of the seam allowance's width where the two
  fabrics lie together (in parallel), or a seam strip's own lab table; ``allowance_mm: 0`` a
  butt seam that adds nothing.

Angles are degrees from the centre front, counter-clockwise seen from above (the sensors'
direction, `cloth.case.reading`: a sensor's angle minus 90), and measure the share of the cut
circumference: a panel from -60 to 60 degrees is a third of every row's rest circumference,
centred on the front. Heights are the body's (m), as the garment's ``bottom`` and ``top``.

The constructors check what a piece knows and `Pieces.check` how pieces fit together and in the
garment, raising `InputError` naming the key (``garment.bands[0].width``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from cloth.errors import InputError

#: Where a band may sit, besides a height (m).
BAND_EDGES = ("top", "bottom")
#: The suffix of the girth line just beside a band (toward the garment's middle, one band
#: width from the band's inner edge).
BESIDE = "_beside"
#: The seam allowance where a case gives none, mm (a common overlock allowance).
ALLOWANCE_MM = 6.0
#: Angles are compared to within this, degrees.
ANGLE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Band:
    """A band: rows of ``material`` of ``width`` (m) at ``at`` ('top', 'bottom' or the height
    of its middle, m), cut with its own ``reduction`` (1) or ``circumference`` (m), of
    ``layers`` plies (1, or 2 for a folded welt), with its own skin ``friction`` (a silicone
    gripper; None: the case's contact friction)."""

    name: str
    material: str
    width: float
    at: str | float = "top"
    reduction: float | None = None
    circumference: float | None = None
    layers: int = 1
    friction: float | None = None

    def span(self, bottom: float, top: float) -> tuple[float, float]:
        """The band's lower and upper edge (m) on a garment from ``bottom`` to ``top``."""
        if self.at == "top":
            return top - self.width, top
        if self.at == "bottom":
            return bottom, bottom + self.width
        middle = float(self.at)
        return middle - 0.5 * self.width, middle + 0.5 * self.width

    def middle(self, bottom: float, top: float) -> float:
        """The height of the band's middle (m): its girth line."""
        low, high = self.span(bottom, top)
        return 0.5 * (low + high)

    def beside(self, bottom: float, top: float) -> float:
        """The height (m) of the line beside the band: one band width from its inner edge,
        toward the garment's middle (`BESIDE`)."""
        low, high = self.span(bottom, top)
        if 0.5 * (low + high) > 0.5 * (bottom + top):
            return low - self.width
        return high + self.width


@dataclass(frozen=True)
class Panel:
    """A sector of the tube of ``material``, from ``from_deg`` to ``to_deg`` (module
    docstring)."""

    material: str
    from_deg: float
    to_deg: float

    @property
    def share(self) -> float:
        """The panel's share of the cut circumference (1)."""
        return (self.to_deg - self.from_deg) / 360.0


@dataclass(frozen=True)
class Layer:
    """A second fabric ``material`` over the sector ``from_deg``-``to_deg`` between heights
    ``bottom`` and ``top`` (m), in parallel with the garment there, of ``layers`` plies."""

    material: str
    from_deg: float
    to_deg: float
    bottom: float
    top: float
    layers: int = 1


@dataclass(frozen=True)
class Seams:
    """Where panels meet: a strip ``allowance_mm`` wide (mm; 0 a butt seam) of the two fabrics
    in parallel, or of a seam strip's ``material`` (a lab table) where given."""

    allowance_mm: float = ALLOWANCE_MM
    material: str | None = None

    @property
    def width(self) -> float:
        """The strip's width, m."""
        return 1e-3 * self.allowance_mm


@dataclass(frozen=True)
class Pieces:
    """A garment's bands, panels, layers and seams (module docstring); all empty for a garment
    of one fabric."""

    bands: tuple[Band, ...] = ()
    panels: tuple[Panel, ...] = ()
    layers: tuple[Layer, ...] = ()
    seams: Seams = field(default_factory=Seams)

    @property
    def any(self) -> bool:
        """Whether the garment has more than its one fabric."""
        return bool(self.bands or self.panels or self.layers)

    @property
    def grip(self) -> float:
        """The largest friction coefficient a band gives its rows (1; 0 for none)."""
        return max((b.friction or 0.0 for b in self.bands), default=0.0)

    @property
    def materials(self) -> tuple[str, ...]:
        """Every material the pieces name, in order of first mention."""
        names = [b.material for b in self.bands] + [p.material for p in self.panels]
        names += [lay.material for lay in self.layers]
        if self.panels and self.seams.material is not None:
            names.append(self.seams.material)
        return tuple(dict.fromkeys(names))

    def band_lines(self, bottom: float, top: float) -> dict[str, float]:
        """The girth lines the bands add, name -> height (m): each band's middle, and the line
        beside it where that lies on the garment."""
        lines = {}
        for band in self.bands:
            lines[band.name] = band.middle(bottom, top)
            beside = band.beside(bottom, top)
            if bottom <= beside <= top:
                lines[band.name + BESIDE] = beside
        return lines

    @classmethod
    def from_block(cls, block: Mapping[str, Any]) -> Pieces:
        """The pieces of a validated ``garment`` block; `InputError` naming the key where one
        does not hold."""
        bands = tuple(_band(b, k) for k, b in enumerate(block.get("bands") or ()))
        panels = tuple(_panel(p, k) for k, p in enumerate(block.get("panels") or ()))
        layers = tuple(_layer(lay, k) for k, lay in enumerate(block.get("layers") or ()))
        seams_block = block.get("seams") or {}
        seams = Seams(
            float(seams_block.get("allowance_mm", ALLOWANCE_MM)), seams_block.get("material")
        )
        if seams.allowance_mm < 0:
            raise InputError(
                f"a seam allowance is a width >= 0 mm, got {seams.allowance_mm:g}",
                field="garment.seams.allowance_mm",
            )
        return cls(bands, panels, layers, seams)

    def check(self, bottom: float, top: float, landmarks: Sequence[str] = ()) -> None:
        """How the pieces fit the garment from ``bottom`` to ``top`` (m) and each other;
        ``landmarks``: the case's girth line names, which a band's name must not take."""
        length = top - bottom
        spans = []
        names: set[str] = set()
        for k, band in enumerate(self.bands):
            key = f"garment.bands[{k}]"
            if band.name in names or band.name in landmarks:
                raise InputError(
                    f"band name {band.name!r} is taken (by another band or a girth line); give "
                    "each band a name of its own",
                    field=f"{key}.name",
                )
            names.add(band.name)
            if band.width > length:
                raise InputError(
                    f"band {band.name!r} is {band.width:g} m wide, wider than the garment "
                    f"({length:.4g} m from {bottom:g} to {top:g} m); give a narrower band",
                    field=f"{key}.width",
                )
            low, high = band.span(bottom, top)
            if low < bottom - 1e-12 or high > top + 1e-12:
                raise InputError(
                    f"band {band.name!r} ({low:.4g}-{high:.4g} m) runs past the garment "
                    f"({bottom:g}-{top:g} m); move it (at) or narrow it (width)",
                    field=f"{key}.at",
                )
            for other, (o_low, o_high) in spans:
                if low < o_high - 1e-12 and o_low < high - 1e-12:
                    raise InputError(
                        f"bands {other!r} and {band.name!r} overlap ({o_low:.4g}-{o_high:.4g} "
                        f"and {low:.4g}-{high:.4g} m); move one or narrow it",
                        field=f"{key}.at",
                    )
            spans.append((band.name, (low, high)))
        if self.panels:
            _check_circle(self.panels)
        for k, layer in enumerate(self.layers):
            key = f"garment.layers[{k}]"
            if layer.bottom < bottom - 1e-12 or layer.top > top + 1e-12:
                raise InputError(
                    f"the layer ({layer.bottom:g}-{layer.top:g} m) lies outside the garment "
                    f"({bottom:g}-{top:g} m); give bottom and top within it",
                    field=f"{key}.bottom" if layer.bottom < bottom - 1e-12 else f"{key}.top",
                )


def _check_circle(panels: Sequence[Panel]) -> None:
    """Panels cover the circle exactly once: sorted by their start, each ends where the next
    starts, and the last where the first starts, 360 degrees on."""
    order = sorted(range(len(panels)), key=lambda k: panels[k].from_deg)
    total = sum(p.to_deg - p.from_deg for p in panels)
    for a, b in zip(order, order[1:] + order[:1], strict=True):
        end, start = panels[a].to_deg, panels[b].from_deg + (360.0 if b == order[0] else 0.0)
        if abs(end - start) > ANGLE_TOLERANCE:
            what = "overlap" if end > start else "leave a gap"
            raise InputError(
                f"panels {a} and {b} {what} around the tube (panel {a} ends at {end:g} degrees, "
                f"panel {b} starts at {start % 360 if b == order[0] else start:g}); panels must "
                f"cover the 360 degrees once, each starting where one ends (they cover "
                f"{total:g})",
                field=f"garment.panels[{b}].from_deg",
            )


def _band(block: Mapping[str, Any], k: int) -> Band:
    key = f"garment.bands[{k}]"
    at = block.get("at", "top")
    if isinstance(at, str) and at not in BAND_EDGES:
        raise InputError(f"at must be top, bottom or a height in m, got {at!r}", field=f"{key}.at")
    reduction, circumference = block.get("reduction"), block.get("circumference")
    if (reduction is None) == (circumference is None):
        raise InputError(
            "give a band either its reduction (1) or its cut circumference (m), one of them",
            field=f"{key}.reduction",
        )
    width = float(block["width"])
    if not width > 0:
        raise InputError(f"a band's width is > 0 m, got {width:g}", field=f"{key}.width")
    return Band(
        name=str(block["name"]),
        material=str(block["material"]),
        width=width,
        at=at if isinstance(at, str) else float(at),
        reduction=None if reduction is None else float(reduction),
        circumference=None if circumference is None else float(circumference),
        layers=int(block.get("layers", 1)),
        friction=None if block.get("friction") is None else float(block["friction"]),
    )


def _angles(block: Mapping[str, Any], key: str) -> tuple[float, float]:
    start, end = float(block["from_deg"]), float(block["to_deg"])
    if not 0 < end - start <= 360:
        raise InputError(
            f"to_deg ({end:g}) must exceed from_deg ({start:g}) by at most 360 degrees; "
            "count across the back past 180 (e.g. 60 to 300)",
            field=f"{key}.to_deg",
        )
    return start, end


def _panel(block: Mapping[str, Any], k: int) -> Panel:
    start, end = _angles(block, f"garment.panels[{k}]")
    return Panel(str(block["material"]), start, end)


def _layer(block: Mapping[str, Any], k: int) -> Layer:
    key = f"garment.layers[{k}]"
    start, end = _angles(block, key)
    bottom, top = float(block["bottom"]), float(block["top"])
    if not top > bottom:
        raise InputError(
            f"a layer's top ({top:g} m) must be above its bottom ({bottom:g} m)",
            field=f"{key}.top",
        )
    return Layer(str(block["material"]), start, end, bottom, top, int(block.get("layers", 1)))


__all__ = [
    "ALLOWANCE_MM",
    "BAND_EDGES",
    "BESIDE",
    "Band",
    "Layer",
    "Panel",
    "Pieces",
    "Seams",
]
