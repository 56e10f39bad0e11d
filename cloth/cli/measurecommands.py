"""The command line's ``cloth compare`` and ``cloth calibrate``: the model against a pressure
sensor's readings, and the skin and fabric fitted to them. `cloth.cli.parser` adds them."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cloth.cli.argtypes import amount


def add_measure_commands(
    commands: Any,
    path: Callable[[str], Path],
    solver_options: Callable[[argparse.ArgumentParser], None],
) -> None:
    """Add ``cloth compare`` and ``cloth calibrate`` to the top-level ``commands`` (argparse's
    sub-parser action); ``path`` and ``solver_options`` are the parser's own."""
    compare = commands.add_parser(
        "compare",
        help="result.nc + measured readings -> compare.csv, agreement.csv, compare.nc, "
        "compare.png; or a study file -> the same over its subjects",
        description="Compare the model's pressure-sensor readings with measured ones, place "
        "by place: bias, limits of agreement, RMSE and r (Bland-Altman), repeats averaged "
        "(docs/validation.md, 'Your own measurements'). Give a result.nc and a measurements "
        "CSV (docs/outputs.md), or one study YAML file: a garment and its subjects, each with "
        "her body and her readings, run and compared one by one.",
    )
    compare.add_argument(
        "inputs",
        type=path,
        nargs="+",
        metavar="FILE",
        help="RESULT.nc MEASURED.csv, or STUDY.yaml",
    )
    compare.add_argument("-o", "--output", type=path, required=True, help="output folder")
    solver_options(compare)
    compare.set_defaults(handler="compare", output_folder=True)

    calibrate = commands.add_parser(
        "calibrate",
        help="case.yaml + measured readings -> the fitted friction, tissue modulus or fabric "
        "scale with intervals, and the calibrated case.yaml",
        description="Fit a case's friction, tissue modulus and fabric scale to measured "
        "pressures by least squares; report each value with its 95 %% interval, say which "
        "the readings cannot determine, and write calibration.csv, fit.csv and the "
        "calibrated case.yaml (docs/validation.md, 'Your own measurements').",
    )
    calibrate.add_argument("case", type=path, help="case YAML file (one subject's body)")
    calibrate.add_argument("measured", type=path, help="measurements CSV (docs/outputs.md)")
    calibrate.add_argument(
        "--fit",
        required=True,
        metavar="NAME[,NAME]",
        help="the parameters to fit: friction, tissue_modulus (the case needs body.tissue), "
        "fabric_scale",
    )
    calibrate.add_argument(
        "--noise",
        type=amount("pressure", "mmHg"),
        default=None,
        help="the readings' noise where the file has no repeats, mmHg (default 2): "
        "which parameters the readings determine depends on it",
    )
    calibrate.add_argument(
        "--base-dir",
        type=path,
        help="folder relative paths in the case are relative to (default: the case file's folder)",
    )
    calibrate.add_argument("-o", "--output", type=path, required=True, help="output folder")
    solver_options(calibrate)
    calibrate.set_defaults(handler="calibrate", output_folder=True)
