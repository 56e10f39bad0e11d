"""``cloth pattern RESULT [RESULT ...] -o pattern.csv``: the cut pattern of one result, or of
every size of a chart (one result per size), in the files a cutting room uses (issue 42).

Formats (``--formats``; default all that apply: ``knitting`` for a tube only):

* ``csv``, ``svg``, ``dxf``: the plain table and outline of `cloth.files.pattern`, per size;
* ``astm``: the graded nest, every size in one DXF in the AAMA / ASTM D6673 convention
  (`cloth.files.astm`), each piece with its cut line (the sew line offset by the seam
  allowance), sew line, notches, grain line and annotation;
* ``pdf``: each size's piece at 1:1 with a 10 cm check square, tiled on A4 or letter where it
  does not fit one page (`cloth.files.printout`);
* ``knitting``: a tube's knitting table over the sizes and its figure (`cloth.files.knitting`).

Files, beside ``output`` (``pattern.csv`` here): with one result ``pattern.csv``, ``.svg``,
``.dxf`` and ``pattern.pdf``; with several, ``pattern_{size}.csv`` etc. per size; always one
``pattern_astm.dxf`` and, for a tube, ``pattern_knitting.csv`` and ``pattern_knitting.png``.

A garment of several fabrics (bands, panels, layers; `cloth.files.garmentpieces`) is cut as
several pieces: ``pattern.csv`` stays the whole garment's rows (a case can wear it), and
``pattern_pieces.csv`` gives every piece's rows, cut length and width; the SVG and DXF show
the pieces side by side on one sheet (`cloth.files.piecesheet`); each piece has its own 1:1
PDF (``pattern_{PIECE}.pdf``) and its own block per size in the nest; the knitting table
covers the body's and the bands' tubes.

A size is named by ``sizes``, else by the result's parametric body (its chart size), else
``sample``. Every input is checked before a file is written.
"""

from __future__ import annotations

import importlib.util
import json
import logging
from collections.abc import Sequence
from pathlib import Path

import xarray as xr

from cloth.errors import InputError
from cloth.files.astm import write_nest
from cloth.files.garmentpieces import COLUMNS as PIECE_COLUMNS
from cloth.files.garmentpieces import (
    PiecePattern,
    garment_pieces,
    pattern_columns,
    piece_rows,
)
from cloth.files.knitting import STEP_MM, check_step, write_knitting
from cloth.files.pattern import CUTS, Pattern, pattern_of, write_csv, write_dxf, write_svg
from cloth.files.piece import SEAM_ALLOWANCE_MM, Piece, check_allowance, piece_of
from cloth.files.piecesheet import write_sheet_dxf, write_sheet_svg
from cloth.files.printout import sheet, write_pdf
from cloth.io import read_netcdf
from cloth.pipeline.sweep import write_rows

log = logging.getLogger(__name__)

FORMATS = ("csv", "svg", "dxf", "astm", "pdf", "knitting")
PLAIN = {"csv": write_csv, "svg": write_svg, "dxf": write_dxf}
#: The formats that draw the pieces' cut lines (their seam allowance): the others are tables.
DRAWN = frozenset({"svg", "dxf", "astm", "pdf"})
#: The Python packages each format needs beyond the dependencies, and the extra with them.
NEEDS = {"dxf": ("ezdxf",), "astm": ("ezdxf",)}


def size_name(result: xr.Dataset) -> str:
    """The chart size of the result's parametric body (torso or leg), else ``sample``."""
    try:
        body = json.loads(str(result.attrs.get("case", "{}"))).get("body", {})
    except json.JSONDecodeError:
        return "sample"
    for kind in ("torso", "leg"):
        if isinstance(body.get(kind), dict) and "size" in body[kind]:
            return str(body[kind]["size"])
    return "sample"


def default_formats(cut: str) -> list[str]:
    """The formats that apply to ``cut`` and whose packages are installed."""
    out = []
    for name in FORMATS:
        if name == "knitting" and cut != "tube":
            continue
        needs = NEEDS.get(name, ())
        if all(importlib.util.find_spec(package) for package in needs):
            out.append(name)
    return out


def check_formats(formats: Sequence[str], cut: str) -> None:
    """`InputError` for an unknown format, a format whose package is missing, or a knitting
    table of a cut that is not a tube."""
    unknown = [f for f in formats if f not in FORMATS]
    if unknown:
        raise InputError(
            f"unknown format {unknown[0]!r}; give some of {', '.join(FORMATS)}", field="--formats"
        )
    for name in formats:
        needs = NEEDS.get(name, ())
        missing = [p for p in needs if importlib.util.find_spec(p) is None]
        if missing:
            raise InputError(
                f"the format {name} needs {missing[0]}: pip install 'cloth[pattern]', or leave "
                f"{name} out of --formats",
                field="--formats",
            )
    if "knitting" in formats and cut != "tube":
        raise InputError(
            "the knitting table is for a tube: give --cut tube, or leave out the format knitting",
            field="--formats",
        )


