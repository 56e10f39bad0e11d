"""A panel's width designed for a target (issue 69): ``cloth design CASE --target LINE=P
--panel K``.

A garment of panels (`cloth.case.pieces`) is cut with each panel's share of the circumference
(its angles). The loop finds the width of panel K (degrees, about its own centre) whose
equilibrium puts the target mean pressure on one girth line, the other panels' fabrics held:
the panels either side of it give up or take what it gains, their outer seams where they were.
A wider panel of a firmer fabric raises the hoop tension everywhere around, so the line's
pressure is monotone in the width, and a secant on it converges in a few equilibria, each
warm-started from the last one's positions (the grid is the same; only its springs' fabrics
move). The first step is a finite difference of `PROBE_DEG`. The width stays between twice the
seam allowance's share and the room its neighbours leave; a target beyond that reach is named
with the closest pressure reached (`PanelDesign.shortfall`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.bodies import Body
from cloth.case import Case
from cloth.case.case import load_case
from cloth.errors import InputError
from cloth.files.body import body_from_record
from cloth.files.casefile import write_case
from cloth.garment.state import State
from cloth.pipeline.sweep import write_rows
from cloth.results.landmarks import landmark_heights
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.solvers.relax import relax
from cloth.stages.case import initial_state, run_case
from cloth.stages.design import AIM, TOLERANCE, line_means, repredeform
from cloth.stages.graded import judge_confirmed

log = logging.getLogger(__name__)

#: The first step's change of the panel's width, degrees.
PROBE_DEG = 5.0
#: Equilibria of the loop at most.
MAX_SOLVES = 8
#: The narrowest panel the loop makes, degrees (besides the seams' room).
MIN_DEG = 2.0


@dataclass(frozen=True)
class PanelDesign:
    """The loop's outcome: the panel (index), its width (degrees) and angles, the target line,
    its target and the mean reached (Pa), every iterate (width, mean), the equilibria solved,
    the tolerance (Pa), the final state and, for a target out of reach, its one-line
    ``shortfall``."""

    panel: int
    width: float
    from_deg: float
    to_deg: float
    line: str
    target: float
    achieved: float
    iterates: tuple[tuple[float, float], ...]
    solves: int
    tolerance: float
    state: State
    shortfall: str | None = None

    @property
    def met(self) -> bool:
        return abs(self.achieved - self.target) <= self.tolerance


def neighbours(panels: list[dict], k: int) -> tuple[int, int]:
    """The panels before and after panel ``k`` around the tube (indices)."""
    order = sorted(range(len(panels)), key=lambda i: panels[i]["from_deg"])
    at = order.index(k)
    return order[at - 1], order[(at + 1) % len(order)]


def with_width(data: dict, k: int, width: float) -> dict:
    """The case mapping ``data`` with panel ``k`` ``width`` degrees wide about its centre, its
    neighbours' inner seams moved with it (module docstring)."""
    panels = data["garment"]["panels"]
    panel = panels[k]
    centre = 0.5 * (panel["from_deg"] + panel["to_deg"])
    start, end = centre - 0.5 * width, centre + 0.5 * width
    before, after = neighbours(panels, k)
    wrap_before = panels[before]["to_deg"] - panel["from_deg"]  # 0 or a multiple of 360
    wrap_after = panels[after]["from_deg"] - panel["to_deg"]
    panels[before]["to_deg"] = start + wrap_before
    panels[after]["from_deg"] = end + wrap_after
    panel["from_deg"], panel["to_deg"] = start, end
    return data


def _limits(data: dict, k: int, allowance_deg: float) -> tuple[float, float]:
    """The panel's narrowest and widest width, degrees."""
    panels = data["garment"]["panels"]
    before, after = neighbours(panels, k)
    room = 360.0 - sum(
        p["to_deg"] - p["from_deg"] for i, p in enumerate(panels) if i not in (k, before, after)
    )
    keep = 2 * (MIN_DEG + 2 * allowance_deg)  # each neighbour keeps some of itself
    if before == after:
        keep = MIN_DEG + 2 * allowance_deg
    low = MIN_DEG + 2 * allowance_deg
    return low, room - keep


