"""The cut pattern of a result (``cloth pattern``): a CSV table and the flat outline as SVG and DXF.

From ``result.nc`` (`cloth.files.result.pattern_variables`), per row j, bottom to top:

* ``pattern_height_mm``: the rest warp coordinate v_j, the row's height on the flat pattern;
* ``cut_height_m``: the body height the row was cut for;
* ``rest_circumference_mm``: the row's rest circumference;
* ``width_mm``: the flat pattern's width there, half the circumference for a two-panel cut
  (``--cut two-panel``, the default: front and back panels sewn at the sides) or all of it for
  a tube knitted or cut in one (``--cut tube``, opened along the centre back);
* ``reduction``: the row's reduction from the body's girth (blank for a rectangle).

Before the table, one comment line per girth line within the pattern: ``# girth line NAME
HEIGHT m``, its cut height. A case wears the file as its garment (``garment.pattern.file``,
`cloth.garment.cut`), placed by these lines; readers of the table skip lines starting ``#``.

The outline is the polygon through the rows' half widths either side of a vertical centre
line, at 1:1 in mm (x across, y up, origin at the bottom row's centre). Each girth line of the
result is drawn across it at its pattern height (its body height mapped through the rows'
cut heights) and labelled with its name. The SVG's ``width``, ``height`` and ``viewBox`` are in
mm; the DXF (R2010, units mm, written with ezdxf, the optional extra ``pattern``) holds the
outline as a closed LWPOLYLINE on layer ``OUTLINE``, the girth lines as LINEs on ``GIRTH`` and
their labels as TEXT on ``LABELS``.
"""

from __future__ import annotations

import csv
import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.garment.cut import LINE_PREFIX
from cloth.io import atomic_output, read_netcdf

log = logging.getLogger(__name__)

CUTS = {"two-panel": 0.5, "tube": 1.0}
FORMATS = ("csv", "svg", "dxf")
#: Text height of the girth-line labels, mm.
LABEL_MM = 8.0


@dataclass(frozen=True)
class Pattern:
    """A flat pattern, rows bottom to top: heights and widths in mm (module docstring)."""

    height: NDArray[np.float64]  # (m,) mm, on the flat pattern
    width: NDArray[np.float64]  # (m,) mm
    circumference: NDArray[np.float64]  # (m,) mm
    cut_height: NDArray[np.float64]  # (m,) m on the body
    reduction: NDArray[np.float64] | None  # (m,) 1
    lines: tuple[tuple[str, float], ...]  # girth line name, height on the pattern in mm
    cut: str
    #: girth line name, its cut height (m on the body the rows were cut for)
    line_heights: tuple[tuple[str, float], ...] = ()

    def outline(self) -> NDArray[np.float64]:
        """(2m, 2) float, mm: the closed outline, up the left side and down the right."""
        half = 0.5 * self.width
        left = np.stack([-half, self.height], axis=1)
        right = np.stack([half, self.height], axis=1)[::-1]
        return np.concatenate([left, right])

    def width_at(self, height: float) -> float:
        return float(np.interp(height, self.height, self.width))


def pattern_of(result: xr.Dataset, cut: str, source: str | Path = "result.nc") -> Pattern:
    """The pattern of a result (``cut``: a key of `CUTS`); `InputError` for a result without
    the pattern's variables (written before they existed: re-run aggregate)."""
    if cut not in CUTS:
        raise InputError(f"unknown cut {cut!r}; give one of {', '.join(CUTS)}", source, "--cut")
    missing = [k for k in ("rest_circumference", "pattern_height") if k not in result]
    if missing:
        raise InputError(
            f"no {missing[0]}: the result predates cut patterns; re-run cloth aggregate",
            source,
        )
    circumference = 1e3 * result["rest_circumference"].values
    height = 1e3 * result["pattern_height"].values
    cut_height = (
        result["cut_height"].values if "cut_height" in result else result["z"].values.mean(axis=1)
    )
    shift = float(result["cut_height"].attrs.get("shift", 0.0)) if "cut_height" in result else 0.0
    lines, line_heights = [], []
    if "landmark" in result.coords:
        for name, worn_z in zip(
            result["landmark"].values, result["landmark_height"].values, strict=True
        ):
            z = float(worn_z) - shift  # on the body the rows were cut for
            if cut_height[0] <= z <= cut_height[-1]:
                lines.append((str(name), float(np.interp(z, cut_height, height))))
                line_heights.append((str(name), z))
    reduction = result["row_reduction"].values if "row_reduction" in result else None
    return Pattern(
        height=height,
        width=CUTS[cut] * circumference,
        circumference=circumference,
        cut_height=cut_height,
        reduction=reduction,
        lines=tuple(lines),
        cut=cut,
        line_heights=tuple(line_heights),
    )


