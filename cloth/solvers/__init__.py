"""Relaxation to equilibrium: the paper's explicit iteration and a sparse Newton solver.

`relax(state, body, settings)` dispatches on ``settings.method``; see docs/solvers.md.
"""

from cloth.case import Settings
from cloth.solvers.common import Diverged, History
from cloth.solvers.relax import relax

__all__ = ["Diverged", "History", "Settings", "relax"]
