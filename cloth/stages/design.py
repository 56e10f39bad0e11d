"""The design loop: the graded pattern that puts target pressures on girth lines (issue 30).

Controls: the knot values of the case's reduction profile (`cloth.case.profile`); a case with
one uniform reduction gets a knot at every target line, all at that reduction. Targets: a mean
pressure per girth line (`Target`: a line the body names, or a height in m, which becomes a
line of the case: a target profile over height), met when every line is within the tolerance
(default 0.5 mmHg).

A case of one uniform reduction first takes one Gauss-Newton step of that reduction alone, to
the uniform reduction whose misses have the least sum of squares: its equilibrium is the
uniform answer the graded one is compared with (`Design.uniform`), and the graded loop's start.

Each iteration is one equilibrium, warm-started from the last one's positions on the recut
pattern (`cloth.garment.predeform.with_profile`), and its sensitivities by the adjoint
(`cloth.results.sensitivity`: one solve per target line with the equilibrium's factor). The
step is Gauss-Newton's, the least-squares solution of J dtheta = -(p - p_target), within the
bounds (`bounded_step`): every knot in [0, 0.6], and no higher than the reduction that strains
its row to the lab curve's last strain (`lab_caps`: beyond it the pressure would come from an
extrapolated curve). The loop stops when every line is within `AIM` of the tolerance, after
`MAX_SOLVES` - 1 equilibria (one is left for the confirmation from scratch), or when the bounds
hold the knots still. A target beyond reach names the line, the closest pressure reached and
the bound that binds (`Design.shortfall`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from cloth.bodies import Body
from cloth.case import Case, Settings
from cloth.case.pieces import BESIDE
from cloth.errors import InputError
from cloth.garment.grid import WEFT
from cloth.garment.predeform import predeform, with_bands, with_profile
from cloth.garment.state import State
from cloth.results.landmarks import landmark_heights
from cloth.results.pressure import MMHG
from cloth.results.sensitivity import Sensitivity, sensitivities
from cloth.results.targets import Target
from cloth.solvers.problem import Problem
from cloth.solvers.relax import Result, relax
from cloth.solvers.stability import counts
from cloth.stages.cuts import state_cut
from cloth.stages.levels import girth_marks

log = logging.getLogger(__name__)

#: Bounds of every knot's reduction.
BOUNDS = (0.0, 0.6)
#: A step of the knots this small (1) makes no progress: the bounds hold them.
STALLED = 1e-6
#: Default tolerance on every line, Pa (0.5 mmHg).
TOLERANCE = 0.5 * MMHG
#: Equilibria of a design at most, the confirmation from scratch included.
MAX_SOLVES = 8
#: The loop aims within this share of the tolerance while it has equilibria left, so that the
#: confirmation from scratch (another equilibrium of the same pattern) lands within it too.
AIM = 0.2


@dataclass(frozen=True)
class Iterate:
    """One equilibrium of the loop: knot values (K,), line means (L,) Pa, Newton iterations."""

    values: NDArray[np.float64]
    means: NDArray[np.float64]
    iterations: int


@dataclass(frozen=True)
class Design:
    """The loop's outcome: the knots and their values, the target lines, their targets and
    the means reached (Pa), every iterate, the equilibria solved, for a target out of reach
    its one-line ``shortfall`` (None when every line is met), and the uniform answer."""

    knots: tuple[str, ...]
    values: NDArray[np.float64]
    lines: tuple[str, ...]
    targets: NDArray[np.float64]
    achieved: NDArray[np.float64]
    iterates: tuple[Iterate, ...]
    solves: int
    tolerance: float
    state: State
    shortfall: str | None = None
    #: For a case of one uniform reduction: the uniform reduction of least squares misses (one
    #: Gauss-Newton step from the case's) and its equilibrium's line means (L,), Pa.
    uniform: tuple[float, NDArray[np.float64]] | None = None
    #: The bands (`cloth.case.pieces`) whose reductions the loop designed too, by name; their
    #: values follow the knots' in ``values``.
    bands: tuple[str, ...] = ()

    @property
    def met(self) -> bool:
        return bool(np.all(np.abs(self.achieved - self.targets) <= self.tolerance))

    @property
    def controls(self) -> tuple[str, ...]:
        """What ``values`` holds: the profile's knots, then ``band NAME`` per designed band."""
        return (*self.knots, *(f"band_{name}" for name in self.bands))

    def reduction(self) -> float | dict[str, float]:
        """The designed profile as a case's ``garment.reduction`` (the case's own where the
        loop designed bands alone)."""
        if not self.knots:
            return self.state.case.to_dict()["garment"]["reduction"]
        return dict(zip(self.knots, self.values[: len(self.knots)].tolist(), strict=True))

    def band_reductions(self) -> dict[str, float]:
        """The designed bands' reductions, by name."""
        tail = self.values[len(self.knots) :].tolist()
        return dict(zip(self.bands, tail, strict=True))


