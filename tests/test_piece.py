"""The pattern piece's geometry (issue 42) against closed forms: the seam allowance's offset of
a rectangle and of a trapezoid (each edge moved out by exactly the allowance, mitred corners),
the crossings of a polygon with a height, a fold refused, and the PDF's tiles."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cloth.errors import InputError
from cloth.files.astm import distance_to
from cloth.files.pattern import Pattern
from cloth.files.piece import crossings, offset, piece_of
from cloth.files.printout import CLEARANCE_MM, MARGIN_MM, OVERLAP_MM, PAPERS, tiles, write_pdf
from tests.pdf import pdf_pages, squares


def test_a_rectangle_grows_by_the_allowance_on_every_side():
    rectangle = np.array([[0.0, 0.0], [200.0, 0.0], [200.0, 300.0], [0.0, 300.0]])
    grown = offset(rectangle, 6.0)
    np.testing.assert_allclose(
        grown, [[-6.0, -6.0], [206.0, -6.0], [206.0, 306.0], [-6.0, 306.0]], atol=1e-12
    )
    np.testing.assert_array_equal(offset(rectangle, 0.0), rectangle)


def test_a_trapezoid_s_slanted_side_moves_out_along_its_normal():
    """Bottom 200 mm, top 100 mm, height 300 mm: the right side x = 100 - y tan t (t its angle
    from vertical, tan t = 50 / 300) moved out by a along its normal is x = 100 - y tan t +
    a / cos t, so the cut line's corner on the bottom's offset (y = -a) is at
    x = 100 + a tan t + a / cos t."""
    a = 6.0
    trapezoid = np.array([[-100.0, 0.0], [100.0, 0.0], [50.0, 300.0], [-50.0, 300.0]])
    grown = offset(trapezoid, a)
    t = math.atan(50.0 / 300.0)
    # the side x = 100 - y tan t moved out by a: x = 100 - y tan t + a / cos t; at y = -a
    x_bottom = 100.0 + a * math.tan(t) + a / math.cos(t)
    assert grown[1] == pytest.approx([x_bottom, -a], abs=1e-9)
    assert grown[0] == pytest.approx([-x_bottom, -a], abs=1e-9)
    # every vertex of the trapezoid is at least a from the cut line, each edge's middle exactly a
    assert distance_to(grown, trapezoid).min() == pytest.approx(a, abs=1e-9)
    middles = 0.5 * (trapezoid + np.roll(trapezoid, -1, axis=0))
    np.testing.assert_allclose(distance_to(grown, middles), a, atol=1e-9)


def test_an_allowance_that_folds_a_tight_notch_is_refused():
    """A V cut 2 mm wide into the sew line closes under a 6 mm allowance: the offset crosses
    itself, and a cut line that crosses itself cannot be cut."""
    vee = np.array(
        [[0, 0], [100, 0], [100, 100], [51, 100], [50, 20], [49, 100], [0, 100]], dtype=float
    )
    with pytest.raises(InputError, match="folds the cut line over itself") as caught:
        offset(vee, 6.0)
    assert caught.value.field == "pattern.seam_allowance_mm"
    assert len(offset(vee, 0.2)) == len(vee)  # narrower than the V: fine


def test_crossings_of_a_height_are_the_polygon_s_sides():
    trapezoid = np.array([[-100.0, 0.0], [100.0, 0.0], [50.0, 300.0], [-50.0, 300.0]])
    np.testing.assert_allclose(crossings(trapezoid, 150.0), [-75.0, 75.0])
    np.testing.assert_allclose(crossings(trapezoid, 0.0), [-100.0, 100.0])


@pytest.mark.parametrize("landscape", [False, True])
@pytest.mark.parametrize("paper", list(PAPERS))
@pytest.mark.parametrize("size", [(150.0, 200.0), (500.0, 400.0), (1200.0, 90.0)])
def test_tiles_cover_the_piece_and_overlap_by_the_band(paper, size, landscape):
    bounds = (-0.5 * size[0], 0.0, 0.5 * size[0], size[1])
    layout = tiles(bounds, paper, landscape)
    width, height = (v - 2 * MARGIN_MM for v in PAPERS[paper])
    if landscape:
        width, height = height, width
    columns = 1 + max(c for _, c, _ in layout)
    rows = 1 + max(r for r, _, _ in layout)
    assert len(layout) == rows * columns
    if size[0] <= width:
        assert columns == 1
    for _, _, (x0, y0, x1, y1) in layout:
        assert x1 - x0 == pytest.approx(width) and y1 - y0 == pytest.approx(height)
    lefts = sorted({w[0] for _, _, w in layout})
    assert np.diff(lefts) == pytest.approx([width - OVERLAP_MM] * (columns - 1))
    assert lefts[0] == bounds[0] and max(w[2] for _, _, w in layout) >= bounds[2]
    assert max(w[3] for _, _, w in layout) >= bounds[3]
    # no tile more than needed: one column fewer would not reach the right edge
    assert lefts[-1] < bounds[2]


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(st.floats(-8.0, 8.0), min_size=4, max_size=60),
    pitch=st.floats(1.0, 15.0),
    allowance=st.floats(0.5, 20.0),
)
def test_any_sew_line_s_cut_line_is_the_allowance_outside_it_or_refused(steps, pitch, allowance):
    """A pattern's sew line: rows ``pitch`` mm apart, half widths a random walk. The cut line
    either is refused as folded, or lies outside the sew line, nowhere nearer than the
    allowance, and every sew vertex is inside it."""
    half = np.maximum(60.0 + np.cumsum(steps), 5.0)
    y = pitch * np.arange(len(half))
    sew = np.concatenate([np.stack([half, y], 1), np.stack([-half, y], 1)[::-1]])
    try:
        cut = offset(sew, allowance)
    except InputError:
        return
    assert distance_to(sew, cut).min() >= allowance - 1e-6
    assert distance_to(cut, sew).min() >= allowance - 1e-6
    for x0, y0 in sew:  # inside: the cut line crosses the vertex's height either side of it
        xs = crossings(cut, y0)
        assert xs.min() < x0 < xs.max()


@pytest.mark.parametrize(("width", "pages"), [(170.0, {(595.3, 841.9)}), (250.0, {(841.9, 595.3)})])
def test_a_piece_is_printed_on_the_orientation_with_fewer_tiles(tmp_path, width, pages):
    """A rectangle 150 mm high: 170 mm wide fits A4 portrait's printable 190 x 277 mm on one
    page; 250 mm wide does not (two tiles) but fits landscape's 277 x 190 on one."""
    height = np.linspace(0.0, 150.0, 4)
    pattern = Pattern(
        height=height,
        width=np.full(4, width - 2 * 6.0 - 2 * CLEARANCE_MM),
        circumference=np.full(4, 2 * width),
        cut_height=1e-3 * height,
        reduction=None,
        lines=(),
        cut="two-panel",
    )
    path = write_pdf(piece_of(pattern, "M", "test"), tmp_path / "p.pdf")
    boxes = re.findall(rb"/MediaBox \[ ?0 0 ([\d.]+) ([\d.]+) ?\]", path.read_bytes())
    sizes = [(round(float(w), 1), round(float(h), 1)) for w, h in boxes]
    assert sizes[0] == (595.3, 841.9) and len(sizes) == 2  # the cover, portrait; one tile
    assert set(sizes[1:]) == pages


