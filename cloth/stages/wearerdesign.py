"""``cloth design CASE --wearers [DIR] --target LINE=LOW:HIGH ... -o OUT``: the robust design
(`cloth.stages.robust`) of a size's pattern for every wearer, confirmed from scratch on each.

In ``OUT``:

* ``case.yaml``: the case on the size's body with the designed reduction profile, cut for that
  body (the pattern every wearer wears);
* ``robust.csv``: per target line, its band, the loop's lowest and highest wearer, the
  confirmed lowest and highest wearer from scratch and who they are, the narrowest band the
  wearers span, the largest stated discretisation error, whether every wearer is inside
  (``met``), the knots' values, the min-max measure t, the equilibria used (mmHg;
  reductions 1) and the ``shortfall`` (blank where every band is met);
* ``confirmed/``: `cloth.stages.wearers` run on ``case.yaml``: every wearer's case and run,
  ``wearers.csv``, ``wearers.nc`` and ``wearers.png``.

A band no profile can hold writes all of these, ``met`` 0, then ends in one line naming the
line, the wearers at its ends and the narrowest band reached (`InputError`, exit status 2).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import xarray as xr

from cloth.bodies.wearers import SIZE
from cloth.case.case import load_case
from cloth.errors import InputError
from cloth.files.body import body_from_record
from cloth.files.casefile import write_case
from cloth.pipeline.sweep import write_rows
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.stages.case import initial_state
from cloth.stages.robust import Robust, robust_design
from cloth.stages.wearers import run_wearers, wearer_cases, wearers_of

log = logging.getLogger(__name__)


def robust_files(
    case_path: Path,
    targets: list[Target],
    output: Path,
    wearers: Path | None = None,
    base_dir: Path | None = None,
    fail: bool = True,
) -> Robust:
    """The robust design of ``case_path`` for the wearers of its size (``wearers``, else the
    shipped ones) and its files in ``output`` (module docstring); ``fail`` False (the
    pipeline): a band not met is reported in robust.csv (``met`` 0, ``shortfall``) only."""
    if not targets:
        raise InputError("give at least one band, e.g. --target B=23:32", field="--target")
    case = load_case(case_path)
    base_dir = Path(case_path).parent if base_dir is None else Path(base_dir)
    folder, index = wearers_of(case, base_dir, wearers)
    cases = wearer_cases(case, folder, index)
    cases.pop(SIZE)
    states, bodies = {}, {}
    for name, data in cases.items():
        states[name] = initial_state(data, base_dir, f"{case_path} (wearer {name})")
        bodies[name] = body_from_record(states[name].body)
    result = robust_design(states, bodies, targets, str(case_path))
    output.mkdir(parents=True, exist_ok=True)
    data = result.apply(case.to_dict())
    designed = write_case(data, output / "case.yaml", base_dir)
    confirmed = run_wearers(designed, output / "confirmed", {}, folder)
    rows = robust_rows(result, confirmed)
    shortfall = result.shortfall or next(
        (
            f"{r['landmark']}: confirmed from scratch the wearers span "
            f"{r['confirmed_min_mmHg']:.2f}-{r['confirmed_max_mmHg']:.2f} mmHg, outside the band "
            f"{r['band_low_mmHg']:.4g}-{r['band_high_mmHg']:.4g}"
            for r in rows
            if not r["met"]
        ),
        None,
    )
    for row in rows:
        row["shortfall"] = shortfall or ""
    write_rows(rows, output / "robust.csv", list(rows[0]))
    log.info(
        "robust design: %s on %d wearers in %d equilibria and %d from scratch",
        "every wearer in every band" if all(r["met"] for r in rows) else "NOT every band met",
        len(result.wearers),
        result.solves,
        len(result.wearers),
    )
    if shortfall is not None and fail:
        raise InputError(shortfall, case_path, "targets")
    return result


def robust_rows(result: Robust, confirmed: xr.Dataset) -> list[dict[str, object]]:
    """robust.csv's rows (module docstring), from the design and the confirmation's
    wearers.nc dataset."""
    names = [str(n) for n in confirmed["wearer"].values]
    wearers = [k for k, n in enumerate(names) if n != SIZE]
    rows = []
    for j, line in enumerate(result.lines):
        values = confirmed["pressure_mean"].sel(landmark=line).values[wearers] / MMHG
        errors = confirmed["pressure_mean_error"].sel(landmark=line).values[wearers] / MMHG
        low, high = result.bands[j] / MMHG
        lo, hi = int(np.nanargmin(values)), int(np.nanargmax(values))
        rows.append(
            {
                "landmark": line,
                "band_low_mmHg": round(float(low), 4),
                "band_high_mmHg": round(float(high), 4),
                "loop_min_mmHg": round(float(result.means[:, j].min() / MMHG), 4),
                "loop_max_mmHg": round(float(result.means[:, j].max() / MMHG), 4),
                "confirmed_min_mmHg": round(float(values[lo]), 4),
                "min_wearer": names[wearers[lo]],
                "confirmed_max_mmHg": round(float(values[hi]), 4),
                "max_wearer": names[wearers[hi]],
                "spread_mmHg": round(float(values[hi] - values[lo]), 4),
                "discretisation_error_mmHg": ""
                if not np.isfinite(errors).any()
                else round(float(np.nanmax(errors)), 4),
                "met": int(bool(np.all((values >= low) & (values <= high)))),
                "t": round(result.t, 4),
                "reduction": _reduction_text(result),
                "wearers": len(wearers),
                "equilibria": result.solves + len(wearers),
            }
        )
    return rows


__all__ = ["robust_files", "robust_rows"]


def _reduction_text(result) -> str:
    """The designed reductions as robust.csv gives them: ``knot=value`` (and ``band_NAME=value``)
    separated by spaces; a uniform reduction the loop left alone as its one number."""
    reduction = result.reduction()
    parts = (
        [f"{k}={v:.5f}" for k, v in reduction.items()]
        if isinstance(reduction, dict)
        else [f"{float(reduction):.5f}"]
    )
    parts += [f"band_{k}={v:.5f}" for k, v in result.band_reductions().items()]
    return " ".join(parts)
