"""Relaxation validated against Laplace's law, orthotropy, the ellipse, and solver agreement."""

from __future__ import annotations

import importlib.util
import itertools

import numpy as np
import pytest

from cloth.bodies import EllipticCylinder
from cloth.files.body import body_from_config
from cloth.garment.grid import FIXED, WEFT, node_area
from cloth.results.pressure import contact_reaction
from cloth.solvers import Settings, relax
from cloth.solvers.newton import _direction, stiffness_at
from cloth.solvers.problem import Problem, turning_gauge
from cloth.stages.case import initial_state

THICKNESS = 0.55e-3  # the example fabric's


def tube(body, reduction, n=64, m=6, around="weft", grading=0.0):
    case = {
        "material": "powernet",
        "body": body,
        "garment": {
            "bottom": 0.1,
            "top": 0.4,
            "reduction": reduction,
            "grid": [n, m],
            "edges": "sliding",
            "around": around,
            "row_grading": grading,
        },
    }
    return initial_state(case)


def solve(state, method="newton", tolerance=1e-10, iterations=60):
    body, _ = body_from_config(state.case.body.block)
    settings = Settings(
        method=method, tolerance=tolerance, max_iterations=iterations, progress=False
    )
    return relax(state, body, settings)


def pressure(state, result):
    ev = result.final
    held = ev.on_body
    reaction = contact_reaction(ev.forces, ev.unbalanced, held)
    area = node_area(ev.x, state.grid)
    return held, np.linalg.norm(reaction, axis=1) / area


def hoop_tension(state, result):
    """N m-1: weft spring force over its tributary width (area / thickness), interior rows."""
    grid = state.grid
    weft = grid.family_slices[WEFT]
    force = np.abs(grid.area[weft] * result.final.springs.stress[weft])
    return (force / (grid.area[weft] / state.fabric.thickness)).reshape(grid.m, grid.n)


@pytest.mark.parametrize("radius", [0.05, 0.10, 0.15])
@pytest.mark.parametrize("reduction", [0.1, 0.2, 0.3])
@pytest.mark.parametrize("grading", [0.0, 0.5])
def test_laplace_on_cylinders(radius, reduction, grading):
    """Laplace's law row by row, with equally spaced rows and with rows graded toward the
    edges (their spacing from a third to the whole of the middle's: each node's area and its
    weft springs' share of it change together, so the pressure does not)."""
    cylinder = {"cylinder": {"radius": radius, "bottom": 0.0, "top": 0.5}}
    state = tube(cylinder, reduction, m=12 if grading else 6, grading=grading)
    if grading:
        gaps = np.diff(state.grid.rest_uv[:: state.grid.n, 1])
        assert gaps.max() / gaps.min() > 2.5  # graded indeed
    result = solve(state)
    assert result.converged
    tension = hoop_tension(state, result)
    assert tension.max() / tension.min() - 1 < 1e-3
    # the chord-consistent reference: nodes on the circle, springs its chords, so the strain is
    # the chord's 2 r sin(pi / n) over the rest length, and p = sigma(eps_chord) t / r exactly
    grid = state.grid
    rest = grid.rest_length[grid.family_slices[WEFT]]
    eps = 2 * radius * np.sin(np.pi / grid.n) / rest - 1
    expected = state.fabric.weft.stress(eps).reshape(grid.m, grid.n).ravel() * THICKNESS / radius
    held, p = pressure(state, result)
    assert np.all(held)
    np.testing.assert_allclose(p, expected, rtol=1e-10)
    assert max(result.history.penetration) <= 1e-6


def test_laplace_discretisation_error_falls_as_one_over_n_squared():
    """Against the continuum (the arc strain 1/(1 - reduction) - 1) the error of the pressure
    falls as 1/n^2 with the nodes around: ratios of 4 from n = 16 to 32 to 64."""
    errors = []
    for n in (16, 32, 64):
        state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=n)
        result = solve(state)
        continuum = float(state.fabric.weft.stress(1 / 0.8 - 1)) * THICKNESS / 0.1
        errors.append(abs(float(pressure(state, result)[1].mean()) / continuum - 1))
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(3.8 < ratio < 4.2 for ratio in ratios), (errors, ratios)


