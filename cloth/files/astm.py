"""The graded nest as a pattern room's CAD loads it: DXF in the AAMA / ASTM D6673 convention
(Gerber AccuMark, Lectra Modaris, Optitex and CLO import it), written and read with ezdxf.

One BLOCK per piece and size, named ``{piece}_{size}``, inserted in model space at the origin:
every size is nested on the grade point (the bottom row's centre, `cloth.files.piece`). In each
block, on the convention's numbered layers:

* ``1``: the boundary (cut line), a closed POLYLINE, and the piece's annotation as TEXT
  (``Piece Name:``, ``Size:``, ``Quantity:``, ``Material:``, ``Seam Allowance:``);
* ``2``: turn points, a POINT at each corner of the cut line;
* ``4``: notches, a LINE from the cut line inward per girth line and side seam;
* ``5``: the grade reference line, the centre line from the grade point up;
* ``7``: the grain line, along the warp;
* ``8``: internal lines: the girth lines across the sew line, named by TEXT on ``15``;
* ``14``: the sew line, a closed POLYLINE;
* ``15``: annotation text: ``Annotation:`` notes (a design's pressure targets) and girth names.

Model space also holds the style's header text (``Style Name:``, ``Sample Size:``, ``Units:
METRIC``). DXF R12 (the release the convention's importers read), units mm, 7-bit ASCII text.
`read_nest` reads such a file back: its audit and per block the entities above.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType

import numpy as np
from numpy.typing import NDArray

from cloth import __version__
from cloth.errors import InputError
from cloth.files.piece import Piece, crossings
from cloth.io import atomic_output

log = logging.getLogger(__name__)

BOUNDARY, TURN, NOTCH, GRADE, GRAIN, INTERNAL, SEW, ANNOTATION = (
    "1",
    "2",
    "4",
    "5",
    "7",
    "8",
    "14",
    "15",
)
#: The convention's layers this file uses, by number, and what each holds.
LAYERS = {
    BOUNDARY: "boundary (cut line) and piece annotation",
    TURN: "turn points",
    NOTCH: "notches",
    GRADE: "grade reference line",
    GRAIN: "grain line",
    INTERNAL: "internal lines (girth lines)",
    SEW: "sew line",
    ANNOTATION: "annotation text",
}
#: Text height, mm.
TEXT_MM = 6.0
#: A cut line's vertex turning by more than this is a turn point, degrees.
TURN_DEGREES = 30.0


def ezdxf_module() -> ModuleType:
    """ezdxf, or an `InputError` naming the extra that installs it."""
    try:
        import ezdxf
    except ImportError:
        raise InputError(
            "the graded nest's DXF needs ezdxf: pip install 'cloth[pattern]', or leave out "
            "the format astm",
            field="--formats",
        ) from None
    # its set-up notes, and R12's note that it has no $INSUNITS, are not the user's concern
    logging.getLogger("ezdxf").setLevel(logging.ERROR)
    return ezdxf


def ascii_text(text: str) -> str:
    """``text`` in the 7-bit ASCII the convention allows ('?' for anything else)."""
    return text.encode("ascii", "replace").decode("ascii")


def write_nest(pieces: Sequence[Piece], path: Path, style: str, sample: str) -> Path:
    """The graded nest of ``pieces`` (module docstring) to ``path``; ``style`` names the
    pattern, ``sample`` its sample size."""
    names = [f"{p.name}_{p.size}" for p in pieces]
    if len(set(names)) != len(names):
        raise InputError("two pieces of the same name and size; give each size once", path)
    ezdxf = ezdxf_module()
    doc = ezdxf.new("R12")  # R12 has no $INSUNITS: the header text says "Units: METRIC" (mm)
    for number in LAYERS:
        doc.layers.add(number)
    space = doc.modelspace()
    for k, text in enumerate(
        (
            f"Style Name: {style}",
            f"Sample Size: {sample}",
            "Units: METRIC",
            f"Author: cloth {__version__}",
        )
    ):
        space.add_text(
            ascii_text(text),
            height=TEXT_MM,
            dxfattribs={"layer": ANNOTATION, "insert": (0.0, -30.0 - 10.0 * k)},
        )
    for piece, name in zip(pieces, names, strict=True):
        block = doc.blocks.new(name=ascii_text(name))
        _draw(block, piece)
        space.add_blockref(block.name, (0.0, 0.0))
    with atomic_output(path) as tmp:
        doc.saveas(tmp)
    log.info("wrote %s: %d pieces nested on the grade point", path, len(pieces))
    return path


def _draw(block, piece: Piece) -> None:
    block.add_polyline2d([tuple(p) for p in piece.cut], close=True, dxfattribs={"layer": BOUNDARY})
    for point in piece.cut[_turns(piece.cut)]:
        block.add_point(tuple(point), dxfattribs={"layer": TURN})
    block.add_polyline2d([tuple(p) for p in piece.sew], close=True, dxfattribs={"layer": SEW})
    for start, end in piece.notches:
        block.add_line(tuple(start), tuple(end), dxfattribs={"layer": NOTCH})
    top = float(piece.sew[:, 1].max())
    block.add_line((0.0, 0.0), (0.0, top), dxfattribs={"layer": GRADE})
    block.add_line(tuple(piece.grain[0]), tuple(piece.grain[1]), dxfattribs={"layer": GRAIN})
    for name, y, left, right in piece.girths:
        block.add_line((left, y), (right, y), dxfattribs={"layer": INTERNAL})
        block.add_text(
            ascii_text(name),
            height=TEXT_MM,
            dxfattribs={"layer": ANNOTATION, "insert": (left + 2.0 * TEXT_MM, y + 2.0)},
        )
    middle = 0.5 * top
    for k, text in enumerate(piece.annotation()):
        layer = ANNOTATION if text.startswith("Annotation:") else BOUNDARY
        block.add_text(
            ascii_text(text),
            height=TEXT_MM,
            dxfattribs={"layer": layer, "insert": (2.0 * TEXT_MM, middle - 1.6 * TEXT_MM * k)},
        )


def _turns(polygon: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(k,) bool: the closed polygon's vertices turning by more than `TURN_DEGREES`."""
    before = polygon - np.roll(polygon, 1, axis=0)
    after = np.roll(polygon, -1, axis=0) - polygon
    cross = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
    dot = np.einsum("ij,ij->i", before, after)
    return np.abs(np.degrees(np.arctan2(cross, dot))) > TURN_DEGREES