def _printed(tmp_path, monkeypatch, piece, paper="A4"):
    """The figures `write_pdf` draws for ``piece``: the cover, then the tiles."""
    import cloth.files.printout as printout

    pages = []
    for name in ("_cover", "_tile"):
        original = getattr(printout, name)
        monkeypatch.setattr(
            printout, name, lambda *a, _f=original, **k: pages.append(_f(*a, **k)) or pages[-1]
        )
    write_pdf(piece, tmp_path / "p.pdf", paper)
    monkeypatch.undo()
    return pages[0], pages[1:]


def _wide_pattern(
    lines=(("waist", 100.0), ("hip", 300.0)), width: float = 600.0, tall: float = 420.0
) -> Pattern:
    height = np.linspace(0.0, tall, 8)
    return Pattern(
        height=height,
        width=np.full(8, width),
        circumference=np.full(8, 2.0 * width),
        cut_height=1e-3 * height,
        reduction=None,
        lines=lines,
        cut="two-panel",
    )


def test_a_tiled_print_is_at_one_to_one_and_its_tiles_meet_at_shared_crosses(tmp_path, monkeypatch):
    """A piece 600 x 420 mm with two girth lines on A4: every page's figure read back. The
    cover's check square is 100 mm (283.46 pt in the PDF), its text says how many pages follow
    and names every tile on its map; each tile maps its window onto the printable area at one
    printed mm per mm, draws the cut line, the sew line, the notches and the girth lines of the
    piece; neighbouring windows overlap by 15 mm, and the crosses in a shared band sit at the
    same places of the piece on both tiles."""
    piece = piece_of(_wide_pattern(), "M", "test")
    cover, tiled = _printed(tmp_path, monkeypatch, piece)
    assert len(tiled) > 1  # the piece does not fit one page
    boxes, streams = pdf_pages(tmp_path / "p.pdf")
    assert len(boxes) == 1 + len(tiled)
    square = 100.0 / 25.4 * 72  # pt
    sides = [side for stream in streams for side in squares(stream)]
    assert any(abs(side - square) < 1e-3 for side in sides), sides
    texts = [t.get_text() for t in cover.axes[0].texts]
    assert f"Paper: A4; {len(tiled)} page(s) after this one, portrait" in texts or (
        f"Paper: A4; {len(tiled)} page(s) after this one, landscape" in texts
    )
    windows = {}
    for fig in tiled:
        (ax,) = fig.axes
        (title,) = fig.texts
        name = title.get_text().split("tile ")[1].split(" ")[0]
        x0, x1 = ax.get_xlim()
        y0, y1 = ax.get_ylim()
        windows[name] = (x0, y0, x1, y1)
        width_mm, height_mm = (v * 25.4 for v in fig.get_size_inches())
        box = ax.get_position()
        assert box.width * width_mm == pytest.approx(x1 - x0, abs=1e-9)  # 1 printed mm per mm
        assert box.height * height_mm == pytest.approx(y1 - y0, abs=1e-9)
        assert box.x0 * width_mm == pytest.approx(
            MARGIN_MM
        ) and box.y0 * height_mm == pytest.approx(MARGIN_MM)
        outline = ax.patches[0].get_xy()
        np.testing.assert_allclose(outline[: len(piece.cut)], piece.cut)
        assert any(np.allclose(p.get_xy()[: len(piece.sew)], piece.sew) for p in ax.patches[1:])
        girths = [ln for ln in ax.lines if ln.get_color() == "tab:red"]
        assert sorted(float(ln.get_ydata()[0]) for ln in girths) == [100.0, 300.0]
    assert set(windows) <= {t for t in texts if len(t) == 2}  # the map names every tile
    cut = piece.cut
    for x, y in cut:  # the tiles cover the cut line
        assert any(a <= x <= c and b <= y <= d for a, b, c, d in windows.values())
    crosses = {}
    for fig, name in zip(tiled, windows, strict=True):
        (ax,) = fig.axes
        bars = [ln for ln in ax.lines if ln.get_color() == "black" and len(ln.get_xdata()) == 2]
        centres = {
            (round(float(np.mean(ln.get_xdata())), 6), round(float(np.mean(ln.get_ydata())), 6))
            for ln in bars
            if np.ptp(ln.get_xdata()) == 8.0 or np.ptp(ln.get_ydata()) == 8.0
        }
        crosses[name] = centres
    for a, wa in windows.items():
        for b, wb in windows.items():
            same_row, same_column = a[0] == b[0], a[1:] == b[1:]
            if same_row and int(b[1:]) == int(a[1:]) + 1:  # b right of a
                assert wa[2] - wb[0] == pytest.approx(OVERLAP_MM)
                middle = round(0.5 * (wb[0] + wa[2]), 6)  # the crosses on the band's middle
                band = {p for p in crosses[a] if p[0] == middle}
                assert len(band) == 3 and band == {p for p in crosses[b] if p[0] == middle}
            if same_column and ord(b[0]) == ord(a[0]) + 1:  # b above a
                assert wa[3] - wb[1] == pytest.approx(OVERLAP_MM)
                middle = round(0.5 * (wb[1] + wa[3]), 6)
                band = {p for p in crosses[a] if p[1] == middle}
                assert len(band) == 3 and band == {p for p in crosses[b] if p[1] == middle}


