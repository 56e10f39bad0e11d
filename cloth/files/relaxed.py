"""Write a relaxation's outcome: the relaxed state plus history and solver attributes.

``relaxed.nc`` is a state file (see `cloth.files.state`) with stage ``relaxed`` and, along the
``iteration`` dimension (the initial state first), and the positions before relaxation
``x_initial``, ``y_initial``, ``z_initial`` (m, dims row, col): ``residual`` (1), ``energy`` (J),
``penetration`` (m), ``contacts`` (count), ``step`` (m), ``iteration_method`` (0 explicit,
1 newton), ``turning_force`` (N: the force the turning gauge carries along its turn, what a
skin's friction would carry; `cloth.solvers.problem.turning_gauge`). Global attributes:
``solver_method``, ``solver_converged`` (0/1), ``solver_iterations``, ``solver_tolerance``,
``solver_residual``, ``solver_linear_solver`` (the backend the run used: ``auto`` resolved,
`cloth.solvers.linear.choose`), ``solver_seconds``, ``solver_turning_node`` (the
gauge node's index, -1 for none), ``solver_factorisations`` (linear systems factorised by the
run, coarse levels included), ``solver_lu_fallbacks`` (of those, the systems cholespy found
not positive definite and SuperLU factorised), ``solver_continuation`` (0/1) and
``solver_coarsest`` (its coarsest level's node limit), ``solver_reuse`` (0/1: factorisations
kept across Newton steps), and ``solver_peak_memory_mib`` (the process's peak resident
memory at its end, MiB); ``solver_unstable_modes`` where the run counted them from its last
factor (`cloth.solvers.saddle.kept_factor`: the aggregate stage then factorises nothing);
with tissue or friction ``solver_lags`` (solves with the skin models' lagged quantities,
`cloth.solvers.lagged`) and the friction variables of `cloth.files.skin`.
``solver_iterations`` and the history are the requested grid's.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from cloth.case import Settings
from cloth.files.skin import friction_variables
from cloth.files.state import state_dataset
from cloth.garment.state import State
from cloth.solvers.common import History
from cloth.solvers.problem import turning_gauge
from cloth.solvers.relax import Result


def history_variables(history: History) -> dict[str, xr.Variable]:
    dim = "iteration"

    def var(values, units, long_name, dtype=np.float64, **attrs):
        return xr.Variable(
            dim, np.asarray(values, dtype=dtype), {"units": units, "long_name": long_name, **attrs}
        )

    return {
        "residual": var(history.residual, "1", "largest free-node force / mean spring force"),
        "energy": var(history.energy, "J", "total strain energy"),
        "penetration": var(history.penetration, "m", "largest depth of a node inside the body"),
        "contacts": var(history.contacts, "1", "nodes on the body", np.int32),
        "step": var(history.step, "m", "largest node displacement of the iteration"),
        "iteration_method": var(
            history.method,
            "1",
            "solver of the iteration",
            np.int8,
            flag_values=np.array([0, 1], dtype=np.int8),
            flag_meanings="explicit newton",
        ),
        "turning_force": var(
            history.turning, "N", "force on the turning gauge node along its turn about the body"
        ),
    }


def relaxed_dataset(
    state: State,
    run: Result,
    settings: Settings,
    previous: dict | None = None,
    stage: str = "relaxed",
) -> xr.Dataset:
    """The ``relaxed.nc`` dataset of ``state`` relaxed by ``run`` with ``settings``
    (``stage="diverged"`` for the last finite state of a failure, `Result.diverged`);
    ``previous``: the initial file's attributes."""
    x, on_body, history = run.final.x, run.final.on_body, run.history
    converged, iterations, linear_solver, seconds = (
        run.converged,
        run.iterations,
        run.linear_solver,
        run.seconds,
    )
    factorisations, peak_memory = run.factorisations, run.peak_memory
    gauge = turning_gauge(state.grid, state.constraint)
    relaxed = state.with_positions(
        x,
        on_body=on_body.astype(np.int8),
        attrs={
            **{k: v for k, v in state.attrs.items() if not k.startswith("solver_")},
            "solver_method": settings.method,
            "solver_converged": int(converged),
            "solver_iterations": int(iterations),
            "solver_tolerance": float(settings.tolerance),
            "solver_residual": float(history.residual[-1]) if len(history) else float("nan"),
            "solver_linear_solver": linear_solver,
            "solver_seconds": float(seconds),
            "solver_turning_node": -1 if gauge is None else int(gauge),
            "solver_factorisations": int(factorisations),
            "solver_lu_fallbacks": int(run.lu_fallbacks),
            "solver_continuation": int(settings.continuation),
            "solver_coarsest": int(settings.coarsest),
            "solver_reuse": int(settings.reuse),
            "solver_peak_memory_mib": float(peak_memory) / 2**20,
            **({"solver_lags": int(run.lags)} if run.lags else {}),
            **(
                {"solver_unstable_modes": int(run.unstable_modes)}
                if run.unstable_modes is not None
                else {}
            ),
        },
    )
    ds = state_dataset(relaxed, stage, previous)
    start = state.x.reshape(state.grid.m, state.grid.n, 3)
    initial = {
        f"{axis}_initial": xr.Variable(
            ("row", "col"),
            start[..., k],
            {"units": "m", "long_name": f"node {axis} before relaxation"},
        )
        for k, axis in enumerate("xyz")
    }
    skin = friction_variables(state.grid, run.friction)
    return ds.assign({**history_variables(history), **initial, **skin})
