"""The graded pattern (issue 30, item 1): a reduction profile over height, recorded in result.nc,
and the cut pattern written by ``cloth pattern`` as CSV, SVG and DXF."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.interpolate import PchipInterpolator

from cloth.case.case import validate_case
from cloth.case.profile import Profile
from cloth.errors import InputError
from cloth.files.pattern import pattern_of, write_csv, write_pattern
from tests.conftest import load_result, run_result

RADIUS = 0.1
KNOTS = {"0.15": 0.10, "waist": 0.25, "0.35": 0.15}
LINES = {"waist": 0.25}


def _case(reduction, grid=(24, 11), **garment) -> dict:
    return {
        "material": "powernet",
        "body": {"cylinder": {"radius": RADIUS}},
        "landmarks": LINES,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": reduction,
            "grid": list(grid),
            "lengthwise_reduction": 0.1,
            "error_estimate": False,
            **garment,
        },
    }


@pytest.fixture(scope="module")
def graded(tmp_path_factory) -> tuple[Path, xr.Dataset]:
    folder = tmp_path_factory.mktemp("graded")
    return folder, load_result(folder, _case(KNOTS))


def test_rows_follow_the_monotone_cubic_through_the_knots(graded):
    """Each row's recorded reduction is PCHIP through the knots (waist resolved from the case's
    landmarks), held beyond the end knots; its rest circumference is (1 - r) 2 pi R."""
    _, ds = graded
    z = ds["cut_height"].values
    knots = np.array([0.15, 0.25, 0.35]), np.array([0.10, 0.25, 0.15])
    expected = PchipInterpolator(*knots)(np.clip(z, 0.15, 0.35))
    np.testing.assert_allclose(ds["row_reduction"].values, expected, rtol=0, atol=1e-12)
    assert ds["row_reduction"].values[0] == pytest.approx(0.10) and z[0] < 0.15
    assert np.all(ds["row_reduction"].values <= 0.25 + 1e-12)  # no overshoot past the knot
    np.testing.assert_allclose(
        ds["rest_circumference"].values, (1 - expected) * 2 * np.pi * RADIUS, rtol=1e-12
    )
    assert ds["rest_circumference"].attrs["units"] == "m"
    assert json.loads(ds["row_reduction"].attrs["profile"]) == KNOTS


def test_a_one_knot_profile_is_the_uniform_reduction(tmp_path):
    """A profile of one knot gives the same garment, to the bit, as the number."""
    a = load_result(tmp_path / "a", _case({"waist": 0.2}, grid=(12, 5)))
    b = load_result(tmp_path / "b", _case(0.2, grid=(12, 5)))
    np.testing.assert_array_equal(a["pressure"].values, b["pressure"].values)


def test_the_lengthwise_profile_sets_each_warp_step(tmp_path):
    lengthwise = {"0.1": 0.0, "0.4": 0.2}
    ds = load_result(tmp_path, _case(0.2, grid=(12, 7), lengthwise_reduction=lengthwise))
    z = ds["cut_height"].values
    middle = 0.5 * (z[1:] + z[:-1])
    steps = np.diff(ds["pattern_height"].values)
    reduction = PchipInterpolator([0.1, 0.4], [0.0, 0.2])(middle)
    np.testing.assert_allclose(steps, np.diff(z) * (1 - reduction), rtol=1e-12)


@pytest.mark.parametrize(
    ("reduction", "field", "words"),
    [
        ({"ankle": 0.2}, "garment.reduction", "neither a height"),
        ({"0.2": 0.1, "0.20": 0.2}, "garment.reduction", "one height"),
        ({"waist": 0.95}, "garment.reduction", "0.9"),
        ({}, "garment.reduction", "non-empty"),
        (1.2, "garment.reduction", "0.9"),
    ],
)
def test_a_bad_profile_is_one_line_naming_the_field(tmp_path, reduction, field, words):
    with pytest.raises(InputError) as caught:
        run_result(tmp_path, _case(reduction), stop="predeform")
    message = str(caught.value)
    assert field in message and words in message and "\n" not in message
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").glob("*.nc"))


def test_profile_keys_from_yaml_numbers_become_heights():
    case = validate_case(_case({0.15: 0.1, "waist": 0.2}))
    assert dict(case.garment.reduction) == {"0.15": 0.1, "waist": 0.2}
    profile = Profile.of(case.garment.reduction)
    np.testing.assert_allclose(profile.heights(LINES), [0.15, 0.25])


def _rows(path: Path) -> list[dict[str, str]]:
    """A written table's rows, its ``#`` comment lines (a pattern's girth lines) left out."""
    with path.open() as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


@pytest.mark.parametrize("cut", ["two-panel", "tube"])
def test_pattern_files_agree_at_one_to_one_in_mm(graded, tmp_path, cut):
    """The CSV's widths are the share of the rest circumference the cut asks for; the DXF reads
    back with ezdxf and its outline's row widths equal the CSV's to 0.01 mm; the SVG is XML
    whose viewBox is its width and height in mm."""
    ezdxf = pytest.importorskip("ezdxf")
    folder, ds = graded
    csv_path, svg_path, dxf_path = write_pattern(
        folder / "out" / "result.nc", tmp_path / "pattern.csv", cut
    )
    rows = _rows(csv_path)
    share = 0.5 if cut == "two-panel" else 1.0
    width = np.array([float(r["width_mm"]) for r in rows])
    height = np.array([float(r["pattern_height_mm"]) for r in rows])
    np.testing.assert_allclose(width, share * 1e3 * ds["rest_circumference"].values, atol=1e-4)
    assert float(rows[-1]["pattern_height_mm"]) == pytest.approx(0.9 * 300.0, rel=1e-9)

    doc = ezdxf.readfile(dxf_path)
    assert doc.units == ezdxf.units.MM
    (outline,) = doc.modelspace().query('LWPOLYLINE[layer=="OUTLINE"]')
    points = np.array([p[:2] for p in outline.get_points()])
    m = len(rows)
    left, right = points[:m], points[m:][::-1]
    np.testing.assert_allclose(right[:, 0] - left[:, 0], width, atol=0.01)
    np.testing.assert_allclose(left[:, 1], height, atol=0.01)
    (girth,) = doc.modelspace().query('LINE[layer=="GIRTH"]')
    z = ds["cut_height"].values
    y_line = np.interp(0.25, z, 1e3 * ds["pattern_height"])
    assert girth.dxf.start.y == pytest.approx(y_line)
    assert [t.dxf.text for t in doc.modelspace().query("TEXT")] == ["waist"]
    # the layers a CAD program sorts by, each in its colour; the outline closed; the girth line
    # across the pattern's width there; its label 8 mm high, 2 mm in from its left end, 2 up
    colours = {layer.dxf.name: layer.dxf.color for layer in doc.layers}
    assert {k: colours.get(k) for k in ("OUTLINE", "GIRTH", "LABELS")} == {
        "OUTLINE": 7,
        "GIRTH": 1,
        "LABELS": 3,
    }
    assert outline.closed and doc.dxfversion == "AC1024"  # R2010
    half = 0.5 * np.interp(y_line, height, width)
    assert (girth.dxf.start.x, girth.dxf.end.x) == pytest.approx((-half, half), abs=0.01)
    (label,) = doc.modelspace().query('TEXT[layer=="LABELS"]')
    assert label.dxf.height == 8.0
    assert (label.dxf.insert.x, label.dxf.insert.y) == pytest.approx(
        (-half + 2.0, y_line + 2.0), abs=0.01
    )

    root = ET.parse(svg_path).getroot()
    assert root.tag.endswith("svg")
    w, h = (float(root.get(k).removesuffix("mm")) for k in ("width", "height"))
    assert [float(v) for v in root.get("viewBox").split()] == pytest.approx([0, 0, w, h], abs=1e-3)
    assert w == pytest.approx(width.max() + 40.0, abs=1e-3)
    # y up on the pattern is y down in SVG: row j at h - 20 - its height, the top row highest
    space = "{http://www.w3.org/2000/svg}"
    polygon = root.find(f"{space}polygon")
    svg = np.array([[float(v) for v in p.split(",")] for p in polygon.get("points").split()])
    np.testing.assert_allclose(svg[:m, 1], h - 20.0 - height, atol=1e-3)
    assert svg[m - 1, 1] < svg[0, 1]
    np.testing.assert_allclose(svg[m:, 0][::-1] - svg[:m, 0], width, atol=1e-3)
    (line,) = root.findall(f"{space}line")
    y_line = h - 20.0 - np.interp(0.25, z, 1e3 * ds["pattern_height"].values)
    assert float(line.get("y1")) == pytest.approx(y_line, abs=1e-3)
    assert float(line.get("y2")) == pytest.approx(y_line, abs=1e-3)
    span = float(line.get("x2")) - float(line.get("x1"))
    assert span == pytest.approx(np.interp(h - 20.0 - y_line, height, width), abs=1e-3)


def test_pattern_cli_refuses_a_bad_format_and_writes_nothing(graded, tmp_path):
    folder, _ = graded
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "cloth",
            "pattern",
            str(folder / "out" / "result.nc"),
            "-o",
            str(tmp_path / "p.csv"),
            "--formats",
            "csv",
            "knitting",  # a knitting table of a two-panel cut
        ],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2 and "--formats" in done.stderr and "tube" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not list(tmp_path.iterdir())


def test_the_csv_and_svg_say_every_number_where_a_cutter_reads_it(graded, tmp_path):
    """The CSV's header and its row numbers, reductions and cut; the SVG's page (the outline
    with a 20 mm margin all round, centred), its girth line's label 2 mm right of the line's
    left end and 2 mm above it; the XML's declaration."""
    folder, ds = graded
    csv_path, svg_path = write_pattern(
        folder / "out" / "result.nc", tmp_path / "p.csv", "tube", formats=["csv", "svg"]
    )
    with csv_path.open() as handle:
        lines = [line for line in handle if line.startswith("#")]
        handle.seek(0)
        header = next(csv.reader(line for line in handle if not line.startswith("#")))
    # one comment line per girth line in the pattern: its name and cut height in m
    inside = [
        (str(n), float(z))
        for n, z in zip(ds["landmark"].values, ds["landmark_height"].values, strict=True)
        if ds["cut_height"].values[0] <= z <= ds["cut_height"].values[-1]
    ]
    assert inside and [line.split()[3] for line in lines] == [n for n, _ in inside]
    np.testing.assert_allclose([float(line.split()[4]) for line in lines], [z for _, z in inside])
    assert all(line.rstrip().endswith(" m") for line in lines)
    assert header == [
        "row",
        "pattern_height_mm",
        "cut_height_m",
        "rest_circumference_mm",
        "width_mm",
        "reduction",
        "cut",
    ]
    rows = _rows(csv_path)
    assert [int(r["row"]) for r in rows] == list(range(len(rows)))
    assert {r["cut"] for r in rows} == {"tube"}
    np.testing.assert_allclose(
        [float(r["reduction"]) for r in rows], ds["row_reduction"].values, atol=1e-6
    )
    np.testing.assert_allclose(
        [float(r["cut_height_m"]) for r in rows], ds["cut_height"].values, atol=1e-6
    )
    text = svg_path.read_text()
    assert text.startswith('<?xml version="1.0" encoding="UTF-8"?>')
    root = ET.fromstring(text)
    space = "{http://www.w3.org/2000/svg}"
    w, h = (float(root.get(k).removesuffix("mm")) for k in ("width", "height"))
    width = np.array([float(r["width_mm"]) for r in rows])
    height = np.array([float(r["pattern_height_mm"]) for r in rows])
    assert h == pytest.approx(height.max() + 40.0, abs=1e-3)
    points = root.find(f"{space}polygon").get("points").split()
    xy = np.array([[float(v) for v in p.split(",")] for p in points])
    assert xy[:, 0].min() == pytest.approx(20.0, abs=1e-3)  # the widest row: margin to margin
    assert xy[:, 0].max() == pytest.approx(w - 20.0, abs=1e-3)
    assert xy[:, 1].min() == pytest.approx(20.0, abs=1e-3)  # the top row: 20 mm down
    assert xy[:, 1].max() == pytest.approx(h - 20.0, abs=1e-3)
    (line,) = root.findall(f"{space}line")
    (label,) = root.findall(f"{space}text")
    assert line.get("stroke") == "red" and label.text == "waist"
    assert float(label.get("x")) == pytest.approx(float(line.get("x1")) + 2.0, abs=1e-3)
    assert float(label.get("y")) == pytest.approx(float(line.get("y1")) - 2.0, abs=1e-3)
    assert float(label.get("font-size")) == 8.0
    assert width.max() == pytest.approx(w - 40.0, abs=1e-3)