def test_every_text_of_the_print_says_what_a_cutter_reads(tmp_path, monkeypatch):
    """The cover: the check square's label and instruction, the piece's annotation, the paper
    and the pages after it, the tile map's title and names; each tile: its name, row and column
    of how many, the grain's label, the girth lines' names, the annotation on the piece."""
    piece = piece_of(_wide_pattern(), "M", "power net", 6.0, ["pressure targets (mmHg): waist 20"])
    cover, tiled = _printed(tmp_path, monkeypatch, piece)
    texts = [t.get_text() for t in cover.axes[0].texts]
    assert texts[0] == "10 cm"
    assert texts[1] == (
        "Check square: it must measure 100 mm x 100 mm. If not, print at 100 % (actual size)."
    )
    annotation = [
        "Piece Name: PANEL",
        "Size: M",
        "Quantity: 2",
        "Material: power net",
        "Seam Allowance: 6 mm",
        "Annotation: pressure targets (mmHg): waist 20",
    ]
    assert piece.annotation() == annotation
    width, height = tiled[0].get_size_inches()
    orientation = "landscape" if width > height else "portrait"
    assert texts[2 : 2 + len(annotation)] == annotation
    assert texts[2 + len(annotation)] == (
        f"Paper: A4; {len(tiled)} page(s) after this one, {orientation}"
    )
    assert texts[-1] == "tiles (overlap dotted)"
    rows = 1 + max(
        ord(t.get_text().split("tile ")[1][0]) - ord("A") for fig in tiled for t in fig.texts
    )
    columns = len(tiled) // rows
    names = sorted(f"{chr(ord('A') + r)}{c + 1}" for r in range(rows) for c in range(columns))
    assert sorted(texts[3 + len(annotation) : -1]) == names  # the map names each tile once
    for fig in tiled:
        (title,) = fig.texts
        name = title.get_text().split("tile ")[1].split(" ")[0]
        r, c = ord(name[0]) - ord("A"), int(name[1:]) - 1
        assert title.get_text() == (
            f"PANEL M: tile {name} (row {r + 1} of {rows} from the bottom, "
            f"column {c + 1} of {columns})"
        )
        (ax,) = fig.axes
        drawn = [t.get_text() for t in ax.texts]
        assert "grain (warp)" in drawn and "waist" in drawn and "hip" in drawn
        assert drawn[-4:] == annotation[:4]
        grain = next(t for t in ax.texts if t.get_text() == "grain (warp)")
        assert grain.get_rotation() == 90.0
        arrow = next(t for t in ax.texts if t.get_text() == "" and hasattr(t, "xy"))
        np.testing.assert_allclose(arrow.xy, piece.grain[1])
        np.testing.assert_allclose(arrow.xyann, piece.grain[0])
        assert arrow.arrow_patch.get_arrowstyle().__class__.__name__ == "CurveAB"  # <->


