"""A pattern piece as a cutting room takes it (issue 42): the sew line of a `Pattern`, its cut
line, notches, grain line, girth lines and annotation, all in mm on the flat pattern.

* **Sew line**: the pattern's outline (`Pattern.outline`): the rows' widths either side of the
  centre line, x across, y up, the grade point (0, 0) at the bottom row's centre.
* **Cut line**: the sew line offset outward by the seam allowance (``allowance``, mm; default
  `SEAM_ALLOWANCE_MM`, suited to the flatlock seams of compression garments), all round: the
  side seams, and the top and bottom edges, which take their hem or band: every edge moved out
  by exactly the allowance, mitred where two meet (`offset`). An allowance of 0 gives the net
  pattern: the cut line is the sew line.
* **Notches**: one per girth line on each side seam, a slit of `NOTCH_MM` (no deeper than the
  allowance) from the cut line inward, horizontal, at the girth line's height.
* **Grain line**: along the warp (y), on the centre line, over the middle 60 % of the height.
* **Girth lines**: across the sew line at their pattern heights, with their names.
* **Annotation**: piece name, size, quantity (a two-panel cut is 2: front and back cut alike; a
  tube 1), material, and notes (the pressure targets of a design).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from cloth.errors import InputError
from cloth.files.pattern import Pattern

#: Default seam allowance, mm: a flatlock seam butts or barely overlaps the panels' edges, and
#: a quarter inch is what its trimming knife leaves.
SEAM_ALLOWANCE_MM = 6.0
#: Depth of a notch's slit, mm (no deeper than the allowance where there is one).
NOTCH_MM = 3.0
#: Piece name and quantity per cut (`cloth.files.pattern.CUTS`).
PIECES = {"two-panel": ("PANEL", 2), "tube": ("TUBE", 1)}


@dataclass(frozen=True)
class Piece:
    """One piece of one size (module docstring); every coordinate in mm on the flat pattern.

    ``sew`` (k, 2) and ``cut`` (k', 2): closed polygons, counter-clockwise, end not repeated;
    ``notches``: (start on the cut line, end inward) pairs of (2,) points; ``grain``: (2, 2);
    ``girths``: (name, height, left x, right x) on the sew line."""

    name: str
    size: str
    quantity: int
    material: str
    allowance: float
    sew: NDArray[np.float64]
    cut: NDArray[np.float64]
    notches: tuple[tuple[NDArray[np.float64], NDArray[np.float64]], ...]
    grain: NDArray[np.float64]
    girths: tuple[tuple[str, float, float, float], ...]
    notes: tuple[str, ...]

    def annotation(self) -> list[str]:
        """The piece's annotation, one ``Key: value`` text per line."""
        return [
            f"Piece Name: {self.name}",
            f"Size: {self.size}",
            f"Quantity: {self.quantity}",
            f"Material: {self.material}",
            f"Seam Allowance: {self.allowance:g} mm",
            *(f"Annotation: {note}" for note in self.notes),
        ]


def crossings(polygon: NDArray[np.float64], y: float) -> NDArray[np.float64]:
    """Sorted x of the closed ``polygon`` (k, 2)'s edges at height ``y`` (a vertex at ``y``
    counts once per side it joins; horizontal edges at ``y`` give their ends)."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    xs = []
    for (x0, y0), (x1, y1) in zip(a, b, strict=True):
        if y0 == y1:
            if y0 == y:
                xs += [x0, x1]
            continue
        if min(y0, y1) <= y <= max(y0, y1):
            xs.append(x0 + (y - y0) * (x1 - x0) / (y1 - y0))
    return np.unique(np.round(np.asarray(xs, dtype=float), 9))


def offset(polygon: NDArray[np.float64], distance: float) -> NDArray[np.float64]:
    """The counter-clockwise ``polygon`` (k, 2) offset outward by ``distance`` (mm, >= 0): each
    edge moved out along its normal by exactly ``distance``, each vertex where its two moved
    edges meet (a mitre). `InputError` where the offset crosses itself (a concave curve tighter
    than the allowance)."""
    if distance == 0:
        return np.array(polygon, dtype=float)
    edge = np.roll(polygon, -1, axis=0) - polygon  # edge i: vertex i -> i + 1
    length = np.linalg.norm(edge, axis=1)
    keep = length > 1e-9 * max(1.0, float(length.max()))
    polygon, edge, length = polygon[keep], edge[keep], length[keep]
    normal = np.stack([edge[:, 1], -edge[:, 0]], axis=1) / length[:, None]  # outward (CCW)
    before = np.roll(normal, 1, axis=0)  # the edge into each vertex
    bisector = before + normal
    # the mitre: the point at distance d from both moved edges, on the bisector
    scale = distance / np.maximum(np.einsum("ij,ij->i", bisector, normal), 1e-12)
    grown = polygon + scale[:, None] * bisector
    moved = np.roll(grown, -1, axis=0) - grown
    if np.any(np.einsum("ij,ij->i", moved, edge) <= 0) or _crosses_itself(grown):
        raise InputError(
            f"the seam allowance of {distance:g} mm folds the cut line over itself (a concave "
            "curve of the sew line is tighter than that); give a smaller allowance",
            field="pattern.seam_allowance_mm",
        )
    return grown


def _crosses_itself(polygon: NDArray[np.float64]) -> bool:
    """Whether two non-adjacent edges of the closed ``polygon`` (k, 2) cross."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    k = len(polygon)

    def side(p, q, r):  # sign of the turn p -> q -> r, broadcast over edge pairs
        return np.sign(
            (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1])
            - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
        )

    i, j = np.triu_indices(k, 2)
    apart = (j - i) % k != k - 1  # the last and the first edge share a vertex
    i, j = i[apart], j[apart]
    crossing = (side(a[i], b[i], a[j]) * side(a[i], b[i], b[j]) < 0) & (
        side(a[j], b[j], a[i]) * side(a[j], b[j], b[i]) < 0
    )
    return bool(crossing.any())


