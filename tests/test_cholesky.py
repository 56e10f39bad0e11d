"""Positive-definite solvers (issue 41): cholespy's Cholesky factor, conjugate gradients on a kept
one, the LU fallback where a matrix is not positive definite, and ``auto`` choosing it exactly
where the case's Newton matrix is positive definite by construction."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from cloth.solvers import linear
from cloth.solvers.cholesky import CholeskyFactor, NotPositiveDefinite, cholesky_factor
from cloth.solvers.krylov import KRYLOV_LIMIT, cg_on
from cloth.solvers.linear import Reuse, choose, lu_fallbacks, spd_factor
from cloth.solvers.stability import factor_inertia, negative_direction
from tests.conftest import load_result, write_obj
from tests.test_linear import held, stiff_chain

#: cholespy is a dependency wherever it has wheels (not Linux on arm64, where auto takes LU).
pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("cholespy") is None, reason="cholespy is not installed"
)
ROOT = Path(__file__).resolve().parents[1]
#: The acceptance: every reported quantity of the two backends' runs within this, relative.
AGREE = 1e-9


def membrane(n: int, tension: float = 1e3) -> sp.csr_matrix:
    """The 5-point Laplacian of an n x n membrane under ``tension`` (N/m), fixed at its edge:
    symmetric positive definite, with the fill of a grid."""
    line = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    return (tension * (sp.kron(line, sp.identity(n)) + sp.kron(sp.identity(n), line))).tocsr()


def test_a_cholesky_factor_solves_a_positive_definite_system_exactly():
    matrix = membrane(40)
    rhs = np.random.default_rng(4).normal(size=(matrix.shape[0], 2))
    factor = cholesky_factor(matrix)
    x = factor.solve(rhs)
    assert x.shape == rhs.shape
    assert np.linalg.norm(matrix @ x - rhs) <= 1e-12 * np.linalg.norm(rhs)
    np.testing.assert_allclose(factor.solve(rhs[:, 0]), x[:, 0], rtol=0, atol=1e-14)
    # its matrix is positive definite: no unstable mode, no direction of negative curvature
    assert factor_inertia(factor) == 0 and negative_direction(factor, matrix.shape[0]) is None


def test_an_indefinite_matrix_is_refused_without_a_word_on_standard_output(capfd):
    """CHOLMOD prints its warning on file descriptor 1, which may be a command's output: the
    refusal is the exception alone."""
    matrix = membrane(10).tolil()
    matrix[37, 37] = -1.0
    with pytest.raises(NotPositiveDefinite, match="not positive definite"):
        cholesky_factor(matrix.tocsr())
    out, _ = capfd.readouterr()
    assert out == ""


def test_a_matrix_that_is_not_positive_definite_is_factorised_by_lu_and_counted():
    matrix = (membrane(12) - 200.0 * sp.identity(144)).tocsr()  # one eigenvalue below 0
    rhs = np.random.default_rng(5).normal(size=144)
    before, factorised = lu_fallbacks(), linear.factorisations()
    factor = spd_factor(matrix)
    assert not isinstance(factor, CholeskyFactor)
    assert lu_fallbacks() == before + 1 and linear.factorisations() == factorised + 2
    assert np.linalg.norm(matrix @ factor.solve(rhs) - rhs) <= 1e-10 * np.linalg.norm(rhs)
    # its pivots count the negative eigenvalues, as SuperLU's always did
    assert factor_inertia(factor) == int(np.sum(np.linalg.eigvalsh(matrix.toarray()) < 0)) == 1


def test_conjugate_gradients_on_a_kept_factor_reach_the_true_residual():
    """Nodes taken into contact change a few rows by four orders of magnitude: CG
    preconditioned by the old Cholesky factor solves the new system to the true relative
    residual asked, in a few iterations (the preconditioned matrix is the identity plus a
    change of rank 6, two rows and columns per node, so CG ends in about as many iterations:
    7 in exact arithmetic, 10 here)."""
    chain = stiff_chain(400)
    contact = held(chain, np.array([50, 200, 333]))
    rhs = np.random.default_rng(6).normal(size=400)
    x, iterations = cg_on(contact, cholesky_factor(chain), rhs, 1e-10)
    assert x is not None and iterations <= 12
    assert np.linalg.norm(contact @ x - rhs) <= 1e-10 * np.linalg.norm(rhs)


def test_conjugate_gradients_stop_on_a_direction_of_negative_curvature():
    chain = stiff_chain(100)
    indefinite = (chain - 3e4 * sp.identity(100)).tocsr()  # some eigenvalues below 0
    rhs = np.random.default_rng(7).normal(size=100)
    x, iterations = cg_on(indefinite, cholesky_factor(chain), rhs, 1e-10)
    assert x is None and iterations <= KRYLOV_LIMIT


def test_reuse_keeps_the_cholesky_factor_and_solves_by_cg():
    chain = stiff_chain(400)
    contact = held(chain, np.array([10, 390]))
    rhs = np.random.default_rng(8).normal(size=400)
    reuse = Reuse("cholespy")
    reuse.rtol = 1e-10
    reuse.solve(chain, rhs)
    assert isinstance(reuse.factor, CholeskyFactor) and reuse.krylov == [0]
    x = reuse.solve(contact, rhs)
    assert 0 < reuse.krylov[-1] <= 10 and reuse.krylov.count(0) == 1
    assert np.linalg.norm(contact @ x - rhs) <= 1e-10 * np.linalg.norm(rhs)


def test_auto_takes_cholesky_only_where_the_matrix_is_positive_definite():
    """cholmod where its extra is installed, else cholespy; never for another case."""
    installed = "cholmod" if importlib.util.find_spec("sksparse") else "cholespy"
    assert choose("auto", positive_definite=True) == installed
    assert choose("auto", positive_definite=False) in linear.AUTO
    assert choose("cholespy") == "cholespy"


def _case(kind: str, folder: Path, grid=(48, 24)) -> dict:
    if kind == "torso":
        body = {"torso": {"size": "M"}}
    else:  # a scan stand-in: the torso's coarse mesh with 1 mm of noise along its normals
        import trimesh

        from cloth.bodies.torso import chart_size, torso_mesh

        vertices, faces = torso_mesh(chart_size("M"), 32, 30)
        normals = trimesh.Trimesh(vertices, faces, process=False).vertex_normals
        noise = np.random.default_rng(41).normal(0.0, 1e-3, len(vertices))[:, None]
        folder.mkdir(parents=True, exist_ok=True)
        scan = write_obj(folder / "scan.obj", vertices + noise * normals, faces)
        # the surface sampled at 6 mm, not the default 3 mm (a quarter of the samples): the
        # solvers are compared on whatever surface is fitted
        body = {"mesh": str(scan), "smoothing": 0.015, "spacing": 0.006}
    return {
        "material": "powernet",
        "body": body,
        "garment": {
            "bottom": 0.86,
            "top": 1.22,
            "reduction": 0.20,
            "grid": list(grid),
            "error_estimate": False,
        },
        # the default path, continuation and reuse, at this size; converged to where the two
        # runs' difference is rounding, not the tolerance's slack
        "solver": {"coarsest": 300, "tolerance": 1e-11},
    }


@pytest.mark.parametrize("kind", ["torso", pytest.param("scan", marks=pytest.mark.slow)])
def test_cholespy_reports_the_garment_superlu_does(tmp_path, kind):
    """The acceptance of issue 41 at CI size: cholespy (the default install's Cholesky, auto's
    choice on the tension field without the cholmod extra) reports every quantity of result.nc
    as SuperLU does within 1e-9 relative (of each
    variable's largest magnitude; positions and forces are converged to 1e-8 of a spring force
    either way, and both runs end on the same iterate to rounding). The history (residual,
    energy per iteration) is each run's path, not the garment, and is not compared."""
    case = _case(kind, tmp_path / "body")
    case["solver"]["linear_solver"] = "cholespy"
    fast = load_result(tmp_path / "cholespy", case)
    case["solver"]["linear_solver"] = "superlu"
    lu = load_result(tmp_path / "superlu", case)
    assert fast.attrs["solver_linear_solver"] == "cholespy"
    assert lu.attrs["solver_linear_solver"] == "superlu"
    assert fast.attrs["converged"] == lu.attrs["converged"] == 1
    compared = 0
    for name, variable in lu.data_vars.items():
        if not np.issubdtype(variable.dtype, np.floating) or "iteration" in variable.dims:
            continue  # the history is each solver's own path
        a, b = variable.values, fast[name].values
        finite = np.isfinite(a)
        np.testing.assert_array_equal(finite, np.isfinite(b), err_msg=name)
        if not finite.any():
            continue
        scale = max(float(np.abs(a[finite]).max()), 1e-300)
        assert float(np.abs(b[finite] - a[finite]).max()) <= AGREE * scale, name
        compared += 1
    assert compared >= 20
    assert {"pressure_mean", "pressure_max", "tension_mean", "normal_force"} <= set(lu.data_vars)


