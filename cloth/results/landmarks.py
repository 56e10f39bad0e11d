"""Landmarks: the girth lines a garment is judged on, and their summaries.

A landmark is a height on the body: the parametric torso's `cloth.bodies.torso.LANDMARKS` from
its size chart or the leg's measuring points, heights given in a case's ``landmarks``, or for
other bodies the rows where the hull girth has a prominent interior minimum or maximum
(`girth_extrema`: ``girth_min_N``, ``girth_max_N``, named where ``body.kind`` says what it is),
else the ``middle`` row.

Its summary (`Landmark`) is read on the body (`cloth.results.bands`): the mean pressure is the
contact force in a band of the body around the line's height over the band's area, the max and
min are a pressure probe's largest and smallest readings around the girth, the tension the
band's mean weft tension (N m-1); pressures in Pa, with mmHg, judged by
`cloth.results.judging`. The band and the probe are the case's ``girth_reading``
(`cloth.case.reading`). The fabric's rows move (issue 40: where the warp is slack they gather,
and the row values grew without converging), the body does not, so the band values converge
with the grid where the row values did not.

The row values stay as diagnostics (``row_mean``, ``row_max``, ``row_min``): each node quantity
interpolated linearly in height between the two rows around the line, column by column (along
the warp lines; `girth_line`, `along`), a line within half a row spacing beyond an edge row
taking that row. `LANDMARK_FIELDS` names the summaries in result.nc and sweep.nc that carry
error estimates; `ROW_FIELDS` the diagnostics.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from cloth.case.reading import Reading
from cloth.garment.grid import Grid
from cloth.results.bands import around, band_weights, probe_readings, weighted_mean
from cloth.results.pressure import MMHG


class NodeFields(Protocol):
    """What a landmark summary reads of the node fields (`cloth.results.fields.Fields`): (N,)
    pressure (Pa), on-body flag, weft tension (N m-1) and deformed node area (m2)."""

    pressure: NDArray[np.float64]
    on_body: NDArray[np.int8]
    tension_weft: NDArray[np.float64]
    area: NDArray[np.float64]


#: Girth-line summary variables: Landmark attribute, units, long name (result.nc, sweep.nc).
LANDMARK_FIELDS = {
    "pressure_mean": ("mean", "Pa", "mean pressure in the body band around the girth line"),
    "pressure_max": ("max", "Pa", "largest probe reading around the girth line"),
    "pressure_min": ("min", "Pa", "smallest probe reading around the girth line"),
    "tension_mean": ("tension", "N m-1", "mean weft tension in the band around the girth line"),
}
#: The row-based diagnostics (no error estimate): Landmark attribute, units, long name.
ROW_FIELDS = {
    "row_pressure_mean": ("row_mean", "Pa", "mean pressure along the fabric rows at the line"),
    "row_pressure_max": ("row_max", "Pa", "max pressure along the fabric rows at the line"),
    "row_pressure_min": ("row_min", "Pa", "min pressure along the fabric rows at the line"),
}


@dataclass(frozen=True)
class Landmark:
    """One girth line's summary (see the module docstring)."""

    name: str
    height: float  # m
    row: int
    mean: float  # Pa, the band's
    max: float  # Pa, the largest probe reading
    min: float  # Pa, the smallest probe reading
    tension: float  # N m-1, the band's mean weft tension
    row_mean: float = float("nan")  # Pa, the row diagnostics
    row_max: float = float("nan")
    row_min: float = float("nan")

    def record(self) -> dict[str, object]:
        """A summary row with Pa, kPa and mmHg (classes and bands: `cloth.results.judging`)."""
        return {
            "landmark": self.name,
            "height_m": self.height,
            "row": self.row,
            "pressure_mean_Pa": self.mean,
            "pressure_max_Pa": self.max,
            "pressure_min_Pa": self.min,
            "pressure_mean_kPa": self.mean / 1e3,
            "pressure_mean_mmHg": self.mean / MMHG,
            "pressure_max_mmHg": self.max / MMHG,
            "pressure_min_mmHg": self.min / MMHG,
            "tension_weft_mean_N_per_m": self.tension,
            "row_pressure_mean_Pa": self.row_mean,
        }


def nearest_row(rows_z: NDArray[np.float64], height: float) -> int | None:
    """The grid row ((m,) mean row heights, m) nearest ``height`` (m), or None when the height
    lies more than half the widest row spacing beyond the garment's edge rows."""
    half = 0.5 * float(np.max(np.abs(np.diff(rows_z)))) if len(rows_z) > 1 else 0.0
    if not rows_z.min() - half <= height <= rows_z.max() + half:
        return None
    return int(np.argmin(np.abs(rows_z - height)))