def test_a_net_pattern_prints_its_cut_line_only_and_its_notches_on_it(tmp_path, monkeypatch):
    """Without a seam allowance the cut line is the sew line, drawn once; each notch is a
    slit from the cut line inward, drawn where the piece says."""
    piece = piece_of(_wide_pattern(), "S", "power net", 0.0)
    _, tiled = _printed(tmp_path, monkeypatch, piece)
    (ax,) = tiled[0].axes
    assert len([p for p in ax.patches if p.__class__.__name__ == "Polygon"]) == 1
    slits = {
        tuple(np.round(np.concatenate([ln.get_xdata(), ln.get_ydata()]), 6))
        for fig in tiled
        for ln in fig.axes[0].lines
    }
    for start, end in piece.notches:
        xs, ys = np.stack([start, end]).T
        assert tuple(np.round(np.concatenate([xs, ys]), 6)) in slits


def test_every_line_of_the_print_is_exact_and_every_outline_open(tmp_path, monkeypatch):
    """Snapping moves a line to the device's pixel grid, so a 1:1 print must have none; a
    filled outline would print the piece solid. The check square is a 100 mm square on the
    cover's printable area, the cut line black and solid."""
    piece = piece_of(_wide_pattern(), "M", "power net", 6.0)
    cover, tiled = _printed(tmp_path, monkeypatch, piece)
    for fig in [cover, *tiled]:
        (ax,) = fig.axes
        for artist in [*ax.patches, *ax.lines]:
            assert artist.get_snap() is False, artist
        for patch in ax.patches:
            assert not patch.get_fill(), patch
    (square,) = [p for p in cover.axes[0].patches if p.__class__.__name__ == "Rectangle"][:1]
    assert square.get_width() == square.get_height() == 100.0
    x, y = square.get_xy()
    width_mm, height_mm = (v * 25.4 for v in cover.get_size_inches())
    assert MARGIN_MM <= x and x + 100.0 <= width_mm - MARGIN_MM
    assert MARGIN_MM <= y and y + 100.0 <= height_mm - MARGIN_MM
    cut = tiled[0].axes[0].patches[0]
    assert cut.get_edgecolor() == (0.0, 0.0, 0.0, 1.0) and cut.get_linestyle() == "solid"


