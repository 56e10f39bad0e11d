"""The pieces of a garment of several fabrics, as a cutting room cuts them (issue 69).

A garment with bands, panels or layers (`cloth.case.pieces`) is cut as several pieces, each a
`Pattern` of its own rows (heights and widths in mm, `cloth.files.pattern`), drawn and nested
as every piece is (`cloth.files.piece`):

* the **body**: each stretch of the garment between its bands (`body_parts`), from band edge
  to band edge, cut as the garment is cut (two panels or a tube) where it has no panels; with
  panels, one piece per **panel** and stretch, each row's width its share of the row's rest
  circumference (the panel's angles), quantity 1;
* each **band**: a straight strip, its cut length the mean rest circumference of its rows and
  its width the band's (twice it for a welt folded double); notches on its lower edge where the
  panels' seams meet it;
* each **layer**: the rows between its heights, each row's width its share of the row's rest
  circumference.

Rows bottom to top, heights on the garment's flat pattern (the rest warp coordinate, mm), so a
piece's girth lines are the garment's that fall on it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from cloth.case.pieces import Pieces
from cloth.files.pattern import CUTS, Pattern
from cloth.garment.layout import row_zones, share_of


@dataclass(frozen=True)
class PiecePattern:
    """One piece of a garment of several fabrics (module docstring).

    ``name`` (``BODY``, ``PANEL_k``, ``BAND_name``, ``LAYER_k``), its ``material`` (the name
    the case gives it), ``quantity`` to cut, its ``pattern`` (mm), its ``kind`` (body, panel,
    band, layer) and ``notches_x``: x (mm, from the piece's centre line) of notches on its lower
    edge (a band's seams)."""

    name: str
    material: str
    quantity: int
    pattern: Pattern
    kind: str
    notches_x: tuple[float, ...] = ()

    @property
    def cut_length(self) -> float:
        """The piece's widest row, mm (a band's cut length)."""
        return float(self.pattern.width.max())

    @property
    def width(self) -> float:
        """The piece's height on the flat pattern, mm (a band's width)."""
        return float(self.pattern.height[-1] - self.pattern.height[0])


def case_pieces(result: xr.Dataset) -> tuple[Pieces, float, float, str]:
    """The pieces, garment bottom and top (m) and material of the case a result holds."""
    case = json.loads(str(result.attrs.get("case", "{}")))
    garment = case.get("garment", {})
    return (
        Pieces.from_block(garment),
        float(garment.get("bottom", 0.0)),
        float(garment.get("top", 0.0)),
        str(case.get("material", "fabric")),
    )


def _between(pattern: Pattern, low: float, high: float, share: float) -> Pattern:
    """The rows of ``pattern`` between cut heights ``low`` and ``high`` (m), with rows added at
    both ends, each width ``share`` x its circumference. An end row is drawn from the piece's
    own rows (linear through its two nearest, `_own`), never from a row beyond it: across a
    seam the next row is another fabric's, cut to another reduction (a band's), and reading it
    would flare the piece's edge toward the band's width (measured: 7.8 mm over the last
    1.4 mm of a stocking's body, which folded its seam allowance)."""
    z = pattern.cut_height
    inside = (z > low) & (z < high)
    cut = np.concatenate(([low], z[inside], [high]))
    own = inside if inside.sum() >= 2 else np.ones_like(inside)  # too few: its neighbours'

    def at(values: NDArray) -> NDArray:
        return _own(cut, z[own], values[own])

    height = at(pattern.height)
    lines = tuple((n, y) for n, y in pattern.lines if height[0] <= y <= height[-1])
    return replace(
        pattern,
        height=height,
        width=share * at(pattern.circumference),
        circumference=at(pattern.circumference),
        cut_height=cut,
        reduction=None if pattern.reduction is None else at(pattern.reduction),
        lines=lines,
        line_heights=tuple((n, z) for n, z in pattern.line_heights if n in dict(lines)),
    )


def _own(at: NDArray, z: NDArray, values: NDArray) -> NDArray:
    """``values`` (given at the rising heights ``z``) at heights ``at``: interpolated between
    them, extended linearly through the two nearest beyond their ends."""
    out = np.interp(at, z, values)
    below, above = at < z[0], at > z[-1]
    if len(z) >= 2:
        out[below] = values[0] + (at[below] - z[0]) * (values[1] - values[0]) / (z[1] - z[0])
        out[above] = values[-1] + (at[above] - z[-1]) * (values[-1] - values[-2]) / (z[-1] - z[-2])
    return out


def body_parts(pieces: Pieces, bottom: float, top: float) -> list[tuple[float, float]]:
    """The stretches of the garment between its bands, (low, high) cut heights in m, bottom to
    top: each is cut as the body's piece (or its panels)."""
    spans = sorted(band.span(bottom, top) for band in pieces.bands)
    out, low = [], bottom
    for start, end in spans:
        if start > low + 1e-9:
            out.append((low, start))
        low = max(low, end)
    if top > low + 1e-9:
        out.append((low, top))
    return out


def garment_pieces(result: xr.Dataset, pattern: Pattern) -> list[PiecePattern]:
    """The pieces of the garment of ``result`` whose whole pattern is ``pattern`` (module
    docstring); empty for a garment of one fabric."""
    pieces, bottom, top, material = case_pieces(result)
    if not pieces.any:
        return []
    zone = row_zones(pattern.cut_height, pieces, bottom, top)
    out: list[PiecePattern] = []
    parts = body_parts(pieces, bottom, top)
    for number, (low, high) in enumerate(parts, start=1):
        suffix = "" if len(parts) == 1 else f"_{number}"
        if pieces.panels:
            for k, panel in enumerate(pieces.panels, start=1):
                rows = _between(pattern, low, high, panel.share)
                out.append(PiecePattern(f"PANEL_{k}{suffix}", panel.material, 1, rows, "panel"))
        else:
            name, quantity = {"two-panel": ("BODY_PANEL", 2), "tube": ("BODY_TUBE", 1)}[pattern.cut]
            rows = _between(pattern, low, high, CUTS[pattern.cut])
            out.append(PiecePattern(f"{name}{suffix}", material, quantity, rows, "body"))
    seams = [share_of(p.from_deg) for p in pieces.panels]
    for k, band in enumerate(pieces.bands):
        rows = zone == k
        length = float(pattern.circumference[rows].mean())
        width = 1e3 * band.width * band.layers
        base = float(np.interp(band.span(bottom, top)[0], pattern.cut_height, pattern.height))
        middle = band.middle(bottom, top)
        strip = Pattern(
            height=np.array([base, base + width]),
            width=np.array([length, length]),
            circumference=np.array([length, length]),
            cut_height=np.array(band.span(bottom, top)),
            reduction=None,
            lines=((band.name, base + 0.5 * width),),
            cut="tube",
            line_heights=((band.name, middle),),
        )
        notches = tuple(float((s - 0.5) * length) for s in seams)
        out.append(PiecePattern(f"BAND_{band.name}", band.material, 1, strip, "band", notches))
    for k, layer in enumerate(pieces.layers, start=1):
        share = (layer.to_deg - layer.from_deg) / 360.0
        out.append(
            PiecePattern(
                f"LAYER_{k}",
                layer.material,
                layer.layers,
                _between(pattern, layer.bottom, layer.top, share),
                "layer",
            )
        )
    return out


def pattern_columns(result: xr.Dataset, pattern: Pattern) -> dict[str, list[str]]:
    """pattern.csv's columns for a garment of several pieces, a text per row: ``piece``, the
    band a row is cut in (``BAND_name``) or ``BODY``; and per panel and layer its width there,
    ``PANEL_k_width_mm`` and ``LAYER_k_width_mm`` (mm; blank where it has no fabric)."""
    pieces, bottom, top, _ = case_pieces(result)
    if not pieces.any:
        return {}
    zone = row_zones(pattern.cut_height, pieces, bottom, top)
    out = {"piece": [f"BAND_{pieces.bands[z].name}" if z >= 0 else "BODY" for z in zone]}
    for k, panel in enumerate(pieces.panels, start=1):
        out[f"PANEL_{k}_width_mm"] = [
            f"{panel.share * c:.4f}" if z < 0 else ""
            for z, c in zip(zone, pattern.circumference, strict=True)
        ]
    for k, layer in enumerate(pieces.layers, start=1):
        share = (layer.to_deg - layer.from_deg) / 360.0
        out[f"LAYER_{k}_width_mm"] = [
            f"{share * c:.4f}" if layer.bottom <= h <= layer.top else ""
            for h, c in zip(pattern.cut_height, pattern.circumference, strict=True)
        ]
    return out


#: The columns of ``pattern_pieces.csv``.
COLUMNS = (
    "piece",
    "kind",
    "material",
    "quantity",
    "row",
    "pattern_height_mm",
    "cut_height_m",
    "width_mm",
    "cut_length_mm",
    "piece_width_mm",
)


def piece_rows(pieces: list[PiecePattern]) -> list[dict[str, object]]:
    """``pattern_pieces.csv``'s rows: per piece and row its height and width (mm), with the
    piece's cut length and width (a band's strip)."""
    rows = []
    for piece in pieces:
        p = piece.pattern
        for j in range(len(p.height)):
            rows.append(
                {
                    "piece": piece.name,
                    "kind": piece.kind,
                    "material": piece.material,
                    "quantity": piece.quantity,
                    "row": j,
                    "pattern_height_mm": f"{p.height[j]:.4f}",
                    "cut_height_m": f"{p.cut_height[j]:.9f}",
                    "width_mm": f"{p.width[j]:.4f}",
                    "cut_length_mm": f"{piece.cut_length:.4f}",
                    "piece_width_mm": f"{piece.width:.4f}",
                }
            )
    return rows


__all__ = [
    "COLUMNS",
    "PiecePattern",
    "body_parts",
    "case_pieces",
    "garment_pieces",
    "pattern_columns",
    "piece_rows",
]