def test_orthotropy_warp_around():
    body = {"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}
    weft = tube(body, 0.2)
    warp = tube(body, 0.2, around="warp")
    p_weft = pressure(weft, solve(weft))[1]
    p_warp = pressure(warp, solve(warp))[1]
    eps = 1 / 0.8 - 1
    ratio = float(weft.fabric.warp.stress(eps) / weft.fabric.weft.stress(eps))
    assert ratio > 1.2  # the fabric really is orthotropic
    np.testing.assert_allclose(p_warp / p_weft, ratio, rtol=5e-3)


def test_elliptic_cylinder_tension_and_curvature():
    state = tube(
        {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}, 0.2, n=128
    )
    result = solve(state)
    assert result.converged
    tension = hoop_tension(state, result)
    assert tension.max() / tension.min() - 1 < 1e-2
    held, p = pressure(state, result)
    ellipse = EllipticCylinder(0.15, 0.10)
    kappa = ellipse.curvature(result.final.closest[:, :2])
    # the node's pressure against T kappa, with T the mean of its two weft springs
    t_node = 0.5 * (tension + np.roll(tension, 1, axis=1)).ravel()
    np.testing.assert_allclose(p[held], (t_node * kappa)[held], rtol=2e-2)


def test_newton_converges_quadratically_without_penetration():
    state = tube(
        {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}, 0.2, n=96
    )
    result = solve(state, tolerance=1e-8)
    r = np.array(result.history.residual)
    assert result.converged and r[-1] <= 1e-8
    # the last steps: r_next <= C r^1.6 with C = e^2 (quadratic convergence gives ~ r^2)
    tail = [(a, b) for a, b in itertools.pairwise(r) if a < 1e-2]
    assert tail, r
    for a, b in tail:
        assert np.log(b) <= 1.6 * np.log(a) + 2, r
    assert max(result.history.penetration) <= 1e-6


def test_newton_and_explicit_agree():
    body = {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}
    state = tube(body, 0.2, n=32, m=4)
    explicit = solve(state, method="explicit", tolerance=1e-7, iterations=20000)
    newton = solve(state, tolerance=1e-11)
    assert explicit.converged and newton.converged
    r = explicit.history.residual[-1]
    forces_e = state.grid.area * explicit.final.springs.stress
    forces_n = state.grid.area * newton.final.springs.stress
    typical = np.mean(np.abs(forces_n))
    assert np.max(np.abs(forces_e - forces_n)) <= 100 * r * typical
    # positions: a residual force r x typical moves a node by about that over its stiffness
    stiffness = typical / np.min(state.grid.rest_length)
    assert np.max(np.abs(explicit.final.x - newton.final.x)) <= 100 * r * typical / stiffness


@pytest.mark.slow  # 300 explicit iterations (7 s; make test-slow)
def test_explicit_uses_the_papers_default_of_300_iterations():
    assert Settings(method="explicit").max_iterations == 300
    state = tube(
        {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}, 0.2, n=32, m=4
    )
    result = solve(state, method="explicit", tolerance=1e-12, iterations=300)
    assert result.iterations == 300 and not result.converged
    r = np.array(result.history.residual)
    assert r[-1] < 1e-2 * r[0]  # it made real progress
    steps = np.array(result.history.step[1:])
    assert np.all(steps >= 0) and steps[-1] < steps[0]


def test_bad_settings_are_refused():
    from cloth.errors import InputError

    for bad in (
        {"method": "verlet"},
        {"linear_solver": "mumps"},
        {"tolerance": 0.0},
        {"tolerance": -1e-8},
        {"blas_threads": 0},
        {"blas_threads": 1.5},
    ):
        with pytest.raises(InputError):
            Settings(**bad)


def test_relax_cli_and_bad_input(tmp_path, capsys):
    import xarray as xr

    from cloth.cli import main
    from cloth.files.state import state_dataset
    from cloth.io import write_netcdf

    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=24, m=3)
    initial = write_netcdf(state_dataset(state, "initial"), tmp_path / "initial.nc")
    out = tmp_path / "relaxed.nc"
    assert main(["--log-level", "WARNING", "relax", str(initial), "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["solver_converged"] == 1 and ds["residual"].values[-1] <= 1e-8
        assert ds.attrs["stage"] == "relaxed" and " relax " in ds.attrs["history"].splitlines()[-1]
    capsys.readouterr()

    ds = state_dataset(state, "initial")
    write_netcdf(ds.drop_vars("x"), tmp_path / "missing.nc")
    old = ds.copy()
    old.attrs["format_version"] = 0
    write_netcdf(old, tmp_path / "old.nc")
    (tmp_path / "corrupt.nc").write_bytes(b"CDF\x01 truncated")
    cases = [
        ([str(tmp_path / "missing.nc")], "missing variable 'x'"),
        ([str(tmp_path / "old.nc")], "format version"),
        ([str(tmp_path / "corrupt.nc")], "not a readable netCDF"),
        ([str(tmp_path / "nope.nc")], "file not found"),
        ([str(initial), "--tolerance", "0"], "tolerance"),
        ([str(initial), "--tolerance=-1e-8"], "tolerance"),
    ]
    # asking for a backend whose package is missing (whichever of the extras is not installed)
    modules = {"pardiso": "pypardiso", "cholmod": "sksparse", "amg": "pyamg"}
    missing = [name for name, module in modules.items() if importlib.util.find_spec(module) is None]
    if missing:
        cases.append(([str(initial), "--linear-solver", missing[0]], "not installed"))
    for args, expected in cases:
        target = tmp_path / "bad.nc"
        assert main(["relax", *args, "-o", str(target)]) == 2, args
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and expected in err[0], (args, err)
        assert not target.exists()
    with pytest.raises(SystemExit) as info:  # argparse: unknown method
        main(["relax", str(initial), "-o", str(tmp_path / "x.nc"), "--method", "verlet"])
    assert info.value.code == 2


def test_newton_converges_on_a_faceted_torso():
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M", "surface": "mesh", "around": 64, "rings": 40}},
        "garment": {"bottom": 0.9, "top": 1.15, "reduction": 0.15, "grid": [32, 12]},
    }
    state = initial_state(case)
    result = solve(state, tolerance=1e-8, iterations=60)
    assert result.converged and result.history.residual[-1] <= 1e-8
    assert max(result.history.penetration) <= 1e-6
    ev = result.final
    # every node is balanced: what the body does not carry is within the tolerance
    assert np.max(np.linalg.norm(ev.free, axis=1)) <= 1e-8 * ev.typical
    held, p = pressure(state, result)
    assert held.sum() > 0.5 * held.size and np.all(p[held] > 0)


@pytest.mark.parametrize("backend", ["amg", "pardiso", "cholmod", "cholespy"])
def test_every_installed_backend_reaches_superlus_equilibrium(backend):
    packages = {"amg": "pyamg", "pardiso": "pypardiso", "cholmod": "sksparse"}
    pytest.importorskip(packages.get(backend, backend))
    body = {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}
    state = tube(body, 0.2, n=48, m=4)
    solid, _ = body_from_config(state.case.body.block)
    results = [
        relax(state, solid, Settings(tolerance=1e-10, linear_solver=name, progress=False))
        for name in ("superlu", backend)
    ]
    assert all(r.converged for r in results)
    assert results[1].linear_solver == backend
    forces = [state.grid.area * r.final.springs.stress for r in results]
    np.testing.assert_allclose(forces[1], forces[0], rtol=0, atol=1e-7 * np.mean(np.abs(forces[0])))
    # sliding around the ellipse is soft: a 1e-10 residual still leaves ~1e-8 m of freedom
    np.testing.assert_allclose(results[0].final.x, results[1].final.x, atol=1e-6)


def test_a_failing_linear_solver_falls_back_to_superlu(monkeypatch, caplog):
    import scipy.sparse as sp

    from cloth.solvers import linear

    def broken(matrix, rhs, name):
        if name != "superlu":
            raise RuntimeError("did not converge")
        return original(matrix, rhs, name)

    original = linear._solve
    monkeypatch.setattr(linear, "_solve", broken)
    matrix = sp.csr_matrix(np.array([[4.0, 1.0], [1.0, 3.0]]))
    with caplog.at_level("WARNING"):
        x = linear.solve(matrix, np.array([1.0, 2.0]), "amg")
    np.testing.assert_allclose(matrix @ x, [1.0, 2.0])
    assert "falls back" in caplog.text or "uses superlu" in caplog.text


def test_a_tube_without_fixed_nodes_is_held_against_turning_at_one_node():
    """A closed tube with no fixed node may turn about the body; node 0 is its gauge. On a
    cylinder every turn is an equilibrium, so the gauge carries nothing, and the gauge node
    keeps exactly one direction fewer than its neighbour in the same row."""
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=32, m=4)
    assert turning_gauge(state.grid, state.constraint) == 0
    fixed = state.constraint.copy()
    fixed[-1] = FIXED
    assert turning_gauge(state.grid, fixed) is None
    result = solve(state)
    ev = result.final
    assert abs(ev.turning) <= 1e-9 * ev.typical
    rank = np.linalg.matrix_rank(ev.projector[:2], tol=1e-9)
    assert rank[1] - rank[0] == 1


