"""The pieces of a garment of several fabrics on one sheet, at 1:1 in mm, as SVG and DXF (issue
69; `cloth.files.garmentpieces`).

The pieces (`cloth.files.piece.Piece`) stand side by side, left to right in the garment's order,
`GAP_MM` apart, each at its own height on the garment's flat pattern (so a band sits above or
below the body it is sewn to). Each has its cut line (solid), its sew line (dashed), its
notches, its girth lines with their names and a label with its name, material and quantity.
The DXF (R2010, units mm) puts them on layers ``CUT``, ``SEW``, ``NOTCH``, ``GIRTH`` and
``LABELS``, each piece's entities in a block named after it, inserted at its place.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np
from numpy.typing import NDArray

from cloth.files.astm import ascii_text, ezdxf_module
from cloth.files.piece import Piece
from cloth.io import atomic_output

#: Space between two pieces on the sheet, and the sheet's margin, mm.
GAP_MM = 30.0
#: Text height of the labels, mm.
LABEL_MM = 8.0


def placements(pieces: Sequence[Piece]) -> list[float]:
    """The x shift (mm) of each piece on the sheet: left to right, `GAP_MM` apart."""
    shifts, right = [], 0.0
    for piece in pieces:
        low, high = float(piece.cut[:, 0].min()), float(piece.cut[:, 0].max())
        shifts.append(right - low)
        right += high - low + GAP_MM
    return shifts


def _label(piece: Piece) -> str:
    return f"{piece.name} ({piece.material}) x{piece.quantity}"


def write_sheet_svg(pieces: Sequence[Piece], path: Path) -> Path:
    """The sheet (module docstring) as SVG: width, height and viewBox in mm, y up flipped."""
    shifts = placements(pieces)
    every = np.concatenate(
        [p.cut + np.array([s, 0.0]) for p, s in zip(pieces, shifts, strict=True)]
    )
    x_low, y_low = every.min(axis=0) - GAP_MM
    x_high, y_high = every.max(axis=0) + GAP_MM + 2 * LABEL_MM
    width, height = x_high - x_low, y_high - y_low

    def at(points: NDArray) -> str:
        return " ".join(f"{x - x_low:.3f},{y_high - y:.3f}" for x, y in points)

    parts = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.3f}mm" height="{height:.3f}mm" '
        f'viewBox="0 0 {width:.3f} {height:.3f}">',
        "<title>cloth pattern pieces, 1:1 in mm</title>",
    ]
    for piece, shift in zip(pieces, shifts, strict=True):
        move = np.array([shift, 0.0])
        parts.append(f'<g id="{escape(piece.name)}">')
        parts.append(
            f'<polygon class="cut" points="{at(piece.cut + move)}" fill="none" stroke="black" '
            'stroke-width="0.5"/>'
        )
        parts.append(
            f'<polygon class="sew" points="{at(piece.sew + move)}" fill="none" stroke="black" '
            'stroke-width="0.3" stroke-dasharray="3 2"/>'
        )
        for start, end in piece.notches:
            parts.append(
                f'<polyline class="notch" points="{at(np.array([start, end]) + move)}" '
                'stroke="black" stroke-width="0.5"/>'
            )
        for name, y, left, right in piece.girths:
            line = np.array([[left, y], [right, y]]) + move
            parts.append(
                f'<polyline class="girth" points="{at(line)}" stroke="red" stroke-width="0.3" '
                'stroke-dasharray="4 2"/>'
            )
            x, yy = at(line[:1] + np.array([2.0, 2.0])).split(",")
            parts.append(
                f'<text x="{x}" y="{yy}" font-size="{LABEL_MM}" font-family="sans-serif">'
                f"{escape(name)}</text>"
            )
        top = np.array([[float(piece.cut[:, 0].min()), float(piece.cut[:, 1].max()) + 4.0]])
        x, y = at(top + move).split(",")
        parts.append(
            f'<text class="label" x="{x}" y="{y}" font-size="{LABEL_MM}" '
            f'font-family="sans-serif">{escape(_label(piece))}</text>'
        )
        parts.append("</g>")
    parts.append("</svg>")
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(parts) + "\n")
    return path


def write_sheet_dxf(pieces: Sequence[Piece], path: Path) -> Path:
    """The sheet (module docstring) as DXF R2010 in mm, one block per piece."""
    ezdxf = ezdxf_module()
    logging.getLogger("ezdxf").setLevel(logging.WARNING)
    doc = ezdxf.new("R2010", setup=True)
    doc.units = ezdxf.units.MM
    for layer, colour in (("CUT", 7), ("SEW", 8), ("NOTCH", 7), ("GIRTH", 1), ("LABELS", 3)):
        doc.layers.add(layer, color=colour)
    space = doc.modelspace()
    for piece, shift in zip(pieces, placements(pieces), strict=True):
        block = doc.blocks.new(name=ascii_text(piece.name))
        block.add_lwpolyline([tuple(p) for p in piece.cut], close=True, dxfattribs={"layer": "CUT"})
        block.add_lwpolyline([tuple(p) for p in piece.sew], close=True, dxfattribs={"layer": "SEW"})
        for start, end in piece.notches:
            block.add_line(tuple(start), tuple(end), dxfattribs={"layer": "NOTCH"})
        for name, y, left, right in piece.girths:
            block.add_line((left, y), (right, y), dxfattribs={"layer": "GIRTH"})
            block.add_text(
                ascii_text(name),
                height=LABEL_MM,
                dxfattribs={"layer": "LABELS", "insert": (left + 2.0, y + 2.0)},
            )
        block.add_text(
            ascii_text(_label(piece)),
            height=LABEL_MM,
            dxfattribs={
                "layer": "LABELS",
                "insert": (float(piece.cut[:, 0].min()), float(piece.cut[:, 1].max()) + 4.0),
            },
        )
        space.add_blockref(block.name, (shift, 0.0))
    with atomic_output(path) as tmp:
        doc.saveas(tmp)
    return path


__all__ = ["GAP_MM", "placements", "write_sheet_dxf", "write_sheet_svg"]
