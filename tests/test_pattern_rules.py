"""The pattern's geometry as a cutting room reads it from the files, checked as rules over random
pieces, seam allowances (0.5-15 mm), sizes and girth lines (hypothesis): pattern_astm.dxf read
back with ezdxf, pattern.pdf with pdfplumber, each in its own coordinates.

* every notch starts on the cut line and ends inside the allowance, short of the sew line;
* every internal line lies within the cut polygon, and every turn point is a vertex of it;
* the grain line lies inside the piece;
* the girth lines sit at their heights.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import Phase, assume, example, given, settings
from hypothesis import strategies as st
from matplotlib.path import Path as PolygonPath

from cloth.errors import InputError
from cloth.files import astm
from cloth.files.pattern import Pattern
from cloth.files.piece import NOTCH_MM, piece_of
from cloth.files.printout import CLEARANCE_MM, MARGIN_MM, tiles, write_pdf

ezdxf = pytest.importorskip("ezdxf")
pdfplumber = pytest.importorskip("pdfplumber")

#: Examples of each rule: a bounded number in make test, more in make test-slow.
COUNTS = [pytest.param(12, id="12"), pytest.param(80, id="80", marks=pytest.mark.slow)]
#: How close a file's coordinate must be to the piece's, mm (DXF: doubles; PDF: 1/100 pt).
DXF_MM, PDF_MM = 1e-6, 0.02
PT_MM = 25.4 / 72.0


def examples(count: int):
    """Hypothesis's settings: ``count`` examples, derandomised, not shrunk (each example writes
    files: a failure is reported as found, at once)."""
    return settings(
        max_examples=count,
        deadline=None,
        derandomize=True,
        database=None,
        phases=(Phase.explicit, Phase.generate),
    )


@st.composite
def patterns(draw) -> tuple[Pattern, float, str]:
    """A pattern (rows' heights and widths, girth lines), a seam allowance (mm) and a size."""
    rows = draw(st.integers(3, 24))
    pitch = draw(st.floats(4.0, 40.0))
    steps = draw(st.lists(st.floats(-6.0, 6.0), min_size=rows, max_size=rows))
    width = np.maximum(draw(st.floats(80.0, 400.0)) + np.cumsum(steps) * 2, 40.0)
    height = pitch * np.arange(rows)
    count = draw(st.integers(1, 4))
    fractions = draw(st.lists(st.floats(0.05, 0.95), min_size=count, max_size=count, unique=True))
    lines = tuple((f"L{k}", float(f * height[-1])) for k, f in enumerate(sorted(fractions)))
    cut = draw(st.sampled_from(["two-panel", "tube"]))
    pattern = Pattern(
        height=height,
        width=width,
        circumference=width * (2 if cut == "two-panel" else 1),
        cut_height=height * 1e-3,
        reduction=None,
        lines=lines,
        cut=cut,
    )
    allowance = draw(st.floats(0.5, 15.0))
    size = draw(st.sampled_from(["XS", "M", "2XL", "42"]))
    return pattern, allowance, size


#: CI's example: a notch at y = 0.75 mm, which the PDF prints at 0.74-0.76 (its 1/100 pt), so a
#: match by rounding to 0.1 mm failed where the match within PDF_MM holds.
NOTCH_ON_A_ROUNDING_EDGE = (
    Pattern(
        height=np.array([0.0, 5.0, 10.0, 15.0]),
        width=np.array([82.2, 82.2, 93.47936012, 96.47936012]),
        circumference=np.array([164.4, 164.4, 186.95872025, 192.95872025]),
        cut_height=np.array([0.0, 0.005, 0.01, 0.015]),
        reduction=None,
        lines=(("L0", 0.75),),
        cut="two-panel",
    ),
    0.5,
    "XS",
)


def inside(polygon: np.ndarray, point, tolerance: float) -> bool:
    """Whether ``point`` is in ``polygon`` or within ``tolerance`` of its boundary."""
    if PolygonPath(polygon).contains_point(point):
        return True
    return float(astm.distance_to(polygon, np.asarray([point], float))[0]) <= tolerance


def distance(polygon: np.ndarray, point) -> float:
    return float(astm.distance_to(polygon, np.asarray([point], float))[0])


def check_notch(start, end, cut, sew, allowance, depth, tolerance):
    """One notch's rule: from the cut line, ``depth`` long, ending inside the allowance (in
    the cut polygon, not past the sew line)."""
    assert distance(cut, start) <= tolerance, ("a notch starts off the cut line", start)
    assert math.dist(start, end) == pytest.approx(depth, abs=tolerance)
    assert inside(cut, end, tolerance), ("a notch ends outside the piece", end)
    if allowance > depth + tolerance:  # short of the sew line, within the allowance
        assert not PolygonPath(sew).contains_point(end) or distance(sew, end) <= tolerance
        assert distance(sew, end) >= allowance - depth - tolerance
    else:  # as deep as the allowance: it ends on the sew line, never past it
        assert distance(sew, end) <= tolerance or not PolygonPath(sew).contains_point(end)


def read_block(path, name: str) -> dict[str, list]:
    """The entities of block ``name`` of the DXF at ``path`` (ezdxf), by layer."""
    doc = ezdxf.readfile(path)
    found: dict[str, list] = {}
    for entity in doc.blocks.get(name):
        found.setdefault(entity.dxf.layer, []).append(entity)
    return found


def a_piece(pattern: Pattern, allowance: float, size: str):
    """The piece of a drawn pattern; an allowance that folds its cut line is refused, which is
    not a piece: hypothesis draws another."""
    try:
        return piece_of(pattern, size, "power net", allowance)
    except InputError:
        assume(False)


def _polyline(entity) -> np.ndarray:
    return np.array([tuple(v.dxf.location)[:2] for v in entity.vertices])


@pytest.mark.parametrize("count", COUNTS)
def test_the_dxf_s_notches_lines_turns_grain_and_girths_hold_for_any_piece(tmp_path, count):
    @examples(count)
    @given(drawn=patterns())
    def rule(drawn):
        pattern, allowance, size = drawn
        piece = a_piece(pattern, allowance, size)
        path = tmp_path / "pattern_astm.dxf"
        astm.write_nest([piece], path, "style", size)
        block = read_block(path, f"{piece.name}_{size}")
        (cut_entity,) = (
            block[astm.BOUNDARY][:1]
            if False
            else [e for e in block[astm.BOUNDARY] if e.dxftype() == "POLYLINE"]
        )
        cut = _polyline(cut_entity)
        (sew,) = [_polyline(e) for e in block[astm.SEW] if e.dxftype() == "POLYLINE"]
        depth = min(NOTCH_MM, allowance)
        notches = [e for e in block.get(astm.NOTCH, []) if e.dxftype() == "LINE"]
        assert len(notches) == 2 * len(pattern.lines)
        for line in notches:
            start, end = tuple(line.dxf.start)[:2], tuple(line.dxf.end)[:2]
            check_notch(start, end, cut, sew, allowance, depth, DXF_MM)
        vertices = {tuple(np.round(v, 6)) for v in cut}
        for point in block.get(astm.TURN, []):
            assert tuple(np.round(tuple(point.dxf.location)[:2], 6)) in vertices
        internal = [e for e in block[astm.INTERNAL] if e.dxftype() == "LINE"]
        heights = sorted(tuple(line.dxf.start)[1] for line in internal)
        np.testing.assert_allclose(heights, [y for _, y in pattern.lines], atol=DXF_MM)
        for line in internal:
            for end in (line.dxf.start, line.dxf.end):
                assert inside(cut, tuple(end)[:2], DXF_MM)
            assert line.dxf.start[1] == pytest.approx(line.dxf.end[1], abs=DXF_MM)
        (grain,) = [e for e in block[astm.GRAIN] if e.dxftype() == "LINE"]
        for end in (grain.dxf.start, grain.dxf.end):
            assert inside(sew, tuple(end)[:2], DXF_MM), ("the grain line leaves the piece", end)

    rule()


def pdf_segments(path, piece) -> list[tuple[np.ndarray, np.ndarray, object, float, bool]]:
    """Every straight two-point stroke of pattern.pdf's tiles (pdfplumber), in the piece's mm:
    each tile page's printable area is its window at 1:1 (`cloth.files.printout.tiles`); the
    last item says whether both ends are on the printable area (a stroke past it is clipped
    there, so only its line, not its ends, is the piece's)."""
    cut = piece.cut
    bounds = (
        float(cut[:, 0].min()) - CLEARANCE_MM,
        float(cut[:, 1].min()) - CLEARANCE_MM,
        float(cut[:, 0].max()) + CLEARANCE_MM,
        float(cut[:, 1].max()) + CLEARANCE_MM,
    )
    portrait, landscape = tiles(bounds, "A4"), tiles(bounds, "A4", landscape=True)
    layout = landscape if len(landscape) < len(portrait) else portrait
    out = []
    with pdfplumber.open(path) as pdf:
        assert len(pdf.pages) == 1 + len(layout)
        for page, (_, _, window) in zip(pdf.pages[1:], layout, strict=True):
            width, height = float(page.width) * PT_MM, float(page.height) * PT_MM
            for line in page.lines:
                if len(line["pts"]) != 2:
                    continue
                ends = [(px * PT_MM, height - py * PT_MM) for px, py in line["pts"]]
                visible = all(
                    MARGIN_MM - PDF_MM <= x <= width - MARGIN_MM + PDF_MM
                    and MARGIN_MM - PDF_MM <= y <= height - MARGIN_MM + PDF_MM
                    for x, y in ends
                )
                a, b = (
                    np.array([window[0] + x - MARGIN_MM, window[1] + y - MARGIN_MM])
                    for x, y in ends
                )
                out.append((a, b, line["stroking_color"], line["linewidth"], visible))
    return out


def _black(colour) -> bool:
    values = colour if isinstance(colour, tuple | list) else (colour,)
    return all(abs(float(v)) < 1e-6 for v in values)


@pytest.mark.parametrize("count", COUNTS)
def test_the_pdf_s_notches_and_girth_lines_hold_for_any_piece(tmp_path, count):
    @examples(count)
    @given(drawn=patterns())
    @example(drawn=NOTCH_ON_A_ROUNDING_EDGE)
    def rule(drawn):
        pattern, allowance, size = drawn
        piece = a_piece(pattern, allowance, size)
        path = write_pdf(piece, tmp_path / "pattern.pdf")
        depth = min(NOTCH_MM, allowance)
        segments = pdf_segments(path, piece)
        notches = [
            (a, b)
            for a, b, colour, width, visible in segments
            if visible
            and _black(colour)
            and width == pytest.approx(0.8)
            and abs(a[1] - b[1]) < PDF_MM
            and math.dist(a, b) == pytest.approx(depth, abs=PDF_MM)
        ]
        for a, b in notches:
            start, end = (a, b) if distance(piece.cut, a) < distance(piece.cut, b) else (b, a)
            check_notch(start, end, piece.cut, piece.sew, allowance, depth, PDF_MM)
        for start, end in piece.notches:  # each notch is printed on some tile, whole
            assert any(
                max(math.dist(start, a), math.dist(end, b)) < PDF_MM
                or max(math.dist(start, b), math.dist(end, a)) < PDF_MM
                for a, b in notches
            ), ("a notch is not printed where the piece has it", start, end)
        heights = [y for _, y in pattern.lines]
        red = [
            (a, b, visible)
            for a, b, colour, _, visible in segments
            if isinstance(colour, tuple | list) and len(colour) == 3 and colour[0] > 0.5
        ]
        for height in heights:  # every girth line is printed, on some tile ...
            assert any(abs(a[1] - height) < PDF_MM for a, _, _ in red), height
        for a, b, visible in red:
            assert abs(a[1] - b[1]) < PDF_MM  # ... horizontal ...
            assert min(abs(a[1] - h) for h in heights) < PDF_MM  # ... at its line's height
            if visible:  # ... and within the cut line (a clipped stroke ends at the page's edge)
                for end in (a, b):
                    assert inside(piece.cut, end, PDF_MM)

    rule()
