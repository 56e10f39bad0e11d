"""The benchmarks' torso case: torso M (smooth), power net, 15 % reduction, 0.80-1.25 m (every
girth line inside the garment), sliding edges, on a grid given as ``"NxM"``."""

from __future__ import annotations

from cloth.files.body import body_from_config
from cloth.stages.case import initial_state

#: The benchmarks' Newton variants: name -> (continuation, reuse).
VARIANTS = {
    "plain": (False, False),
    "reuse": (False, True),
    "continuation": (True, False),
    "continuation+reuse": (True, True),
}


def torso_case(grid: str):
    """(n, m, the wrapped state, its body) of the torso case on ``grid`` (``"448x224"``)."""
    n, m = (int(v) for v in grid.split("x"))
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {
            "bottom": 0.80,
            "top": 1.25,
            "reduction": 0.15,
            "grid": [n, m],
            "edges": "sliding",
        },
    }
    state = initial_state(case)
    return n, m, state, body_from_config(state.case.body.block)[0]