@pytest.mark.parametrize(
    ("width", "tall"),
    [(600.0, 420.0), (1500.0, 300.0)],  # the map's height binds its scale, then its width
)
def test_the_cover_s_tile_map_is_the_tiles_scaled_and_the_pdf_names_its_maker(
    tmp_path, monkeypatch, caplog, width, tall
):
    """The cover's map: the piece's cut line and every tile's window scaled by one factor from
    the first tile's corner, each tile's name at its window's centre, all inside the printable
    area; the tiles cover the cut line with 5 mm to spare; the log line and the PDF's creator."""
    import logging

    from cloth.files.printout import tiles

    caplog.set_level(logging.INFO, logger="cloth.files.printout")
    piece = piece_of(_wide_pattern(width=width, tall=tall), "M", "power net", 6.0)
    cover, tiled = _printed(tmp_path, monkeypatch, piece)
    (ax,) = cover.axes
    cut = piece.cut
    bounds = (
        cut[:, 0].min() - CLEARANCE_MM,
        cut[:, 1].min() - CLEARANCE_MM,
        cut[:, 0].max() + CLEARANCE_MM,
        cut[:, 1].max() + CLEARANCE_MM,
    )
    portrait, landscape = tiles(bounds, "A4"), tiles(bounds, "A4", landscape=True)
    layout = landscape if len(landscape) < len(portrait) else portrait
    assert len(tiled) == len(layout)
    union = [min(w[0] for *_, w in layout), min(w[1] for *_, w in layout)]
    union += [max(w[2] for *_, w in layout), max(w[3] for *_, w in layout)]
    assert union[0] <= bounds[0] and union[1] <= bounds[1]
    assert union[2] >= bounds[2] and union[3] >= bounds[3]
    outline, *rectangles = [p for p in ax.patches if p.__class__.__name__ != "Rectangle"] + [
        p for p in ax.patches[1:] if p.__class__.__name__ == "Rectangle"
    ]
    drawn = outline.get_xy()[: len(cut)]
    # one scale and one offset map the cut line onto its drawing
    scale = np.ptp(drawn[:, 0]) / np.ptp(cut[:, 0])
    assert np.ptp(drawn[:, 1]) / np.ptp(cut[:, 1]) == pytest.approx(scale)
    origin = drawn[0] - scale * (cut[0] - np.array(union[:2]))
    np.testing.assert_allclose(drawn, origin + scale * (cut - np.array(union[:2])), atol=1e-9)
    assert scale == pytest.approx(min(150.0 / (union[2] - union[0]), 90.0 / (union[3] - union[1])))
    width_mm, height_mm = (v * 25.4 for v in cover.get_size_inches())
    assert len(rectangles) == len(layout)
    names = {t.get_text(): t.get_position() for t in ax.texts if len(t.get_text()) == 2}
    for (row, column, (a, b, c, d)), rectangle in zip(layout, rectangles, strict=True):
        np.testing.assert_allclose(
            rectangle.get_xy(), origin + scale * (np.array([a, b]) - union[:2]), atol=1e-9
        )
        assert rectangle.get_width() == pytest.approx(scale * (c - a))
        assert rectangle.get_height() == pytest.approx(scale * (d - b))
        assert not rectangle.get_fill()
        name = f"{chr(ord('A') + row)}{column + 1}"
        centre = origin + scale * (np.array([(a + c) / 2, (b + d) / 2]) - union[:2])
        np.testing.assert_allclose(names[name], centre, atol=1e-9)
        x, y = rectangle.get_xy()
        assert MARGIN_MM <= x and x + rectangle.get_width() <= width_mm - MARGIN_MM
        assert MARGIN_MM <= y and y + rectangle.get_height() <= height_mm - MARGIN_MM
    title = next(t for t in ax.texts if t.get_text() == "tiles (overlap dotted)")
    assert title.get_position()[1] == pytest.approx(origin[1] + scale * (union[3] - union[1]) + 3.0)
    orientation = " landscape" if layout is landscape else ""
    assert f"wrote {tmp_path / 'p.pdf'}: {len(layout)} tile(s) on A4{orientation} at 1:1" in (
        caplog.text
    )
    paper = next(t.get_text() for t in ax.texts if t.get_text().startswith("Paper: "))
    assert paper.endswith("landscape" if layout is landscape else "portrait")
    assert (width > 1000.0) == (layout is landscape)  # the wide piece prints turned
    import matplotlib.pyplot as plt

    assert plt.get_fignums() == []  # every page's figure closed
    assert b"/Creator (cloth)" in (tmp_path / "p.pdf").read_bytes()


