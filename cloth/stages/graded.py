"""``cloth design CASE --target LINE=PRESSURE ... -o DIR``: a graded pattern designed to targets
(`cloth.stages.design`), confirmed from scratch, and written for the pattern maker.

In ``DIR``:

* ``case.yaml``: the case with the designed reduction profile, its relative paths stored
  relative to ``DIR`` (`cloth.files.casefile`): it runs as written, and the confirmation runs it
  so;
* ``design_iterations.csv``: every equilibrium of the loop: its knot values and line means;
* ``confirmed/``: the designed case relaxed from scratch (``initial.nc``, ``relaxed.nc``,
  ``result.nc``, ``summary.csv``; with its error estimate where the case asks for one);
* ``design_confirmed.csv``: per target line, the target, the loop's value, the confirmed value
  and its estimated discretisation error, whether it is met, the uniform answer, the designed
  knot values and the equilibria used (mmHg; reductions 1);
* ``design_profile.png``: per line, the target, the uniform answer and the graded answer;
* the pattern (`cloth.stages.patterns`): ``pattern.csv``, ``.svg`` and ``.dxf`` (the plain
  outline), ``pattern_astm.dxf`` (the piece in the AAMA / ASTM D6673 convention) and
  ``pattern.pdf`` (1:1 with a check square), and for a tube ``pattern_knitting.csv`` and
  ``.png``; the DXF files where ezdxf is installed. The cut (``--cut``) is a tube on a leg
  (a stocking is knitted in the round), two panels elsewhere, unless given.

``cloth design CASE --sizes S,M,L`` designs every size of the chart at once
(`cloth.stages.chart`).

A target out of reach writes all of these, marked ``met`` 0, and then ends in one line naming
the line, the closest pressure and the bound (`InputError`, exit status 2).
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.case import Case
from cloth.case.case import load_case
from cloth.errors import InputError
from cloth.files.body import body_from_record
from cloth.files.casefile import write_case
from cloth.files.pattern import CUTS
from cloth.files.piece import SEAM_ALLOWANCE_MM
from cloth.pipeline.designplots import plot_profile_design
from cloth.pipeline.sweep import write_rows
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.stages.case import initial_state, run_case
from cloth.stages.design import TOLERANCE, Design, design, hold_band_ratios
from cloth.stages.patterns import default_formats, write_patterns

log = logging.getLogger(__name__)


def design_files(
    case_path: Path,
    targets: list[Target],
    output: Path,
    tolerance: float = TOLERANCE,
    base_dir: Path | None = None,
    cut: str = "auto",
    allowance: float = SEAM_ALLOWANCE_MM,
    paper: str = "A4",
    band_ratio: float | None = None,
) -> Design:
    """The design of ``case_path`` to ``targets`` and its files in ``output`` (module
    docstring); `InputError` after writing them when a target is out of reach. ``band_ratio``:
    every band at most this times the line beside it (`design_one`)."""
    check_targets(targets)
    case = load_case(case_path)
    base_dir = Path(case_path).parent if base_dir is None else Path(base_dir)
    cut = cut_of(case, cut)
    result, rows = design_one(
        case, targets, output, tolerance, base_dir, str(case_path), band_ratio
    )
    write_rows(rows, output / "design_confirmed.csv", list(rows[0]))
    plot_profile_design(rows, output / "design_profile.png")
    formats = default_formats(cut)
    write_patterns(
        [output / "confirmed" / "result.nc"],
        output / "pattern.csv",
        cut,
        formats,
        allowance=allowance,
        paper=paper,
        notes=[target_note(rows)],
        style=output.name,
    )
    log.info(
        "design: %s in %d equilibria (%d in the loop, 1 confirmation)%s",
        verdicts(rows),
        result.solves + 1,
        result.solves,
        "" if "dxf" in formats else "; no DXF (pip install 'cloth[pattern]')",
    )
    raise_unmet(result, rows, tolerance, case_path)
    return result


def check_targets(targets: list[Target]) -> None:
    if not targets:
        raise InputError("give at least one target, e.g. --target waist=20", field="--target")


def cut_of(case: Case, cut: str) -> str:
    """``cut``, or for ``auto`` the cut of the case's garment: a tube on a leg (a stocking is
    knitted in the round), two panels elsewhere."""
    if cut == "auto":
        return "tube" if case.body.kind == "leg" else "two-panel"
    if cut not in CUTS:
        raise InputError(
            f"unknown cut {cut!r}; give auto or one of {', '.join(CUTS)}", field="--cut"
        )
    return cut


def target_note(rows: list[dict[str, object]]) -> str:
    """The design's pressure targets as the pattern's annotation note."""
    targets = dict.fromkeys(f"{row['landmark']} {row['target_mmHg']:.4g}" for row in rows)
    return "pressure targets (mmHg): " + ", ".join(targets)


def design_one(
    case: Case,
    targets: list[Target],
    output: Path,
    tolerance: float,
    base_dir: Path,
    source: str,
    band_ratio: float | None = None,
) -> tuple[Design, list[dict[str, object]]]:
    """The design of ``case`` (paths relative to ``base_dir``) into ``output``: its case.yaml,
    design_iterations.csv and confirmation from scratch (module docstring); the outcome and its
    design_confirmed.csv rows, not yet written. ``band_ratio``: every band presses at most
    this times the line beside it (`cloth.stages.design.hold_band_ratios`)."""
    state = initial_state(case, base_dir, source)
    body = body_from_record(state.body)
    result = design(state, body, targets, tolerance, source)
    if band_ratio is not None:
        result = hold_band_ratios(result, body, targets, band_ratio, tolerance, source)
    output.mkdir(parents=True, exist_ok=True)
    data = result.state.case.to_dict()
    data["garment"]["reduction"] = result.reduction()
    designed = write_case(data, output / "case.yaml", base_dir)  # its paths from output
    _iterations(result, output / "design_iterations.csv")
    run_case(designed, output / "confirmed", {}, stop_after="aggregate")  # as written
    confirmed = xr.load_dataset(output / "confirmed" / "result.nc")
    return result, confirmed_rows(result, confirmed)


#: design_confirmed.csv's ``verdict`` values (`judge_confirmed`).
VERDICTS = ("met", "missed", "grid cannot tell")


def judge_confirmed(miss: float, error: float, tolerance: float) -> dict[str, object]:
    """The verdict on one confirmed line: ``miss`` the confirmed value less the target,
    ``error`` its stated discretisation error (NaN where the confirmation states none),
    ``tolerance`` the design's; all Pa.

    ``met`` 1 only where the line is within the tolerance of its target *and* its stated error
    is within the tolerance too (issue 54: a value whose error is larger than the tolerance
    cannot be said to meet it). The ``verdict`` is ``met``, ``missed`` (off by more than the
    tolerance, on a grid whose error is within it) or ``grid cannot tell`` (the stated error is
    larger than the tolerance, or not stated); ``error_past_tolerance_mmHg`` says by how much
    the error is too large (0 where the grid can tell, NaN where no error is stated)."""
    decided = math.isfinite(error) and error <= tolerance
    if not decided:
        verdict = "grid cannot tell"
    elif abs(miss) <= tolerance:
        verdict = "met"
    else:
        verdict = "missed"
    past = (error - tolerance) / MMHG if not decided else 0.0
    return {
        "met": int(verdict == "met"),
        "verdict": verdict,
        "error_past_tolerance_mmHg": past,
    }


def verdicts(rows: list[dict[str, object]]) -> str:
    """The design's verdicts in words, for its log line: "every target met", or how many lines
    are met, missed and undecided by the grid."""
    if all(row["met"] for row in rows):
        return "every target met"
    counts = {v: sum(row["verdict"] == v for row in rows) for v in VERDICTS}
    return "NOT every target met (" + ", ".join(f"{n} {v}" for v, n in counts.items() if n) + ")"


def raise_unmet(
    result: Design, rows: list[dict[str, object]], tolerance: float, source: Path | str
) -> None:
    """`InputError` for a design out of reach, or confirmed off its target on a grid that can
    tell, else nothing; a warning per line the grid cannot decide (`judge_confirmed`)."""
    if result.shortfall is not None:
        raise InputError(result.shortfall, source, "targets")
    for row in rows:
        if row["verdict"] == "grid cannot tell":
            past = row["error_past_tolerance_mmHg"]
            log.warning(
                "%s: %s: confirmed %.2f +- %.2f mmHg, target %.2f +- %.2g mmHg: the grid cannot "
                "tell whether it is met (%s); refine the grid",
                source,
                row["landmark"],
                row["confirmed_mmHg"],
                row["confirmed_error_mmHg"],
                row["target_mmHg"],
                tolerance / MMHG,
                f"its stated error is {past:.2f} mmHg past the tolerance"
                if math.isfinite(past)
                else "the confirmation states no error",
            )
    missed = [row for row in rows if row["verdict"] == "missed"]
    if missed:
        worst = max(missed, key=lambda row: abs(row["confirmed_mmHg"] - row["target_mmHg"]))
        raise InputError(
            f"{worst['landmark']}: confirmed at {worst['confirmed_mmHg']:.2f} mmHg from "
            f"scratch, target {worst['target_mmHg']:.2f} +- {tolerance / MMHG:.2g} mmHg; the "
            "loop's equilibrium and the one from scratch differ (see design_confirmed.csv)",
            source,
            "targets",
        )


def _iterations(result: Design, path: Path) -> None:
    rows = []
    for k, it in enumerate(result.iterates, start=1):
        row: dict[str, object] = {"equilibrium": k, "newton_iterations": it.iterations}
        row.update(
            {
                f"reduction_{key}": float(v)
                for key, v in zip(result.controls, it.values, strict=True)
            }
        )
        row.update(
            {
                f"{line}_mmHg": float(p) / MMHG
                for line, p in zip(result.lines, it.means, strict=True)
            }
        )
        rows.append(row)
    header = list(dict.fromkeys(k for row in rows for k in row))
    write_rows(rows, path, header)


def confirmed_rows(result: Design, confirmed: xr.Dataset) -> list[dict[str, object]]:
    """design_confirmed.csv's rows: per target line of ``result``, its value, error and
    whether it is met read from ``confirmed`` (the confirmation's own result.nc), beside the
    loop's value (``designed_mmHg``) and the uniform answer; mmHg."""
    names = [str(v) for v in confirmed["landmark"].values]
    error = (
        confirmed["pressure_mean_error"].values
        if "pressure_mean_error" in confirmed
        else np.full(len(names), np.nan)
    )
    rows = []
    for k, line in enumerate(result.lines):
        at = names.index(line)
        value = float(confirmed["pressure_mean"].values[at])
        row: dict[str, object] = {
            "landmark": line,
            "height_m": float(confirmed["landmark_height"].values[at]),
            "target_mmHg": result.targets[k] / MMHG,
            "designed_mmHg": result.achieved[k] / MMHG,
            "confirmed_mmHg": value / MMHG,
            "confirmed_error_mmHg": float(error[at]) / MMHG,
            "tolerance_mmHg": result.tolerance / MMHG,
        }
        row.update(judge_confirmed(value - result.targets[k], float(error[at]), result.tolerance))
        if result.uniform is not None:
            row["uniform_reduction"] = result.uniform[0]
            row["uniform_mmHg"] = float(result.uniform[1][k]) / MMHG
        row.update(
            {
                f"reduction_{key}": float(v)
                for key, v in zip(result.controls, result.values, strict=True)
            }
        )
        row["equilibria"] = result.solves + 1
        rows.append(row)
    return rows