def line_means(
    state: State, result: Result, heights: dict[str, float], body: Body
) -> NDArray[np.float64]:
    """(L,) float, Pa: the girth lines' mean pressures at ``result``'s equilibrium, bottom to
    top (the lines beyond the garment left out), as result.nc reports them."""
    return np.array([mark.mean for mark in girth_marks(state, result.final, heights, body)])


def finite_difference_jacobian(
    state: State, body: Body, settings: Settings, heights: dict[str, float], step: float
) -> NDArray[np.float64]:
    """(L, K) float, Pa: d(line means)/d(knot values) by central differences of ``step`` over
    full equilibria warm-started from ``state`` (an equilibrium): 2K solves. The adjoint's
    check (tests/test_sensitivity.py) and the design loop's where no adjoint is available."""
    values = np.asarray(state.case.garment.reduction_profile.values, dtype=float)
    columns = []
    for k in range(len(values)):
        means = []
        for sign in (1.0, -1.0):
            shifted = values.copy()
            shifted[k] += sign * step
            moved = with_profile(state, shifted)
            means.append(line_means(moved, relax(moved, body, settings), heights, body))
        columns.append((means[0] - means[1]) / (2.0 * step))
    return np.stack(columns, axis=1)


def _start(state: State, body: Body, targets: list[Target], source: str) -> State:
    """``state`` with the knots of the design: its profile's, or one per target line at its
    uniform reduction (pre-deformed again for the new case)."""
    garment = state.case.garment
    if garment.reduction is None:
        raise InputError(
            "a design needs a graded pattern; give garment.reduction, not circumference",
            source,
            "garment.reduction",
        )
    profile = garment.reduction_profile
    if not profile.uniform:
        return state
    data = state.case.to_dict()
    data["garment"]["reduction"] = {t.line: profile.values[0] for t in targets}
    case = Case.from_dict(data, source)
    return repredeform(state, case, body, source)


def repredeform(state: State, case: Case, body: Body, source: str) -> State:
    """``case`` pre-deformed on ``state``'s body, wearing ``state``'s pattern where it wears
    one (cut again with ``case``'s garment), its record kept."""
    fresh = predeform(
        case,
        state.fabric,
        body,
        state.body,
        source,
        pattern=state_cut(state, case),
        fabrics=state.fabrics,
    )
    if "pattern_body" in state.attrs:
        fresh.attrs["pattern_body"] = state.attrs["pattern_body"]
    return fresh


def _height_lines(state: State, body: Body, targets: list[Target], source: str) -> State:
    """``state`` with a girth line at each target given at a height (``1.05=18``: a target
    profile over height) that the body does not name: the case's ``landmarks`` get it, so the
    loop, the confirmation and the summary all report it."""
    known = landmark_heights(state)
    extra = {t.line: float(t.line) for t in targets if t.line not in known and _is_height(t.line)}
    if not extra:
        return state
    data = state.case.to_dict()
    data["landmarks"] = {**(data.get("landmarks") or {}), **extra}
    return repredeform(state, Case.from_dict(data, source), body, source)


def _is_height(text: str) -> bool:
    try:
        return np.isfinite(float(text))
    except ValueError:
        return False


