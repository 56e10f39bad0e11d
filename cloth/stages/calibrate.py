"""``cloth calibrate``: fit a case's skin and fabric parameters to measured pressures.

The parameters (`cloth.results.calibration.PARAMETERS`): ``friction`` (``contact.friction``),
``tissue_modulus`` (``body.tissue.modulus``; the case must have a tissue layer, whose thickness
and ``bands`` stay as they are) and ``fabric_scale`` (the case's ``fabric_scale``). Each
evaluation is the case with the parameters set, pre-deformed and relaxed from scratch
(friction depends on the path, so never from another evaluation's equilibrium) with the case's
solver, no coarser levels, and read by the model's probe at every reading's place
(`cloth.results.sensing`).

The steps: the readings' derivatives in the parameters at the start by forward differences
(`Parameter.step`); which of them the readings determine (`cloth.results.calibration.
determined`, with the readings' noise: the repeats' pooled standard deviation where the file
has repeats, else ``noise``); a bounded least-squares fit of the determined ones
(`scipy.optimize.least_squares`, trust-region reflective, the same differences for its
Jacobian), the others held at their start; their 95 % intervals at the end
(`cloth.results.calibration.intervals`, from central differences). Writes calibration.csv
(`CALIBRATION_COLUMNS`), fit.csv (`FIT_COLUMNS`, the readings before and after) and the
calibrated case.yaml.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from cloth.case.case import following_skin, load_case, validate_case
from cloth.errors import EXIT_DIVERGED, InputError, StageFailed
from cloth.files.body import body_from_record
from cloth.files.casefile import write_case
from cloth.files.measured import Measurements, read_measurements
from cloth.io import atomic_folder
from cloth.pipeline.sweep import write_rows
from cloth.results.agreement import average_repeats, pooled_sd
from cloth.results.calibration import PARAMETERS, Interval, Parameter, determined, intervals
from cloth.results.landmarks import contact_force, landmark_heights
from cloth.results.pressure import MMHG
from cloth.results.sensing import Places, locate, model_readings
from cloth.solvers import Diverged, relax
from cloth.stages.case import initial_state
from cloth.stages.levels import reported_fields

log = logging.getLogger(__name__)

#: The readings' noise (Pa) where the file has no repeats: a pressure sensor's typical
#: repeatability under a garment, 2 mmHg.
NOISE = 2.0 * MMHG
#: Evaluations of the least-squares fit at most (each an equilibrium, plus one per fitted
#: parameter for its derivatives).
MAX_EVALUATIONS = 12
#: calibration.csv's columns.
CALIBRATION_COLUMNS = ["parameter", "units", "start", "value", "low", "high", "determined"]
#: fit.csv's columns.
FIT_COLUMNS = [
    "height_m",
    "angle_deg",
    "probe_mm",
    "measured_mmHg",
    "before_mmHg",
    "after_mmHg",
]


def parameter_names(text: str) -> tuple[str, ...]:
    """``--fit``'s comma-separated names, checked against `PARAMETERS`."""
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    for name in names:
        if name not in PARAMETERS:
            raise InputError(
                f"unknown parameter {name!r}; fit any of {', '.join(PARAMETERS)}", field="--fit"
            )
    if not names or len(set(names)) != len(names):
        raise InputError("name each parameter once, e.g. friction,tissue_modulus", field="--fit")
    return names


def start_values(data: dict, names: tuple[str, ...], source: str) -> dict[str, float]:
    """The case's own value of each parameter ``names``; `InputError` where the case cannot
    take one (a tissue modulus without a tissue layer)."""
    tissue = data["body"].get("tissue")
    out = {}
    for name in names:
        if name == "friction":
            out[name] = float((data.get("contact") or {}).get("friction", 0.0))
        elif name == "tissue_modulus":
            if not tissue:
                raise InputError(
                    "--fit tissue_modulus needs the case's body.tissue (thickness and a "
                    "starting modulus, docs/config.md)",
                    source,
                    "body.tissue",
                )
            out[name] = float(tissue["modulus"])
        else:
            out[name] = float(data.get("fabric_scale", 1.0))
    return out


def with_values(data: dict, values: dict[str, float]) -> dict:
    """The case mapping ``data`` with the parameters ``values`` set; the solver's continuation
    and reuse left to follow the skin (`cloth.case.case.following_skin`)."""
    out = following_skin(data)
    for name, value in values.items():
        if name == "friction":
            out["contact"] = {**(out.get("contact") or {}), "friction": float(value)}
        elif name == "tissue_modulus":
            out["body"]["tissue"] = {**out["body"]["tissue"], "modulus": float(value)}
        else:
            out["fabric_scale"] = float(value)
    return out


