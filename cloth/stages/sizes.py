"""``cloth sizes CASE --population FILE --target LINE=LOW:HIGH ... -o DIR`` (issue 62): a size
chart designed for a measured population, one garment per size, confirmed by equilibrium.

1. **The people** (`cloth.files.population`): her girths at the target lines and the sizing
   measures (``--by``), by the chart's names (a survey's ``ankle_cm`` is B).
2. **Calibrate** the fast model (`cloth.results.tubemodel`) on full equilibria: the people at
   the primary measure's 5th, 50th and 95th percentile, each wearing a pattern cut by Laplace
   to the low end, the middle and the high end of every band, and of the people in the
   primary measure's middle fifth those at the 5th and 95th percentile of each shape feature
   (her stature and girth ratios against the template's), cut to the middle. Each pattern is
   cut, as a size's is, on the template's body with her girths at the sizing lines.
3. **Search** the chart with the fast model (`cloth.results.sizechart`), a margin inside
   every band: the one asked, or by default (``margin`` None) twice the fast model's rms
   error on the equilibria it was fitted to, at least `LEAST_MARGIN`.
4. **Confirm** every size from scratch on its extreme wearers: of the people who fit it, those
   with the lowest and the highest predicted pressure at each target line (the ends of its
   ranges), each a parametric leg or torso of her measures (`cloth.bodies.person`) wearing the
   size's pattern, cut for the size's body in ``chart.csv`` and placed by the lowest girth
   line. A size is confirmed where every confirmation converged and is inside every band.
5. Where one is not, it is **recut** from what its own equilibria read (`cloth.results.recut`:
   its cut moved so the confirmed extremes are centred in the band, or its range narrowed
   where they spread wider than the band) and confirmed again, up to ``rounds`` rounds in all.
   A size still not confirmed is written with ``confirmed`` 0, and the command ends with
   `shortfall_of`'s one line, exit status 2 (`cloth.stages.sizeruns`).

Each run is a plain ``cloth run`` of the ``case.yaml`` written beside it. Last, each size's
garment runs on its own body (``{size}/``, the size's row of ``chart.csv``), and a stocking's
sizes get their knitting table (``pattern_knitting.csv``, `cloth.files.knitting`).
`cloth.stages.sizetables` writes the tables and `cloth.figures.sizes` the figure.
"""

from __future__ import annotations

import csv
import logging
import os
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import NDArray

from cloth.bodies.avatar import ChartTargets, chart_rows, chart_targets
from cloth.bodies.leg import ABOVE, BELOW
from cloth.bodies.person import person_body, template_girths
from cloth.case.case import load_case
from cloth.case.locations import relocated
from cloth.files.material import case_fabric
from cloth.files.population import read_population
from cloth.io import atomic_output
from cloth.progress import progress
from cloth.results.pressure import MMHG
from cloth.results.recut import recut
from cloth.results.sizechart import Chart, People, Size, design_chart, extreme_wearers
from cloth.results.tubemodel import Calibration, LineModel, Tension, laplace
from cloth.stages.case import run_case
from cloth.stages.sizerequest import Request, measure_names, template_of
from cloth.stages.sizeruns import NO_RECUT, Confirmation, Run, confirmed, shortfall

log = logging.getLogger(__name__)

#: The least margin inside a band the search keeps by default, Pa.
LEAST_MARGIN = 0.5 * MMHG
#: The reductions a run's pattern may be cut with (the case schema's).
REDUCTION = (0.0, 0.89)
#: How far inside a wearer's body a garment's edge is kept, m.
INSET = 0.002
#: Quantiles of the primary measure whose people calibrate the fast model.
CALIBRATE_AT = (0.05, 0.5, 0.95)


def _cm(row: dict[str, str], column: str) -> float:
    return 0.01 * float(row[column])


def body_extent(kind: str, row: dict[str, str]) -> tuple[float, float]:
    """The heights (m) a parametric leg or torso of the chart ``row`` spans: a leg `BELOW` B
    to `ABOVE` G (`cloth.bodies.leg`), a torso its bottom to top."""
    if kind == "leg":
        return _cm(row, "B_height_cm") - BELOW, _cm(row, "G_height_cm") + ABOVE
    return _cm(row, "bottom_height_cm"), _cm(row, "top_height_cm")