def design(
    state: State,
    body: Body,
    targets: list[Target],
    tolerance: float = TOLERANCE,
    source: str = "case",
) -> Design:
    """The design loop (module docstring) from the pre-deformed ``state`` of a case on
    ``body``; `InputError` naming ``source`` for a target line the body does not have."""
    settings = replace(state.case.solver, progress=False)
    if not counts(Problem.of(state, body)):
        field = (
            "body.tissue"
            if state.skin.tissue is not None
            else "contact.friction"
            if state.skin.friction
            else "body.surface"
        )
        raise InputError(
            "the design's sensitivities take a smooth body without tissue or friction; remove "
            "the skin model, or give the mesh surface: smooth (docs/solvers.md, Sensitivities)",
            source,
            field,
        )
    state = _height_lines(state, body, targets, source)
    heights = landmark_heights(state)
    unknown = [t.line for t in targets if t.line not in heights]
    if unknown:
        raise InputError(
            f"no girth line {unknown[0]!r} on this body; its lines: {', '.join(heights)}",
            source,
            "targets",
        )
    lines = {t.line: heights[t.line] for t in targets}
    order = sorted(lines, key=lines.__getitem__)
    goal = np.array([next(t.pressure for t in targets if t.line == name) for name in order])
    graded = not state.case.garment.reduction_profile.uniform
    # a target on a band's line is met by the band's own reduction (cloth.case.pieces)
    bands, knots = band_controls(state, targets)
    if knots:
        banded = {state.case.garment.pieces.bands[k].name for k in bands}
        state = _start(state, body, [t for t in targets if t.line not in banded], source)
    values = controls_of(state, knots, bands)
    n_knots = len(values) - len(bands)

    def sensitivity(state: State, result: Result) -> Sensitivity:
        return line_sensitivities(state, body, result, lines, bands, knots)

    result = relax(state, body, settings)
    state = state.with_positions(result.final.x)
    sens = sensitivity(state, result)
    _check_lines(sens, order, lines, state, source)
    solves, iterates, shortfall, uniform = 1, [_iterate(values, sens, result)], None, None
    if not graded and knots and not bands:
        caps = lab_caps(state, result, heights)
        uniform = _uniform(state, body, settings, sens, goal, caps, lines)
        solves += 1
    pinned, upper = np.zeros(len(values), bool), np.full(len(values), BOUNDS[1])
    while True:  # Gauss-Newton from the case's own equilibrium
        miss = sens.means - goal
        _log(solves, values, sens.means, goal)
        if np.all(np.abs(miss) <= AIM * tolerance) or solves >= MAX_SOLVES - 1:
            break
        upper = np.full(len(values), BOUNDS[1])
        if n_knots:
            upper[:n_knots] = lab_caps(state, result, heights)
        step, pinned, left = bounded_step(sens.jacobian, miss, values, upper)
        held = pinned.any() and np.all(np.abs(miss[left]) <= AIM * tolerance)
        if held or np.max(np.abs(step)) <= STALLED:  # the bounds hold the knots where they are
            break
        values = values + step
        moved = with_controls(state, values, knots, bands)
        result = relax(moved, body, settings)
        solves += 1
        state = moved.with_positions(result.final.x)
        sens = sensitivity(state, result)
        iterates.append(_iterate(values, sens, result))
    if not np.all(np.abs(sens.means - goal) <= tolerance):
        shortfall = _shortfall(order, sens, goal, values, tolerance, pinned, upper)
    return Design(
        knots=state.case.garment.reduction_profile.keys if knots else (),
        values=values,
        lines=tuple(order),
        targets=goal,
        achieved=sens.means,
        iterates=tuple(iterates),
        solves=solves,
        tolerance=tolerance,
        state=state,
        shortfall=shortfall,
        uniform=uniform,
        bands=tuple(state.case.garment.pieces.bands[k].name for k in bands),
    )


#: Rounds of `hold_band_ratios` at most (the line beside a band moves a little with it).
RATIO_ROUNDS = 3


def band_ratios(state: State, body: Body) -> dict[str, tuple[float, float]]:
    """Each band's mean pressure and the line beside it's (Pa), at ``state``'s equilibrium (one
    relaxation from it, which ends where it starts); bands whose line beside is off the
    garment are left out."""
    heights = landmark_heights(state)
    wanted = {}
    for band in state.case.garment.pieces.bands:
        if band.reduction is not None and band.name + BESIDE in heights:
            wanted[band.name] = heights[band.name]
            wanted[band.name + BESIDE] = heights[band.name + BESIDE]
    if not wanted:
        return {}
    result = relax(state, body, replace(state.case.solver, progress=False))
    marks = {m.name: m.mean for m in girth_marks(state, result.final, wanted, body)}
    return {
        name: (marks[name], marks[name + BESIDE])
        for name in wanted
        if not name.endswith(BESIDE) and name in marks and name + BESIDE in marks
    }


def hold_band_ratios(
    result: Design,
    body: Body,
    targets: list[Target],
    ratio: float,
    tolerance: float = TOLERANCE,
    source: str = "case",
) -> Design:
    """``result`` with every band pressing at most ``ratio`` times the line beside it (a
    stocking's top band no tourniquet; `cloth.case.pieces.BESIDE`): where one presses more, the
    design is run again with that band's line targeted at ``ratio`` x the line beside's mean,
    the other targets kept, until none presses more or after `RATIO_ROUNDS` rounds."""
    held: dict[str, float] = {}
    for _ in range(RATIO_ROUNDS):
        over = {
            name: (band, beside)
            for name, (band, beside) in band_ratios(result.state, body).items()
            if band > ratio * beside + AIM * tolerance or name in held
        }
        if not over or all(
            abs(band - ratio * beside) <= AIM * tolerance for band, beside in over.values()
        ):
            break
        held = {name: ratio * beside for name, (_, beside) in over.items()}
        log.info(
            "design: bands over %.3g x the line beside: %s; their reductions designed to it",
            ratio,
            ", ".join(
                f"{n} {b / MMHG:.2f} > {ratio:g} x {s / MMHG:.2f} mmHg"
                for n, (b, s) in over.items()
            ),
        )
        kept = [t for t in targets if t.line not in held]
        result = design(
            result.state,
            body,
            kept + [Target(name, value) for name, value in held.items()],
            tolerance,
            source,
        )
    return result