@dataclass
class Model:
    """The case's readings as a function of its parameters (module docstring): ``data`` the
    case mapping, ``measured`` the readings, ``base_dir`` for its files, ``overrides`` of its
    solver block; `places` found at the first evaluation; every evaluation kept by values."""

    data: dict
    measured: Measurements
    base_dir: Path
    overrides: dict
    source: str
    places: Places | None = None

    def __post_init__(self) -> None:
        self.cache: dict[tuple[tuple[str, float], ...], NDArray[np.float64]] = {}

    def readings(self, values: dict[str, float]) -> NDArray[np.float64]:
        """(R,) Pa: the model's reading at every measured reading with ``values`` set."""
        key = tuple(sorted((k, round(v, 12)) for k, v in values.items()))
        if key in self.cache:
            return self.cache[key]
        case = with_values(self.data, values)
        case["garment"] = {**case["garment"], "error_estimate": False}
        state = initial_state(validate_case(case, self.source), self.base_dir, self.source)
        body = body_from_record(state.body)
        settings = replace(state.case.solver, progress=False, **self.overrides)
        try:
            final = relax(state, body, settings).final
        except Diverged as exc:
            raise StageFailed(
                f"the case diverged with {values} ({exc}); start nearer, or fit fewer parameters",
                EXIT_DIVERGED,
            ) from None
        final, fields = reported_fields(state, final, body)
        shape = (state.grid.m, state.grid.n)
        if self.places is None:
            heights = landmark_heights(state.with_positions(final.x))
            self.places = locate(self.measured, heights, final.x, shape)
        out = model_readings(
            self.places, final.x, contact_force(fields), fields.area, state.case.reading
        )
        if not np.isfinite(out).all():
            bad = int(np.flatnonzero(~np.isfinite(out))[0])
            raise self.measured.error(bad, "height_m", "the probe there holds no garment")
        log.info(
            "calibrate: %s -> rms misfit %.3f mmHg",
            ", ".join(f"{k} {v:.4g}" for k, v in values.items()),
            rms(out - self.measured.pressure) / MMHG,
        )
        self.cache[key] = out
        return out


def rms(values: NDArray[np.float64]) -> float:
    """The root mean square of ``values``."""
    return float(np.sqrt(np.mean(values * values)))


def jacobian(
    model: Model,
    fixed: dict[str, float],
    params: list[Parameter],
    u: NDArray[np.float64],
    central: bool = False,
) -> NDArray[np.float64]:
    """(R, q) Pa per u: the readings' differences in ``params`` at ``u`` (the others
    ``fixed``): forward, or ``central`` where the step back stays within the bound (the
    intervals' Jacobian, second-order accurate)."""
    base = model.readings(fixed | values_of(params, u))
    columns = []
    for k, parameter in enumerate(params):
        ahead, back = u.copy(), u.copy()
        ahead[k] += parameter.step
        back[k] -= parameter.step
        forward = model.readings(fixed | values_of(params, ahead))
        if central and back[k] >= parameter.bound:
            behind = model.readings(fixed | values_of(params, back))
            columns.append((forward - behind) / (2 * parameter.step))
        else:
            columns.append((forward - base) / parameter.step)
    return np.stack(columns, axis=1) if columns else np.zeros((len(base), 0))


def values_of(params: list[Parameter], u: NDArray[np.float64]) -> dict[str, float]:
    """Parameter name -> value at internal coordinates ``u``."""
    return {p.name: p.of_u(float(v)) for p, v in zip(params, u, strict=True)}


@dataclass(frozen=True)
class Calibration:
    """What a calibration found: per parameter its ``start`` and fitted ``value``, its
    ``interval`` (None where not determined) and whether it is ``determined``; the readings
    ``before`` and ``after`` (R,) Pa, the noise ``sigma`` (Pa) the intervals use, the
    calibrated case mapping ``case`` and the readings' ``heights`` (R,) m."""

    start: dict[str, float]
    value: dict[str, float]
    interval: dict[str, Interval | None]
    determined: dict[str, bool]
    before: NDArray[np.float64]
    after: NDArray[np.float64]
    sigma: float
    case: dict
    heights: NDArray[np.float64]


def _place_keys(measured: Measurements) -> tuple:
    """Each reading's place: its point, height, angle and probe, as sequences."""
    return (
        measured.point,
        measured.height.tolist(),
        measured.angle.tolist(),
        measured.probe.tolist(),
    )


def readings_noise(measured: Measurements, noise: float) -> float:
    """The readings' noise (Pa): the repeats' pooled standard deviation where there are
    repeats, else ``noise``."""
    keys = list(zip(*_place_keys(measured), strict=True))
    averaged = average_repeats([str(k) for k in keys], measured.pressure)
    found = pooled_sd(averaged.count, averaged.sd)
    return found if math.isfinite(found) and found > 0 else noise