def panel_design(
    state: State,
    body: Body,
    target: Target,
    panel: int,
    tolerance: float = TOLERANCE,
    source: str = "case",
) -> PanelDesign:
    """The loop (module docstring) from the pre-deformed ``state`` of a case of panels."""
    data = state.case.to_dict()
    panels = data["garment"].get("panels") or []
    if len(panels) < 2:
        raise InputError(
            "a panel's width is designed between its neighbours; give the garment two panels "
            "or more",
            source,
            "garment.panels",
        )
    if not 0 <= panel < len(panels):
        raise InputError(
            f"no panel {panel}; the garment has panels 0-{len(panels) - 1}", field="--panel"
        )
    heights = landmark_heights(state)
    if target.line not in heights:
        raise InputError(
            f"no girth line {target.line!r} on this body; its lines: {', '.join(heights)}",
            source,
            "targets",
        )
    lines = {target.line: heights[target.line]}
    seams = state.case.garment.pieces.seams
    grid = state.grid
    weft = grid.rest_length[: grid.n * grid.m].reshape(grid.m, grid.n).sum(axis=1)
    circumference = float(weft.min())  # the narrowest row: the seams' largest share
    allowance_deg = 360.0 * seams.width / float(circumference)
    low, high = _limits(data, panel, allowance_deg)
    settings = replace(state.case.solver, progress=False)
    width = float(panels[panel]["to_deg"] - panels[panel]["from_deg"])

    def solve(width: float, start: State) -> tuple[float, State]:
        case = Case.from_dict(with_width(state.case.to_dict(), panel, width), source)
        fresh = repredeform(start, case, body, source).with_positions(
            start.x
        )  # warm: the same grid, other fabrics
        result = relax(fresh, body, settings)
        solved = fresh.with_positions(result.final.x)
        means = line_means(solved, result, lines, body)
        if means.size == 0:
            raise InputError(
                f"girth line {target.line!r} is beyond the garment; target a line it covers",
                source,
                "targets",
            )
        return float(means[0]), solved

    mean, current = solve(width, state)
    iterates = [(width, mean)]
    previous = None
    while abs(mean - target.pressure) > AIM * tolerance and len(iterates) < MAX_SOLVES:
        if previous is None:
            step = PROBE_DEG if mean < target.pressure else -PROBE_DEG
            probe = float(np.clip(width + step, low, high))
        else:
            slope = (mean - previous[1]) / (width - previous[0])
            if slope == 0 or not np.isfinite(slope):
                break
            probe = float(np.clip(width - (mean - target.pressure) / slope, low, high))
        if abs(probe - width) < 1e-9:
            break
        previous = (width, mean)
        width = probe
        mean, current = solve(width, current)
        iterates.append((width, mean))
        log.info(
            "panel design: panel %d %.3f degrees wide, %s %.2f mmHg (target %.2f)",
            panel,
            width,
            target.line,
            mean / MMHG,
            target.pressure / MMHG,
        )
    shortfall = None
    if abs(mean - target.pressure) > tolerance:
        bound = "its widest" if width >= high - 1e-9 else "its narrowest" if width <= low else ""
        shortfall = (
            f"{target.line}: target {target.pressure / MMHG:.2f} mmHg not reached by panel "
            f"{panel}'s width; the closest is {mean / MMHG:.2f} mmHg at {width:.4g} degrees"
            + (f" ({bound}, {low:.4g}-{high:.4g} degrees)" if bound else "")
        )
    final = current.case.garment.pieces.panels[panel]
    return PanelDesign(
        panel=panel,
        width=width,
        from_deg=final.from_deg,
        to_deg=final.to_deg,
        line=target.line,
        target=target.pressure,
        achieved=mean,
        iterates=tuple(iterates),
        solves=len(iterates),
        tolerance=tolerance,
        state=current,
        shortfall=shortfall,
    )


def panel_files(
    case_path: Path,
    target: Target,
    panel: int,
    output: Path,
    tolerance: float = TOLERANCE,
    base_dir: Path | None = None,
) -> PanelDesign:
    """The panel design of ``case_path`` and its files in ``output``: the designed case.yaml,
    design_iterations.csv (each equilibrium's width and mean), its confirmation from scratch
    (``confirmed/``) and design_confirmed.csv (the line's target, the loop's and the
    confirmation's mean with its error, and the verdict, as a graded design's); `InputError`
    after writing them when the target is out of reach or confirmed off it."""
    case = load_case(case_path)
    base_dir = Path(case_path).parent if base_dir is None else Path(base_dir)
    state = initial_state(case, base_dir, str(case_path))
    result = panel_design(
        state, body_from_record(state.body), target, panel, tolerance, str(case_path)
    )
    output.mkdir(parents=True, exist_ok=True)
    designed = write_case(result.state.case.to_dict(), output / "case.yaml", base_dir)
    write_rows(
        [
            {"equilibrium": k, "panel_width_deg": w, f"{result.line}_mmHg": p / MMHG}
            for k, (w, p) in enumerate(result.iterates, start=1)
        ],
        output / "design_iterations.csv",
        ["equilibrium", "panel_width_deg", f"{result.line}_mmHg"],
    )
    run_case(designed, output / "confirmed", {}, stop_after="aggregate")
    with xr.open_dataset(output / "confirmed" / "result.nc") as confirmed:
        confirmed = confirmed.load()
    names = [str(v) for v in confirmed["landmark"].values]
    at = names.index(result.line)
    value = float(confirmed["pressure_mean"].values[at])
    error = (
        float(confirmed["pressure_mean_error"].values[at])
        if "pressure_mean_error" in confirmed
        else float("nan")
    )
    row = {
        "landmark": result.line,
        "height_m": float(confirmed["landmark_height"].values[at]),
        "target_mmHg": result.target / MMHG,
        "designed_mmHg": result.achieved / MMHG,
        "confirmed_mmHg": value / MMHG,
        "confirmed_error_mmHg": error / MMHG,
        "tolerance_mmHg": tolerance / MMHG,
        **judge_confirmed(value - result.target, error, tolerance),
        "panel": panel,
        "panel_from_deg": result.from_deg,
        "panel_to_deg": result.to_deg,
        "panel_width_deg": result.width,
        "equilibria": result.solves + 1,
    }
    write_rows([row], output / "design_confirmed.csv", list(row))
    log.info(
        "panel design: panel %d %.4g degrees wide (%.4g to %.4g), %s confirmed %.2f mmHg, "
        "target %.2f mmHg: %s",
        panel,
        result.width,
        result.from_deg,
        result.to_deg,
        result.line,
        value / MMHG,
        result.target / MMHG,
        row["verdict"],
    )
    if result.shortfall is not None:
        raise InputError(result.shortfall, case_path, "targets")
    if row["verdict"] == "missed":
        raise InputError(
            f"{result.line}: confirmed at {value / MMHG:.2f} mmHg from scratch, target "
            f"{result.target / MMHG:.2f} +- {tolerance / MMHG:.2g} mmHg (design_confirmed.csv)",
            case_path,
            "targets",
        )
    return result


__all__ = [
    "MAX_SOLVES",
    "PROBE_DEG",
    "PanelDesign",
    "neighbours",
    "panel_design",
    "panel_files",
    "with_width",
]