def band_controls(state: State, targets: list[Target]) -> tuple[tuple[int, ...], bool]:
    """The bands (indices) whose reductions a design moves, those with a target on their line
    (and a reduction of their own), and whether the profile's knots are controls too (a
    target on another line, or no band targeted)."""
    band_of = {
        b.name: k for k, b in enumerate(state.case.garment.pieces.bands) if b.reduction is not None
    }
    bands = tuple(sorted({band_of[t.line] for t in targets if t.line in band_of}))
    return bands, any(t.line not in band_of for t in targets) or not bands


def with_controls(
    state: State, values: NDArray[np.float64], knots: bool, bands: tuple[int, ...]
) -> State:
    """``state`` recut with the control ``values``: the knots' (where ``knots``), then
    ``bands``' reductions (`cloth.garment.predeform.with_profile`, `with_bands`)."""
    n_knots = len(values) - len(bands)
    moved = with_profile(state, values[:n_knots]) if knots and n_knots else state
    if bands:
        moved = with_bands(moved, dict(zip(bands, values[n_knots:].tolist(), strict=True)))
    return moved


def controls_of(state: State, knots: bool, bands: tuple[int, ...]) -> NDArray[np.float64]:
    """The design's control values: the profile's knot values (where ``knots``), then the
    reductions of ``bands``."""
    garment = state.case.garment
    values = list(garment.reduction_profile.values) if knots else []
    values += [float(garment.pieces.bands[k].reduction) for k in bands]
    return np.asarray(values, dtype=float)


def _iterate(values: NDArray, sens: Sensitivity, result: Result) -> Iterate:
    return Iterate(values.copy(), sens.means.copy(), result.iterations)


def _log(solves: int, values: NDArray, means: NDArray, goal: NDArray) -> None:
    log.info(
        "design: equilibrium %d, knots %s, lines %s mmHg (targets %s)",
        solves,
        np.round(values, 4).tolist(),
        np.round(means / MMHG, 2).tolist(),
        np.round(goal / MMHG, 2).tolist(),
    )


def _uniform(
    state: State,
    body: Body,
    settings: Settings,
    sens: Sensitivity,
    goal: NDArray,
    upper: NDArray,
    lines: dict[str, float],
) -> tuple[float, NDArray[np.float64]]:
    """The uniform answer (`Design.uniform`): one Gauss-Newton step of the case's uniform
    reduction alone, to the least squares of the misses, within the bounds; its equilibrium's
    line means (one equilibrium, warm-started)."""
    r0 = float(state.case.garment.reduction_profile.values[0])
    slope = sens.jacobian.sum(axis=1, keepdims=True)
    shift = float(np.linalg.lstsq(slope, goal - sens.means, rcond=None)[0][0])
    r = float(np.clip(r0 + shift, BOUNDS[0], upper.min()))
    moved = with_profile(state, np.full(len(sens.knots), r))
    result = relax(moved, body, settings)
    return r, line_means(moved.with_positions(result.final.x), result, lines, body)


def _check_lines(
    sens: Sensitivity, order: list[str], lines: dict[str, float], state: State, source: str
) -> None:
    """`InputError` for a target line beyond the garment (no value there to design)."""
    if len(sens.lines) == len(order):
        return
    beyond = next(name for name in order if name not in sens.lines)
    raise InputError(
        f"girth line {beyond!r} at {lines[beyond]:.4g} m is beyond the garment "
        f"({state.case.garment.bottom:.4g}-{state.case.garment.top:.4g} m); target a line "
        "the garment covers",
        source,
        "targets",
    )