def test_each_tile_s_overlap_bands_and_crosses_lie_where_its_neighbours_are(tmp_path, monkeypatch):
    """On every tile, towards each neighbour only: the band's inner edge dotted 15 mm inside
    the window's edge, and three crosses (arms 4 mm) on the band's middle line, 15 mm from the
    window's ends and at its middle."""
    piece = piece_of(_wide_pattern(), "M", "power net", 6.0)
    _, tiled = _printed(tmp_path, monkeypatch, piece)
    names = {}
    for fig in tiled:
        name = fig.texts[0].get_text().split("tile ")[1].split(" ")[0]
        names[name] = fig
    for name, fig in names.items():
        (ax,) = fig.axes
        x0, x1 = ax.get_xlim()
        y0, y1 = ax.get_ylim()
        row, column = name[0], int(name[1:])
        neighbours = {
            "left": f"{row}{column - 1}" in names,
            "right": f"{row}{column + 1}" in names,
            "below": f"{chr(ord(row) - 1)}{column}" in names,
            "above": f"{chr(ord(row) + 1)}{column}" in names,
        }
        dotted = {
            (tuple(np.round(ln.get_xdata(), 6)), tuple(np.round(ln.get_ydata(), 6)))
            for ln in ax.lines
            if ln.get_linestyle() == ":"
        }
        expected_edges = set()
        expected_crosses = set()
        ys = (y0 + OVERLAP_MM, 0.5 * (y0 + y1), y1 - OVERLAP_MM)
        xs = (x0 + OVERLAP_MM, 0.5 * (x0 + x1), x1 - OVERLAP_MM)
        for side, edge, middle in (
            ("left", x0 + OVERLAP_MM, x0 + 7.5),
            ("right", x1 - OVERLAP_MM, x1 - 7.5),
        ):
            if neighbours[side]:
                expected_edges.add(((round(edge, 6),) * 2, (round(y0, 6), round(y1, 6))))
                expected_crosses |= {(round(middle, 6), round(y, 6)) for y in ys}
        for side, edge, middle in (
            ("below", y0 + OVERLAP_MM, y0 + 7.5),
            ("above", y1 - OVERLAP_MM, y1 - 7.5),
        ):
            if neighbours[side]:
                expected_edges.add(((round(x0, 6), round(x1, 6)), (round(edge, 6),) * 2))
                expected_crosses |= {(round(x, 6), round(middle, 6)) for x in xs}
        assert dotted == expected_edges, name
        arms = [
            ln
            for ln in ax.lines
            if ln.get_linestyle() == "-"
            and ln.get_color() == "black"
            and len(ln.get_xdata()) == 2
            and (np.ptp(ln.get_xdata()) == 8.0 or np.ptp(ln.get_ydata()) == 8.0)
        ]
        centres = {
            (round(float(np.mean(ln.get_xdata())), 6), round(float(np.mean(ln.get_ydata())), 6))
            for ln in arms
        }
        assert centres == expected_crosses, name
        for ln in arms:  # one horizontal and one vertical arm through each centre
            assert np.ptp(ln.get_xdata()) == 0.0 or np.ptp(ln.get_ydata()) == 0.0
        assert len(arms) == 2 * len(expected_crosses)


