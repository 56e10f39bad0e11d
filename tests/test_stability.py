"""Unstable modes of an equilibrium (`cloth.solvers.stability`): the inertia of Newton's matrix
from an unpivoted LU, checked against the eigenvalues of a uniformly deformed flat patch, which
are known in closed form."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from cloth.bodies import Cylinder
from cloth.garment.grid import FIXED, FREE, rectangle
from cloth.garment.mechanics import stiffness
from cloth.solvers import linear
from cloth.solvers.problem import Problem
from cloth.solvers.stability import negative_eigenvalues, unstable_modes
from tests.conftest import make_fabric

N, M, WIDTH, HEIGHT = 9, 7, 0.24, 0.18


@pytest.fixture
def fabric():
    """The test knit with a compression modulus of 1 % of its first slopes: compressed springs
    then soften across (A sigma / l < 0) and the patch has unstable modes to count (the default
    pure tension field has none, `test_a_pure_tension_field_has_no_unstable_mode`)."""
    return make_fabric(compression=0.01)


def patch_eigenvalues(fabric, lx: float, ly: float) -> np.ndarray:
    """The eigenvalues (N/m) of the stiffness of an N x M patch stretched by lx along the weft
    and ly along the warp, its edge nodes fixed, on its interior nodes' moves.

    Every spring is axis-aligned, so each spring's Hessian A [(sigma'/L) d d^T + (sigma/l)
    (I - d d^T)] is diagonal: x, y and z decouple, and each is a Dirichlet Laplacian on the
    (N - 2) x (M - 2) interior with one coupling along the weft and one along the warp (axial or
    across). Its eigenvalues are k_weft s_p + k_warp t_q, s_p = 2 - 2 cos(p pi / (N - 1)),
    t_q = 2 - 2 cos(q pi / (M - 1)), p = 1..N-2, q = 1..M-2."""
    t = fabric.thickness
    dx, dv = WIDTH / (N - 1), HEIGHT / (M - 1)
    ew, ev = lx - 1.0, ly - 1.0
    area_w, area_v = t * dv, t * dx  # interior rows and columns: full tributary widths
    axial_w = area_w * float(fabric.weft.tangent(ew)) / dx
    across_w = area_w * float(fabric.weft.stress(ew)) / (lx * dx)
    axial_v = area_v * float(fabric.warp.tangent(ev)) / dv
    across_v = area_v * float(fabric.warp.stress(ev)) / (ly * dv)
    s = 2.0 - 2.0 * np.cos(np.arange(1, N - 1) * np.pi / (N - 1))
    q = 2.0 - 2.0 * np.cos(np.arange(1, M - 1) * np.pi / (M - 1))
    blocks = [(axial_w, across_v), (across_w, axial_v), (across_w, across_v)]  # x, y, z
    return np.concatenate([(a * s[:, None] + b * q[None, :]).ravel() for a, b in blocks])


def patch_problem(fabric, lx: float, ly: float):
    """The patch, stretched, 1 m from a thin cylinder (so no node touches it), edges fixed."""
    grid = rectangle(N, M, WIDTH, HEIGHT, fabric)
    u, v = grid.rest_uv.T
    x = np.stack([1.0 + lx * u, ly * v, np.zeros_like(u)], axis=1)
    rows, cols = np.divmod(np.arange(grid.n_nodes), N)
    edge = (rows == 0) | (rows == M - 1) | (cols == 0) | (cols == N - 1)
    constraint = np.where(edge, FIXED, FREE).astype(np.int8)
    problem = Problem(grid, Cylinder(radius=0.02, bottom=-1.0, top=1.0), constraint)
    return problem, problem.evaluate(x)


@pytest.mark.parametrize(
    ("lx", "ly", "expect"),
    [
        (1.25, 1.12, "none"),  # stretched both ways: a stable membrane
        (1.02, 0.80, "some"),  # weft barely stretched, warp compressed: a few wrinkle modes
        (0.97, 0.95, "many"),  # compressed both ways: every out-of-plane mode buckles
    ],
)
@pytest.mark.parametrize("dissect", [False, True], ids=["mmd", "nested-dissection"])
def test_unstable_modes_of_a_deformed_patch_are_the_closed_form_count(
    fabric, monkeypatch, lx, ly, expect, dissect
):
    """A compressed spring's Hessian is A sigma / l < 0 across it: a membrane without bending
    stiffness buckles. The count of negative pivots equals the closed form's count of negative
    eigenvalues, in both orderings SuperLU uses."""
    if dissect:
        monkeypatch.setattr(linear, "DISSECT_FROM", 0)
    eigenvalues = patch_eigenvalues(fabric, lx, ly)
    assert np.min(np.abs(eigenvalues)) > 1e-6 * np.max(np.abs(eigenvalues))  # no near-zero one
    negative = int(np.count_nonzero(eigenvalues < 0))
    interior = (N - 2) * (M - 2)
    assert {"none": negative == 0, "some": 0 < negative < interior, "many": negative >= interior}[
        expect
    ]
    problem, ev = patch_problem(fabric, lx, ly)
    assert unstable_modes(problem, ev) == negative


def test_negative_eigenvalues_of_a_shifted_laplacian():
    """The 1-D Dirichlet Laplacian 2 - 2 cos(k pi / (n + 1)) shifted by s has as many negative
    eigenvalues as k with 2 - 2 cos(k pi / (n + 1)) < s."""
    n, shift = 300, 0.7
    laplacian = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n), format="csr")
    eigen = 2.0 - 2.0 * np.cos(np.arange(1, n + 1) * np.pi / (n + 1))
    matrix = (laplacian - shift * sp.identity(n)).tocsr()
    assert negative_eigenvalues(matrix) == int(np.count_nonzero(eigen < shift)) > 0


def test_a_factor_that_pivots_or_a_matrix_that_is_not_square_is_refused():
    swap = sp.csr_matrix(np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 2.0]]))
    with pytest.raises(ValueError, match="pivoted"):
        negative_eigenvalues(swap)
    with pytest.raises(ValueError, match="square"):
        negative_eigenvalues(sp.csr_matrix(np.ones((2, 3))))


def test_the_result_stage_records_unstable_modes_and_warns_of_a_saddle(fabric, caplog):
    """`stability` (the aggregate stage's `unstable_modes` attribute): the count, a warning
    where it is not 0, none for a stable patch, and -1 where the skin models make it undefined."""
    from dataclasses import replace

    from cloth.stages.results import stability

    saddle, ev = patch_problem(fabric, 0.97, 0.95)
    with caplog.at_level("WARNING", logger="cloth.stages.results"):
        modes = stability(saddle, ev)
    assert modes == int(np.count_nonzero(patch_eigenvalues(fabric, 0.97, 0.95) < 0)) > 0
    assert f"the equilibrium is a saddle: {modes} unstable modes." in caplog.text
    assert "the reported pressures are those of one balanced state" in caplog.text
    before = linear.factorisations()  # a count relax made from its own factor: none here
    assert stability(saddle, ev, counted=modes) == modes
    assert linear.factorisations() == before
    caplog.clear()
    stable, ev = patch_problem(fabric, 1.25, 1.12)
    with caplog.at_level("WARNING", logger="cloth.stages.results"):
        assert stability(stable, ev) == 0
    assert "saddle" not in caplog.text
    assert stability(replace(stable, tissue=object()), ev) == -1


def test_a_pure_tension_field_has_no_unstable_mode():
    """With no compression modulus a spring's energy is a convex, non-decreasing function of its
    length, so convex in the node positions: the patch compressed both ways, every out-of-plane
    mode a buckling one at 1 %, has none; its Hessian is positive semi-definite (the least
    eigenvalue of the dense matrix is >= 0 to rounding)."""
    tension = make_fabric(compression=0.0)
    assert tension.weft.compression_modulus == 0.0 == tension.warp.compression_modulus
    for lx, ly in ((0.97, 0.95), (1.02, 0.80), (1.25, 1.12)):
        problem, ev = patch_problem(tension, lx, ly)
        assert unstable_modes(problem, ev) == 0
        k = stiffness(ev.x, problem.grid).toarray()
        least = float(np.linalg.eigvalsh(k).min())
        assert least >= -1e-9 * float(np.abs(k).max())


@pytest.mark.parametrize("reuse", [False, True], ids=["plain", "reuse"])
def test_relax_leaves_a_saddle_for_a_minimum_and_counts_its_modes(tmp_path, reuse):
    """A tube on a cone pushes its rows up the slope and compresses the warp: with a 1 %
    compression modulus (the power net ingested so) Newton converges to a saddle (unstable
    modes counted afresh at it; relax reports the same count from its own last factor). With
    ``leave_saddles`` relax moves along its unstable modes and converges again, to a minimum of
    lower energy, and reports its count, 0, which a fresh factorisation at that equilibrium
    confirms."""
    from dataclasses import replace

    from cloth.cli import main
    from cloth.files.body import body_from_config
    from cloth.solvers import Settings, relax
    from cloth.stages.case import initial_state

    root = Path(__file__).resolve().parents[1]
    regularised = tmp_path / "powernet_c1.nc"
    assert (
        main(
            [
                "material",
                "ingest",
                str(root / "data/materials/powernet.csv"),
                "--knots",
                "8",
                "--compression-ratio",
                "0.01",
                "-o",
                str(regularised),
            ]
        )
        == 0
    )
    cone = {"cone": {"radius_bottom": 0.13, "radius_top": 0.09, "bottom": 0.0, "top": 0.5}}
    state = initial_state(
        {
            "material": str(regularised),
            "body": cone,
            "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.15, "grid": [96, 24]},
        },
        root,
    )
    body, _ = body_from_config(state.case.body.block)
    settings = Settings(
        method="newton",
        linear_solver="superlu",
        tolerance=1e-10,
        reuse=reuse,
        leave_saddles=True,
        progress=False,
    )
    problem = Problem.of(state, body)
    stuck = relax(state, body, replace(settings, leave_saddles=False))
    at_saddle = unstable_modes(problem, problem.evaluate(stuck.final.x))
    assert stuck.converged and at_saddle > 0
    assert stuck.unstable_modes in (at_saddle, None)  # None: the last factor was GMRES's
    assert reuse or stuck.unstable_modes == at_saddle
    result = relax(state, body, settings)
    assert result.converged and result.unstable_modes == 0
    assert unstable_modes(problem, problem.evaluate(result.final.x)) == 0
    assert result.final.energy < stuck.final.energy
