"""Patterns a cutting room can use (issue 42): every size of a chart designed at once, the graded
nest in the AAMA / ASTM D6673 DXF convention read back with ezdxf, the 1:1 PDF measured in its
own units, and the stocking's knitting table.

The read-back checks numbers the design fixes independently of the writers: each piece's sew
line is as wide at each girth line as the confirmed result's rest circumference there (split by
the cut) to 0.1 mm, the cut line lies the seam allowance outside the sew line, and the check
square is 100 mm = 283.46 pt."""

from __future__ import annotations

import csv
import itertools
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from cloth.files.astm import LAYERS, distance_to, read_nest
from cloth.files.piece import NOTCH_MM
from tests.pdf import pdf_pages, squares

ezdxf = pytest.importorskip("ezdxf")

ROOT = Path(__file__).resolve().parents[1]
SIZES = ["S", "M", "L"]
TORSO_TARGETS = ["waist=10", "underbust=12"]
LEG_TARGETS = ["B=30", "C=21", "F=12"]
PT_PER_MM = 72.0 / 25.4


def _cloth(*args: str) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "cloth", "--log-level", "ERROR", *args]
    return subprocess.run(command, capture_output=True, text=True, cwd=ROOT)


def _design(folder: Path, body: dict, garment: dict, targets: list[str], *extra: str):
    case = {
        "material": "powernet",
        "body": body,
        "garment": {"error_estimate": False, **garment},
        "solver": {"method": "newton", "tolerance": 1.0e-8, "max_iterations": 150},
    }
    (folder / "case.yaml").write_text(yaml.safe_dump(case))
    done = _cloth(
        "design",
        str(folder / "case.yaml"),
        "--sizes",
        ",".join(SIZES),
        *[f"--target={t}" for t in targets],
        "-o",
        str(folder / "out"),
        *extra,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return folder / "out"


@pytest.fixture(scope="module")
def torso(tmp_path_factory) -> Path:
    """Torso S, M, L at CI size, two-panel cut, the default 6 mm seam allowance."""
    return _design(
        tmp_path_factory.mktemp("torso"),
        {"torso": {"size": "M", "around": 48, "rings": 30}},
        {"bottom": 0.9, "top": 1.15, "reduction": 0.15, "grid": [24, 8]},
        TORSO_TARGETS,
    )


@pytest.fixture(scope="module")
def stocking(tmp_path_factory) -> Path:
    """Leg S, M, L at CI size: a tube (the cut a leg takes by default), its knitting table."""
    return _design(
        tmp_path_factory.mktemp("leg"),
        {"leg": {"size": "M"}},
        {
            "bottom": 0.09,
            "top": 0.77,
            "reduction": 0.16,
            "grid": [16, 24],
            "edges": "sliding",
            "lengthwise_reduction": 0.15,
        },
        LEG_TARGETS,
    )


def _rows(path: Path) -> list[dict[str, str]]:
    """A written table's rows, its ``#`` comment lines (a pattern's girth lines) left out."""
    with path.open() as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def _lines(result: xr.Dataset) -> dict[str, tuple[float, float]]:
    """Per girth line on the garment: its pattern height (mm) and the rest circumference
    there (mm), from result.nc's rows: the design's own numbers."""
    cut = result["cut_height"].values
    height = 1e3 * result["pattern_height"].values
    circumference = 1e3 * result["rest_circumference"].values
    out = {}
    for name, z in zip(result["landmark"].values, result["landmark_height"].values, strict=True):
        if cut[0] <= z <= cut[-1]:
            y = float(np.interp(z, cut, height))
            out[str(name)] = (y, float(np.interp(y, height, circumference)))
    return out


def test_every_size_is_designed_warm_started_from_the_one_before(torso):
    rows = _rows(torso / "design_confirmed.csv")
    assert [(r["size"], r["landmark"]) for r in rows] == [
        (size, line) for size in SIZES for line in ("waist", "underbust")
    ]
    for row in rows:
        assert abs(float(row["confirmed_mmHg"]) - float(row["target_mmHg"])) <= 0.5
        decided = float(row["confirmed_error_mmHg"]) <= 0.5  # NaN: not decided (issue 54)
        assert (row["met"], row["verdict"]) == (
            ("1", "met") if decided else ("0", "grid cannot tell")
        )
    # each size after the first starts from the designed knots of the one before it
    for before, after in itertools.pairwise(SIZES):
        designed = yaml.safe_load((torso / before / "case.yaml").read_text())
        first = _rows(torso / after / "design_iterations.csv")[0]
        for knot, value in designed["garment"]["reduction"].items():
            assert float(first[f"reduction_{knot}"]) == pytest.approx(
                value, rel=1e-5
            )  # the CSV's 6 digits
    # a bigger body, the same pressures: a bigger reduction (Laplace: p ~ T / R at equal T
    # per unit length needs more strain on the flatter curve)
    waist = {r["size"]: float(r["reduction_waist"]) for r in rows}
    assert waist["S"] < waist["M"] < waist["L"]
    assert (torso / "design_reductions.png").stat().st_size > 0


def test_the_graded_nest_holds_every_piece_on_the_convention_s_layers(torso):
    nest = read_nest(torso / "pattern_astm.dxf")
    assert nest.errors == 0
    assert "Units: METRIC" in nest.header and "Sample Size: M" in nest.header
    assert set(nest.pieces) == {f"PANEL_{size}" for size in SIZES}
    doc = ezdxf.readfile(torso / "pattern_astm.dxf")
    assert doc.dxfversion == "AC1009"  # R12
    for block in doc.blocks:
        if not block.name.startswith("*"):
            assert {e.dxf.layer for e in block} <= set(LAYERS)
    for size in SIZES:
        piece = nest.pieces[f"PANEL_{size}"]
        assert piece.insert == (0.0, 0.0)  # nested on the grade point
        assert len(piece.cut) == 1 and len(piece.sew) == 1 and len(piece.grain) == 1
        assert len(piece.grade) == 1 and len(piece.turns) == 4
        assert piece.fields == {
            "Piece Name": "PANEL",
            "Size": size,
            "Quantity": "2",
            "Material": "power net 80/20 (illustrative)",
            "Seam Allowance": "6 mm",
        }
        assert "Annotation: pressure targets (mmHg): waist 10, underbust 12" in piece.notes
        (grain,) = piece.grain
        assert grain[0, 0] == grain[1, 0] == 0.0 and grain[1, 1] > grain[0, 1]  # the warp: up
        result = xr.load_dataset(torso / size / "confirmed" / "result.nc")
        lines = _lines(result)
        assert sorted(n for n in piece.notes if n in lines) == sorted(lines)
        assert len(piece.notches) == 2 * len(lines)  # one per girth line on each side seam
        assert len(piece.internal) == len(lines)
        # each girth line drawn level at its height across the sewn width, side seam to seam
        heights = sorted(y for y, _ in lines.values())
        drawn = sorted(piece.internal, key=lambda line: line[0][1])
        for line, y in zip(drawn, heights, strict=True):
            assert np.allclose(line[:, 1], y, atol=1e-6)
            assert np.ptp(line[:, 0]) == pytest.approx(piece.sew_width_at(y), abs=1e-6)
        # the turn points are the cut line's four corners: its lowest and highest vertices
        # at the left and the right side seam
        cut = piece.cut[0]
        corners = {
            (x > 0, y > np.mean(cut[:, 1]))
            for x, y in (np.asarray(t).ravel()[:2] for t in piece.turns)
        }
        assert corners == {(False, False), (False, True), (True, False), (True, True)}
        for turn in piece.turns:
            x, y = np.asarray(turn).ravel()[:2]
            assert np.min(np.hypot(cut[:, 0] - x, cut[:, 1] - y)) < 1e-9  # a vertex of the cut
            assert y in (pytest.approx(cut[:, 1].min()), pytest.approx(cut[:, 1].max()))


@pytest.mark.parametrize("allowance", [0.0, 6.0, 12.5])
def test_widths_at_the_girth_lines_are_the_design_s_and_the_allowance_lies_outside(
    torso, tmp_path, allowance
):
    results = [str(torso / size / "confirmed" / "result.nc") for size in SIZES]
    done = _cloth(
        "pattern",
        *results,
        "--sizes",
        ",".join(SIZES),
        "--formats",
        "astm",
        "--seam-allowance",
        str(allowance),
        "-o",
        str(tmp_path / "pattern.csv"),
    )
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pattern_astm.dxf"]
    nest = read_nest(tmp_path / "pattern_astm.dxf")
    assert nest.errors == 0
    for size in SIZES:
        piece = nest.pieces[f"PANEL_{size}"]
        lines = _lines(xr.load_dataset(torso / size / "confirmed" / "result.nc"))
        for _name, (y, circumference) in lines.items():
            assert piece.sew_width_at(y) == pytest.approx(0.5 * circumference, abs=0.1)
        cut, sew = piece.cut[0], piece.sew[0]
        if allowance == 0:
            np.testing.assert_allclose(cut, sew, atol=1e-9)
        else:
            # nowhere nearer than the allowance, and every sew edge's middle exactly there
            assert distance_to(sew, cut).min() == pytest.approx(allowance, abs=1e-6)
            middles = 0.5 * (sew + np.roll(sew, -1, axis=0))
            np.testing.assert_allclose(distance_to(cut, middles), allowance, atol=1e-6)
        depth = NOTCH_MM if allowance == 0 else min(NOTCH_MM, allowance)
        heights = sorted(y for y, _ in lines.values())
        for start, end in piece.notches:
            assert distance_to(cut, start[None])[0] == pytest.approx(0.0, abs=1e-6)
            assert np.linalg.norm(end - start) == pytest.approx(depth, abs=1e-9)
            assert abs(end[0]) < abs(start[0]) and end[1] == start[1]  # inward, level
            assert min(abs(start[1] - y) for y in heights) < 1e-9


@pytest.mark.parametrize(("paper", "box"), [("A4", (595.276, 841.890)), ("letter", (612, 792))])
def test_the_check_square_measures_100_mm_and_a_wide_piece_tiles(torso, tmp_path, paper, box):
    done = _cloth(
        "pattern",
        str(torso / "L" / "confirmed" / "result.nc"),
        "--formats",
        "pdf",
        "--paper",
        paper,
        "-o",
        str(tmp_path / "pattern.csv"),
    )
    assert done.returncode == 0, done.stderr
    boxes, streams = pdf_pages(tmp_path / "pattern.pdf")
    assert boxes[0][2:] == pytest.approx(box, abs=1e-2)  # the cover: portrait
    turned = tuple(reversed(box))
    assert all(p[2:] == pytest.approx(box, abs=1e-2) for p in boxes[1:]) or all(
        p[2:] == pytest.approx(turned, abs=1e-2) for p in boxes[1:]
    )
    sides = [side for stream in streams for side in squares(stream)]
    assert any(abs(side - 100.0 * PT_PER_MM) < 0.1 * PT_PER_MM for side in sides), sides
    # the panel is wider than the printable width: it tiles, one page per tile after the
    # cover, portrait or landscape, whichever takes fewer
    result = xr.load_dataset(torso / "L" / "confirmed" / "result.nc")
    margin = 2 * (6.0 + 5.0)  # the allowance and the clearance, both sides
    width = 0.5e3 * float(result["rest_circumference"].max()) + margin
    height = 1e3 * float(np.ptp(result["pattern_height"].values)) + margin

    def count(length: float, printable: float) -> int:
        return (
            1 if length <= printable else 1 + int(np.ceil((length - printable) / (printable - 15)))
        )

    page = [v / PT_PER_MM - 20.0 for v in box]
    assert width > page[0]
    portrait = count(width, page[0]) * count(height, page[1])
    landscape = count(width, page[1]) * count(height, page[0])
    assert len(boxes) == 1 + min(portrait, landscape)


def test_the_stocking_s_knitting_table_has_every_size_and_its_girth_points(stocking):
    rows = _rows(stocking / "pattern_knitting.csv")
    assert [r["size"] for r in rows] == sorted((r["size"] for r in rows), key=SIZES.index) and {
        r["size"] for r in rows
    } == set(SIZES)
    assert {r["piece"] for r in rows} == {"TUBE"}  # one tube each: a stocking of one piece
    nest = read_nest(stocking / "pattern_astm.dxf")
    assert set(nest.pieces) == {f"TUBE_{size}" for size in SIZES}
    assert {p.fields["Quantity"] for p in nest.pieces.values()} == {"1"}
    for size in SIZES:
        mine = [r for r in rows if r["size"] == size]
        result = xr.load_dataset(stocking / size / "confirmed" / "result.nc")
        height = 1e3 * result["pattern_height"].values
        heights = np.array([float(r["course_height_mm"]) for r in mine])
        assert [int(r["course"]) for r in mine] == list(range(len(mine)))
        np.testing.assert_allclose(np.diff(heights)[:-1], 5.0)
        assert heights[-1] == pytest.approx(height[-1] - height[0], abs=0.01)
        np.testing.assert_allclose(
            [float(r["rest_circumference_mm"]) for r in mine],
            np.interp(heights + height[0], height, 1e3 * result["rest_circumference"].values),
            atol=0.01,
        )
        # each course's body height is where the row at its pattern height was cut
        np.testing.assert_allclose(
            [float(r["body_height_m"]) for r in mine],
            np.interp(heights + height[0], height, result["cut_height"].values),
            atol=1e-5,
        )
        lines = _lines(result)
        marked = {r["girth_point"]: r for r in mine if r["girth_point"]}
        assert set(marked) == set(lines) and {"B", "C", "F"} <= set(marked)
        for name, row in marked.items():
            exact = lines[name][0] - height[0]
            assert float(row["girth_point_height_mm"]) == pytest.approx(exact, abs=0.01)
            assert abs(float(row["course_height_mm"]) - exact) <= 2.5 + 1e-9
    assert (stocking / "pattern_knitting.png").stat().st_size > 0


def _refused(folder: Path, body: dict, *args: str) -> str:
    """``cloth design`` of a case on ``body`` with ``args``: refused in one line, exit 2, no
    output folder; the line."""
    case = {
        "material": "powernet",
        "body": body,
        "garment": {"bottom": 0.1, "top": 0.3, "reduction": 0.15, "grid": [24, 8]},
    }
    (folder / "case.yaml").write_text(yaml.safe_dump(case))
    done = _cloth("design", str(folder / "case.yaml"), "-o", str(folder / "out"), *args)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1, done.stderr
    assert not (folder / "out").exists()
    return lines[0]


def test_a_size_not_in_the_chart_is_one_line_naming_the_chart_s_sizes(tmp_path):
    line = _refused(tmp_path, {"torso": {"size": "M"}}, "--sizes", "S,XL", "--target=waist=10")
    assert "size 'XL' is not in the chart" in line and "S, M, L" in line
    assert "size_chart.csv" in line and "--sizes" in line


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--sizes", "S,,L"], "size names separated by commas"),
        (["--sizes", "S,S"], "the size 'S' is given twice"),
        (["--seam-allowance", "-2"], "must be a length >= 0 in mm"),
        (["--seam-allowance", "nan"], "must be a length >= 0 in mm"),
    ],
)
def test_a_bad_chart_option_is_one_line(tmp_path, args, words):
    assert words in _refused(tmp_path, {"torso": {"size": "M"}}, "--target=waist=10", *args)


def test_sizes_need_a_chart_body(tmp_path):
    body = {"cylinder": {"radius": 0.1}}
    line = _refused(tmp_path, body, "--sizes", "S", "--target=middle=10")
    assert "parametric torso or leg" in line and "one case file per size" in line