def test_a_line_at_the_garment_s_edge_is_drawn_and_a_bad_result_is_named(graded, tmp_path):
    from cloth.files.pattern import pattern_of

    _, ds = graded
    z = ds["cut_height"].values
    both = (
        ds.drop_dims("landmark")
        .assign_coords(landmark=["low", "high"])
        .assign(landmark_height=("landmark", [float(z[0]), float(z[-1])]))
    )
    pattern = pattern_of(both, "tube")
    assert [name for name, _ in pattern.lines] == ["low", "high"]
    heights = 1e3 * ds["pattern_height"].values
    assert [y for _, y in pattern.lines] == pytest.approx([heights[0], heights[-1]])
    with pytest.raises(InputError, match="unknown cut 'kilt'") as caught:
        pattern_of(ds, "kilt", "r.nc")
    assert caught.value.field == "--cut" and "two-panel, tube" in str(caught.value)
    assert str(caught.value.source) == "r.nc"
    old = pattern_of(ds.drop_vars("cut_height"), "tube")  # a result from before cut heights
    np.testing.assert_allclose(old.cut_height, ds["z"].values.mean(axis=1))
    with pytest.raises(InputError, match="no pattern_height") as caught:
        pattern_of(ds.drop_vars("pattern_height"), "tube", "r.nc")
    assert str(caught.value.source) == "r.nc"
    assert pattern_of(ds.drop_vars("row_reduction"), "tube").reduction is None


