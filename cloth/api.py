"""cloth from Python (issue 70): the stages a command runs, as functions of cases and files.

Each function is a thin layer over the stage its command calls (``cloth run``, ``cloth
design``, ``cloth sizes``, ``cloth compare``, ``cloth calibrate``), so an answer is the same
either way, and bad input raises `cloth.InputError` with the command's one-line message. A
case is a `cloth.Case` (``Case.load(path)``, ``Case.of(mapping)``), a mapping as a case file
holds it, or the path of a case file; a case given as an object is written as ``case.yaml``
into the output folder first (its relative paths taken from ``base_dir``), as the commands
read one.

Examples
--------
>>> import cloth
>>> case = {"material": "powernet", "body": {"torso": {"size": "M"}},
...         "garment": {"bottom": 0.9, "top": 1.15, "reduction": 0.15, "grid": [24, 8]}}
>>> run = cloth.run(case, "out")  # doctest: +SKIP
>>> run.summary[["landmark", "pressure_mean_mmHg"]]  # doctest: +SKIP
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import xarray as xr

from cloth.bodies import Body
from cloth.case import Case
from cloth.case.case import validate_case
from cloth.errors import InputError
from cloth.files.body import body_from_config
from cloth.files.casefile import write_case
from cloth.files.material import load_fabric
from cloth.materials.curves import Fabric
from cloth.results.pressure import MMHG
from cloth.results.targets import Target
from cloth.stages.case import run_case

#: What a case may be given as.
CaseLike = Case | Mapping[str, Any] | str | Path


@dataclass(frozen=True)
class Run:
    """One case run (`run`): its output ``folder``, ``result`` (result.nc, loaded: every field
    on every node, `docs/outputs.md`) and ``summary`` (summary.csv as a `pandas.DataFrame`, a
    row per girth line: pressures in Pa and mmHg with their stated errors)."""

    folder: Path
    result: xr.Dataset
    summary: Any


def _case_file(case: CaseLike, output: Path, base_dir: str | Path | None) -> tuple[Path, Path]:
    """The case file a command would read for ``case`` and the folder its paths are relative
    to: a path as it is; an object written as ``output``/case.yaml (paths from ``base_dir``,
    default the working folder), validated first."""
    if isinstance(case, str | Path):
        path = Path(case)
        return path, path.parent if base_dir is None else Path(base_dir)
    typed = case if isinstance(case, Case) else validate_case(dict(case))
    output.mkdir(parents=True, exist_ok=True)
    written = write_case(typed.to_dict(), output / "case.yaml", base_dir or ".")
    return written, written.parent


def run(
    case: CaseLike,
    output: str | Path | None = None,
    *,
    base_dir: str | Path | None = None,
    stop_after: str = "aggregate",
    figures: bool = False,
) -> Run:
    """Run a case to its results, as ``cloth run`` does.

    Parameters
    ----------
    case : Case, mapping or path
        The case (module docstring).
    output : path, optional
        The folder of its files (initial.nc, relaxed.nc, result.nc, summary.csv); default a new
        temporary folder.
    base_dir : path, optional
        The folder the case's relative paths are relative to (default: a case file's own
        folder, else the working folder).
    stop_after : {'aggregate', 'relax', 'predeform'}
        The last stage (default the results; ``figures`` adds the figures and the view).
    figures : bool
        Also draw the figures and the interactive view (as ``cloth run`` without
        ``--stop-after``).

    Returns
    -------
    Run
        The folder, result.nc loaded as an `xarray.Dataset` (node fields on dims (row, col),
        SI units, CF-1.11) and summary.csv as a `pandas.DataFrame`.
    """
    folder = Path(output) if output is not None else Path(tempfile.mkdtemp(prefix="cloth-"))
    path, base = _case_file(case, folder, base_dir)
    run_case(path, folder, {}, base, stop_after=None if figures else stop_after)
    if stop_after != "aggregate" and not figures:
        return Run(folder, xr.Dataset(), None)
    import pandas  # xarray's own dependency

    with xr.open_dataset(folder / "result.nc") as opened:
        result = opened.load()
    return Run(folder, result, pandas.read_csv(folder / "summary.csv"))


def _targets(targets: Mapping[str, float | tuple[float, float]] | Sequence[str]) -> list[Target]:
    """Targets as ``{line: mmHg}``, ``{line: (low, high)}`` or the command's texts."""
    if isinstance(targets, Mapping):
        out = []
        for line, value in targets.items():
            if isinstance(value, tuple | list):
                low, high = (float(v) * MMHG for v in value)
                out.append(Target(str(line), 0.5 * (low + high), (low, high)))
            else:
                out.append(Target(str(line), float(value) * MMHG))
        return out
    return [Target.parse(text) for text in targets]