def test_every_label_and_pen_of_the_print_is_where_its_layout_says(tmp_path, monkeypatch):
    """Each text at its place, size and alignment, each line in its pen (module constants of
    `cloth.files.printout` restated here as literals, mm and pt): the cover's "10 cm" at the
    check square's centre, the instruction one line pitch (6 mm) under the square, the
    annotation from 20 mm under it at 6 mm a line, the map's names and title; on each tile its
    title centred 5 mm from the page's top, the grain's label 3 mm right of its arrow and
    halfway up it, each girth line's name 8 mm in and 1.5 mm above it in the line's red, the
    annotation 8 mm in from half the sew line's height down at 6 mm a line; the cut line 0.8 pt
    black solid, the sew line 0.5 pt grey dashed, notches 0.8 pt black, girth lines 0.5 pt red
    dashed, the overlap edges 0.4 pt grey dotted and the crosses 0.5 pt black."""
    from matplotlib.colors import to_rgba

    piece = piece_of(_wide_pattern(), "M", "power net", 6.0, ["pressure targets (mmHg): waist 20"])
    cover, tiled = _printed(tmp_path, monkeypatch, piece)
    (ax,) = cover.axes
    height_mm = cover.get_size_inches()[1] * 25.4
    left, top = 15.0, height_mm - 15.0  # margin 10 mm + inset 5 mm
    texts = {t.get_text(): t for t in ax.texts}
    label = texts["10 cm"]
    assert label.get_position() == pytest.approx((left + 50.0, top - 50.0))
    assert (label.get_ha(), label.get_va()) == ("center", "center")
    square = next(p for p in ax.patches if p.__class__.__name__ == "Rectangle")
    assert square.get_xy() == pytest.approx((left, top - 100.0)) and square.get_linewidth() == 0.8
    instruction = next(t for t in ax.texts if t.get_text().startswith("Check square"))
    assert instruction.get_position() == pytest.approx((left, top - 106.0))
    assert (instruction.get_fontsize(), instruction.get_va()) == (8.0, "top")
    lines = [*piece.annotation(), next(t for t in texts if t.startswith("Paper: "))]
    for k, line in enumerate(lines):
        text = texts[line]
        assert text.get_position() == pytest.approx((left, top - 120.0 - 6.0 * k)), line
        assert (text.get_fontsize(), text.get_va()) == (9.0, "top")
    assert texts["tiles (overlap dotted)"].get_fontsize() == 8.0
    for name in (t for t in texts if re.fullmatch(r"[A-Z]\d+", t)):
        assert texts[name].get_fontsize() == 7.0
    outline, *rectangles = ax.patches[1:]
    assert outline.get_linewidth() == 0.6 and outline.get_linestyle() == "solid"
    for rectangle in rectangles:
        assert rectangle.get_linewidth() == 0.4 and rectangle.get_linestyle() == ":"
    red = to_rgba("tab:red")
    sew_top = float(piece.sew[:, 1].max())
    for fig in tiled:
        page_height = fig.get_size_inches()[1] * 25.4
        (title,) = fig.texts
        assert title.get_position() == pytest.approx((0.5, (page_height - 5.0) / page_height))
        assert (title.get_ha(), title.get_va(), title.get_fontsize()) == ("center", "center", 7.0)
        (tile,) = fig.axes
        drawn = {t.get_text(): t for t in tile.texts if t.get_text()}
        (gx0, gy0), (_, gy1) = piece.grain
        grain = drawn["grain (warp)"]
        assert grain.get_position() == pytest.approx((gx0 + 3.0, 0.5 * (gy0 + gy1)))
        assert (grain.get_fontsize(), grain.get_va()) == (7.0, "center")
        arrow = next(t for t in tile.texts if t.get_text() == "" and hasattr(t, "xy"))
        assert arrow.arrow_patch.get_linewidth() == 0.6
        for name, y, line_left, _ in piece.girths:
            text = drawn[name]
            assert text.get_position() == pytest.approx((line_left + 8.0, y + 1.5)), name
            assert text.get_fontsize() == 7.0 and to_rgba(text.get_color()) == red
        for k, line in enumerate(piece.annotation()[:4]):
            text = drawn[line]
            assert text.get_position() == pytest.approx((8.0, 0.5 * sew_top - 6.0 * k)), line
            assert text.get_fontsize() == 8.0
        cut, sew = tile.patches
        assert cut.get_linewidth() == 0.8 and cut.get_edgecolor() == to_rgba("black")
        assert sew.get_linewidth() == 0.5 and sew.get_linestyle() == "--"
        assert sew.get_edgecolor() == to_rgba("0.3")
        girths = {round(y, 6) for _, y, _, _ in piece.girths}
        for ln in tile.lines:
            xs, ys = ln.get_xdata(), ln.get_ydata()
            style = (ln.get_linewidth(), ln.get_linestyle(), to_rgba(ln.get_color()))
            if ln.get_linestyle() == "--":  # a girth line, at its height, across the piece
                assert round(float(ys[0]), 6) in girths and style == (0.5, "--", red)
                (line,) = [g for g in piece.girths if round(g[1], 6) == round(float(ys[0]), 6)]
                np.testing.assert_allclose(xs, line[2:], rtol=0, atol=1e-12)
            elif ln.get_linestyle() == ":":  # an overlap band's inner edge
                assert style == (0.4, ":", to_rgba("0.4"))
            else:  # a notch or a cross's arm
                assert ln.get_linestyle() == "-" and to_rgba(ln.get_color()) == to_rgba("black")
                is_notch = any(
                    np.allclose(np.stack([xs, ys], axis=1), [start, end])
                    for start, end in piece.notches
                )
                assert ln.get_linewidth() == (0.8 if is_notch else 0.5)