def write_patterns(
    results: Sequence[str | Path],
    output: str | Path,
    cut: str = "two-panel",
    formats: Sequence[str] | None = None,
    sizes: Sequence[str] | None = None,
    allowance: float = SEAM_ALLOWANCE_MM,
    paper: str = "A4",
    notes: Sequence[str] = (),
    step: float = STEP_MM,
    style: str | None = None,
) -> list[Path]:
    """The pattern files of ``results`` (module docstring), one result per size (``sizes``
    names them, in order); every input checked before the first file is written."""
    output = Path(output)
    results = [Path(r) for r in results]
    if not results:
        raise InputError("give at least one result.nc", field="result")
    if cut not in CUTS:
        raise InputError(f"unknown cut {cut!r}; give one of {', '.join(CUTS)}", field="--cut")
    sheet(paper)  # an unknown paper refused before any file
    formats = default_formats(cut) if formats is None else list(formats)
    check_formats(formats, cut)
    datasets = [read_netcdf(r, "result") for r in results]
    if sizes is None:
        sizes = [size_name(d) for d in datasets]
    sizes = [str(s) for s in sizes]
    if len(sizes) != len(results):
        raise InputError(
            f"{len(sizes)} size names for {len(results)} results; give one per result",
            field="--sizes",
        )
    if len(set(sizes)) != len(sizes):
        repeated = next(s for s in sizes if sizes.count(s) > 1)
        raise InputError(
            f"the size {repeated!r} is named twice; name each result's size once (--sizes)",
            field="--sizes",
        )
    patterns = {
        size: pattern_of(data, cut, path)
        for size, data, path in zip(sizes, datasets, results, strict=True)
    }
    if "knitting" in formats:
        check_step(step)  # refused before any file
    material = str(datasets[0].attrs.get("fabric_name", "fabric"))
    several = {
        size: garment_pieces(data, patterns[size])
        for size, data in zip(sizes, datasets, strict=True)
    }
    check_allowance(allowance)
    drawn = bool(DRAWN & set(formats))  # a table alone (csv, knitting) cuts no piece
    pieces = {
        size: _pieces(pattern, several[size], size, material, allowance, notes) if drawn else []
        for size, pattern in patterns.items()
    }
    one = len(results) == 1
    written: list[Path] = []
    for (size, pattern), data in zip(patterns.items(), datasets, strict=True):
        stem = output.stem if one else f"{output.stem}_{size}"
        written += _size_files(
            data, pattern, pieces[size], several[size], formats, output, stem, paper
        )
    if "astm" in formats:
        nest = output.with_name(f"{output.stem}_astm.dxf")
        written.append(
            write_nest(
                [piece for size in sizes for piece in pieces[size]],
                nest,
                style or output.parent.name,
                sizes[len(sizes) // 2],
            )
        )
    if "knitting" in formats:
        tubes = {}  # a garment of several pieces: its knitted tubes, the body and the bands
        for size in sizes:
            if not several[size]:
                tubes[size] = patterns[size]
            for part in several[size]:
                if part.kind in ("body", "band"):
                    tubes[size, part.name] = part.pattern
        written += write_knitting(
            tubes,
            output.with_name(f"{output.stem}_knitting.csv"),
            output.with_name(f"{output.stem}_knitting.png"),
            step,
        )
    return written


def _pieces(
    pattern: Pattern,
    several: list[PiecePattern],
    size: str,
    material: str,
    allowance: float,
    notes: Sequence[str],
) -> list[Piece]:
    """One size's pieces with their cut lines: the garment's one piece, or each of its
    ``several`` (a garment of several fabrics)."""
    if not several:
        return [piece_of(pattern, size, material, allowance, notes)]
    return [
        piece_of(
            part.pattern,
            size,
            part.material,
            allowance,
            notes,
            name=part.name,
            quantity=part.quantity,
            edge_notches=part.notches_x,
        )
        for part in several
    ]


def _size_files(
    data: xr.Dataset,
    pattern: Pattern,
    pieces: list[Piece],
    several: list[PiecePattern],
    formats: Sequence[str],
    output: Path,
    stem: str,
    paper: str,
) -> list[Path]:
    """One size's files: the table, outline and 1:1 PDF of its one piece; for a garment of
    several pieces (``several``), the whole garment's table, every piece's rows
    (``{stem}_pieces.csv``), the pieces on one sheet (SVG, DXF) and a 1:1 PDF per piece."""
    written: list[Path] = []
    for name in formats:
        if name == "csv":
            columns = pattern_columns(data, pattern)
            written.append(write_csv(pattern, output.with_name(f"{stem}.csv"), columns))
            if several:
                written.append(
                    write_rows(
                        piece_rows(several),
                        output.with_name(f"{stem}_pieces.csv"),
                        list(PIECE_COLUMNS),
                    )
                )
        elif name in PLAIN:
            target = output.with_name(f"{stem}.{name}")
            if several:
                sheet_writer = write_sheet_svg if name == "svg" else write_sheet_dxf
                written.append(sheet_writer(pieces, target))
            else:
                written.append(PLAIN[name](pattern, target))
    if "pdf" in formats:
        for piece in pieces:
            suffix = f"_{piece.name}" if several else ""
            written.append(write_pdf(piece, output.with_name(f"{stem}{suffix}.pdf"), paper))
    for path in written:
        log.info("wrote %s", path)
    return written
