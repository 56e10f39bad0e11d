"""A measured person as a one-row size chart (issue 62): the parametric leg or torso of her
measures, in the columns of the chart she is measured against.

A population (`cloth.files.population`) measures a few of a chart's girths (ANSUR II: the
ankle B, the calf C and the thigh G) and some heights. Her row is the template size's row
(``template``: the chart's row of the size nearest her, as given) with:

* every girth she has measured, hers;
* every other girth the template's times her measured-over-template ratio, interpolated
  linearly in height between her measured lines and held beyond them (a leg with a larger
  ankle and calf than the template's has a proportionally larger B1 between them);
* every height she has measured (``{point}_height``), hers; every other height of the row
  (``*_height_cm``: the girth lines', a torso chart's bottom and top) mapped
  piecewise linearly through the floor (0), her measured heights and her stature against the
  template's (her stature alone: the template's heights scaled by it);
* her stature where measured, else the template's;
* no ranges: she is one body.

Lengths in m in, cm in the row (the chart's units).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np


def _cells(row: Mapping[str, str], name: str) -> float | None:
    text = (row.get(name) or "").strip()
    return float(text) if text else None


def template_girths(
    row: Mapping[str, str], points: tuple[str, ...]
) -> tuple[dict[str, float], dict[str, float], float]:
    """The template ``row``'s girths and heights at ``points`` and its stature, m (a girth
    given as a range alone at the range's centre)."""
    girth, height = {}, {}
    for point in points:
        value = _cells(row, f"{point}_cm")
        if value is None:
            low, high = _cells(row, f"{point}_min_cm"), _cells(row, f"{point}_max_cm")
            value = 0.5 * (low + high) if low is not None and high is not None else None
        if value is not None:
            girth[point] = 0.01 * value
        h = _cells(row, f"{point}_height_cm")
        if h is not None:
            height[point] = 0.01 * h
    stature = _cells(row, "stature_cm")
    return girth, height, 0.01 * stature if stature is not None else float("nan")


def person_body(
    template: Mapping[str, str],
    points: tuple[str, ...],
    girths: Mapping[str, float],
    heights: Mapping[str, float],
    stature: float | None,
    name: str,
) -> dict[str, str]:
    """Her one-row chart (module docstring): ``template`` the chart's row, ``points`` the
    chart's girth lines bottom to top, her ``girths`` and ``heights`` (point -> m) and
    ``stature`` (m, or None), named ``name``."""
    t_girth, t_height, t_stature = template_girths(template, points)
    measured = [p for p in points if p in girths and p in t_girth and p in t_height]
    row = {k: v for k, v in template.items() if not k.endswith(("_min_cm", "_max_cm"))}
    row["size"] = name
    if measured:
        at = np.array([t_height[p] for p in measured])
        ratio = np.array([girths[p] / t_girth[p] for p in measured])
        for point in points:
            if point in t_girth and point in t_height:
                scale = girths[point] / t_girth[point] if point in girths else None
                if scale is None:
                    scale = float(np.interp(t_height[point], at, ratio))
                row[f"{point}_cm"] = f"{100 * t_girth[point] * scale:.6g}"
    her_stature = stature if stature is not None and np.isfinite(stature) else t_stature
    anchors = [(0.0, 0.0)]
    anchors += sorted((t_height[p], heights[p]) for p in points if p in heights and p in t_height)
    if np.isfinite(t_stature):
        anchors.append((t_stature, her_stature))
    kept = [anchors[0]]
    for pair in anchors[1:]:
        if pair[0] > kept[-1][0] and pair[1] > kept[-1][1]:
            kept.append(pair)
    if len(kept) > 1:
        xs, ys = np.array(kept).T
        slope = (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
        for column in [c for c in template if c.endswith("_height_cm")]:
            point = column.removesuffix("_height_cm")
            own = _cells(template, column)
            if point in heights:
                value = heights[point]
            elif own is None:
                continue
            elif 0.01 * own <= xs[-1]:
                value = float(np.interp(0.01 * own, xs, ys))
            else:
                value = ys[-1] + slope * (0.01 * own - xs[-1])
            row[column] = f"{100 * value:.6g}"
    if np.isfinite(her_stature):
        row["stature_cm"] = f"{100 * her_stature:.6g}"
    return row


__all__ = ["person_body", "template_girths"]