def lab_caps(state: State, result: Result, heights: dict[str, float]) -> NDArray[np.float64]:
    """(K,) float, 1: each knot's largest reduction, the lesser of `BOUNDS`' upper one and the
    one that strains its row (the row nearest the knot) to the lab curve's last strain
    eps_lab: a row of rest length L0 (1 - r) stretched to the length it has now holds if
    (1 + eps)(1 - r) / (1 - r_cap) = 1 + eps_lab, eps its largest weft strain now."""
    grid = state.grid
    lab = float(grid.curves[WEFT].knot_strain[-1])
    strain = result.final.springs.strain[grid.family_slices[WEFT]].reshape(grid.m, -1).max(axis=1)
    rows = state.row_values("row_reduction")
    cap_rows = 1.0 - (1.0 + strain) * (1.0 - rows) / (1.0 + lab)
    profile = state.case.garment.reduction_profile
    marks = {**state.body.get("landmarks", {}), **state.case.landmarks, **heights}
    knots = profile.heights(marks)
    cut = state.row_values("cut_height")
    nearest = np.abs(cut[None, :] - knots[:, None]).argmin(axis=1)
    return np.minimum(BOUNDS[1], cap_rows[nearest])


def bounded_step(
    jacobian: NDArray, miss: NDArray, values: NDArray, upper: NDArray
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:
    """The Gauss-Newton step of the knots ((K,), 1) for ``miss`` ((L,), Pa) with ``jacobian``
    ((L, K), Pa), within [`BOUNDS`[0], ``upper``]: a knot the full step takes past a bound is
    pinned there, and the others solve again for what is left on the lines it does not
    dominate (`_lines_left`). Returns the step, the pinned knots (K,) and the lines the free
    knots answer to (L,)."""
    lower = np.full_like(values, BOUNDS[0])
    pinned = np.zeros(len(values), bool)
    step = np.zeros_like(values)
    for _ in range(len(values)):
        step[pinned] = (
            np.clip(values[pinned] + step[pinned], lower[pinned], upper[pinned]) - values[pinned]
        )
        free = ~pinned
        rhs = -(miss + jacobian[:, pinned] @ step[pinned])
        lines = _lines_left(jacobian, pinned)
        step[free] = (
            np.linalg.lstsq(jacobian[np.ix_(lines, free)], rhs[lines], rcond=None)[0]
            if free.any() and lines.any()
            else 0.0
        )
        trial = values + step
        out = free & ((trial < lower - 1e-12) | (trial > upper + 1e-12))
        if not out.any():
            break
        pinned |= out
    step = np.clip(values + step, lower, np.maximum(upper, lower)) - values
    return step, pinned, _lines_left(jacobian, pinned)


def _lines_left(jacobian: NDArray, pinned: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """The lines the free knots still answer to: a pinned knot gives up the line it moves most
    (else the free knots would trade every other line's target for that line's miss)."""
    left = np.ones(jacobian.shape[0], bool)
    for k in np.flatnonzero(pinned):
        if left.sum() <= 1:
            break
        share = np.where(left, np.abs(jacobian[:, k]), -np.inf)
        left[int(np.argmax(share))] = False
    return left


def line_sensitivities(
    state: State,
    body: Body,
    result: Result,
    lines: dict[str, float],
    bands: tuple[int, ...] = (),
    knots: bool = True,
) -> Sensitivity:
    """The lines' means and their derivatives in the knots (where ``knots``) and ``bands``'
    reductions at ``result``'s equilibrium (`cloth.results.sensitivity.sensitivities`)."""
    return sensitivities(state, body, result.final, lines, result.factor, bands, knots)


def _shortfall(
    order: list[str],
    sens: Sensitivity,
    goal: NDArray,
    values: NDArray,
    tolerance: float,
    pinned: NDArray[np.bool_],
    upper: NDArray,
) -> str:
    """One line: the worst line missed, the closest pressure reached, the bounds that bind."""
    miss = sens.means - goal
    worst = int(np.argmax(np.abs(miss)))
    binding = []
    for knot, value, cap in zip(
        np.asarray(sens.knots)[pinned], values[pinned], upper[pinned], strict=True
    ):
        if value <= BOUNDS[0] + 1e-9:
            binding.append(f"{knot} at its lower bound {BOUNDS[0]:g} (no reduction)")
        elif cap < BOUNDS[1]:
            binding.append(
                f"{knot} at {value:.4g}, where the weft reaches the lab curve's last strain"
            )
        else:
            binding.append(f"{knot} at its upper bound {BOUNDS[1]:g}")
    why = "; ".join(binding) if binding else "no bound binding: the equilibria ran out"
    return (
        f"{order[worst]}: target {goal[worst] / MMHG:.2f} mmHg not reached; the closest is "
        f"{sens.means[worst] / MMHG:.2f} mmHg (tolerance {tolerance / MMHG:.2g} mmHg); "
        f"reduction {why}"
    )