def test_write_pattern_refuses_an_unknown_format_naming_the_option(graded, tmp_path):
    folder, _ = graded
    with pytest.raises(InputError, match="unknown format 'pdf'; give some of csv, svg, dxf") as e:
        write_pattern(folder / "out" / "result.nc", tmp_path / "p.csv", formats=["csv", "pdf"])
    assert e.value.field == "--formats" and not list(tmp_path.iterdir())
    written = write_pattern(folder / "out" / "result.nc", tmp_path / "p.csv", formats=["csv"])
    assert written == [tmp_path / "p.csv"]
    assert {r["cut"] for r in _rows(written[0])} == {"two-panel"}  # the default cut


def test_dxf_without_ezdxf_is_refused_before_any_file(graded, tmp_path, monkeypatch):
    import cloth.files.pattern as pattern

    folder, ds = graded
    monkeypatch.setattr(pattern, "_ezdxf", lambda: None)
    with pytest.raises(InputError, match=r"DXF needs ezdxf: pip install 'cloth\[pattern\]'") as e:
        pattern.write_pattern(folder / "out" / "result.nc", tmp_path / "p.csv")
    assert e.value.field == "--formats" and not list(tmp_path.iterdir())
    assert pattern.write_pattern(
        folder / "out" / "result.nc", tmp_path / "p.csv", formats=["svg"]
    ) == [tmp_path / "p.svg"]
    stale = tmp_path / "stale.nc"
    ds.drop_vars("pattern_height").to_netcdf(stale)
    with pytest.raises(InputError, match="no pattern_height") as e:
        pattern.write_pattern(stale, tmp_path / "q.csv", formats=["csv"])
    assert str(e.value.source) == str(stale)


