"""The garment's pattern as cut, and its placement on the body that wears it (issue 52).

A garment is a pattern cut once: each row's rest circumference and the warp's rest coordinate,
as functions of the height the row was cut for (its *cut height*, in the frame of the body it
was cut for). Three sources (the case's ``garment`` block, docs/config.md):

* the case's own body (no ``pattern``): the graded pattern of `cloth.garment.predeform`, a
  reduction of the wearer's own girths, or one ``circumference`` (a rectangle): `BodyCut` on
  the wearer;
* ``pattern: {body: BLOCK}``: the same cut from another body, the one the size was cut for (a
  chart's body, an avatar), then worn unchanged by the case's body: `BodyCut` on that body;
* ``pattern: {file: pattern.csv}``: the rows of a pattern the tool wrote (``cloth pattern``),
  linear between its rows: `TableCut`.

**Placement.** A pattern is placed on its wearer by one girth line (``pattern.place``): the
pattern's line at the wearer's line, the cut heights shifted by the wearer's height of that line
minus the pattern's; the rows keep their rest lengths. By default the lowest girth line both
know (a torso's hip, a leg's B: where a garment pulled on from below comes to sit); ``none``
keeps the cut frame (a pattern on bodies without girth lines, such as cylinders). The choice is
logged. On the body it was cut for the shift is 0 and the rows are the ones a reduction gives on
that body, bit for bit (`BodyCut` computes them by the same code).
"""

from __future__ import annotations

import csv
import logging
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import Body, polygon_perimeter
from cloth.case import GarmentSpec
from cloth.case.profile import lengthwise_spans
from cloth.errors import InputError

log = logging.getLogger(__name__)

#: ``pattern.place`` that keeps the cut frame.
NO_PLACEMENT = "none"
#: The columns of a pattern file this module reads (`cloth.files.pattern.write_csv`).
PATTERN_COLUMNS = ("cut_height_m", "pattern_height_mm", "rest_circumference_mm")
#: The comment lines of a pattern file that give its girth lines: ``# girth line NAME H m``.
LINE_PREFIX = "# girth line "


@dataclass(frozen=True)
class Rows:
    """A pattern's rows at given cut heights (m of them).

    Attributes
    ----------
    circumference : (m,) float, m
        Rest circumference.
    rest_v : (m,) float, m
        Warp rest coordinate, 0 at the first row.
    reduction : (m,) float, 1, or None
        The reduction from the cut body's girth (a graded pattern), else None.
    cut_girth : (m,) float, m, or None
        The cut body's convex-hull girth at the rows (a `BodyCut`), else None.
    """

    circumference: NDArray[np.float64]
    rest_v: NDArray[np.float64]
    reduction: NDArray[np.float64] | None = None
    cut_girth: NDArray[np.float64] | None = None


@dataclass(frozen=True)
class BodyCut:
    """The graded (or rectangle) pattern of ``garment`` cut for ``body`` (module docstring).

    ``lines``: girth line -> height on ``body`` (m), the body's own (the placement's);
    ``extra``: the case's landmarks, which a reduction profile may name too."""

    body: Body
    garment: GarmentSpec
    lines: Mapping[str, float] = field(default_factory=dict)
    extra: Mapping[str, float] = field(default_factory=dict)

    def rows(
        self, heights: NDArray[np.float64], hull_girth: NDArray[np.float64], source: str
    ) -> Rows:
        """The rows at cut ``heights`` ((m,), m) whose convex-hull girths on ``body`` are
        ``hull_girth`` ((m,), m; `cloth.garment.predeform.row_girths`)."""
        garment = self.garment
        profile = garment.reduction_profile
        marks = {**self.lines, **self.extra}
        try:
            spans = lengthwise_spans(garment.lengthwise_profile, heights, marks)
            reduction = None
            if profile is not None:
                reduction = profile.evaluate(heights, marks)
                circumference = (1.0 - reduction) * hull_girth
            else:
                circumference = np.full(len(heights), float(garment.circumference))
        except InputError as exc:
            raise InputError(exc.detail, source, exc.field) from None
        rest_v = np.concatenate(([0.0], np.cumsum(spans)))
        return Rows(circumference, rest_v, reduction, hull_girth)


