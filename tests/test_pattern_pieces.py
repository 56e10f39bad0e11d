"""The pattern of a garment of several pieces (issue 69), read back from its files: every piece
in the nest with its seam allowance and notches, the panels' widths summing to each row's rest
circumference, a band's strip its cut length and width, the pieces' table and sheet."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import xarray as xr
from matplotlib.path import Path as PolygonPath

from cloth.files import astm
from cloth.files.piece import NOTCH_MM
from cloth.stages.patterns import write_patterns
from tests.conftest import run_result

ALLOWANCE = 8.0
TOL = 1e-6
PANELS = [("powernet", -60, 60), ("lightnet", 60, 300)]
CASE = {
    "material": "powernet",
    "body": {"cone": {"radius_bottom": 0.12, "radius_top": 0.10, "bottom": 0.0, "top": 0.5}},
    "garment": {
        "bottom": 0.1,
        "top": 0.4,
        "reduction": 0.15,
        "grid": [24, 12],
        "error_estimate": False,
        "panels": [{"material": m, "from_deg": a, "to_deg": b} for m, a, b in PANELS],
        "bands": [
            {"name": "topband", "material": "elastic25", "width": 0.03, "reduction": 0.05},
            {
                "name": "welt",
                "material": "elastic25",
                "at": "bottom",
                "width": 0.02,
                "reduction": 0.05,
                "layers": 2,
            },
        ],
        "layers": [
            {"material": "controlnet", "from_deg": -30, "to_deg": 30, "bottom": 0.2, "top": 0.3}
        ],
    },
    "landmarks": {"mid": 0.25},
}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pieces")
    out = run_result(folder, CASE)
    paths = write_patterns(
        [out / "result.nc"], folder / "pattern.csv", "tube", allowance=ALLOWANCE, sizes=["M"]
    )
    return folder, out, paths


def _dist(polygon, point) -> float:
    return float(astm.distance_to(polygon, np.asarray([point], float))[0])


def test_every_piece_is_its_own_block_with_its_allowance_and_notches(written):
    folder, _, _ = written
    nest = astm.read_nest(folder / "pattern_astm.dxf")
    assert nest.errors == 0
    names = {"PANEL_1_M", "PANEL_2_M", "BAND_topband_M", "BAND_welt_M", "LAYER_1_M"}
    assert set(nest.pieces) == names
    for piece in nest.pieces.values():
        (cut,), (sew,) = piece.cut, piece.sew
        # the cut line is the sew line's edges moved out by the allowance, all round (its
        # edges' midpoints; its corners are mitres, further from the sew line's corners)
        middles = 0.5 * (cut + np.roll(cut, -1, axis=0))
        away = np.array([_dist(sew, p) for p in middles])
        assert away.min() == pytest.approx(ALLOWANCE, abs=1e-6)
        assert np.median(away) == pytest.approx(ALLOWANCE, abs=1e-6)
        assert np.all(away >= ALLOWANCE - 1e-6)
        assert all(PolygonPath(cut).contains_point(p) for p in sew)
        for notch in piece.notches:
            start, end = notch
            assert _dist(cut, start) <= TOL
            assert math.dist(start, end) == pytest.approx(min(NOTCH_MM, ALLOWANCE), abs=TOL)
            assert PolygonPath(cut).contains_point(end) or _dist(cut, end) <= TOL
            assert not PolygonPath(sew).contains_point(end)  # within the allowance
    # the panels: a notch on each side seam at every girth line they cover
    for name in ("PANEL_1_M", "PANEL_2_M"):
        assert len(nest.pieces[name].notches) == 2 * len(nest.pieces[name].internal)
        assert {round(n[0][1], 6) for n in nest.pieces[name].notches} == {
            round(line[0][1], 6) for line in nest.pieces[name].internal
        }
    # a band: its girth line's two notches, and one on its lower edge at each seam
    band = nest.pieces["BAND_topband_M"]
    (cut,) = band.cut
    bottom = float(cut[:, 1].min())
    edge = sorted(float(n[0][0]) for n in band.notches if abs(n[0][1] - bottom) <= TOL)
    length = band.sew_width_at(float(band.sew[0][:, 1].mean()))
    seams = sorted(((a + 180) / 360 % 1 - 0.5) * length for _, a, _ in PANELS)
    assert edge == pytest.approx(seams, abs=1e-6)  # where the panels' seams meet the band


def test_the_panels_widths_add_up_to_each_rows_circumference(written):
    folder, out, _ = written
    nest = astm.read_nest(folder / "pattern_astm.dxf")
    result = xr.load_dataset(out / "result.nc")
    v = 1e3 * result["pattern_height"].values
    circumference = 1e3 * result["rest_circumference"].values
    band = np.asarray(result.attrs["row_band"] if "row_band" in result.attrs else [])
    sew = [nest.pieces[n] for n in ("PANEL_1_M", "PANEL_2_M")]
    low = max(float(p.sew[0][:, 1].min()) for p in sew)
    high = min(float(p.sew[0][:, 1].max()) for p in sew)
    inside = (v > low + 1e-6) & (v < high - 1e-6)
    assert inside.sum() >= 3
    for y, c in zip(v[inside], circumference[inside], strict=True):
        total = sum(p.sew_width_at(y) for p in sew)
        assert total == pytest.approx(c, rel=1e-9)
        shares = [p.sew_width_at(y) / c for p in sew]
        assert shares == pytest.approx([120 / 360, 240 / 360], rel=1e-9)
    del band


def test_a_bands_strip_is_its_cut_length_by_its_width(written):
    folder, out, _ = written
    rows = list(csv.DictReader((folder / "pattern_pieces.csv").open()))
    result = xr.load_dataset(out / "result.nc")
    z = result["z"].values.mean(axis=1)
    circumference = 1e3 * result["rest_circumference"].values
    for name, low, high, layers in (("topband", 0.37, 0.40, 1), ("welt", 0.10, 0.12, 2)):
        mine = [r for r in rows if r["piece"] == f"BAND_{name}"]
        assert len(mine) == 2 and mine[0]["kind"] == "band"
        length = float(mine[0]["cut_length_mm"])
        cut = result["cut_height"].values
        band_rows = (cut >= low - 1e-9) & (cut <= high + 1e-9)
        assert length == pytest.approx(circumference[band_rows].mean(), abs=1e-4)  # 0.1 um
        assert float(mine[0]["piece_width_mm"]) == pytest.approx(1e3 * (high - low) * layers)
    del z
    pieces = {r["piece"] for r in rows}
    assert pieces == {"PANEL_1", "PANEL_2", "BAND_topband", "BAND_welt", "LAYER_1"}


def test_the_sheet_and_the_pdfs_hold_every_piece(written):
    folder, _, paths = written
    svg = (folder / "pattern.svg").read_text()
    for name in ("PANEL_1", "PANEL_2", "BAND_topband", "BAND_welt", "LAYER_1"):
        assert f'<g id="{name}">' in svg
        assert (folder / f"pattern_{name}.pdf").is_file()
    import ezdxf

    doc = ezdxf.readfile(folder / "pattern.dxf")
    assert {b.name for b in doc.blocks if not b.name.startswith("*")} >= {
        "PANEL_1",
        "BAND_welt",
        "LAYER_1",
    }
    knitting = list(csv.DictReader((folder / "pattern_knitting.csv").open()))
    assert {r["size"] for r in knitting} == {"M"}
    assert {r["piece"] for r in knitting} == {"BAND_topband", "BAND_welt"}  # panels: not knitted
    assert all(p.is_file() for p in paths)


def test_pattern_csv_says_each_rows_piece_and_the_panels_widths(written):
    """pattern.csv stays the whole garment's rows (a case can wear it) and says which piece
    each row is cut in, and each panel's and layer's width there: the panels' widths add up to
    the row's rest circumference."""
    from cloth.garment.cut import read_pattern

    folder, out, _ = written
    rows = [
        r
        for r in csv.DictReader(
            line for line in (folder / "pattern.csv").open() if not line.startswith("#")
        )
    ]
    result = xr.load_dataset(out / "result.nc")
    cut = result["cut_height"].values
    for row, z in zip(rows, cut, strict=True):
        band = "BAND_topband" if z >= 0.37 - 1e-9 else "BAND_welt" if z <= 0.12 + 1e-9 else "BODY"
        assert row["piece"] == band
        if band == "BODY":
            widths = float(row["PANEL_1_width_mm"]) + float(row["PANEL_2_width_mm"])
            assert widths == pytest.approx(float(row["rest_circumference_mm"]), abs=2e-4)
        else:
            assert row["PANEL_1_width_mm"] == row["PANEL_2_width_mm"] == ""
        assert (row["LAYER_1_width_mm"] != "") == (0.2 <= z <= 0.3)
    worn = read_pattern(folder / "pattern.csv")  # still a pattern a case wears
    assert len(worn.cut_height) == len(rows)


