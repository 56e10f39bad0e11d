"""``cloth design CASE --sizes S,M,L --target ... -o DIR``: every size of a size chart designed
to the same pressure targets at once (issue 42); or ``cloth design S.yaml M.yaml L.yaml``, one
case file per size (the pipeline's ``profile_designs`` with a list of ``bodies``), each size
named by its file's stem.

With ``--sizes`` the case's body is a parametric torso or leg, and each size is the case with
that size of the body's chart (`cloth.bodies.torso`, `cloth.bodies.leg`); a size not in the
chart is refused before any equilibrium, naming the chart's sizes.

The sizes are designed in the order given. Each after the first starts from the designed
reduction profile of the one before it (its knots and their values: the warm start), not from
the case's uniform reduction; ``cold=True`` starts each from the case. Each size is the single
design of `cloth.stages.graded` in ``DIR/{size}/`` (case.yaml, design_iterations.csv,
confirmed/, design_profile.png). Over the chart, in ``DIR``:

* ``design_confirmed.csv``: one row per size and target line (column ``size`` first);
* ``design_reductions.png``: each size's confirmed reduction profile over the body's height,
  its knots marked;
* the pattern of every size (`cloth.stages.patterns`): ``pattern_{size}.csv``, ``.svg``,
  ``.dxf`` and ``.pdf``, the graded nest ``pattern_astm.dxf``, and for a tube the knitting
  table ``pattern_knitting.csv`` and ``.png``.

A size whose targets are out of reach is written like the others, marked ``met`` 0, and the
command then ends in one line naming the size and the line (exit status 2).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from cloth.bodies.leg import DEFAULT_LEG_CHART, read_leg_chart
from cloth.bodies.torso import DEFAULT_CHART, read_chart
from cloth.case import Case
from cloth.case.case import load_case
from cloth.errors import InputError
from cloth.figures.plots import save_figure
from cloth.files.piece import SEAM_ALLOWANCE_MM
from cloth.paths import input_file
from cloth.pipeline.designplots import plot_profile_design
from cloth.pipeline.sweep import write_rows
from cloth.results.targets import Target
from cloth.stages.design import TOLERANCE, Design
from cloth.stages.graded import (
    check_targets,
    cut_of,
    design_one,
    raise_unmet,
    target_note,
)
from cloth.stages.patterns import write_patterns

log = logging.getLogger(__name__)

CHARTS = {"torso": (DEFAULT_CHART, read_chart), "leg": (DEFAULT_LEG_CHART, read_leg_chart)}


@dataclass(frozen=True)
class SizeCase:
    """One size of a chart design: its case, the folder its relative paths are relative to,
    and where it came from (for messages)."""

    case: Case
    base_dir: Path
    source: str


def chart_sizes(case_path: Path, sizes: list[str], base_dir: Path | None) -> dict[str, SizeCase]:
    """The case at ``case_path`` once per size of its body's chart (module docstring)."""
    case = load_case(case_path)
    base_dir = Path(case_path).parent if base_dir is None else Path(base_dir)
    kind = case.body.kind
    if kind not in CHARTS:
        raise InputError(
            f"--sizes takes a case on a parametric torso or leg (a size chart's body), not a "
            f"{kind}; give one case file per size instead",
            case_path,
            "body",
        )
    default, read = CHARTS[kind]
    params = case.body.params
    chart = default
    if "chart" in params:
        chart = input_file(params["chart"], base_dir, case_path, f"body.{kind}.chart", "chart")
    known = list(read(chart))
    repeated = [s for s in sizes if sizes.count(s) > 1]
    if repeated:
        raise InputError(f"the size {repeated[0]!r} is given twice", field="--sizes")
    for size in sizes:
        if size not in known:
            raise InputError(
                f"size {size!r} is not in the chart; its sizes: {', '.join(known)}",
                chart,
                "--sizes",
            )
    out = {}
    for size in sizes:
        data = case.to_dict()
        data["body"][kind]["size"] = size
        out[size] = SizeCase(Case.from_dict(data, str(case_path)), base_dir, str(case_path))
    return out