def test_a_shifted_pattern_s_girth_lines_are_where_its_rows_were_cut(tmp_path):
    """A result worn on a body 0.05 m taller than the one its rows were cut for (cut_height's
    ``shift``): its girth lines (worn heights) go back to the cut body's heights, interpolated
    on the pattern's heights; a line beyond the cut rows is left out, and the CSV's girth-line
    comments and its reduction column say so."""
    cut = np.array([0.80, 0.90, 1.00])
    result = xr.Dataset(
        {
            "rest_circumference": ("row", [0.70, 0.65, 0.72]),
            "pattern_height": ("row", [0.0, 0.1, 0.2]),
            "cut_height": ("row", cut, {"shift": 0.05}),
            "landmark_height": ("landmark", [0.90, 1.00, 1.10]),
        },
        coords={"landmark": ["low", "mid", "high"]},
    )
    pattern = pattern_of(result, "tube")
    assert [name for name, _ in pattern.lines] == ["low", "mid"]  # high: 1.05 m, past 1.00
    assert pattern.lines[0][1] == pytest.approx(50.0) and pattern.lines[1][1] == pytest.approx(
        150.0
    )
    assert pattern.line_heights == (("low", pytest.approx(0.85)), ("mid", pytest.approx(0.95)))
    assert pattern.reduction is None
    path = tmp_path / "p.csv"
    write_csv(pattern, path)
    text = path.read_text().splitlines()
    assert text[:2] == ["# girth line low 0.850000000 m", "# girth line mid 0.950000000 m"]
    rows = list(csv.DictReader(text[2:]))
    assert [r["reduction"] for r in rows] == ["", "", ""]  # no row reductions in the result
    lines = path.read_bytes().split(b"\n")[:-1]
    assert all(line.endswith(b"\r") for line in lines)  # one line ending: RFC 4180's CRLF
    unshifted = pattern_of(result.assign(cut_height=("row", cut)), "tube")
    assert [name for name, _ in unshifted.lines] == ["low", "mid"]
    assert unshifted.lines[0][1] == pytest.approx(100.0)


def test_a_result_without_cut_heights_places_its_lines_on_its_rows_heights():
    """A result from before cut heights: the rows' mean heights stand for them, unshifted."""
    result = xr.Dataset(
        {
            "rest_circumference": ("row", [0.70, 0.65, 0.72]),
            "pattern_height": ("row", [0.0, 0.1, 0.2]),
            "z": (("row", "col"), [[0.80, 0.80], [0.90, 0.90], [1.00, 1.00]]),
            "landmark_height": ("landmark", [0.85]),
        },
        coords={"landmark": ["low"]},
    )
    pattern = pattern_of(result, "two-panel")
    assert pattern.lines == (("low", pytest.approx(50.0)),)
    np.testing.assert_allclose(pattern.cut_height, [0.8, 0.9, 1.0])
    np.testing.assert_allclose(pattern.width, [350.0, 325.0, 360.0])  # half the girth