def design(
    case: CaseLike,
    targets: Mapping[str, float | tuple[float, float]] | Sequence[str],
    output: str | Path,
    *,
    tolerance_mmHg: float = 0.5,
    panel: int | None = None,
    band_ratio_max: float | None = None,
    base_dir: str | Path | None = None,
):
    """Design a case's pattern for target pressures, as ``cloth design CASE`` does: the graded
    pattern (a band's line moves its band), or panel ``panel``'s width for one target.

    Parameters
    ----------
    case : Case, mapping or path
    targets : mapping of str to float, mmHg, or the command's texts (``"waist=20"``)
    output : path
        The design's folder: case.yaml, design_iterations.csv, confirmed/,
        design_confirmed.csv and the pattern's files.
    tolerance_mmHg : float, mmHg
    panel : int, optional
        Meet the one target by this panel's width (`cloth.stages.paneldesign`).
    band_ratio_max : float, optional
        Every band at most this times the line beside it.
    base_dir : path, optional

    Returns
    -------
    cloth.stages.design.Design or cloth.stages.paneldesign.PanelDesign
        The loop's outcome (its state, values, the lines reached, Pa).
    """
    from cloth.stages.graded import design_files  # the design's stack: only where it is asked
    from cloth.stages.paneldesign import panel_files  # as above

    output = Path(output)
    path, base = _case_file(case, output / "input", base_dir)
    wanted = _targets(targets)
    tolerance = tolerance_mmHg * MMHG
    if panel is not None:
        if len(wanted) != 1:
            raise InputError("a panel's width meets one target", field="targets")
        return panel_files(path, wanted[0], panel, output, tolerance, base)
    return design_files(path, wanted, output, tolerance, base, band_ratio=band_ratio_max)


def sizes(
    case: CaseLike,
    targets: Mapping[str, tuple[float, float]] | Sequence[str],
    output: str | Path,
    *,
    population: str | Path | None = None,
    by: Sequence[str] | None = None,
    coverage: float = 0.95,
    max_sizes: int = 8,
    base_dir: str | Path | None = None,
):
    """Design the size chart a measured population needs, as ``cloth sizes`` does.

    Parameters
    ----------
    case : Case, mapping or path
    targets : mapping of str to (low, high), mmHg, or the command's texts (``"B=23:32"``)
    output : path
    population : path, optional
        The population file (default the shipped one of the case's body).
    by : sequence of str, optional
        The girth lines the sizes are by (default the first target's).
    coverage : float, 1
        The share of the population the chart must fit.
    max_sizes : int
    base_dir : path, optional

    Returns
    -------
    The chart (`cloth.stages.sizes.design_sizes`), its files written into ``output``.

    Raises
    ------
    InputError
        Where a size is still not confirmed after its rounds (its files are written, with
        ``confirmed`` 0), as the command's exit status 2.
    """
    from cloth.stages.sizerequest import (  # the size chart's stack: only where asked
        Request,
        bands_of,
        population_of,
        sizing_names,
    )
    from cloth.stages.sizes import design_sizes  # as above
    from cloth.stages.sizetables import write_sizes  # as above

    output = Path(output)
    path, _ = _case_file(case, output / "input", base_dir)
    bands = bands_of(_targets(targets))
    request = Request(
        population=population_of(path, "default" if population is None else str(population)),
        bands=bands,
        by=sizing_names(",".join(by)) if by is not None else (bands[0].line,),
        coverage=coverage,
        max_sizes=max_sizes,
    )
    chart = design_sizes(path, request, output, {})
    write_sizes(chart, output)
    return chart


def compare(result: str | Path, readings: str | Path, output: str | Path) -> dict[str, Path]:
    """A pressure sensor's readings beside the model's probe, as ``cloth compare`` does:
    compare.csv, agreement.csv, compare.nc and compare.png in ``output``; returns the files
    written, by name (`cloth.stages.compare.compare`)."""
    from cloth.stages.compare import compare as compare_files  # only where asked

    return compare_files(Path(result), Path(readings), Path(output))


def calibrate(
    case: CaseLike,
    readings: str | Path,
    fit: Sequence[str],
    output: str | Path,
    *,
    base_dir: str | Path | None = None,
    noise_mmHg: float | None = None,
):
    """Fit the skin (friction, tissue modulus, fabric scale) to readings, as ``cloth
    calibrate`` does; its files in ``output``; returns the fit
    (`cloth.stages.calibrate.fit`)."""
    from cloth.stages.calibrate import (  # the calibration's stack: only where asked
        NOISE,
        parameter_names,
        write_calibration,
    )
    from cloth.stages.calibrate import fit as fit_case  # as above

    output = Path(output)
    path, base = _case_file(case, output / "input", base_dir)
    noise = NOISE if noise_mmHg is None else noise_mmHg * MMHG
    found = fit_case(path, Path(readings), parameter_names(",".join(fit)), base, {}, noise)
    write_calibration(found, Path(readings), output, base)
    return found


def material(source: str | Path) -> Fabric:
    """A fabric: a lab table (CSV), a material.nc, or a shipped fabric's name (``powernet``,
    ``elastic25``, ``lightnet``, ``controlnet``), as a case's ``material`` names it."""
    return load_fabric(str(source))


def body(block: Mapping[str, Any], base_dir: str | Path = ".") -> Body:
    """A body from a case's ``body`` block (``{"torso": {"size": "M"}}``, ``{"avatar":
    {"chart": "leg", "size": "M"}}``, ``{"mesh": "scan.obj", "units": "mm"}``), as a case
    reads it.

    Its ``query(points)``, points (N, 3) float in m, gives the signed distances (N,) m
    (positive outside), the closest surface points (N, 3) m and the unit outward normals
    (N, 3); ``girth(height)`` the girth at a height (m)."""
    return body_from_config(dict(block), base_dir)[0]


__all__ = [
    "Run",
    "body",
    "calibrate",
    "compare",
    "design",
    "material",
    "run",
    "sizes",
]
