"""A piece printed at 1:1 (issue 42): a PDF a sample room prints on A4 or letter and checks.

Page 1 (portrait) carries the check square (100 mm x 100 mm: measure it; printed at "actual
size" it is exactly that), the piece's annotation (`cloth.files.piece.Piece.annotation`) and,
where the piece is tiled, the map of its tiles. The pages after it carry the piece at true
scale: on one page where it fits the printable area (the paper less `MARGIN_MM` each side), else
on tiles of that area that overlap by `OVERLAP_MM`, the paper turned to landscape where that
takes fewer tiles. A tile is named by its row (A, B, ... from the bottom)
and column (1, 2, ... from the left); the inner edge of each overlap band is dotted, and crosses
on the band's middle line sit at the same place of the piece on both tiles that share it: lay
the tiles with their crosses on each other and tape them.

matplotlib writes the PDF (already a dependency; reportlab would be another for the same
result): each page is a figure of the paper's size in inches whose axes span the printable
area with limits in mm, so one data mm is one printed mm; snapping and path simplification are
off, so the PDF's coordinates are exact (PDF units: 1 pt = 25.4 / 72 mm).
"""

from __future__ import annotations

import logging
import math
import string
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.patches import Polygon, Rectangle

from cloth.errors import InputError
from cloth.files.piece import Piece
from cloth.io import atomic_output

log = logging.getLogger(__name__)

#: Paper sizes, mm (width, height), portrait.
PAPERS = {"A4": (210.0, 297.0), "letter": (215.9, 279.4)}
#: Unprinted margin on every side, mm (most printers print to within 5 mm of the edge).
MARGIN_MM = 10.0
#: Overlap of neighbouring tiles, mm.
OVERLAP_MM = 15.0
#: Side of the check square, mm.
SQUARE_MM = 100.0
#: Clearance around the piece's cut line, mm.
CLEARANCE_MM = 5.0
MM_PER_INCH = 25.4
#: The print's pens (matplotlib keywords): line widths in pt, colours, dashes. Every line is
#: unsnapped (its PDF coordinates exact) and every outline unfilled.
PENS = {
    "square": {"linewidth": 0.8},
    "cut": {"linewidth": 0.8, "edgecolor": "black"},
    "sew": {"linewidth": 0.5, "edgecolor": "0.3", "linestyle": "--"},
    "notch": {"color": "black", "linewidth": 0.8},
    "grain": {"arrowstyle": "<->", "linewidth": 0.6},
    "girth": {"color": "tab:red", "linewidth": 0.5, "linestyle": "--"},
    "map": {"linewidth": 0.6},
    "map_tile": {"linewidth": 0.4, "linestyle": ":"},
    "overlap": {"color": "0.4", "linewidth": 0.4, "linestyle": ":"},
    "cross": {"color": "black", "linewidth": 0.5},
}
#: The print's type: font sizes in pt, and the cover's layout: the check square's and the
#: text's distance from the printable area's top-left corner, the line pitch (mm).
FONTS = {"cover": 9, "instruction": 8, "piece": 8, "small": 7, "map": 8}
INSET_MM = 5.0
LINE_PITCH_MM = 6.0
#: Half the arm of an overlap cross, mm.
CROSS_MM = 4.0


def tiles(
    bounds: tuple[float, float, float, float], paper: str, landscape: bool = False
) -> list[tuple[int, int, tuple[float, float, float, float]]]:
    """The tiles covering ``bounds`` (x0, y0, x1, y1, mm) on ``paper`` (turned a quarter where
    ``landscape``): (row, column, window (x0, y0, x1, y1) mm), rows from the bottom, columns
    from the left; one tile where the bounds fit the printable area."""
    width, height = _printable(paper, landscape)
    x0, y0, x1, y1 = bounds
    columns = _count(x1 - x0, width)
    rows = _count(y1 - y0, height)
    out = []
    for r in range(rows):
        for c in range(columns):
            left = x0 + c * (width - OVERLAP_MM)
            bottom = y0 + r * (height - OVERLAP_MM)
            out.append((r, c, (left, bottom, left + width, bottom + height)))
    return out


def tile_name(row: int, column: int) -> str:
    return f"{string.ascii_uppercase[row % 26]}{column + 1}"