def girth_line(rows_z: NDArray[np.float64], height: float) -> tuple[int, int, float] | None:
    """Where the girth line at ``height`` (m) lies on a grid whose rows have the mean heights
    ``rows_z`` ((m,), m, bottom to top): the row below, the row above and the weight t of the
    upper, so that a node quantity q along the line is (1 - t) q[below] + t q[above], column by
    column (`along`). At or beyond an edge row (within `nearest_row`'s reach) the line is that
    row: (j, j, 0). None beyond the garment."""
    nearest = nearest_row(rows_z, height)
    if nearest is None:
        return None
    if height <= rows_z[0] or height >= rows_z[-1]:
        edge = 0 if height <= rows_z[0] else len(rows_z) - 1
        return edge, edge, 0.0
    above = int(np.searchsorted(rows_z, height, side="right"))
    below = above - 1
    if not (0 <= below < above < len(rows_z)) or rows_z[above] <= rows_z[below]:
        return nearest, nearest, 0.0  # rows out of height order: the nearest row
    return below, above, float((height - rows_z[below]) / (rows_z[above] - rows_z[below]))


def along(values: NDArray[np.float64], line: tuple[int, int, float]) -> NDArray[np.float64]:
    """A node quantity ((m, n): rows x columns) along a girth line (`girth_line`): (n,)."""
    below, above, t = line
    return (1.0 - t) * values[below] + t * values[above]


def contact_force(fields: NodeFields) -> NDArray[np.float64]:
    """(N,) N: each node's contact force f_i = p_i a_i, 0 off the body (what a band and a
    probe sum, `cloth.results.bands`)."""
    return np.where(fields.on_body.astype(bool), fields.pressure, 0.0) * fields.area


def landmarks(
    heights: dict[str, float],
    x: NDArray[np.float64],
    fields: NodeFields,
    grid: Grid,
    reading: Reading | None = None,
    half_widths: Mapping[str, float] | None = None,
) -> list[Landmark]:
    """The summary of the girth line at each landmark height (module docstring), bottom to
    top, read as ``reading`` says (default `Reading()`); a line beyond the garment (more than
    half a row spacing past its edge rows) has none. ``half_widths``: line name -> the half-width
    (m) of its band of the body where it is not the reading's (a garment's band,
    `band_half_widths`)."""
    reading = reading or Reading()
    half_widths = half_widths or {}
    rows_z = x.reshape(grid.m, grid.n, 3)[..., 2].mean(axis=1)
    pressure = np.where(fields.on_body.astype(bool), fields.pressure, 0.0)
    force = contact_force(fields)
    tension = np.nan_to_num(fields.tension_weft)
    angles = around(reading)
    out = []
    for name, height in sorted(heights.items(), key=lambda item: item[1]):
        line = girth_line(rows_z, height)
        if line is None:
            continue
        own = reading
        if name in half_widths:
            own = replace(reading, half_width=float(half_widths[name]))
        weight = band_weights(x[:, 2], (grid.m, grid.n), height, own).value
        probes = probe_readings(
            x, force, fields.area, height, angles, reading.probe_diameter, reading
        )
        rows = along(pressure.reshape(grid.m, grid.n), line)
        out.append(
            Landmark(
                name,
                float(height),
                nearest_row(rows_z, height),
                weighted_mean(force, fields.area, weight),
                float(np.nanmax(probes)) if np.isfinite(probes).any() else float("nan"),
                float(np.nanmin(probes)) if np.isfinite(probes).any() else float("nan"),
                weighted_mean(tension * fields.area, fields.area, weight),
                float(rows.mean()),
                float(rows.max()),
                float(rows.min()),
            )
        )
    return out


def sensor_readings(
    reading: Reading, x: NDArray[np.float64], fields: NodeFields
) -> NDArray[np.float64]:
    """(S,) Pa: what each of the case's sensors (`cloth.case.reading.Sensor`) reads
    (`cloth.results.bands.probe_readings`); NaN where its footprint holds no garment."""
    force = contact_force(fields)
    return np.array(
        [
            probe_readings(
                x, force, fields.area, s.height, np.array([s.angle]), s.diameter, reading
            )[0]
            for s in reading.sensors
        ]
    )