def test_a_compressible_fabric_falls_back_to_lu(tmp_path):
    """A compression modulus (1 %, given at ingestion) makes compressed springs soften the
    fabric across them: the Newton matrix is not positive definite by construction, so auto
    takes an LU backend, and relaxed.nc says which."""
    from cloth.cli import main

    material = tmp_path / "powernet_c1.nc"
    csv = ROOT / "data/materials/powernet.csv"
    command = ["material", "ingest", str(csv), "--compression-ratio", "0.01", "-o", str(material)]
    assert main(command) == 0
    case = _case("torso", tmp_path, grid=(24, 12))
    case["material"] = str(material)
    result = load_result(tmp_path / "out", case)
    assert result.attrs["solver_linear_solver"] in linear.AUTO
    assert result.attrs["solver_lu_fallbacks"] == 0


def test_positive_definite_cases_are_those_of_a_convex_energy_without_skin_models():
    from dataclasses import replace

    from cloth.case.skin import Contact, Skin
    from cloth.solvers.relax import positive_definite
    from cloth.stages.case import initial_state

    case = _case("torso", Path("."), grid=(16, 8))
    state = initial_state(case)
    assert state.grid.convex and positive_definite(state)
    bending = initial_state({**case, "garment": {**case["garment"], "bend_modulus": 1e4}})
    assert not bending.grid.convex and not positive_definite(bending)
    rubbing = replace(state, skin=Skin(None, Contact(0.5, None)))
    assert not positive_definite(rubbing)