def check_allowance(allowance: float) -> None:
    """`InputError` for a seam ``allowance`` (mm) that is negative or not finite."""
    if not (np.isfinite(allowance) and allowance >= 0):
        raise InputError(
            f"must be a length >= 0 in mm (0: the net pattern), got {allowance}",
            field="pattern.seam_allowance_mm",
        )


def piece_of(
    pattern: Pattern,
    size: str,
    material: str,
    allowance: float = SEAM_ALLOWANCE_MM,
    notes: Sequence[str] = (),
    name: str | None = None,
    quantity: int | None = None,
    edge_notches: Sequence[float] = (),
) -> Piece:
    """The piece of ``pattern`` for ``size`` (module docstring); `InputError` for a negative or
    non-finite allowance. ``name`` and ``quantity``: a piece of a garment of several
    (`cloth.files.garmentpieces`), in place of the cut's; ``edge_notches``: x (mm) of notches
    on its lower edge (where a band meets the panels' seams)."""
    check_allowance(allowance)
    own_name, own_quantity = PIECES[pattern.cut]
    name = own_name if name is None else name
    quantity = own_quantity if quantity is None else quantity
    sew = pattern.outline()
    if _signed_area(sew) < 0:
        sew = sew[::-1]
    cut = offset(sew, allowance)
    depth = NOTCH_MM if allowance == 0 else min(NOTCH_MM, allowance)
    notches = []
    girths = []
    for line, y in pattern.lines:
        half = 0.5 * pattern.width_at(y)
        girths.append((line, y, -half, half))
        xs = crossings(cut, y)
        left, right = float(xs[0]), float(xs[-1])
        notches.append((np.array([left, y]), np.array([left + depth, y])))
        notches.append((np.array([right, y]), np.array([right - depth, y])))
    lowest = float(cut[:, 1].min())
    for x in edge_notches:
        notches.append((np.array([x, lowest]), np.array([x, lowest + depth])))
    top = float(pattern.height.max())
    bottom = float(pattern.height.min())
    grain = np.array([[0.0, bottom + 0.2 * (top - bottom)], [0.0, bottom + 0.8 * (top - bottom)]])
    return Piece(
        name=name,
        size=size,
        quantity=quantity,
        material=material,
        allowance=float(allowance),
        sew=sew,
        cut=cut,
        notches=tuple(notches),
        grain=grain,
        girths=tuple(girths),
        notes=tuple(notes),
    )


def _signed_area(polygon: NDArray[np.float64]) -> float:
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