def write_csv(
    pattern: Pattern, path: Path, columns: Mapping[str, Sequence[str]] | None = None
) -> Path:
    """The table (module docstring), after one comment line per girth line, ``# girth line NAME
    HEIGHT m`` (its cut height), which a case's ``garment.pattern.file`` places the pattern by
    (`cloth.garment.cut.read_pattern`). ``columns``: more columns by name, a text per row (a
    garment of several pieces' `cloth.files.garmentpieces.pattern_columns`)."""
    columns = dict(columns or {})
    with atomic_output(path) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.writer(handle)  # RFC 4180's CRLF, the comment lines' too
        for name, z in pattern.line_heights:
            handle.write(f"{LINE_PREFIX}{name} {z:.9f} m{writer.dialect.lineterminator}")
        writer.writerow(
            [
                "row",
                "pattern_height_mm",
                "cut_height_m",
                "rest_circumference_mm",
                "width_mm",
                "reduction",
                "cut",
                *columns,
            ]
        )
        for j in range(len(pattern.height)):
            reduction = "" if pattern.reduction is None else f"{pattern.reduction[j]:.6f}"
            writer.writerow(
                [
                    j,
                    f"{pattern.height[j]:.4f}",
                    f"{pattern.cut_height[j]:.9f}",
                    f"{pattern.circumference[j]:.4f}",
                    f"{pattern.width[j]:.4f}",
                    reduction,
                    pattern.cut,
                    *(values[j] for values in columns.values()),
                ]
            )
    return path


def write_svg(pattern: Pattern, path: Path) -> Path:
    """The outline at 1:1 in mm, a margin of 20 mm, y up (flipped into SVG's y down)."""
    margin = 20.0
    outline = pattern.outline()
    width = float(pattern.width.max()) + 2 * margin
    height = float(pattern.height.max()) + 2 * margin
    x0 = 0.5 * width

    def at(x: float, y: float) -> str:
        return f"{x0 + x:.3f},{height - margin - y:.3f}"

    points = " ".join(at(x, y) for x, y in outline)
    parts = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.3f}mm" height="{height:.3f}mm" '
        f'viewBox="0 0 {width:.3f} {height:.3f}">',
        f"<title>cloth pattern ({escape(pattern.cut)}), 1:1 in mm</title>",
        f'<polygon id="outline" points="{points}" fill="none" stroke="black" stroke-width="0.5"/>',
    ]
    for name, y in pattern.lines:
        half = 0.5 * pattern.width_at(y)
        left, right = at(-half, y).split(","), at(half, y).split(",")
        parts.append(
            f'<line class="girth" x1="{left[0]}" y1="{left[1]}" x2="{right[0]}" y2="{right[1]}" '
            'stroke="red" stroke-width="0.3" stroke-dasharray="4 2"/>'
        )
        label = at(-half + 2.0, y + 2.0).split(",")
        parts.append(
            f'<text x="{label[0]}" y="{label[1]}" font-size="{LABEL_MM}" '
            f'font-family="sans-serif">{escape(name)}</text>'
        )
    parts.append("</svg>")
    with atomic_output(path) as tmp:
        tmp.write_text("\n".join(parts) + "\n")
    return path


def write_dxf(pattern: Pattern, path: Path) -> Path:
    ezdxf = _ezdxf()
    logging.getLogger("ezdxf").setLevel(logging.WARNING)  # its set-up notes are not ours
    doc = ezdxf.new("R2010", setup=True)
    doc.units = ezdxf.units.MM
    for layer, colour in (("OUTLINE", 7), ("GIRTH", 1), ("LABELS", 3)):
        doc.layers.add(layer, color=colour)
    space = doc.modelspace()
    space.add_lwpolyline(
        [tuple(p) for p in pattern.outline()], close=True, dxfattribs={"layer": "OUTLINE"}
    )
    for name, y in pattern.lines:
        half = 0.5 * pattern.width_at(y)
        space.add_line((-half, y), (half, y), dxfattribs={"layer": "GIRTH"})
        space.add_text(
            name, height=LABEL_MM, dxfattribs={"layer": "LABELS", "insert": (-half + 2.0, y + 2.0)}
        )
    with atomic_output(path) as tmp:
        doc.saveas(tmp)
    return path


def _ezdxf():
    try:
        import ezdxf
    except ImportError:
        return None
    return ezdxf


WRITERS = {"csv": write_csv, "svg": write_svg, "dxf": write_dxf}


def write_pattern(
    result: str | Path,
    output: str | Path,
    cut: str = "two-panel",
    formats: Sequence[str] = FORMATS,
) -> list[Path]:
    """``result.nc`` -> the pattern beside ``output``: ``output`` with each format's suffix
    (``pattern.csv`` -> pattern.csv, pattern.svg, pattern.dxf). Checks every input before it
    writes: an unknown format, or DXF without ezdxf, is an `InputError` and nothing is written."""
    output = Path(output)
    unknown = [f for f in formats if f not in WRITERS]
    if unknown:
        raise InputError(
            f"unknown format {unknown[0]!r}; give some of {', '.join(FORMATS)}", field="--formats"
        )
    if "dxf" in formats and _ezdxf() is None:
        raise InputError(
            "DXF needs ezdxf: pip install 'cloth[pattern]', or pass --formats csv svg",
            field="--formats",
        )
    pattern = pattern_of(read_netcdf(result, "result"), cut, result)
    written = [WRITERS[f](pattern, output.with_suffix(f".{f}")) for f in formats]
    for path in written:
        log.info("wrote %s", path)
    return written