def sheet(paper: str, landscape: bool = False) -> tuple[float, float]:
    """The page of ``paper`` (width, height), mm, portrait or ``landscape``."""
    if paper not in PAPERS:
        raise InputError(
            f"unknown paper {paper!r}; give one of {', '.join(PAPERS)}", field="--paper"
        )
    width, height = PAPERS[paper]
    return (height, width) if landscape else (width, height)


def _printable(paper: str, landscape: bool = False) -> tuple[float, float]:
    width, height = sheet(paper, landscape)
    return width - 2 * MARGIN_MM, height - 2 * MARGIN_MM


def _count(length: float, printable: float) -> int:
    if length <= printable:
        return 1
    return 1 + math.ceil((length - printable) / (printable - OVERLAP_MM))


def write_pdf(piece: Piece, path: Path, paper: str = "A4") -> Path:
    """``piece`` at 1:1 on ``paper`` to ``path`` (module docstring)."""
    cut = piece.cut
    bounds = (
        float(cut[:, 0].min()) - CLEARANCE_MM,
        float(cut[:, 1].min()) - CLEARANCE_MM,
        float(cut[:, 0].max()) + CLEARANCE_MM,
        float(cut[:, 1].max()) + CLEARANCE_MM,
    )
    portrait, landscape = tiles(bounds, paper), tiles(bounds, paper, landscape=True)
    turned = len(landscape) < len(portrait)
    layout = landscape if turned else portrait
    page = sheet(paper, turned)
    with atomic_output(path) as tmp, PdfPages(tmp, metadata={"Creator": "cloth"}) as pdf:
        pdf.savefig(_cover(piece, paper, layout, bounds, turned))
        for row, column, window in layout:
            pdf.savefig(_tile(piece, page, row, column, window, layout))
    plt.close("all")
    log.info(
        "wrote %s: %d tile(s) on %s%s at 1:1",
        path,
        len(layout),
        paper,
        " landscape" if turned else "",
    )
    return path


def _page(page: tuple[float, float]):
    width, height = page
    fig = plt.figure(figsize=(width / MM_PER_INCH, height / MM_PER_INCH))
    return fig, width, height


def _cover(piece: Piece, paper: str, layout, bounds, turned: bool) -> plt.Figure:
    fig, width, height = _page(sheet(paper))
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_xlim(0.0, width)
    ax.set_ylim(0.0, height)
    ax.set_axis_off()
    left, top = MARGIN_MM + INSET_MM, height - MARGIN_MM - INSET_MM
    square = (left, top - SQUARE_MM)
    ax.add_patch(Rectangle(square, SQUARE_MM, SQUARE_MM, fill=False, snap=False, **PENS["square"]))
    ax.text(left + 0.5 * SQUARE_MM, top - 0.5 * SQUARE_MM, "10 cm", ha="center", va="center")
    ax.text(
        left,
        top - SQUARE_MM - LINE_PITCH_MM,
        "Check square: it must measure 100 mm x 100 mm. If not, print at 100 % (actual size).",
        fontsize=FONTS["instruction"],
        va="top",
    )
    orientation = "landscape" if turned else "portrait"
    lines = [
        *piece.annotation(),
        f"Paper: {paper}; {len(layout)} page(s) after this one, {orientation}",
    ]
    below = top - SQUARE_MM - 20.0
    for k, text in enumerate(lines):
        ax.text(left, below - LINE_PITCH_MM * k, text, fontsize=FONTS["cover"], va="top")
    if len(layout) > 1:
        _tile_map(ax, layout, bounds, (left, MARGIN_MM + INSET_MM), piece)
    return fig


def _tile_map(ax, layout, bounds, corner, piece: Piece) -> None:
    """The tiles' layout, scaled into the lower part of the cover."""
    x0, y0 = bounds[0], bounds[1]
    span_x = max(w[2] for _, _, w in layout) - x0
    span_y = max(w[3] for _, _, w in layout) - y0
    scale = min(150.0 / span_x, 90.0 / span_y)

    def at(x, y):
        return corner[0] + (x - x0) * scale, corner[1] + (y - y0) * scale

    outline = [at(*p) for p in piece.cut]
    ax.add_patch(Polygon(outline, fill=False, snap=False, **PENS["map"]))
    for row, column, (a, b, c, d) in layout:
        size = ((c - a) * scale, (d - b) * scale)
        ax.add_patch(Rectangle(at(a, b), *size, fill=False, snap=False, **PENS["map_tile"]))
        name = tile_name(row, column)
        ax.text(*at(0.5 * (a + c), 0.5 * (b + d)), name, fontsize=FONTS["small"])
    title = (corner[0], corner[1] + span_y * scale + 3.0)
    ax.text(*title, "tiles (overlap dotted)", fontsize=FONTS["map"])


