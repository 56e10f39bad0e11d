"""Coulomb friction between fabric and skin: the capstan equation, and the frictionless limits."""

from __future__ import annotations

import numpy as np
import pytest

from cloth.case import Contact, Skin
from cloth.contact.friction import Friction
from cloth.errors import InputError
from cloth.files.body import body_from_config
from cloth.garment.grid import FIXED, FREE, WEFT, build_grid, node_area
from cloth.garment.state import State
from cloth.materials.curves import Fabric, StressStrainCurve
from cloth.results.pressure import contact_reaction
from cloth.solvers import Settings, relax
from cloth.solvers.newton import stiffness_at
from cloth.solvers.problem import Problem
from cloth.stages.case import initial_state

RADIUS, HEIGHT, WIDTH = 0.1, 0.2, 0.01
CYLINDER = {"cylinder": {"radius": RADIUS, "bottom": 0.0, "top": 0.5}}
SETTINGS = Settings(tolerance=1e-9, max_iterations=150, progress=False, log_every=0)


def strip(arc_nodes=100, straight=0.1, pretension=0.05):
    """A strip (2 rows, WIDTH apart) over half a vertical cylinder: up its +x side, over the
    half turn (angle pi) and down its -x side, its two ends fixed; rest length 1/(1 +
    pretension) of the path, a linear fabric (1 MPa, 1 mm)."""
    spacing = np.pi * RADIUS / arc_nodes
    count = round(straight / spacing)
    angle = np.linspace(0.0, np.pi, arc_nodes + 1)
    path = np.concatenate(
        [
            np.column_stack([np.full(count, RADIUS), -spacing * np.arange(count, 0, -1)]),
            RADIUS * np.column_stack([np.cos(angle), np.sin(angle)]),
            np.column_stack([np.full(count, -RADIUS), -spacing * np.arange(1, count + 1)]),
        ]
    )
    n = len(path)
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    curve = StressStrainCurve.linear(1e6)
    fabric = Fabric("linear", weft=curve, warp=curve, thickness=1e-3)
    grid = build_grid(n, 2, length / (1 + pretension), [0.0, WIDTH], fabric)
    x = np.concatenate([np.column_stack([path, np.full(n, z)]) for z in (HEIGHT, HEIGHT + WIDTH)])
    constraint = np.full(2 * n, FREE, np.int8)
    constraint[[0, n - 1, n, 2 * n - 1]] = FIXED
    return grid, x, constraint, fabric


def relaxed(grid, x, constraint, fabric, mu):
    skin = Skin(contact=Contact(friction=mu))  # a hand-built state: no case, only its skin
    state = State(
        grid, x, constraint, np.zeros(len(x), np.int8), fabric, "weft", None, {}, skin=skin
    )
    body, _ = body_from_config(CYLINDER)
    result = relax(state, body, SETTINGS)
    assert result.converged
    return result


def end_tensions(grid, result):
    """Strip tension (N) in the first span (the pulled end) and the last (the fixed end)."""
    weft = grid.family_slices[WEFT]
    force = (grid.area[weft] * result.final.springs.stress[weft]).reshape(grid.m, -1).sum(axis=0)
    return float(force[0]), float(force[-1])


@pytest.mark.parametrize(
    ("mu", "pulls"), [(0.2, (0.005, 0.02, 0.04)), (0.5, (0.02, 0.04, 0.06, 0.08))]
)
def test_a_strip_over_a_half_cylinder_holds_until_the_capstan_ratio(mu, pulls):
    """Pretension T1, then the first end pulled further by each of ``pulls`` (m): while the
    pulled end's tension T2 is below T1 e^(mu pi) the far end keeps T1 (the strip sticks near
    it); beyond, the whole contact slips and T2 / T_far = e^(mu pi), the onset of slip."""
    grid, x, constraint, fabric = strip()
    pretensioned = relaxed(grid, x, constraint, fabric, 0.0)
    _, t1 = end_tensions(grid, pretensioned)
    capstan = np.exp(mu * np.pi)
    held, slipped = [], []
    for pull in pulls:
        start = pretensioned.final.x.copy()
        start[[0, grid.n]] -= [0.0, pull, 0.0]
        result = relaxed(grid, start, constraint, fabric, mu)
        assert result.lags >= 1
        t2, far = end_tensions(grid, result)
        if t2 / t1 <= 0.99 * capstan:
            held.append(far / t1)
        elif t2 / t1 >= 1.01 * capstan:
            slipped.append((far / t1, t2 / far))
            assert np.count_nonzero(result.friction["state"] == 2) >= 0.9 * np.count_nonzero(
                result.friction["state"]
            )
    assert held and slipped
    np.testing.assert_allclose(held, 1.0, atol=1e-3)  # the far end does not feel the pull
    for far, ratio in slipped:
        assert far > 1.01
        assert abs(ratio / capstan - 1) < 0.01  # slip sets in at the capstan ratio