def fit(
    case_path: Path,
    measured_path: Path,
    names: tuple[str, ...],
    base_dir: Path | None = None,
    overrides: dict | None = None,
    noise: float = NOISE,
) -> Calibration:
    """Fit the parameters ``names`` of the case at ``case_path`` to the readings at
    ``measured_path`` (module docstring)."""
    source = str(case_path)
    data = load_case(case_path).to_dict()
    measured = read_measurements(measured_path)
    if len(measured.subjects) > 1:
        raise InputError(
            f"readings of {len(measured.subjects)} subjects; a case is one body: give one "
            "subject's readings (a study compares several, docs/validation.md)",
            measured.source,
            "subject",
        )
    if data["garment"].get("grid") == "auto":
        raise InputError(
            "calibrate fits on one grid: give garment.grid as [around, rows] (the grid auto "
            "would refine on every evaluation)",
            source,
            "garment.grid",
        )
    start = start_values(data, names, source)
    if "friction" in names:  # the solver must take friction: checked before any equilibrium
        validate_case(with_values(data, {"friction": 0.5}), source)
    folder = case_path.parent if base_dir is None else base_dir
    model = Model(data, measured, folder, dict(overrides or {}), source)
    params = [PARAMETERS[n] for n in names]
    u0 = np.array([p.to_u(start[p.name]) for p in params])
    before = model.readings(start)
    sigma0 = readings_noise(measured, noise)
    spans = np.array([p.span for p in params])
    known = determined(jacobian(model, {}, params, u0), spans, sigma0)
    places = len({(p, h, a, d) for p, h, a, d in zip(*_place_keys(measured), strict=True)})
    if places < len(params):
        log.warning(
            "calibrate: %d reading place%s cannot determine %d parameters, %d at most",
            places,
            "" if places == 1 else "s",
            len(params),
            places,
        )
    for p, ok in zip(params, known, strict=True):
        if not ok:
            log.warning(
                "calibrate: the readings do not determine %s (too little of the readings "
                "changes with it, or not apart from the others): held at its start, %g",
                p.name,
                start[p.name],
            )
    free = [p for p, ok in zip(params, known, strict=True) if ok]
    fixed = {p.name: start[p.name] for p, ok in zip(params, known, strict=True) if not ok}
    u = np.array([p.to_u(start[p.name]) for p in free])
    if free:
        u = _least_squares(model, fixed, free, u)
    values = fixed | values_of(free, u)
    after = model.readings(values)
    slopes = jacobian(model, fixed, free, u, central=True)
    found, sigma = intervals(slopes, after - measured.pressure, u, free, sigma0)
    spans_free = np.array([p.span for p in free])
    still = determined(slopes, spans_free, sigma) if free else []
    interval: dict[str, Interval | None] = {n: None for n in names}
    flags = {n: False for n in names}
    for p, item, ok in zip(free, found, still, strict=True):
        interval[p.name] = item
        flags[p.name] = bool(ok)
    log.info(
        "calibrate: rms misfit %.3f mmHg at the start, %.3f mmHg fitted",
        rms(before - measured.pressure) / MMHG,
        rms(after - measured.pressure) / MMHG,
    )
    case = with_values(data, values)
    heights = model.places.height if model.places is not None else measured.height
    return Calibration(start, values, interval, flags, before, after, sigma, case, heights)


def _least_squares(
    model: Model, fixed: dict[str, float], params: list[Parameter], u0: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The bounded least-squares fit of ``params`` from ``u0`` (module docstring)."""
    target = model.measured.pressure
    lower = np.array([p.bound for p in params])
    scale = np.array([p.span for p in params])

    def residual(u: NDArray[np.float64]) -> NDArray[np.float64]:
        return (model.readings(fixed | values_of(params, u)) - target) / MMHG

    def derivative(u: NDArray[np.float64]) -> NDArray[np.float64]:
        return jacobian(model, fixed, params, u) / MMHG

    solution = least_squares(
        residual,
        np.maximum(u0, lower),
        jac=derivative,
        bounds=(lower, np.full(len(params), np.inf)),
        x_scale=scale,
        max_nfev=MAX_EVALUATIONS,
        xtol=1e-4,
        ftol=1e-6,
    )
    return solution.x


def write_calibration(found: Calibration, measured_path: Path, output: Path, base_dir: Path):
    """calibration.csv, fit.csv and case.yaml into ``output`` (module docstring)."""
    measured = read_measurements(measured_path)
    rows = []
    for name, start in found.start.items():
        item = found.interval[name]
        rows.append(
            {
                "parameter": name,
                "units": PARAMETERS[name].units,
                "start": start,
                "value": found.value[name],
                "low": "" if item is None else item.low,
                "high": "" if item is None else item.high,
                "determined": int(found.determined[name]),
            }
        )
    with atomic_folder(output) as folder:  # the three files together or none
        _write_files(found, rows, measured, folder, base_dir)


def _write_files(found: Calibration, rows: list[dict], measured, folder: Path, base_dir: Path):
    write_rows(rows, folder / "calibration.csv", CALIBRATION_COLUMNS)
    fit_rows = [
        {
            "height_m": float(h),
            "angle_deg": float(a),
            "probe_mm": float(1e3 * d),
            "measured_mmHg": float(p / MMHG),
            "before_mmHg": float(b / MMHG),
            "after_mmHg": float(f / MMHG),
        }
        for h, a, d, p, b, f in zip(
            found.heights,
            measured.angle,
            measured.probe,
            measured.pressure,
            found.before,
            found.after,
            strict=True,
        )
    ]
    write_rows(fit_rows, folder / "fit.csv", FIT_COLUMNS)
    write_case(found.case, folder / "case.yaml", base_dir)