def _tile(
    piece: Piece, page: tuple[float, float], row: int, column: int, window, layout
) -> plt.Figure:
    fig, width, height = _page(page)
    pw, ph = width - 2 * MARGIN_MM, height - 2 * MARGIN_MM
    ax = fig.add_axes((MARGIN_MM / width, MARGIN_MM / height, pw / width, ph / height))
    x0, y0, x1, y1 = window
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_axis_off()
    _draw_piece(ax, piece)
    rows = 1 + max(r for r, _, _ in layout)
    columns = 1 + max(c for _, c, _ in layout)
    _overlaps(ax, window, row > 0, row < rows - 1, column > 0, column < columns - 1)
    fig.text(
        0.5,
        (height - 0.5 * MARGIN_MM) / height,
        f"{piece.name} {piece.size}: tile {tile_name(row, column)} "
        f"(row {row + 1} of {rows} from the bottom, column {column + 1} of {columns})",
        ha="center",
        va="center",
        fontsize=FONTS["small"],
    )
    return fig


def _draw_piece(ax, piece: Piece) -> None:
    ax.add_patch(Polygon(piece.cut, fill=False, snap=False, **PENS["cut"]))
    if piece.allowance > 0:
        ax.add_patch(Polygon(piece.sew, fill=False, snap=False, **PENS["sew"]))
    for start, end in piece.notches:
        ax.plot(*np.stack([start, end]).T, snap=False, **PENS["notch"])
    (gx0, gy0), (gx1, gy1) = piece.grain
    ax.annotate("", xy=(gx1, gy1), xytext=(gx0, gy0), arrowprops=PENS["grain"])
    grain = (gx0 + 3.0, 0.5 * (gy0 + gy1))
    ax.text(*grain, "grain (warp)", rotation=90, fontsize=FONTS["small"], va="center")
    for name, y, left, right in piece.girths:
        ax.plot([left, right], [y, y], snap=False, **PENS["girth"])
        ax.text(left + 8.0, y + 1.5, name, fontsize=FONTS["small"], color=PENS["girth"]["color"])
    middle = 0.5 * float(piece.sew[:, 1].max())
    for k, text in enumerate(piece.annotation()[:4]):
        ax.text(8.0, middle - LINE_PITCH_MM * k, text, fontsize=FONTS["piece"])


def _overlaps(ax, window, below: bool, above: bool, left: bool, right: bool) -> None:
    """The overlap bands this tile shares with its neighbours: the band's inner edge dotted,
    and crosses on the band's middle line, at the same places on both tiles that share it."""
    x0, y0, x1, y1 = window
    half = 0.5 * OVERLAP_MM
    marks = []
    style = {**PENS["overlap"], "snap": False}
    for shared, edge, middle in (
        (left, x0 + OVERLAP_MM, x0 + half),
        (right, x1 - OVERLAP_MM, x1 - half),
    ):
        if shared:
            ax.plot([edge, edge], [y0, y1], **style)
            marks += [(middle, y) for y in (y0 + OVERLAP_MM, 0.5 * (y0 + y1), y1 - OVERLAP_MM)]
    for shared, edge, middle in (
        (below, y0 + OVERLAP_MM, y0 + half),
        (above, y1 - OVERLAP_MM, y1 - half),
    ):
        if shared:
            ax.plot([x0, x1], [edge, edge], **style)
            marks += [(x, middle) for x in (x0 + OVERLAP_MM, 0.5 * (x0 + x1), x1 - OVERLAP_MM)]
    for x, y in marks:
        ax.plot([x - CROSS_MM, x + CROSS_MM], [y, y], snap=False, **PENS["cross"])
        ax.plot([x, x], [y - CROSS_MM, y + CROSS_MM], snap=False, **PENS["cross"])