@dataclass(frozen=True)
class TableCut:
    """A pattern's rows read from a file (module docstring): (k,) cut heights (m, increasing),
    rest circumferences (m) and warp rest coordinates (m); ``lines`` name -> cut height (m)."""

    cut_height: NDArray[np.float64]
    circumference: NDArray[np.float64]
    rest_v: NDArray[np.float64]
    lines: Mapping[str, float] = field(default_factory=dict)
    path: str = "pattern.csv"

    def rows(self, heights: NDArray[np.float64], source: str) -> Rows:
        """The rows at cut ``heights`` ((m,), m): the file's own where they are its rows, else
        linear between them; `InputError` for heights past the pattern."""
        low, high = float(self.cut_height[0]), float(self.cut_height[-1])
        tolerance = 1e-9
        if heights[0] < low - tolerance or heights[-1] > high + tolerance:
            raise InputError(
                f"the garment's rows ({heights[0]:.6g}-{heights[-1]:.6g} m) run past the pattern "
                f"{self.path} (cut heights {low:.6g}-{high:.6g} m); give garment bottom and top "
                "within them",
                source,
                "garment.bottom",
            )
        if len(heights) == len(self.cut_height) and np.allclose(
            heights, self.cut_height, rtol=0.0, atol=tolerance
        ):
            return Rows(self.circumference.copy(), self.rest_v - self.rest_v[0])
        circumference = np.interp(heights, self.cut_height, self.circumference)
        rest_v = np.interp(heights, self.cut_height, self.rest_v)
        return Rows(circumference, rest_v - rest_v[0])

    def to_attr(self) -> dict:
        """The table as a JSON-ready mapping (a state's ``pattern_table`` attribute)."""
        return {
            "cut_height": self.cut_height.tolist(),
            "circumference": self.circumference.tolist(),
            "rest_v": self.rest_v.tolist(),
            "lines": dict(self.lines),
            "path": self.path,
        }

    @classmethod
    def from_attr(cls, data: Mapping) -> TableCut:
        return cls(
            np.asarray(data["cut_height"], dtype=float),
            np.asarray(data["circumference"], dtype=float),
            np.asarray(data["rest_v"], dtype=float),
            {str(k): float(v) for k, v in data.get("lines", {}).items()},
            str(data.get("path", "pattern.csv")),
        )


def read_pattern(path: str | Path) -> TableCut:
    """The pattern file ``path`` (``cloth pattern``'s CSV: `PATTERN_COLUMNS`, its girth lines
    in ``# girth line`` comments); one line naming the file and the column where it does not
    hold."""
    path = Path(path)
    if not path.is_file():
        raise InputError("pattern file not found; check the path", path, "garment.pattern.file")
    text = path.read_text()
    lines: dict[str, float] = {}
    body = []
    for number, line in enumerate(text.splitlines(), start=1):
        if line.startswith(LINE_PREFIX):
            parts = line[len(LINE_PREFIX) :].split()
            try:
                lines[parts[0]] = float(parts[1])
            except (IndexError, ValueError):
                raise InputError(
                    f"line {number}: expected '{LINE_PREFIX}NAME HEIGHT m', found {line!r}",
                    path,
                    "girth line",
                ) from None
        elif not line.lstrip().startswith("#") and line.strip():
            body.append(line)
    reader = csv.DictReader(body)
    columns = [c.strip() for c in reader.fieldnames or []]
    for column in PATTERN_COLUMNS:
        if column not in columns:
            raise InputError(
                f"no column {column}; a pattern file is the pattern.csv that cloth pattern writes",
                path,
                column,
            )
    values = {c: [] for c in PATTERN_COLUMNS}
    for number, row in enumerate(reader, start=2):
        for column in PATTERN_COLUMNS:
            try:
                values[column].append(float(row[column]))
            except (TypeError, ValueError):
                raise InputError(
                    f"row {number}: {row[column]!r} is not a number", path, column
                ) from None
    cut_height = np.asarray(values["cut_height_m"])
    circumference = 1e-3 * np.asarray(values["rest_circumference_mm"])
    rest_v = 1e-3 * np.asarray(values["pattern_height_mm"])
    if len(cut_height) < 2:
        raise InputError("a pattern needs at least 2 rows", path, "row")
    checks = (
        ("cut_height_m", np.diff(cut_height) > 0, "increase from row to row"),
        ("pattern_height_mm", np.diff(rest_v) > 0, "increase from row to row"),
        ("rest_circumference_mm", circumference > 0, "be positive"),
    )
    for column, ok, what in checks:
        if not np.all(ok) or not np.all(np.isfinite(values[column])):
            raise InputError(f"the values must be finite and {what}", path, column)
    return TableCut(cut_height, circumference, rest_v, lines, str(path))


def placement(
    place: str | None,
    pattern_lines: Mapping[str, float],
    wearer_lines: Mapping[str, float],
    source: str,
) -> tuple[str, float]:
    """The girth line a pattern is placed by and the shift (m) from cut heights to the wearer's
    (module docstring): ``place`` a line both know, `NO_PLACEMENT`, or None (the lowest line
    both know; none where they share none)."""
    shared = [name for name in pattern_lines if name in wearer_lines]
    if place == NO_PLACEMENT or (place is None and not shared):
        return NO_PLACEMENT, 0.0
    if place is None:
        place = min(shared, key=pattern_lines.__getitem__)
    if place not in shared:
        ours, theirs = ", ".join(pattern_lines) or "none", ", ".join(wearer_lines) or "none"
        raise InputError(
            f"girth line {place!r} is not on both the pattern (lines {ours}) and the wearer "
            f"(lines {theirs}); give one of {', '.join(shared) or NO_PLACEMENT}",
            source,
            "garment.pattern.place",
        )
    return place, float(wearer_lines[place]) - float(pattern_lines[place])


def cut_girths(hulls: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """(m,) float, m: the perimeters of the rows' convex hulls."""
    return np.array([polygon_perimeter(h) for h in hulls])


__all__ = [
    "LINE_PREFIX",
    "NO_PLACEMENT",
    "BodyCut",
    "Rows",
    "TableCut",
    "cut_girths",
    "placement",
    "read_pattern",
]
