"""The uniform design answer met (issue 52, item 7): the confirmation iterated by a secant.

design.csv interpolates the sweep linearly between two swept reductions; its interval holds
the discretisation error only, so a confirmation can miss the target by more than it states
(torso M, 20 mmHg at the waist: 19.74 confirmed, -1.3 %, stated 0.05 mmHg). Here each
answered target whose confirmation misses by more than the confirmation's stated error is run
again at a corrected reduction: first r + (target - p) / slope (the sweep's slope at the
answer, design.csv's ``slope_Pa``), then the secant through the last two confirmations, at most
`MAX_STEPS` times, each a full case run from scratch (its case.yaml beside the confirmation's
result.nc, the reduction changed) into ``folder/{case}/step{k}/``.

design_confirmed.csv gets per row: ``secant_steps``; ``final_reduction``, ``final_mmHg`` and
``final_error_mmHg`` (the last confirmation and its stated error); ``met`` (1 where the final
value is within its stated error of the target); ``interpolation_error`` (1, in reduction: the
final miss over the slope) and ``reduction_error_total`` (design.csv's interval plus it); and
``how``: ``confirmed`` (the first confirmation already within its stated error), ``secant`` (met
after the steps), ``interval`` (not met: read the answer with ``reduction_error_total``),
``no estimate`` (the confirmation states no error: nothing to meet) or ``not converged`` (the
last confirmation's relaxation stopped short of its tolerance: its value is no equilibrium's,
so nothing is met, whatever it reads). A confirmation that did not converge is never within
its error: the secant goes on from it. (Before, the stocking's design on the avatar leg S said
"met" on a confirmation and a step that had both stalled at a residual of 4.7e-3.)
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

from cloth.case.case import load_case
from cloth.files.casefile import write_case
from cloth.io import read_netcdf
from cloth.pipeline.sweep import mean_error
from cloth.results.pressure import MMHG
from cloth.stages.case import run_case

log = logging.getLogger(__name__)

#: Secant steps (full confirmations) at most per target.
MAX_STEPS = 3


def _read(path: Path, landmark: str) -> tuple[float, float, bool]:
    """The line's mean pressure (Pa), its stated error (Pa) and whether the relaxation
    converged, from a confirmation's result.nc."""
    ds = read_netcdf(path, "result", ("pressure_mean",))
    value = float(ds["pressure_mean"].sel(landmark=landmark))
    error = float(mean_error(ds).sel(landmark=landmark))
    return value, error, bool(int(ds.attrs.get("converged", 0)))


def _within(value: float, error: float, settled: bool, goal: float) -> bool:
    """Whether a confirmation meets ``goal`` (Pa): converged, and ``value`` within its stated
    ``error`` of it (Pa; NaN never meets)."""
    return settled and abs(value - goal) <= error


def next_reduction(history: list[tuple[float, float]], goal: float, slope: float) -> float:
    """The next reduction (1) toward the pressure ``goal`` (Pa) from ``history`` ((reduction,
    pressure) pairs, the last the latest): the slope's step from one, the secant's from two."""
    (r1, p1) = history[-1]
    if len(history) >= 2:
        r0, p0 = history[-2]
        if p1 != p0:
            slope = (p1 - p0) / (r1 - r0)
    return r1 + (goal - p1) / slope


def iterate_row(row: dict, result: Path, folder: Path) -> dict[str, object]:
    """The secant columns (module docstring) of one confirmed design row."""
    goal = float(row["target_Pa"])
    slope = float(row.get("slope_Pa", "nan") or "nan")
    reduction = float(row["reduction"])
    value, error, settled = _read(result, row["landmark"])
    history = [(reduction, value)]
    how = "confirmed"
    case_path = result.parent / "case.yaml"
    steps = 0
    if not math.isfinite(error):
        how = "no estimate"
    elif not _within(value, error, settled, goal):
        how = "interval"
        while (
            steps < MAX_STEPS
            and not _within(value, error, settled, goal)
            and case_path.is_file()
            and math.isfinite(slope)
            and slope != 0
        ):
            steps += 1
            reduction = next_reduction(history, goal, slope)
            target = folder / result.parent.name / f"step{steps}"
            data = load_case(case_path).to_dict()
            data["garment"]["reduction"] = reduction
            base = case_path.parent
            written = write_case(data, target / "case.yaml", base)
            run_case(written, target, {}, stop_after="aggregate")
            value, error, settled = _read(target / "result.nc", row["landmark"])
            history.append((reduction, value))
            log.info(
                "secant %s, step %d: reduction %.6f gives %.4f +- %.3f mmHg (target %.4f)",
                row["landmark"],
                steps,
                reduction,
                value / MMHG,
                error / MMHG,
                goal / MMHG,
            )
            if _within(value, error, settled, goal):
                how = "secant"
    met = _within(value, error, settled, goal)
    if not settled:
        how = "not converged"
        log.warning(
            "secant %s: the last confirmation (reduction %.6f) did not converge: not met",
            row["landmark"],
            reduction,
        )
    interpolation = abs(value - goal) / abs(slope) if math.isfinite(slope) and slope else math.nan
    stated = float(row.get("reduction_error", "nan") or "nan")
    return {
        "secant_steps": steps,
        "final_reduction": reduction,
        "final_mmHg": value / MMHG,
        "final_error_mmHg": error / MMHG,
        "met": int(met),
        "interpolation_error": interpolation,
        "reduction_error_total": stated + (0.0 if met else interpolation),
        "how": how,
    }


__all__ = ["MAX_STEPS", "iterate_row", "next_reduction"]