def test_a_step_without_a_descent_direction_stays_in_the_allowed_directions():
    """Where no shifted Newton matrix gives a descent direction (here the exact stiffness is
    turned negative definite), the scaled gradient step still moves only where the constraints
    let nodes move (it once moved held nodes into the body) and goes downhill."""
    body = {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}
    state = tube(body, 0.2, n=32, m=4)
    problem = Problem.of(state, body_from_config(body)[0])
    ev = solve(state, iterations=1).final  # every node on the body, not yet balanced
    stiff = stiffness_at(problem, ev)
    projector, _ = problem.basis(ev.x, ev.normal, ev.on_body)

    def flipped(project: bool):
        return stiff(project) if project else -stiff(project)

    dx, slope = _direction(problem, ev, ev.on_body, projector, flipped, "superlu", (False,))
    assert np.all(ev.on_body)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", projector, dx), dx, rtol=0, atol=1e-18)
    assert slope > 0 and np.abs(dx).max() > 1e-7


def test_factorisations_and_peak_memory_are_recorded(monkeypatch):
    """Every linear system a run factorises is counted (here against a count of the backend's
    calls, with cholespy's attempts on a matrix that is not positive definite, which SuperLU
    then factorises, counted twice), at least one per Newton iteration, and relaxed.nc records
    the counts and the peak memory."""
    from cloth.files.relaxed import relaxed_dataset
    from cloth.solvers import linear

    calls = []
    factorise, fresh = linear._solve, linear.Reuse._fresh  # direct solves; kept factors
    monkeypatch.setattr(linear, "_solve", lambda *a: calls.append(1) or factorise(*a))
    monkeypatch.setattr(linear.Reuse, "_fresh", lambda *a: calls.append(1) or fresh(*a))
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=32, m=4)
    body, _ = body_from_config(state.case.body.block)
    # a backend whose every factorisation goes through the two (cholmod's, auto's choice where
    # its extra is installed, through its own)
    settings = Settings(tolerance=1e-10, linear_solver="cholespy", progress=False)
    result = relax(state, body, settings)
    assert result.iterations > 0 and len(calls) >= result.iterations
    assert result.factorisations == len(calls) + result.lu_fallbacks
    assert result.peak_memory > 2**20
    ds = relaxed_dataset(state, result, Settings())
    assert ds.attrs["solver_factorisations"] == result.factorisations
    assert ds.attrs["solver_lu_fallbacks"] == result.lu_fallbacks
    assert ds.attrs["solver_peak_memory_mib"] == pytest.approx(result.peak_memory / 2**20)