class Sizing:
    """The runs of one ``cloth sizes``: the case, its template, the people and the fabric."""

    def __init__(self, case_path: Path, request: Request, output: Path, overrides: dict) -> None:
        self.case_path = case_path
        self.base_dir = case_path.parent
        self.case = load_case(case_path)
        self.request = request
        self.output = output
        self.overrides = overrides
        self.kind, self.chart, self.size, self.spec = template_of(self.case, self.base_dir)
        self.targets: ChartTargets = chart_targets(self.chart, self.size)
        self.points = tuple(sorted(self.targets.height, key=self.targets.height.get))
        self.people = read_population(request.population, request.ages)
        measure_names(request, self.people, self.points)
        rows = chart_rows(self.chart)[1]
        self.template = next(r for r in rows if (r.get("size") or "").strip() == self.size)
        self.tension = Tension.of(case_fabric(self.case, self.base_dir))
        self.bands = {b.line: b for b in request.bands}
        self.lines = tuple(self.bands)
        self.girths = {line: self.people.measures[line] for line in self.lines}
        self.calibration: dict[str, tuple[list[float], list[float], list[float]]] = {
            line: ([], [], []) for line in self.lines
        }
        shapes = {line: self.shape_features(line) for line in self.lines}
        self.features = {line: shapes[line][0] for line in self.lines}
        #: line -> each feature's name and spread (`shape_features`)
        self.feature_names = {line: shapes[line][1] for line in self.lines}
        self.feature_spreads = {line: shapes[line][2] for line in self.lines}

    def shape_features(self, line: str) -> tuple[NDArray[np.float64], list[str], list[float]]:
        """(P, F) each person's shape against the template's at ``line`` (module docstring of
        `cloth.results.tubemodel`): her stature over its (``stature``), and each other girth
        she has over her girth at the line (``{point}_over_{line}``), each over the
        template's, less 1; standardised across the people (NaN where not measured); with
        the features' names and their spreads (standard deviations before standardising)."""
        measures = self.people.measures
        t_girth, _, t_stature = template_girths(self.template, self.points)
        columns, names = [], []
        if "stature" in measures and np.isfinite(t_stature):
            columns.append(measures["stature"] / t_stature - 1.0)
            names.append("stature")
        for point in self.points:
            if point != line and point in measures and point in t_girth:
                ratio = measures[point] / measures[line]
                columns.append(ratio / (t_girth[point] / t_girth[line]) - 1.0)
                names.append(f"{point}_over_{line}")
        if not columns:
            return np.zeros((len(self.people.weight), 0)), [], []
        table = np.column_stack(columns)
        spread = np.nanstd(table, axis=0)
        spread = np.where(spread > 0, spread, 1.0)
        return table / spread, names, spread.tolist()

    def offsets(self, models: dict[str, LineModel]) -> dict[str, NDArray[np.float64]]:
        """Each line's shape term (Pa) on every person (`Calibration.offset`)."""
        return {line: models[line].calibration.offset(self.features[line]) for line in self.lines}

    # -- bodies and cases ---------------------------------------------------------------------

    def person_row(self, index: int, name: str) -> dict[str, str]:
        """Person ``index``'s one-row chart, named ``name``."""
        measures = self.people.measures
        girths = {p: float(measures[p][index]) for p in self.points if p in measures}
        girths = {p: g for p, g in girths.items() if np.isfinite(g)}
        heights = {
            p: float(measures[f"{p}_height"][index])
            for p in self.points
            if f"{p}_height" in measures and np.isfinite(measures[f"{p}_height"][index])
        }
        stature = measures.get("stature")
        height = float(stature[index]) if stature is not None else None
        return person_body(self.template, self.points, girths, heights, height, name)

    def write_chart(self, rows: list[dict[str, str]], path: Path) -> Path:
        """A chart of ``rows`` in the template's columns (ranges where a row has them)."""
        columns = list(dict.fromkeys(k for row in rows for k in row))
        with atomic_output(path) as tmp, tmp.open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=columns, restval="")
            writer.writeheader()
            writer.writerows(rows)
        return path

    def case_data(
        self, folder: Path, body: tuple[Path, str], pattern: tuple[Path, str], rest: dict
    ) -> tuple[dict, dict[str, float]]:
        """The case of one run in ``folder`` (the case's garment, solver and material, the
        body ``body`` (chart, size), the pattern cut on ``pattern`` (chart, size) by the
        reduction profile that gives each line's ``rest`` circumference (m) there) and the
        rest circumferences it cuts: a reduction is kept within `REDUCTION` (a row cannot be
        cut larger than the body it is cut on)."""
        data = relocated(self.case.to_dict(), self.base_dir, folder)
        extra = {k: v for k, v in self.spec.items() if k in ("surface", "around", "rings")}
        cut_chart, cut_size = pattern
        cut = chart_targets(cut_chart, cut_size)

        def block(chart: Path, size: str) -> dict:
            return {self.kind: {**extra, "chart": os.path.relpath(chart, folder), "size": size}}

        data["body"] = {**{k: v for k, v in data["body"].items() if k != self.kind}}
        data["body"].update(block(*body))
        garment = data["garment"]
        garment["bottom"], garment["top"] = self.extent(
            garment["bottom"], garment["top"], self.row_of(*body), self.row_of(*pattern)
        )
        garment.pop("circumference", None)
        garment["pattern"] = {"body": block(*pattern)}
        reduction = {
            line: float(np.clip(1.0 - rest[line] / cut.girth[line], *REDUCTION))
            for line in self.lines
        }
        garment["reduction"] = reduction
        return data, {line: (1.0 - reduction[line]) * cut.girth[line] for line in self.lines}

    def row_of(self, chart: Path, size: str) -> dict[str, str]:
        """The row of ``size`` in ``chart``."""
        return next(r for r in chart_rows(chart)[1] if (r.get("size") or "").strip() == size)

    def extent(
        self, bottom: float, top: float, wearer: dict[str, str], pattern: dict[str, str]
    ) -> tuple[float, float]:
        """The garment's ``bottom`` and ``top`` (m, the pattern body's frame) kept `INSET`
        inside the wearer's body once placed by the lowest girth line (a shorter wearer's
        leg ends lower than the template's)."""
        line = self.points[0]
        shift = _cm(wearer, f"{line}_height_cm") - _cm(pattern, f"{line}_height_cm")
        low, high = body_extent(self.kind, wearer)
        return max(bottom, low - shift + INSET), min(top, high - shift - INSET)

    def features_of(self, person: int) -> dict[str, NDArray[np.float64]]:
        return {line: self.features[line][person] for line in self.lines}

    def run(
        self, name: str, folder: Path, data: dict, girth: dict, rest: dict, features: dict
    ) -> Run:
        """Write ``data`` as ``folder/case.yaml``, run it to its summary and read it back."""
        path = folder / "case.yaml"
        folder.mkdir(parents=True, exist_ok=True)
        with atomic_output(path) as tmp:
            tmp.write_text(yaml.safe_dump(data, sort_keys=False))
        run_case(path, folder, self.overrides, stop_after="aggregate")
        out = Run(name, folder, girth, rest, features)
        with (folder / "summary.csv").open() as handle:
            for row in csv.DictReader(handle):
                if row["landmark"] in self.bands:
                    out.pressure[row["landmark"]] = float(row["pressure_mean_Pa"] or "nan")
                    out.error[row["landmark"]] = float(row.get("pressure_mean_error_Pa") or "nan")
                    out.converged = row.get("converged", "1") == "1"
        return out

    def learn(self, runs: list[Run]) -> None:
        """Add each converged run (its weft term by Laplace, her shape features and the band
        mean) to the calibration."""
        for run in runs:
            if not run.converged:
                continue
            for line in self.lines:
                p = run.pressure.get(line, float("nan"))
                weft = float(laplace(self.tension, run.girth[line], run.rest[line]))
                if np.isfinite(p):
                    self.calibration[line][0].append(weft)
                    self.calibration[line][1].append(run.features[line])
                    self.calibration[line][2].append(p)

    def models(self) -> dict[str, LineModel]:
        out = {}
        for line in self.lines:
            weft, features, pressure = self.calibration[line]
            count = self.features[line].shape[1]
            table = np.array(features).reshape(len(weft), count)
            out[line] = LineModel(self.tension, Calibration.fit(weft, table, pressure))
        return out

    def errors(self, models: dict[str, LineModel]) -> dict[str, float]:
        """Each line's rms error (Pa) of the fast model on the equilibria it was fitted to
        (NaN where none)."""
        out = {}
        for line in self.lines:
            weft, features, pressure = self.calibration[line]
            if not pressure:
                out[line] = float("nan")
                continue
            calibration = models[line].calibration
            table = np.array(features).reshape(len(weft), self.features[line].shape[1])
            predicted = calibration.hoop * np.array(weft) + calibration.offset(table)
            out[line] = float(np.sqrt(np.mean((predicted - np.array(pressure)) ** 2)))
        return out

    def margins(self, models: dict[str, LineModel]) -> dict[str, float]:
        """The search's margin at each line (module docstring, step 3), Pa."""
        if self.request.margin is not None:
            return dict.fromkeys(self.lines, self.request.margin)
        errors = self.errors(models)
        return {
            line: max(LEAST_MARGIN, 2 * errors[line]) if np.isfinite(errors[line]) else LEAST_MARGIN
            for line in self.lines
        }

    def population(self, models: dict[str, LineModel]) -> People:
        return People(self.girths, self.offsets(models), self.people.weight)

    # -- the steps ----------------------------------------------------------------------------

    def calibrate(self) -> list[Run]:
        """Step 2 (module docstring)."""
        primary = self.girths[self.request.by[0]]
        complete = np.ones(len(primary), dtype=bool)
        for values in self.girths.values():
            complete &= np.isfinite(values)
        index = np.flatnonzero(complete)
        exact = LineModel(self.tension, Calibration.exact())
        runs = []
        chosen: dict[int, float] = {}
        for q in CALIBRATE_AT:
            value = np.quantile(primary[index], q)
            person = int(index[np.argmin(np.abs(primary[index] - value))])
            chosen.setdefault(person, q)
        # then the ends of each shape feature among the middle of the primary measure
        low, high = np.quantile(primary[index], [0.4, 0.6])
        middle = index[(primary[index] >= low) & (primary[index] <= high)]
        features = self.features[self.request.by[0]][middle]
        for column in range(features.shape[1]):
            values = features[:, column]
            known = np.isfinite(values)
            for q in (CALIBRATE_AT[0], CALIBRATE_AT[-1]):
                if known.any():
                    target = np.nanquantile(values, q)
                    person = int(middle[known][np.argmin(np.abs(values[known] - target))])
                    chosen.setdefault(person, 0.5)
        rows = []
        for k, person in enumerate(chosen):
            rows.append(self.person_row(person, f"calibrate_{k + 1}"))
            rows.append(self.size_body(person, f"calibrate_{k + 1}_size"))
        folder = self.output / "calibration"
        self.write_chart(rows, folder / "people.csv")
        for k, (person, q) in enumerate(
            progress(list(chosen.items()), desc="calibration", unit="case")
        ):
            name = f"calibrate_{k + 1}"
            girth = {line: float(self.girths[line][person]) for line in self.lines}
            # the band's low end by Laplace for the smallest, its middle, its high end: the
            # weft terms differ, so the fit tells the hoop from the warp
            rest = {
                line: float(exact.rest_for(girth[line], b.low + q * (b.high - b.low)))
                for line, b in self.bands.items()
            }
            target = folder / name
            bodies = folder / "people.csv"
            data, cut = self.case_data(target, (bodies, name), (bodies, f"{name}_size"), rest)
            runs.append(self.run(name, target, data, girth, cut, self.features_of(person)))
        self.learn(runs)
        return runs

    def search(self, models: dict[str, LineModel]) -> Chart:
        """Step 3, with the fast ``models`` of this round."""
        r = self.request
        return design_chart(
            self.population(models),
            r.by,
            models,
            self.bands,
            r.coverage,
            r.max_sizes,
            r.variants,
            self.margins(models),
        )

    def size_body(self, person: int, name: str) -> dict[str, str]:
        """The body a size centred on person ``person``'s sizing measures would be cut on:
        the template with her girths at the sizing lines (`size_rows` alike)."""
        measures = {m: float(self.girths[m][person]) for m in self.request.by}
        return person_body(self.template, self.points, measures, {}, None, name)

    def size_rows(self, chart: Chart) -> list[dict[str, str]]:
        """chart.csv's rows: each size's body at its ranges' centres (`cloth.bodies.person`,
        from the template), with its ranges."""
        rows = []
        for size in chart.sizes:
            centre = {m: 0.5 * (low + high) for m, (low, high) in size.ranges.items()}
            row = person_body(self.template, self.points, centre, {}, None, size.name)
            for m, (low, high) in size.ranges.items():
                row[f"{m}_min_cm"] = f"{100 * low:.6g}"
                row[f"{m}_max_cm"] = f"{100 * high:.6g}"
            rows.append(row)
        return rows

    def extremes(self, size: Size, models: dict[str, LineModel]) -> dict[str, int]:
        """The size's extreme wearers by the fast ``models`` (module docstring, step 4;
        `cloth.results.sizechart.extreme_wearers`): name -> person index."""
        return extreme_wearers(size, self.population(models), models, self.lines)

    def confirm(
        self, sizes: list[Size], chart_path: Path, models: dict[str, LineModel]
    ) -> list[Confirmation]:
        """Step 4: every size of ``sizes`` on its extreme wearers by the fast ``models``
        (its corrected model where it was recut), each in ``{size}/confirm/`` anew; a recut
        size's confirmations of the round before move to ``{size}/confirm_round{k}/`` (k its
        recuts: round k's)."""
        found = []
        jobs = []
        for size in sizes:
            wearers = self.extremes(size, models) if len(size.members) else {}
            folder = self.output / size.name / "confirm"
            if size.recuts and folder.is_dir():  # the round before, kept beside: what it read
                kept = folder.with_name(f"confirm_round{size.recuts}")
                shutil.rmtree(kept, ignore_errors=True)
                folder.rename(kept)
            shutil.rmtree(folder, ignore_errors=True)  # a run into a folder used before
            rows = [self.person_row(p, n) for n, p in wearers.items()]
            if rows:
                self.write_chart(rows, folder / "people.csv")
            confirmation = Confirmation(size, [], wearers)
            found.append(confirmation)
            for name, person in wearers.items():
                girth = {line: float(self.girths[line][person]) for line in self.lines}
                body = (folder / "people.csv", name)
                jobs.append((confirmation, name, folder / name, body, girth))
        for confirmation, name, target, body, girth in progress(
            jobs, desc="confirmations", unit="case"
        ):
            size = confirmation.size
            pattern = (chart_path, size.name)
            data, cut = self.case_data(target, body, pattern, size.rest)
            person = confirmation.wearers[name]
            run = self.run(name, target, data, girth, cut, self.features_of(person))
            confirmation.runs.append(run)
        return found

    def recut(
        self, chart: Chart, confirmations: list[Confirmation], models: dict[str, LineModel]
    ) -> tuple[Chart, list[Confirmation]]:
        """Step 5: each size not confirmed recut from its confirmations
        (`cloth.results.recut`) and confirmed again, the others as they were; the chart of
        them (chart.csv rewritten, its coverage recounted) and their confirmations."""
        out = list(confirmations)
        again = []
        people = self.population(models)
        for k, c in enumerate(confirmations):
            if confirmed(c, self.bands):
                continue
            found = recut(c.size, c.reads(), people, models, self.bands)
            log.info("%s %s: %s", c.size.name, "recut" if found.size else "not recut", found.why)
            if found.size is None:
                out[k] = replace(c, why=f"{NO_RECUT}: {found.why}")
                continue
            out[k] = replace(c, size=found.size, why=found.why)
            again.append(k)
        sizes = [c.size for c in out]
        weight = self.people.weight
        total = float(weight[chart.people].sum())
        fitted = sum(float(weight[s.members[s.fits]].sum()) for s in sizes)
        chart = replace(chart, sizes=tuple(sizes), coverage=fitted / total if total else 0.0)
        if again:
            self.write_chart(self.size_rows(chart), self.output / "chart.csv")
            found = self.confirm([out[k].size for k in again], self.output / "chart.csv", models)
            for k, c in zip(again, found, strict=True):
                out[k] = replace(c, why=out[k].why)
        return chart, out

    def size_cases(self, chart: Chart, chart_path: Path) -> list[Path]:
        """Each size's ``{size}/case.yaml`` (its garment as a pattern on its own body, the
        size's row of chart.csv) run into ``{size}/`` (its result.nc gives the knitting
        table); the results."""
        results = []
        for size in progress(list(chart.sizes), desc="sizes' own bodies", unit="case"):
            folder = self.output / size.name
            data, _ = self.case_data(
                folder, (chart_path, size.name), (chart_path, size.name), size.rest
            )
            path = folder / "case.yaml"
            folder.mkdir(parents=True, exist_ok=True)
            with atomic_output(path) as tmp:
                tmp.write_text(yaml.safe_dump(data, sort_keys=False))
            run_case(path, folder, self.overrides, stop_after="aggregate")
            results.append(folder / "result.nc")
        return results


