"""The files of ``cloth sizes`` (issue 62): sizes.csv, fabric_requirement.csv, the knitting
table and sizes.png, from what `cloth.stages.sizes.design_sizes` found.

``sizes.csv``, one row per size (docs/outputs.md, "Designing a size chart"):

* ``size``; ``{measure}_min_cm`` and ``{measure}_max_cm`` per sizing measure (the chart's
  names: B for the ankle), limits included;
* ``people`` (the population's people in its ranges) and ``share`` (their weight's share of
  the people the chart was designed for, 0-1), ``fit_share`` (the share who fit it);
* per target line: ``{line}_rest_circumference_cm`` (the pattern's row there);
  ``{line}_min_mmHg`` and ``{line}_max_mmHg`` (the fast model's lowest and highest over the
  people who fit) with ``{line}_min_who`` and ``{line}_max_who`` (their ids);
  ``{line}_confirmed_min_mmHg`` and ``{line}_confirmed_max_mmHg`` (the equilibria's, over the
  extreme wearers) with ``{line}_confirmed_min_who`` and ``{line}_confirmed_max_who`` (the
  wearer's run, then her id) and ``{line}_confirmed_error_mmHg`` (the largest stated
  discretisation error among them);
* ``confirmed`` (1 where every confirmation converged and is inside every band), ``recut``
  (how many times the size was recut from its confirmations, `cloth.results.recut`; 0 as
  searched), ``grid_tells`` (1 where every confirmation's stated error is within
  max(1 %, 0.1 mmHg)).

``fast_model.csv``, one row per target line: the fast model the chart was searched with
(`cloth.results.tubemodel`): ``line``, ``hoop``, ``constant_Pa``, per shape feature
``{feature}_Pa_per_std`` (its coefficient, Pa per standard deviation) and ``{feature}_std``
(that standard deviation over the people, 1), ``equilibria`` (how many it was fitted to) and
``rms_error_mmHg`` (its rms error on them).

``fabric_requirement.csv``, one row per size of the chart asked for (`cloth.results.fabricneed`):
``size``, ``{measure}_min_cm``, ``{measure}_max_cm``, ``strain_min``, ``strain_max``,
``rest_circumference_cm``, ``tension_floor_N_per_m``, ``tension_roof_N_per_m``,
``linear_modulus_N_per_m``; where the case's fabric is cut, ``fabric_rest_circumference_cm``,
``fabric_strain_min``, ``fabric_strain_max`` and its tension at them,
``fabric_tension_min_N_per_m`` and ``fabric_tension_max_N_per_m``; ``fabric_holds`` (0 or 1).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from cloth.errors import InputError
from cloth.pipeline.sweep import write_rows
from cloth.results.fabricneed import Need, requirement
from cloth.results.pressure import MMHG
from cloth.results.sizechart import offset_range
from cloth.stages.sizeruns import confirmed
from cloth.stages.sizes import Outcome, shortfall_of

log = logging.getLogger(__name__)

#: The grid's accuracy criterion (docs/validation.md): max(1 %, 0.1 mmHg).
CRITERION = (0.01, 0.1 * MMHG)


def _within(value: float, error: float) -> bool:
    return np.isfinite(error) and error <= max(CRITERION[0] * abs(value), CRITERION[1])


def size_rows(outcome: Outcome) -> tuple[list[dict[str, object]], list[str]]:
    """sizes.csv's rows and header (module docstring)."""
    sizing, chart = outcome.sizing, outcome.chart
    ids = sizing.people.ids
    weight = sizing.people.weight
    total = float(weight[chart.people].sum())
    header = ["size"]
    for m in chart.measures:
        header += [f"{m}_min_cm", f"{m}_max_cm"]
    header += ["people", "share", "fit_share"]
    for line in sizing.lines:
        header += [
            f"{line}_rest_circumference_cm",
            f"{line}_min_mmHg",
            f"{line}_min_who",
            f"{line}_max_mmHg",
            f"{line}_max_who",
            f"{line}_confirmed_min_mmHg",
            f"{line}_confirmed_min_who",
            f"{line}_confirmed_max_mmHg",
            f"{line}_confirmed_max_who",
            f"{line}_confirmed_error_mmHg",
        ]
    header += ["confirmed", "recut", "grid_tells"]
    rows = []
    for confirmation in outcome.confirmations:
        size = confirmation.size
        row: dict[str, object] = {"size": size.name}
        for m in chart.measures:
            low, high = size.ranges.get(m, (np.nan, np.nan))
            row[f"{m}_min_cm"], row[f"{m}_max_cm"] = 100 * low, 100 * high
        row["people"] = len(size.members)
        row["share"] = float(weight[size.members].sum()) / total if total else 0.0
        row["fit_share"] = float(weight[size.members[size.fits]].sum()) / total if total else 0.0
        fitted = size.members[size.fits] if size.fits.any() else size.members
        tells = bool(confirmation.runs)
        for line in sizing.lines:
            rest = size.rest[line]
            row[f"{line}_rest_circumference_cm"] = 100 * rest
            if len(fitted):
                bend = outcome.models[line].calibration.offset(sizing.features[line][fitted])
                p = size.pressure(outcome.models, line, sizing.girths[line][fitted], bend) / MMHG
                lo, hi = int(np.argmin(p)), int(np.argmax(p))
                row[f"{line}_min_mmHg"], row[f"{line}_min_who"] = float(p[lo]), ids[fitted[lo]]
                row[f"{line}_max_mmHg"], row[f"{line}_max_who"] = float(p[hi]), ids[fitted[hi]]
            runs = [r for r in confirmation.runs if np.isfinite(r.pressure.get(line, np.nan))]
            if runs:
                low_run = min(runs, key=lambda r: r.pressure[line])
                high_run = max(runs, key=lambda r: r.pressure[line])
                who = {n: ids[p] for n, p in confirmation.wearers.items()}
                row[f"{line}_confirmed_min_mmHg"] = low_run.pressure[line] / MMHG
                row[f"{line}_confirmed_min_who"] = f"{low_run.name}: {who[low_run.name]}"
                row[f"{line}_confirmed_max_mmHg"] = high_run.pressure[line] / MMHG
                row[f"{line}_confirmed_max_who"] = f"{high_run.name}: {who[high_run.name]}"
                errors = [r.error.get(line, np.nan) for r in runs]
                row[f"{line}_confirmed_error_mmHg"] = (
                    float(np.nanmax(errors)) / MMHG if np.isfinite(errors).any() else float("nan")
                )
                tells &= all(_within(r.pressure[line], r.error.get(line, np.nan)) for r in runs)
        row["confirmed"] = int(confirmed(confirmation, sizing.bands))
        row["recut"] = size.recuts
        row["grid_tells"] = int(tells)
        rows.append(row)
    return rows, header