def test_the_tiles_count_the_piece_s_own_extent_and_the_map_shows_for_two_or_more():
    """A window from y = -100 to 200 mm is 300 mm tall (two A4 rows of 277 mm printable), not
    its top's 200; exactly the printable area is one tile; an unknown paper names its field and
    the papers there are."""
    assert len(tiles((0.0, -100.0, 150.0, 200.0), "A4")) == 2
    assert len(tiles((0.0, 0.0, 190.0, 277.0), "A4")) == 1  # 210 - 20 by 297 - 20
    assert len(tiles((0.0, 0.0, 190.0, 277.0 + 1e-9), "A4")) == 2
    with pytest.raises(InputError) as caught:
        tiles((0.0, 0.0, 1.0, 1.0), "A5")
    assert caught.value.field == "--paper"
    assert str(caught.value).endswith("unknown paper 'A5'; give one of A4, letter")


@pytest.mark.parametrize(
    ("width", "tall", "maps"), [(150.0, 200.0, False), (300.0, 200.0, True), (185.0, 185.0, True)]
)
def test_the_cover_maps_the_tiles_only_where_there_are_two_or_more(
    tmp_path, monkeypatch, width, tall, maps
):
    """A panel that fits one A4 page has no tile map; one two pages wide has; so has a net
    panel 185 mm square, which the 5 mm clearance on each side takes past the 190 mm the page
    prints either way (portrait 190 x 277, landscape 277 x 190)."""
    piece = piece_of(_wide_pattern((), width=width, tall=tall), "M", "power net", 0.0)
    cover, tiled = _printed(tmp_path, monkeypatch, piece)
    assert len(tiled) == (2 if maps else 1)
    texts = [t.get_text() for t in cover.axes[0].texts]
    assert ("tiles (overlap dotted)" in texts) == maps


def test_a_seam_allowance_under_a_millimetre_still_prints_its_sew_line(tmp_path, monkeypatch):
    """0.5 mm of allowance: the cut line and, inside it, the sew line (two outlines)."""
    piece = piece_of(_wide_pattern(), "M", "power net", 0.5)
    _, tiled = _printed(tmp_path, monkeypatch, piece)
    cut, sew = tiled[0].axes[0].patches
    np.testing.assert_allclose(sew.get_xy()[: len(piece.sew)], piece.sew)
    np.testing.assert_allclose(cut.get_xy()[: len(piece.cut)], piece.cut)
