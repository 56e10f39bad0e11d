"""Robust design (issue 52, item 5): one reduction profile that puts every wearer of a size
inside a pressure band on each target line, centred where it can be.

The wearers wear one pattern (`cloth.garment.cut`): the case's garment cut for the size's body
with the profile's knot values theta (K,), placed on each wearer. A band [low_l, high_l] per line
l has centre c_l and half-width h_l; wearer w's mean pressure on line l is p_wl(theta). The
design minimises t = max over w, l of |p_wl - c_l| / h_l: t <= 1 is every wearer inside every
band, and the least t the profile that centres them best (a min-max over the wearers).

Each iteration relaxes every wearer (warm-started on the recut pattern,
`cloth.garment.predeform.with_profile`), takes each wearer's sensitivities d p_w / d theta by the
adjoint of its equilibrium (`cloth.results.sensitivity`), and solves the linearised min-max as a
linear programme (`scipy.optimize.linprog`, HiGHS) for the step, within the knots' bounds
(`cloth.stages.design.BOUNDS`, `lab_caps`) and a trust region of `STEP` per knot. It stops when
the step is below `STALLED` or after `MAX_ROUNDS` rounds. Where t stays above 1 no profile puts
every wearer in its band: `Robust.shortfall` names the line, the wearers at its ends and the
narrowest band the profile reached there.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linprog

from cloth.bodies import Body
from cloth.case import Case
from cloth.errors import InputError
from cloth.garment.state import State
from cloth.results.landmarks import landmark_heights
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.solvers.relax import relax
from cloth.stages.design import (
    BOUNDS,
    band_controls,
    controls_of,
    lab_caps,
    line_sensitivities,
    repredeform,
    with_controls,
)

log = logging.getLogger(__name__)

#: Largest change of a knot's reduction in one round (1): the linearisation's trust region.
STEP = 0.05
#: A step this small (1) ends the loop.
STALLED = 1e-4
#: Rounds (each one equilibrium per wearer) at most.
MAX_ROUNDS = 8


@dataclass(frozen=True)
class Robust:
    """The robust design's outcome: the knots and their values (K,), the target lines (L,),
    their bands ((L, 2), Pa), the wearers (W,), each wearer's line means at the last round
    ((W, L), Pa), the min-max measure ``t`` there (<= 1: every wearer inside every band), the
    rounds and equilibria solved, and the one-line ``shortfall`` where no profile is found."""

    knots: tuple[str, ...]
    values: NDArray[np.float64]
    lines: tuple[str, ...]
    bands: NDArray[np.float64]
    wearers: tuple[str, ...]
    means: NDArray[np.float64]
    t: float
    rounds: int
    solves: int
    shortfall: str | None = None
    #: The bands (`cloth.case.pieces`) whose reductions were designed too, by name; their values
    #: follow the knots' in ``values``.
    bands_designed: tuple[str, ...] = ()
    #: The case's own ``garment.reduction``, kept where the knots were not designed.
    case_reduction: object = None

    def reduction(self) -> float | dict[str, float]:
        """The designed profile as a case's ``garment.reduction`` (the case's own where the
        bands alone were designed)."""
        if not self.knots:
            return self.case_reduction
        return dict(zip(self.knots, self.values[: len(self.knots)].tolist(), strict=True))

    def band_reductions(self) -> dict[str, float]:
        """The designed bands' reductions, by name."""
        return dict(zip(self.bands_designed, self.values[len(self.knots) :].tolist(), strict=True))

    def apply(self, data: dict) -> dict:
        """The case mapping ``data`` with the design's profile and bands' reductions."""
        data["garment"]["reduction"] = self.reduction()
        reductions = self.band_reductions()
        for band in data["garment"].get("bands") or []:
            if band["name"] in reductions:
                band["reduction"] = reductions[band["name"]]
        return data


def measure(means: NDArray, bands: NDArray) -> float:
    """max |p - c| / h over wearers and lines: <= 1 where every wearer is inside every band."""
    centre, half = bands.mean(axis=1), 0.5 * (bands[:, 1] - bands[:, 0])
    return float(np.max(np.abs(means - centre) / half))


def minmax_step(
    means: NDArray, jacobians: NDArray, bands: NDArray, values: NDArray, upper: NDArray
) -> tuple[NDArray[np.float64], float]:
    """The step (K,) of the linearised min-max (module docstring) from ``means`` (W, L) with
    ``jacobians`` (W, L, K) within [BOUNDS[0], ``upper``] and the trust region; and the t it
    predicts."""
    w, lines, k = jacobians.shape
    centre, half = bands.mean(axis=1), 0.5 * (bands[:, 1] - bands[:, 0])
    rows, rhs = [], []
    for a in range(w):
        for b in range(lines):
            scaled = jacobians[a, b] / half[b]
            gap = (means[a, b] - centre[b]) / half[b]
            rows.append([*scaled, -1.0])  # (p + J d - c) / h <= t
            rhs.append(-gap)
            rows.append([*(-scaled), -1.0])  # -(p + J d - c) / h <= t
            rhs.append(gap)
    low = np.maximum(BOUNDS[0] - values, -STEP)
    high = np.minimum(upper - values, STEP)
    bounds = [(float(lo), float(max(lo, hi))) for lo, hi in zip(low, high, strict=True)]
    cost = np.zeros(k + 1)
    cost[-1] = 1.0
    done = linprog(cost, A_ub=np.array(rows), b_ub=np.array(rhs), bounds=[*bounds, (0, None)])
    if done.status != 0:
        return np.zeros(k), measure(means, bands)
    return done.x[:k], float(done.x[-1])


