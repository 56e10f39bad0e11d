"""The smooth parametric torso: its closest points, normals and curvature are exact, it is the
surface the torso mesh samples, and Newton converges quadratically on it."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from cloth.bodies import MeshBody, polygon_perimeter
from cloth.bodies.torso import LANDMARKS, SmoothTorso, chart_size, superellipse, torso_mesh
from cloth.files.body import body_from_config
from cloth.garment.grid import FREE
from cloth.solvers import Settings, relax
from cloth.stages.case import initial_state

RNG = np.random.default_rng(7)


@pytest.fixture(scope="module")
def torso() -> SmoothTorso:
    return SmoothTorso(chart_size("M"))


def surface_points(body: SmoothTorso, count: int, low: float, high: float) -> np.ndarray:
    """Points on the surface by the superellipse's angle parametrisation (independent of the
    implicit form the body uses)."""
    z = RNG.uniform(low, high, count)
    angle = RNG.uniform(0, 2 * np.pi, count)
    a, front, back = body._profile(z)[0]
    x, y = superellipse(angle)
    return np.column_stack([a * x, np.where(y > 0, y * front, y * back), z])


def test_closest_points_are_exact_feet_of_the_normal(torso):
    on = surface_points(torso, 4000, torso.bottom - 0.02, torso.top + 0.02)
    offset = RNG.uniform(-0.01, 0.01, len(on))
    normal = torso.query(on)[2]
    points = on + offset[:, None] * normal  # 1 cm in and out along the normal
    distance, closest, n = torso.query(points)
    # the surface's own points come back to themselves, at the signed offset
    np.testing.assert_allclose(distance, offset, atol=1e-12)
    np.testing.assert_allclose(closest, on, atol=1e-12)
    np.testing.assert_allclose(n, normal, atol=1e-9)
    assert np.abs(torso.implicit(closest)[0]).max() <= 1e-12


def test_implicit_derivatives_match_finite_differences(torso):
    q = surface_points(torso, 200, torso.bottom + 0.01, torso.top - 0.01)
    _, g, h = torso.implicit(q)
    step = 1e-6
    for axis in range(3):
        dq = np.zeros(3)
        dq[axis] = step
        plus, minus = torso.implicit(q + dq), torso.implicit(q - dq)
        fd_g = (plus[0] - minus[0]) / (2 * step)
        fd_h = (plus[1] - minus[1]) / (2 * step)
        np.testing.assert_allclose(g[:, axis], fd_g, atol=1e-6 * np.abs(g).max())
        np.testing.assert_allclose(h[:, :, axis], fd_h, atol=1e-6 * np.abs(h).max())


def test_distance_hessian_is_the_derivative_of_the_normal(torso):
    q = surface_points(torso, 200, torso.bottom + 0.01, torso.top - 0.01)
    hessian = torso.hessian(q)
    step = 1e-6
    for axis in range(3):
        dq = np.zeros(3)
        dq[axis] = step
        fd = (torso.query(q + dq)[2] - torso.query(q - dq)[2]) / (2 * step)
        np.testing.assert_allclose(hessian[:, :, axis], fd, atol=1e-6 * np.abs(hessian).max())
    # the shape operator: symmetric, the normal in its null space, convex around (>= 0 on the
    # horizontal tangent)
    normal = torso.query(q)[2]
    np.testing.assert_allclose(hessian, hessian.transpose(0, 2, 1), atol=1e-12)
    assert np.abs(np.einsum("pij,pj->pi", hessian, normal)).max() <= 1e-9
    around = np.cross([0.0, 0.0, 1.0], normal)
    around /= np.linalg.norm(around, axis=1, keepdims=True)
    assert np.einsum("pi,pij,pj->p", around, hessian, around).min() >= -1e-9


def test_sections_have_the_chart_girths_and_the_mesh_lies_on_the_surface(torso):
    chart = chart_size("M")
    for landmark in LANDMARKS:
        # measured on the surface itself: points on G = 0 along 4096 horizontal rays (exact,
        # G is homogeneous in x, y at a height), Richardson-extrapolated polygon perimeters
        z = chart.height[landmark]
        perimeters = []
        for count in (2048, 4096):
            angle = 2 * np.pi * np.arange(count) / count
            ray = np.column_stack([np.cos(angle), np.sin(angle), np.full(count, z)])
            ring = torso.locate(ray)[0]
            assert np.abs(torso.implicit(ring)[0]).max() <= 1e-12
            perimeters.append(polygon_perimeter(ring[:, :2]))
        measured = (4 * perimeters[1] - perimeters[0]) / 3
        assert measured == pytest.approx(chart.girth[landmark], rel=1e-6)
    around = 128
    vertices, faces = torso_mesh(chart, around=around, rings=120)
    # the mesh's rings are scaled to the girth by their polygon's perimeter, which falls short
    # of the curve's by about (2 pi / around)^2 / 24 of it: vertices lie that far outside
    distance = torso.query(vertices[:-2])[0]
    radius = 0.2
    assert distance.min() >= 0
    assert distance.max() <= radius * (2 * np.pi / around) ** 2 / 24 * 2
    # and the surface within a chord's sagitta, h^2 kappa / 8, of the mesh's faces
    mesh = MeshBody(vertices, faces)
    p = surface_points(torso, 2000, 0.9, 1.2)
    kappa = np.linalg.eigvalsh(torso.hessian(p)).max()
    side = vertices[faces[: -2 * around]]  # the side faces (the caps are not the surface)
    h = np.linalg.norm(side - np.roll(side, 1, axis=1), axis=2).max()
    assert np.abs(mesh.query(p)[0]).max() <= h**2 * kappa / 8 + distance.max()


def test_newton_converges_quadratically_on_the_smooth_torso():
    case = {
        "material": "powernet",
        "body": {"torso": {"size": "M"}},
        "garment": {"bottom": 0.86, "top": 1.22, "reduction": 0.15, "grid": [48, 16]},
    }
    state = initial_state(case)
    body, _ = body_from_config(state.case.body.block)
    assert isinstance(body, SmoothTorso)
    settings = Settings(tolerance=1e-8, max_iterations=40, progress=False, log_every=0)
    result = relax(state, body, settings)
    r = np.array(result.history.residual)
    assert result.converged and r[-1] <= 1e-8
    tail = [(a, b) for a, b in itertools.pairwise(r) if a < 1e-3]
    assert tail, r
    for a, b in tail:  # r_next <= C r^1.6 (quadratic gives ~ r^2)
        assert np.log(b) <= 1.6 * np.log(a) + 2, r
    assert max(result.history.penetration) <= 1e-9
    # frictionless: every free node the body holds is pushed along its normal only
    ev = result.final
    held = ev.on_body & (state.constraint == FREE)
    force, normal = ev.forces[held], ev.normal[held]
    tangential = force - np.einsum("ij,ij->i", force, normal)[:, None] * normal
    assert held.sum() > 0.5 * state.grid.n_nodes
    assert np.linalg.norm(tangential, axis=1).max() <= 1e-8 * ev.typical