def test_zero_friction_is_the_frictionless_solver_bit_for_bit():
    case = {
        "material": "powernet",
        "body": CYLINDER,
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [24, 4]},
    }
    body, _ = body_from_config(CYLINDER)
    plain = relax(initial_state(case), body, SETTINGS)
    zero = relax(initial_state({**case, "contact": {"friction": 0.0}}), body, SETTINGS)
    np.testing.assert_array_equal(zero.final.x, plain.final.x)
    assert zero.lags == 0 and zero.history.residual == plain.history.residual


def test_friction_leaves_laplaces_pressure_on_a_cylinder():
    """The wrapped tube is already a frictionless equilibrium: friction carries nothing and the
    pressure stays T / r."""
    case = {
        "material": "powernet",
        "body": CYLINDER,
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [48, 4]},
    }
    body, _ = body_from_config(CYLINDER)

    def pressure(result):
        ev = result.final
        reaction = contact_reaction(ev.forces, ev.unbalanced, ev.on_body)
        return np.linalg.norm(reaction, axis=1) / node_area(ev.x, state.grid)

    state = initial_state(case)
    frictionless = pressure(relax(state, body, SETTINGS))
    for mu in (0.3, 0.9):
        result = relax(initial_state({**case, "contact": {"friction": mu}}), body, SETTINGS)
        assert result.converged
        np.testing.assert_allclose(pressure(result), frictionless, rtol=1e-6)
        assert np.abs(result.friction["force"]).max() < 1e-5 * result.final.typical


def test_the_friction_hessian_is_the_potentials():
    """Newton's friction blocks against central differences of the friction force, in stick
    and in slip."""
    grid, x, constraint, _ = strip(arc_nodes=12, straight=0.03)
    body, _ = body_from_config(CYLINDER)
    rng = np.random.default_rng(5)
    normal = np.zeros_like(x)
    normal[:, :2] = x[:, :2] / np.linalg.norm(x[:, :2], axis=1)[:, None]
    friction = Friction(0.4, 1e-4, x.copy(), rng.uniform(0.1, 1.0, len(x)), normal)
    problem = Problem(grid, body, constraint, None, None, friction)
    moved = x + rng.choice([3e-5, 3e-3], size=(len(x), 1)) * rng.standard_normal(x.shape)
    k_skin = stiffness_at(problem, problem.evaluate(moved))(True) - stiffness_at(
        Problem(grid, body, constraint), problem.evaluate(moved)
    )(True)
    step = 1e-9
    for node in range(0, len(x), 7):
        for axis in range(3):
            plus, minus = moved.copy(), moved.copy()
            plus[node, axis] += step
            minus[node, axis] -= step
            column = -(friction.response(plus)[0] - friction.response(minus)[0]) / (2 * step)
            np.testing.assert_allclose(
                k_skin[:, 3 * node + axis].toarray().ravel(),
                column.ravel(),
                rtol=1e-4,
                atol=1e-6 * max(np.abs(column).max(), 1.0),
            )


@pytest.mark.parametrize(
    ("contact", "field"),
    [
        ({"friction": -0.1}, "contact.friction"),
        ({"friction": float("nan")}, "contact.friction"),
        ({"friction": 0.3, "slip_length": 0.0}, "contact.slip_length"),
    ],
)
def test_bad_friction_is_refused_naming_the_field(contact, field):
    case = {
        "material": "powernet",
        "body": CYLINDER,
        "contact": contact,
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [12, 3]},
    }
    body, _ = body_from_config(CYLINDER)
    with pytest.raises(InputError) as error:
        relax(initial_state(case), body, SETTINGS)
    assert error.value.field == field


def test_friction_needs_newton_and_the_wrap_as_its_path():
    case = {
        "material": "powernet",
        "body": CYLINDER,
        "contact": {"friction": 0.3},
        "garment": {"bottom": 0.1, "top": 0.4, "reduction": 0.2, "grid": [12, 3]},
    }
    body, _ = body_from_config(CYLINDER)
    state = initial_state(case)
    with pytest.raises(InputError, match="newton"):
        relax(state, body, Settings(method="explicit", progress=False))
    with pytest.raises(InputError, match="path"):
        relax(state, body, Settings(continuation=True, progress=False))
