"""Contact pressure: the body's normal reaction on each node over the node's area on the body.

Node area: the deformed tributary area (`cloth.garment.grid.node_area`).

Reaction: what the springs push into the body and the body balances, -(R - r) with r the part
the body cannot balance (`Evaluation.free` before edge constraints): along the surface normal on
a smooth body, in the normal cone of the faces on a mesh.

Units and classes: 1 mmHg = `MMHG` Pa; the RAL-GZ 387 medical compression classes (mmHg) and
the comfort groups of knitted compression garments (kPa) a pressure falls in.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: 1 mmHg in Pa, by its definition: mercury's conventional density 13.5951 g/cm3 x standard
#: gravity 9.80665 m/s2 x 1 mm = 133.322387415 Pa (rounded to 133.322, a value exactly on a
#: class edge such as 32 mmHg read as 32.0001 and fell out of its class).
MMHG = 13.5951e3 * 9.80665 * 1e-3
#: RAL-GZ 387 medical compression classes, mmHg (class: lower, upper).
RAL_CLASSES = (("I", 18.0, 21.0), ("II", 23.0, 32.0), ("III", 34.0, 46.0), ("IV", 49.0, np.inf))
#: Comfort groups of knitted compression garments, kPa.
COMFORT_GROUPS = (("I", 0.4, 1.3), ("II", 1.3, 2.0), ("III", 2.0, 3.3), ("IV", 3.3, np.inf))


def ral_class(mmhg: float) -> str:
    """RAL-GZ 387 class of a pressure in mmHg ('-' below class I or between classes)."""
    for name, low, high in RAL_CLASSES:
        if low <= mmhg <= high:
            return name
    return "-"


def comfort_group(kpa: float) -> str:
    """Comfort group of a knitted garment's pressure in kPa ('-' below group I)."""
    for name, low, high in COMFORT_GROUPS:
        if low <= kpa < high:
            return name
    return "-"


def contact_reaction(
    forces: NDArray[np.float64], unbalanced: NDArray[np.float64], held: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """(N, 3) float, N: the body's reaction on each held node (zero elsewhere)."""
    reaction = np.zeros_like(forces)
    reaction[held] = -(forces[held] - unbalanced[held])
    return reaction