def landmark_heights(state) -> dict[str, float]:
    """A state's girth lines, name -> height (m): its body's (the torso's size chart), updated
    by the case's ``landmarks``, else the body's girth extrema (`girth_extrema`); and the lines
    of the garment's bands (`cloth.case.pieces.Pieces.band_lines`, on the wearer: shifted as the
    pattern is placed)."""
    heights = dict(state.body.get("landmarks", {}))
    heights.update(state.case.landmarks)
    heights = heights or girth_extrema(state)
    garment = state.case.garment
    shift = float(state.attrs.get("cut_shift", 0.0) or 0.0)
    lines = garment.pieces.band_lines(garment.bottom, garment.top)
    heights.update({name: z + shift for name, z in lines.items()})
    return heights


def band_half_widths(state) -> dict[str, float]:
    """Girth line name -> the half-width (m) of the body's band it is read over, where it is
    not the case's ``girth_reading``: a garment's band is read over its own width at most, so
    that its value is the band's, not the fabric's beside it."""
    half = state.case.reading.half_width
    return {b.name: min(half, 0.5 * b.width) for b in state.case.garment.pieces.bands}


#: A girth extremum is a landmark when it stands out of the profile by this share of the
#: median girth (find_peaks' prominence: 1 % is 9 mm on a 90 cm waist), ...
PROMINENCE = 0.01
#: ... and lies this far (m) from a more prominent one of its kind.
SEPARATION = 0.05


def girth_extrema(state) -> dict[str, float]:
    """Landmarks of a body without a size chart: the rows where the body's hull girth has a
    prominent interior minimum or maximum (`scipy.signal.find_peaks`: prominence at least
    `PROMINENCE` x the median girth, `SEPARATION` apart), ``girth_min_N`` / ``girth_max_N``
    bottom to top, else the middle row. A wiggle of a scan's girth (a few mm over a few cm) is
    not a landmark. Where the case says what the body is (``body.kind``), they are named
    (`anatomical`)."""
    raw = state.attrs.get("hull_girth", "[]")
    girth = np.asarray(json.loads(raw) if isinstance(raw, str) else raw, dtype=float)
    z = state.x.reshape(state.grid.m, state.grid.n, 3)[..., 2].mean(axis=1)
    out: dict[str, float] = {}
    if girth.size == state.grid.m and girth.size >= 3:
        from scipy.signal import find_peaks  # 0.8 s to import: only where it is needed

        spacing = max(float(np.median(np.abs(np.diff(z)))), 1e-12)
        options = {
            "prominence": PROMINENCE * float(np.median(girth)),
            "distance": max(1, round(SEPARATION / spacing)),
        }
        maxima = find_peaks(girth, **options)[0]
        minima = find_peaks(-girth, **options)[0]
        found = sorted([(int(j), "max") for j in maxima] + [(int(j), "min") for j in minima])
        for number, (j, kind) in enumerate(found, start=1):
            out[f"girth_{kind}_{number}"] = float(z[j])
    kind = state.case.body.option("kind") if hasattr(state, "case") else None
    if out and kind is not None:
        out = anatomical(out, kind)
    return out or {"middle": float(0.5 * (z.min() + z.max()))}


def anatomical(extrema: dict[str, float], kind: str) -> dict[str, float]:
    """Girth extrema (`girth_extrema`) named for the body ``kind``: on a torso the lowest
    minimum above a maximum is the waist, the maximum below it the hip and the one above it the
    bust; on a leg the lowest minimum is B (the ankle), the maximum above it C (the calf) and the
    minimum above that D (below the knee). Extrema without a name keep theirs."""
    order = sorted(extrema.items(), key=lambda item: item[1])
    kinds = [("max" if name.startswith("girth_max") else "min", name, z) for name, z in order]
    names: dict[str, str] = {}
    if kind == "torso":
        for k, (what, name, _) in enumerate(kinds):
            if what == "min" and any(w == "max" for w, _, _ in kinds[:k]):
                below = [n for w, n, _ in kinds[:k] if w == "max"]
                above = [n for w, n, _ in kinds[k + 1 :] if w == "max"]
                names.update({name: "waist", below[-1]: "hip"})
                if above:
                    names[above[0]] = "bust"
                break
    elif kind == "leg":
        wanted = iter([("min", "B"), ("max", "C"), ("min", "D")])
        step = next(wanted)
        for what, name, _ in kinds:
            if what == step[0]:
                names[name] = step[1]
                step = next(wanted, None)
                if step is None:
                    break
    return {names.get(name, name): z for name, z in order}
