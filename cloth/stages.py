"""The pipeline's stages that join several of the package's parts, one function each, file in,
datasets out (the CLI parses and writes; `cloth.aggregate` computes, `cloth.resultfile` lays
out the result file). Kept apart so that those modules import only downward.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from cloth.aggregate import (
    girth_extrema,
    lab_range_variables,
    landmarks,
    node_average,
    node_fields,
)
from cloth.bodies import body_from_config
from cloth.grid import WEFT
from cloth.mechanics import spring_state
from cloth.resultfile import result_dataset, summary_rows
from cloth.solvers.problem import Problem
from cloth.state import read_state


def aggregate(relaxed_path: str | Path, base_dir: str | Path = ".") -> tuple[xr.Dataset, list]:
    """relaxed.nc -> (result dataset, summary rows): the stage's function.

    Rebuilds the model and body from the state file, evaluates the final positions (forces,
    contact, normals) and computes every field, landmark and total.
    """
    state, ds = read_state(relaxed_path, "relaxed")
    body, ref = body_from_config(state.case["body"], base_dir)
    ev = Problem.of(state, body).evaluate(state.x)
    fields = node_fields(
        state.grid, state.x, ev.springs, state.fabric.thickness, ev.forces, ev.unbalanced,
        ev.on_body, ev.normal, state.constraint,
    )  # fmt: skip
    heights = dict(ref.get("landmarks", {}))
    heights.update(state.case.get("landmarks", {}))
    if not heights:
        heights = girth_extrema(state)
    marks = landmarks(heights, state.x, fields, state.grid)
    result = result_dataset(state, fields, marks, ds)
    if "x_initial" in ds:
        start = np.stack([ds[f"{a}_initial"].values.ravel() for a in "xyz"], axis=1)
        before = node_average(state.grid, spring_state(start, state.grid).stress, WEFT)
        result = result.assign(
            {
                f"{a}_initial": ds[f"{a}_initial"].variable for a in "xyz"
            }
            | {
                "stress_weft_initial": (
                    ("row", "col"), before.reshape(state.grid.m, state.grid.n),
                    {"units": "Pa", "long_name": "weft stress before relaxation"},
                )
            }
        )  # fmt: skip
    result = result.assign(lab_range_variables(state, ev.springs.strain))
    name = Path(relaxed_path).parent.name
    return result, summary_rows(result, name)