def test_a_piece_s_edge_at_a_band_is_its_own_fabric_s_not_the_band_s(written):
    """A panel's end row at a band's seam is the body's own row there: on the cone, cut to one
    reduction, the body's rest circumference is 0.85 x the cone's girth at each cut height
    (a line), so the panels' end rows add up to 0.85 x 2 pi r at the seam (0.12 m and 0.37 m),
    not to a mix with the band's row beyond it (cut to 0.95 x)."""
    folder, out, _ = written
    nest = astm.read_nest(folder / "pattern_astm.dxf")
    result = xr.load_dataset(out / "result.nc")
    cut = result["cut_height"].values
    circumference = 1e3 * result["rest_circumference"].values
    body = (cut > 0.12 + 1e-9) & (cut < 0.37 - 1e-9)

    def cone(z):  # 0.85 x the cone's girth at cut height z, mm
        return 0.85 * 2e3 * math.pi * (0.12 - 0.02 * np.asarray(z) / 0.5)

    assert circumference[body] == pytest.approx(cone(cut[body]), rel=1e-6)  # the premise
    sew = [nest.pieces[n] for n in ("PANEL_1_M", "PANEL_2_M")]
    for end, seam in ((min, 0.12), (max, 0.37)):
        y = end(float(end(p.sew[0][:, 1])) for p in sew)  # the panels' end row at the seam
        total = sum(p.sew_width_at(y) for p in sew)
        assert total == pytest.approx(float(cone(seam)), rel=1e-6)