def robust_design(
    states: dict[str, State], bodies: dict[str, Body], targets: list[Target], source: str
) -> Robust:
    """The robust design (module docstring) from each wearer's pre-deformed ``states`` on its
    ``bodies``, to the bands of ``targets`` (a single value is a band of the design's default
    tolerance, 0.5 mmHg, either side)."""
    names = list(states)
    first = states[names[0]]
    if first.case.garment.reduction is None:
        raise InputError(
            "a design needs a graded pattern; give garment.reduction", source, "garment.reduction"
        )
    for name in names:
        unknown = [t.line for t in targets if t.line not in landmark_heights(states[name])]
        if unknown:
            raise InputError(f"wearer {name} has no girth line {unknown[0]!r}", source, "targets")
    order = sorted({t.line for t in targets}, key=landmark_heights(first).__getitem__)
    by_line = {t.line: t for t in targets}
    half = 0.5 * MMHG
    bands = np.array(
        [by_line[n].band or (by_line[n].pressure - half, by_line[n].pressure + half) for n in order]
    )
    profile = first.case.garment.reduction_profile
    # a band's line is held by the band's own reduction (cloth.case.pieces)
    band_index, knots = band_controls(first, targets)
    banded = {first.case.garment.pieces.bands[k].name for k in band_index}
    body_lines = [n for n in order if n not in banded]
    if profile.uniform and knots:  # a knot per target line, all at the case's reduction
        data = first.case.to_dict()
        data["garment"]["reduction"] = dict.fromkeys(body_lines, float(profile.values[0]))
        case = Case.from_dict(data, source)
        states = {n: repredeform(s, case, bodies[n], source) for n, s in states.items()}
    values = controls_of(states[names[0]], knots, band_index)
    n_knots = len(values) - len(band_index)
    settings = replace(first.case.solver, progress=False)
    solves, rounds, t = 0, 0, np.inf
    while True:
        means, jacobians, caps = [], [], []
        for name in names:
            state = states[name]
            result = relax(state, bodies[name], settings)
            solves += 1
            state = state.with_positions(result.final.x)
            states[name] = state
            heights = landmark_heights(state)
            lines = {n: heights[n] for n in order}
            sens = line_sensitivities(state, bodies[name], result, lines, band_index, knots)
            if len(sens.lines) != len(order):
                raise InputError(
                    f"wearer {name}: a target line is beyond her garment "
                    f"({', '.join(n for n in order if n not in sens.lines)})",
                    source,
                    "targets",
                )
            means.append(sens.means)
            jacobians.append(sens.jacobian)
            cap = np.full(len(values), BOUNDS[1])
            if n_knots:
                cap[:n_knots] = lab_caps(state, result, heights)
            caps.append(cap)
        means_w, jac_w = np.array(means), np.array(jacobians)
        t = measure(means_w, bands)
        rounds += 1
        log.info(
            "robust design: round %d, knots %s, t %.3f (<= 1: every wearer in every band)",
            rounds,
            np.round(values, 4).tolist(),
            t,
        )
        if rounds >= MAX_ROUNDS:
            break
        upper = np.min(np.array(caps), axis=0)
        step, predicted = minmax_step(means_w, jac_w, bands, values, upper)
        if np.max(np.abs(step)) <= STALLED:
            break
        log.info("robust design: step %s, linearised t %.3f", np.round(step, 5).tolist(), predicted)
        values = values + step
        states = {n: with_controls(s, values, knots, band_index) for n, s in states.items()}
    shortfall = None if t <= 1.0 else _shortfall(order, bands, names, means_w)
    last = states[names[0]]
    return Robust(
        knots=last.case.garment.reduction_profile.keys if knots else (),
        values=values,
        lines=tuple(order),
        bands=bands,
        wearers=tuple(names),
        means=means_w,
        t=t,
        rounds=rounds,
        solves=solves,
        shortfall=shortfall,
        bands_designed=tuple(last.case.garment.pieces.bands[k].name for k in band_index),
        case_reduction=last.case.to_dict()["garment"]["reduction"],
    )


def _shortfall(order: list[str], bands: NDArray, names: list[str], means: NDArray) -> str:
    """One line: the line furthest outside its band, the wearers at its ends and the
    narrowest band the profile reached there (mmHg)."""
    centre, half = bands.mean(axis=1), 0.5 * (bands[:, 1] - bands[:, 0])
    excess = np.max(np.abs(means - centre) / half, axis=0)
    line = int(np.argmax(excess))
    low, high = int(np.argmin(means[:, line])), int(np.argmax(means[:, line]))
    span = means[high, line] - means[low, line]
    width = bands[line, 1] - bands[line, 0]
    reason = (
        f"its wearers span {span / MMHG:.1f} mmHg there, more than the band's {width / MMHG:.1f}"
        if span > width
        else "the bounds of the reduction hold the profile short of it"
    )
    return (
        f"{order[line]}: no reduction profile puts every wearer in "
        f"{bands[line, 0] / MMHG:.4g}-{bands[line, 1] / MMHG:.4g} mmHg: {reason} (wearers "
        f"{names[low]} {means[low, line] / MMHG:.1f} and {names[high]} "
        f"{means[high, line] / MMHG:.1f} mmHg); the narrowest band reached: "
        f"{means[low, line] / MMHG:.1f}-{means[high, line] / MMHG:.1f} mmHg"
    )


__all__ = ["MAX_ROUNDS", "STEP", "Robust", "measure", "minmax_step", "robust_design"]