def test_the_stability_count_takes_a_cholesky_factor_where_there_is_one(monkeypatch):
    """At a tension-field equilibrium the exact constrained matrix is positive definite: the
    count is 0 from a Cholesky factor, and the LU's pivots (the path where Cholesky fails)
    say the same."""
    from cloth.files.body import body_from_config
    from cloth.solvers import Settings, relax, stability
    from cloth.solvers.problem import Problem
    from cloth.stages.case import initial_state

    state = initial_state(_case("torso", Path("."), grid=(24, 12)))
    body, _ = body_from_config(state.case.body.block)
    result = relax(state, body, Settings(tolerance=1e-10, progress=False))
    problem = Problem.of(state, body)
    ev = problem.evaluate(result.final.x)
    tried = []
    real = linear.cholesky_factor  # what spd_factor calls
    monkeypatch.setattr(linear, "cholesky_factor", lambda m: tried.append(1) or real(m))
    assert stability.unstable_modes(problem, ev) == 0 and tried == [1]

    def refuse(matrix):
        raise NotPositiveDefinite("as if indefinite")

    monkeypatch.setattr(linear, "cholesky_factor", refuse)
    assert stability.unstable_modes(problem, ev) == 0  # from the LU's pivots
    assert stability.negative_eigenvalues(stability.exact_matrix(problem, ev)) == 0