@dataclass
class NestPiece:
    """One block of a graded nest as read back (mm): its polylines, lines and texts by layer."""

    block: str
    insert: tuple[float, float] | None = None
    cut: list[NDArray[np.float64]] = field(default_factory=list)
    sew: list[NDArray[np.float64]] = field(default_factory=list)
    notches: list[NDArray[np.float64]] = field(default_factory=list)  # (2, 2) each
    grain: list[NDArray[np.float64]] = field(default_factory=list)
    grade: list[NDArray[np.float64]] = field(default_factory=list)
    internal: list[NDArray[np.float64]] = field(default_factory=list)
    turns: list[NDArray[np.float64]] = field(default_factory=list)
    fields: dict[str, str] = field(default_factory=dict)  # layer 1's "Key: value" texts
    notes: list[str] = field(default_factory=list)  # layer 15's texts

    def sew_width_at(self, y: float) -> float:
        """The sew line's width at height ``y``, mm."""
        xs = crossings(self.sew[0], y)
        return float(xs[-1] - xs[0])


@dataclass
class Nest:
    """A graded nest read back: the audit's error count, the header texts and the pieces."""

    errors: int
    header: list[str]
    pieces: dict[str, NestPiece]


def read_nest(path: str | Path) -> Nest:
    """The graded nest at ``path`` (module docstring), read and audited with ezdxf."""
    ezdxf = ezdxf_module()
    doc = ezdxf.readfile(str(path))
    auditor = doc.audit()
    pieces: dict[str, NestPiece] = {}
    for block in doc.blocks:
        if block.name.startswith("*") or block.name.startswith("$"):
            continue
        piece = NestPiece(block.name)
        polylines = {BOUNDARY: piece.cut, SEW: piece.sew}
        lines = {
            NOTCH: piece.notches,
            GRAIN: piece.grain,
            GRADE: piece.grade,
            INTERNAL: piece.internal,
        }
        for entity in block:
            layer, kind = entity.dxf.layer, entity.dxftype()
            if kind == "POLYLINE":
                points = np.array([(v.dxf.location.x, v.dxf.location.y) for v in entity.vertices])
                polylines.get(layer, []).append(points)
            elif kind == "LINE":
                start, end = entity.dxf.start, entity.dxf.end
                lines.get(layer, []).append(np.array([(start.x, start.y), (end.x, end.y)]))
            elif kind == "POINT" and layer == TURN:
                piece.turns.append(np.array([entity.dxf.location.x, entity.dxf.location.y]))
            elif kind == "TEXT":
                text = entity.dxf.text
                if layer == BOUNDARY and ":" in text:
                    key, value = text.split(":", 1)
                    piece.fields[key.strip()] = value.strip()
                elif layer == ANNOTATION:
                    piece.notes.append(text)
        pieces[block.name] = piece
    header = []
    for entity in doc.modelspace():
        if entity.dxftype() == "INSERT" and entity.dxf.name in pieces:
            insert = entity.dxf.insert
            pieces[entity.dxf.name].insert = (float(insert[0]), float(insert[1]))
        elif entity.dxftype() == "TEXT":
            header.append(entity.dxf.text)
    return Nest(len(auditor.errors), header, pieces)


def distance_to(polygon: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.float64]:
    """(p,) distances of ``points`` (p, 2) to the closed ``polygon`` (k, 2)'s edges, mm."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    edge = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", edge, edge), 1e-300)
    rel = points[:, None, :] - a[None, :, :]
    t = np.clip(np.einsum("pkj,kj->pk", rel, edge) / length2, 0.0, 1.0)
    nearest = a[None] + t[..., None] * edge[None]
    return np.sqrt(((points[:, None, :] - nearest) ** 2).sum(axis=2)).min(axis=1)
