"""Judging the girth-line summaries (`cloth.case.judge.Judge`): the compression class at the
class point, each point's graduation as a share of it, and the pressure bands.

Columns added to every summary row (each row gets the same columns, blank where they do not
apply):

* ``pressure_band``: the bands the mean pressure falls in (only when the case defines bands);
* where the lines include the class point (a stocking's B): ``compression_class`` (on the class
  point's row; '-' in no class), ``share_of_class_point`` (1: the line's mean over the class
  point's), ``graduation_low`` and ``graduation_high`` (1, the limits of the line's point) and
  ``graduation_met`` (1 inside them, 0 outside; blank for lines without limits).
"""

from __future__ import annotations

from cloth.case.judge import Judge


def judged(rows: list[dict[str, object]], judge: Judge) -> list[dict[str, object]]:
    """``rows`` (summary rows with ``landmark`` and ``pressure_mean_mmHg``) with the judge's
    columns (module docstring), new dicts in the same order."""
    out = [dict(row) for row in rows]
    if judge.bands:
        for row in out:
            row["pressure_band"] = judge.band(float(row["pressure_mean_mmHg"]))
    at = {str(row["landmark"]): float(row["pressure_mean_mmHg"]) for row in out}
    point = judge.class_point
    if point not in at:
        return out
    for row in out:
        name = str(row["landmark"])
        mmhg = float(row["pressure_mean_mmHg"])
        row["compression_class"] = judge.compression_class(mmhg) if name == point else ""
        row["share_of_class_point"] = mmhg / at[point] if at[point] > 0 else float("nan")
        limits = judge.graduation.get(name)
        row["graduation_low"] = "" if limits is None else limits[0]
        row["graduation_high"] = "" if limits is None else limits[1]
        share = row["share_of_class_point"]
        row["graduation_met"] = "" if limits is None else int(limits[0] <= share <= limits[1])
    return out