@dataclass
class Outcome:
    """What ``cloth sizes`` found: the final chart and its confirmations, every round's, the
    calibration runs, and the fast model the chart was searched with."""

    sizing: Sizing
    chart: Chart
    confirmations: list[Confirmation]
    calibration: list[Run]
    models: dict[str, LineModel]
    rounds: int


def shortfall_of(outcome: Outcome) -> str | None:
    """The command's last line where a size is not confirmed (`cloth.stages.sizeruns.
    shortfall`); None where every size is."""
    sizing = outcome.sizing
    return shortfall(outcome.confirmations, sizing.bands, sizing.people.ids, outcome.rounds)


def design_sizes(case_path: Path, request: Request, output: Path, overrides: dict) -> Outcome:
    """Steps 1-5 of the module docstring into ``output``; the tables and the figure are
    `cloth.stages.sizetables.write_sizes`'."""
    sizing = Sizing(case_path, request, output, overrides)
    calibration = sizing.calibrate()
    chart_path = output / "chart.csv"
    models = sizing.models()
    errors = sizing.errors(models)
    for line in sizing.lines:
        log.info(
            "the fast model at %s: hoop %.3f, shape terms %s Pa; rms error %.2f mmHg on %d "
            "equilibria",
            line,
            models[line].calibration.hoop,
            np.array2string(models[line].calibration.shape, precision=0),
            errors[line] / MMHG,
            len(sizing.calibration[line][2]),
        )
    chart = sizing.search(models)
    log.info(
        "%d sizes cover %.1f %% of %d people (asked %.1f %%), each held over the central "
        "%.0f %% of their shape terms",
        len(chart.sizes),
        100 * chart.coverage,
        len(chart.people),
        100 * request.coverage,
        100 * chart.shape_share,
    )
    sizing.write_chart(sizing.size_rows(chart), chart_path)
    confirmations = sizing.confirm(list(chart.sizes), chart_path, models)
    round_ = 1
    while round_ < request.rounds and not all(confirmed(c, sizing.bands) for c in confirmations):
        round_ += 1
        log.info("round %d: the sizes not confirmed, recut from their equilibria", round_)
        chart, confirmations = sizing.recut(chart, confirmations, models)
    results = sizing.size_cases(chart, chart_path)
    if sizing.kind == "leg" and results:  # a stocking is knitted as a tube
        from cloth.stages.patterns import write_patterns  # late: the pattern writers

        names = [size.name for size in chart.sizes]
        write_patterns(results, output / "pattern.csv", "tube", ["knitting"], names)
    return Outcome(sizing, chart, confirmations, calibration, models, round_)


__all__ = ["CALIBRATE_AT", "Outcome", "design_sizes", "shortfall_of"]