def file_sizes(case_paths: list[Path], base_dir: Path | None) -> dict[str, SizeCase]:
    """One size per case file, named by the file's stem."""
    names = [Path(p).stem for p in case_paths]
    repeated = [n for n in names if names.count(n) > 1]
    if repeated:
        raise InputError(
            f"two case files named {repeated[0]!r}: a size is named by its case file's stem; "
            "rename one",
            field="input",
        )
    return {
        name: SizeCase(
            load_case(path),
            Path(path).parent if base_dir is None else Path(base_dir),
            str(path),
        )
        for name, path in zip(names, case_paths, strict=True)
    }


def design_chart(
    sizes: dict[str, SizeCase],
    targets: list[Target],
    output: Path,
    tolerance: float = TOLERANCE,
    cut: str = "auto",
    allowance: float = SEAM_ALLOWANCE_MM,
    paper: str = "A4",
    cold: bool = False,
) -> dict[str, Design]:
    """Every size of ``sizes`` designed to ``targets``, its files in ``output`` (module
    docstring); `InputError` after writing them when a size's target is out of reach."""
    check_targets(targets)
    first = next(iter(sizes.values()))
    cut = cut_of(first.case, cut)
    designs: dict[str, Design] = {}
    rows: list[dict[str, object]] = []
    previous: Design | None = None
    for size, entry in sizes.items():
        case = entry.case
        if previous is not None and not cold:
            case = warm_case(case, previous, entry.source)
        start = time.perf_counter()
        result, size_rows = design_one(
            case, targets, output / size, tolerance, entry.base_dir, entry.source
        )
        plot_profile_design(size_rows, output / size / "design_profile.png")
        log.info(
            "size %s: %d equilibria (%d in the loop, 1 confirmation), %.1f s%s",
            size,
            result.solves + 1,
            result.solves,
            time.perf_counter() - start,
            "" if previous is None or cold else f", warm-started from size {list(designs)[-1]}",
        )
        designs[size] = result
        rows += [{"size": size, **row} for row in size_rows]
        previous = result
    header = list(dict.fromkeys(key for row in rows for key in row))
    write_rows(rows, output / "design_confirmed.csv", header)
    results = {size: output / size / "confirmed" / "result.nc" for size in sizes}
    plot_reductions(results, output / "design_reductions.png")
    write_patterns(
        list(results.values()),
        output / "pattern.csv",
        cut,
        None,  # every format that applies and is installed
        sizes=list(results),
        allowance=allowance,
        paper=paper,
        notes=[target_note(rows)],
        style=output.name,
    )
    for size, result in designs.items():
        raise_unmet(
            result,
            [row for row in rows if row["size"] == size],
            tolerance,
            f"{sizes[size].source} (size {size})",
        )
    return designs


def warm_case(case: Case, previous: Design, source: str = "case") -> Case:
    """``case`` starting from ``previous``'s designed reduction profile (the warm start)."""
    data = case.to_dict()
    data["garment"]["reduction"] = previous.reduction()
    return Case.from_dict(data, source)


def plot_reductions(results: dict[str, Path], path: Path) -> Path:
    """Each size's confirmed reduction profile (row_reduction) over the body height the rows
    were cut for, its knots marked."""
    fig, ax = plt.subplots(figsize=(5.5, 4.5), layout="constrained")
    for size, file in results.items():
        result = xr.load_dataset(file)
        height = result["cut_height"].values
        reduction = result["row_reduction"].values
        (line,) = ax.plot(reduction, height, label=size)
        if "landmark" in result.coords:
            lines = result["landmark_height"].values
            inside = (lines >= height.min()) & (lines <= height.max())
            ax.plot(
                np.interp(lines[inside], height, reduction),
                lines[inside],
                "o",
                color=line.get_color(),
                ms=4,
            )
    ax.set_xlabel("reduction of the rest circumference from the body's girth [1]")
    ax.set_ylabel("body height [m]")
    ax.set_title("designed reduction profile per size (dots: girth lines)", fontsize=10)
    ax.legend(title="size", fontsize=8)
    return save_figure(fig, path)