def needs_of(outcome: Outcome) -> list[Need]:
    """The chart asked for and its sizes' needs at the primary line (`requirement`)."""
    sizing, request = outcome.sizing, outcome.sizing.request
    primary = request.by[0]
    people = outcome.chart.people
    weight = sizing.people.weight[people]
    offsets = outcome.models[primary].calibration.offset(sizing.features[primary])
    return requirement(
        sizing.girths[primary][people],
        weight,
        outcome.models[primary],
        sizing.bands[primary],
        request.coverage,
        request.max_sizes,
        offset_range(offsets[people], weight, request.coverage),
    )


def need_rows(outcome: Outcome, needs: list[Need]) -> tuple[list[dict[str, object]], list[str]]:
    """fabric_requirement.csv's rows and header (module docstring)."""
    primary = outcome.sizing.request.by[0]
    header = [
        "size",
        f"{primary}_min_cm",
        f"{primary}_max_cm",
        "strain_min",
        "strain_max",
        "rest_circumference_cm",
        "tension_floor_N_per_m",
        "tension_roof_N_per_m",
        "linear_modulus_N_per_m",
        "fabric_rest_circumference_cm",
        "fabric_strain_min",
        "fabric_strain_max",
        "fabric_tension_min_N_per_m",
        "fabric_tension_max_N_per_m",
        "fabric_holds",
    ]
    rows = []
    for k, need in enumerate(needs):
        rows.append(
            {
                "size": f"R{k + 1}",
                f"{primary}_min_cm": 100 * need.low,
                f"{primary}_max_cm": 100 * need.high,
                "strain_min": need.strain_min,
                "strain_max": need.strain_max,
                "rest_circumference_cm": 100 * need.rest,
                "tension_floor_N_per_m": need.tension_floor,
                "tension_roof_N_per_m": need.tension_roof,
                "linear_modulus_N_per_m": need.linear_modulus,
                "fabric_rest_circumference_cm": 100 * need.fabric_rest,
                "fabric_strain_min": need.fabric_window[0],
                "fabric_strain_max": need.fabric_window[1],
                "fabric_tension_min_N_per_m": need.fabric_tension[0],
                "fabric_tension_max_N_per_m": need.fabric_tension[1],
                "fabric_holds": int(need.fabric_holds),
            }
        )
    return rows, header


def _places(outcome: Outcome, size) -> np.ndarray:
    """Each member of ``size``: 0 inside every band, 1 below one, 2 above one (the fast
    model's; `cloth.figures.sizes.KINDS`)."""
    sizing = outcome.sizing
    below = np.zeros(len(size.members), dtype=bool)
    above = np.zeros(len(size.members), dtype=bool)
    for line, band in sizing.bands.items():
        model = outcome.models[line]
        offset = model.calibration.offset(sizing.features[line][size.members])
        p = size.pressure(outcome.models, line, sizing.girths[line][size.members], offset)
        below |= p < band.low - 1e-9 * band.high
        above |= p > band.high * (1 + 1e-9)
    return np.where(size.fits, 0, np.where(below, 1, 2))


