"""The knitting table of a tube over a size chart (issue 42): what a circular-knitting room sets
per course for each size of a stocking.

Per size and course, bottom to top (``knitting.csv``):

* ``piece``: the tube: ``TUBE`` for a garment of one piece; for a garment of several
  (`cloth.files.garmentpieces`), ``BODY_TUBE`` or ``BODY_TUBE_k`` (the body between its bands)
  and ``BAND_name`` (each band's tube);

* ``course``: the course's number, 0 at the tube's bottom edge;
* ``course_height_mm``: its rest height on the tube from the bottom edge (the warp's rest
  coordinate, `cloth.files.pattern.Pattern.height`), every ``step`` mm (default `STEP_MM`) and
  the top edge;
* ``body_height_m``: the body height the course was cut for;
* ``rest_circumference_mm``: the tube's rest circumference there, linear between the grid's
  rows (the knitted tube's size before it is pulled on);
* ``girth_point``: the name of the girth line (measuring point) whose height is nearest this
  course, on that one course; blank elsewhere (two lines nearest one course: both, spaced);
* ``girth_point_height_mm``: that girth line's exact rest height from the bottom edge (the
  course is within half a step of it).

``knitting.png``: the graded tubes side by side, each laid flat (width half its
circumference), the girth points marked.
"""

from __future__ import annotations

import csv
import logging
from collections.abc import Mapping
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from cloth.errors import InputError
from cloth.figures.plots import save_figure
from cloth.files.pattern import Pattern
from cloth.io import atomic_output

log = logging.getLogger(__name__)

#: A tube's key: its size, or (size, piece) for a garment of several pieces.
Tube = str | tuple[str, str]
#: The piece of a garment's one tube.
TUBE = "TUBE"
#: Default course step, mm.
STEP_MM = 5.0
COLUMNS = [
    "size",
    "piece",
    "course",
    "course_height_mm",
    "body_height_m",
    "rest_circumference_mm",
    "girth_point",
    "girth_point_height_mm",
]


def check_step(step: float) -> None:
    """`InputError` for a course step that is not a finite length > 0 (mm)."""
    if not (np.isfinite(step) and step > 0):
        raise InputError(f"must be a length > 0 in mm, got {step}", field="--course-step")


def course_heights(pattern: Pattern, step: float) -> np.ndarray:
    """(c,) mm: the courses' rest heights from the bottom edge, every ``step`` and the top."""
    check_step(step)
    bottom, top = float(pattern.height[0]), float(pattern.height[-1])
    heights = np.arange(0.0, top - bottom, step)
    return np.append(heights, top - bottom)


def knitting_rows(patterns: Mapping[Tube, Pattern], step: float = STEP_MM) -> list[dict]:
    """The table's rows (module docstring) for each tube of ``patterns``: by size name (the
    garment's one tube), or by (size, piece) for a garment of several pieces (its body's and
    its bands' tubes, `cloth.files.garmentpieces`)."""
    rows = []
    for key, pattern in patterns.items():
        size, piece = key if isinstance(key, tuple) else (key, TUBE)
        heights = course_heights(pattern, step)
        at = pattern.height[0] + heights
        circumference = np.interp(at, pattern.height, pattern.circumference)
        body = np.interp(at, pattern.height, pattern.cut_height)
        marks: dict[int, list[tuple[str, float]]] = {}
        for name, y in pattern.lines:
            marks.setdefault(int(np.argmin(np.abs(at - y))), []).append((name, y - at[0]))
        for k in range(len(heights)):
            here = marks.get(k, [])
            rows.append(
                {
                    "size": size,
                    "piece": piece,
                    "course": k,
                    "course_height_mm": f"{heights[k]:.2f}",
                    "body_height_m": f"{body[k]:.5f}",
                    "rest_circumference_mm": f"{circumference[k]:.2f}",
                    "girth_point": " ".join(name for name, _ in here),
                    "girth_point_height_mm": " ".join(f"{y:.2f}" for _, y in here),
                }
            )
    return rows


def write_knitting(
    patterns: Mapping[Tube, Pattern], csv_path: Path, png_path: Path, step: float = STEP_MM
) -> list[Path]:
    """``knitting.csv`` and ``knitting.png`` (module docstring) of the tubes ``patterns``
    (`cloth.stages.patterns.check_formats` refuses another cut before any file)."""
    with atomic_output(csv_path) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(knitting_rows(patterns, step))
    log.info("wrote %s", csv_path)
    return [csv_path, plot_tubes(patterns, png_path)]


def plot_tubes(patterns: Mapping[Tube, Pattern], path: Path) -> Path:
    """The tubes laid flat side by side at one scale, girth points marked, mm."""
    fig, ax = plt.subplots(figsize=(2.0 + 1.6 * len(patterns), 6.0), layout="constrained")
    gap = 0.25 * max(float(p.circumference.max()) for p in patterns.values())
    x = 0.0
    for size, pattern in patterns.items():
        half = 0.25 * pattern.circumference  # lay-flat width / 2
        y = pattern.height - pattern.height[0]
        centre = x + float(half.max())
        ax.fill_betweenx(y, centre - half, centre + half, color="tab:blue", alpha=0.25)
        ax.plot(centre - half, y, color="tab:blue", linewidth=0.8)
        ax.plot(centre + half, y, color="tab:blue", linewidth=0.8)
        for name, line in pattern.lines:
            w = 0.25 * float(np.interp(line, pattern.height, pattern.circumference))
            h = line - pattern.height[0]
            ax.plot([centre - w, centre + w], [h, h], color="tab:red", linewidth=0.8)
            ax.annotate(
                name, (centre + w, h), xytext=(2, 0), textcoords="offset points", fontsize=7
            )
        label = " ".join(size) if isinstance(size, tuple) else size
        ax.text(centre, -0.04 * float(y[-1]), label, ha="center", va="top")
        x = centre + float(half.max()) + gap
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_ylabel("course height from the bottom edge [mm]")
    ax.set_title("graded tubes laid flat (width = half the rest circumference)", fontsize=10)
    return save_figure(fig, path)