def test_relax_hands_every_step_to_its_callbacks_in_phases():
    from cloth.solvers.stepper import Step

    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=24, m=3)
    body, _ = body_from_config(state.case.body.block)
    seen = []

    def record(iteration, stepper, step, history):
        assert isinstance(step, Step) and history.residual[-1] == step.evaluation.residual
        seen.append((iteration, stepper.name, stepper.code, history.method[-1]))

    settings = Settings(method="explicit+newton", warm_start=4, tolerance=1e-10, progress=False)
    result = relax(state, body, settings, callbacks=[record])
    assert result.converged and [s[0] for s in seen] == list(range(1, result.iterations + 1))
    assert [s[1] for s in seen[:4]] == ["explicit"] * 4 and seen[4][1] == "newton"
    assert all(code == method for _, _, code, method in seen)


@pytest.mark.parametrize("limit", [1, None])
def test_relax_limits_the_blas_threads_while_it_runs(limit):
    """``blas_threads`` caps every loaded BLAS library's threads during the run (numpy's and a
    backend's OpenBLAS spin-wait against each other on 2 cores) and lifts the cap after; None
    leaves the libraries alone."""
    from threadpoolctl import threadpool_info

    def counts() -> list[int]:
        return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]

    before = counts()
    assert before  # numpy's and scipy's OpenBLAS at least
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=24, m=3)
    body, _ = body_from_config(state.case.body.block)
    during = []
    settings = Settings(tolerance=1e-10, progress=False, blas_threads=limit)
    relax(state, body, settings, callbacks=[lambda *_: during.append(counts())])
    assert during and all(
        seen == ([1] * len(seen) if limit == 1 else before[: len(seen)]) for seen in during
    )
    assert counts() == before