def corridors(needs: list[Need], count: int = 20):
    """sizes.png's third panel: each needed size's corridor where the case's fabric is cut
    (`cloth.results.fabricneed`, "The case's fabric"), over its strain window there at
    ``count`` strains (`cloth.figures.sizes.Corridor`)."""
    from cloth.figures.sizes import Corridor  # late: matplotlib

    out = []
    for need in needs:
        strain = np.linspace(*need.fabric_window, count)
        floor, roof = need.corridor(strain, need.fabric_rest)
        out.append(Corridor(strain, floor, roof, need.fabric_holds))
    return out


def figure(outcome: Outcome, needs: list[Need], path: Path) -> Path:
    """sizes.png (`cloth.figures.sizes`) from the outcome and the needed sizes."""
    from cloth.figures.sizes import SizeBox, plot_sizes  # late: matplotlib

    sizing, chart = outcome.sizing, outcome.chart
    primary = chart.measures[0]
    model = outcome.models[primary]
    band = sizing.bands[primary]
    people = chart.people
    kind = np.full(len(sizing.people.weight), 3)  # in no size (`cloth.figures.sizes.KINDS`)
    boxes = []
    offsets = model.calibration.offset(sizing.features[primary][people])
    ends = offset_range(offsets, sizing.people.weight[people], chart.shape_share)
    for c in outcome.confirmations:
        kind[c.size.members] = _places(outcome, c.size)
        points = [
            (r.girth[primary], r.pressure.get(primary, np.nan), r.error.get(primary, np.nan))
            for r in c.runs
        ]

        def span(g, size=c.size):
            models = outcome.models
            return np.stack([size.pressure(models, primary, g, end) for end in ends])

        boxes.append(SizeBox(c.size.name, c.size.ranges, span, points))
    values = {m: sizing.girths[m][people] for m in chart.measures}
    return plot_sizes(
        chart.measures,
        values,
        kind[people],
        boxes,
        (band.low, band.high),
        corridors(needs),
        model.tension,
        path,
    )


def model_rows(outcome: Outcome) -> tuple[list[dict[str, object]], list[str]]:
    """fast_model.csv's rows and header (module docstring)."""
    sizing = outcome.sizing
    errors = sizing.errors(outcome.models)
    rows, header = [], ["line", "hoop", "constant_Pa", "equilibria", "rms_error_mmHg"]
    for line in sizing.lines:
        calibration = outcome.models[line].calibration
        row: dict[str, object] = {
            "line": line,
            "hoop": calibration.hoop,
            "constant_Pa": float(calibration.shape[0]),
            "equilibria": len(sizing.calibration[line][2]),
            "rms_error_mmHg": errors[line] / MMHG,
        }
        names = sizing.feature_names[line]
        for name, value, spread in zip(
            names, calibration.shape[1:], sizing.feature_spreads[line], strict=True
        ):
            row[f"{name}_Pa_per_std"] = float(value)
            row[f"{name}_std"] = float(spread)
            header += [c for c in (f"{name}_Pa_per_std", f"{name}_std") if c not in header]
        rows.append(row)
    return rows, header


def write_sizes(outcome: Outcome, output: Path, fail: bool = True) -> dict[str, Path]:
    """sizes.csv, fabric_requirement.csv and sizes.png into ``output``; their paths. Then,
    where a size is not confirmed, `InputError` with `cloth.stages.sizes.shortfall_of`'s line
    (the command's exit status 2; the files stay written, that size's ``confirmed`` 0); with
    ``fail`` False (``--report-unmet``, the pipeline's size charts) a warning of it."""
    rows, header = size_rows(outcome)
    needs = needs_of(outcome)
    need_table, need_header = need_rows(outcome, needs)
    paths = {
        "sizes": write_rows(rows, output / "sizes.csv", header),
        "fabric_requirement": write_rows(
            need_table, output / "fabric_requirement.csv", need_header
        ),
    }
    fast_rows, fast_header = model_rows(outcome)
    paths["fast_model"] = write_rows(fast_rows, output / "fast_model.csv", fast_header)
    paths["figure"] = figure(outcome, needs, output / "sizes.png")
    log.info(
        "wrote %s: %d sizes cover %.1f %% (asked %.1f %%), %d confirmed, %d recut",
        output,
        len(rows),
        100 * outcome.chart.coverage,
        100 * outcome.sizing.request.coverage,
        sum(int(r["confirmed"]) for r in rows),
        sum(1 for r in rows if int(str(r["recut"])) > 0),
    )
    missing = shortfall_of(outcome)
    if missing is not None and fail:
        raise InputError(missing, outcome.sizing.case_path, "--target")
    if missing is not None:
        log.warning("%s", missing)
    return paths


__all__ = ["CRITERION", "need_rows", "needs_of", "size_rows", "write_sizes"]