def test_at_a_saddle_newton_follows_the_unstable_mode():
    """Near an equilibrium, an exact step refused with negative curvature marks a saddle: the
    step then solves the exact matrix shifted past its negative eigenvalue (by twice the
    curvature along the refused step) and points along the unstable mode more than the
    projected Hessian's step does (at 204,800 nodes on the torso that one crawled along such a
    mode, docs/performance.md). Far from an equilibrium the projected Hessian still comes
    first."""
    from dataclasses import replace

    import scipy.sparse as sp

    from cloth.solvers.newton import SADDLE_RESIDUAL, newton_matrix

    body = {"elliptic_cylinder": {"a": 0.15, "b": 0.10, "bottom": 0.0, "top": 0.5}}
    state = tube(body, 0.2, n=32, m=4)
    problem = Problem.of(state, body_from_config(body)[0])
    ev = solve(state, tolerance=1e-6).final
    assert ev.residual < SADDLE_RESIDUAL
    stiff = stiffness_at(problem, ev)
    held = ev.on_body
    projector, _ = problem.basis(ev.x, ev.normal, held)
    blocks = sp.block_diag(list(projector), format="csr")
    exact = newton_matrix(problem, ev, held, projector, stiff(False)).toarray()
    values, vectors = np.linalg.eigh(exact)
    lowest = np.flatnonzero(values > 1.5)[0]  # constrained directions are 1 (+ regularisation)
    mode = vectors[:, lowest]
    soften = 1.1 * values[lowest] * blocks  # the softest free mode's curvature becomes negative

    def softened(project: bool):
        return stiff(project) if project else stiff(project) - soften

    # a load with as much along the mode as the residual has in all
    free = np.einsum("nij,nj->ni", projector, ev.loads).ravel()
    loads = ev.loads + np.linalg.norm(free) * mode.reshape(-1, 3)
    rhs = np.einsum("nij,nj->ni", projector, loads).ravel()
    saddle = newton_matrix(problem, ev, held, projector, softened(False))
    refused = np.linalg.solve(saddle.toarray(), rhs)
    assert rhs @ refused < 0  # the exact step is refused
    curvature = refused @ (saddle @ refused) / (refused @ refused)
    assert curvature < 0
    along = {}
    for name, residual in (("near", ev.residual), ("far", 10 * SADDLE_RESIDUAL)):
        at = replace(ev, residual=residual, loads=loads)
        dx, slope = _direction(problem, at, held, projector, softened, "superlu", (False, True))
        assert slope > 0
        along[name] = abs(mode @ dx.ravel()) / np.linalg.norm(dx)
        if name == "near":
            shifted = saddle + (-2.0 * curvature) * sp.identity(saddle.shape[0])
            np.testing.assert_allclose(shifted @ dx.ravel(), rhs, atol=1e-9 * np.abs(rhs).max())
        else:
            projected = newton_matrix(problem, ev, held, projector, stiff(True))
            np.testing.assert_allclose(projected @ dx.ravel(), rhs, atol=1e-9 * np.abs(rhs).max())
    assert along["near"] > along["far"]
