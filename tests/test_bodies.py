"""Bodies: closed forms exact, mesh queries within the faceting error, units and axes, torso."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from cloth.bodies import Cone, Cylinder, EllipticCylinder, MeshBody, loop_around
from cloth.bodies.torso import LANDMARKS, chart_size, torso_mesh
from cloth.errors import InputError
from tests.conftest import write_obj

RNG = np.random.default_rng(7)


def random_points(count, radius, z=(0.2, 0.8)):
    r = radius * RNG.uniform(0.3, 1.7, count)
    t = RNG.uniform(0, 2 * np.pi, count)
    return np.column_stack([r * np.cos(t), r * np.sin(t), RNG.uniform(*z, count)])


def test_cylinder_is_exact():
    body = Cylinder(0.1)
    p = random_points(500, 0.1)
    d, q, n = body.query(p)
    r = np.hypot(p[:, 0], p[:, 1])
    np.testing.assert_allclose(d, r - 0.1, atol=1e-15)
    np.testing.assert_allclose(np.hypot(q[:, 0], q[:, 1]), 0.1, atol=1e-15)
    np.testing.assert_allclose(p - q, d[:, None] * n, atol=1e-12)


@pytest.mark.parametrize(("a", "b"), [(0.15, 0.10), (0.10, 0.15), (0.12, 0.12)])
def test_ellipse_closest_point_is_exact(a, b):
    body = EllipticCylinder(a, b)
    p = random_points(400, 0.12)
    p[:5, :2] = [[0, 0.3], [0.3, 0], [0.01, 0], [0, -0.02], [0, 0]]  # axes and centre
    d, q, n = body.query(p)
    # on the ellipse, and p - q along the normal there: the exact characterisation
    np.testing.assert_allclose((q[:, 0] / a) ** 2 + (q[:, 1] / b) ** 2, 1.0, atol=1e-12)
    np.testing.assert_allclose(p - q, d[:, None] * n, atol=1e-9)
    # nothing on a fine sampling of the ellipse is closer (to 1e-9 m)
    t = np.linspace(0, 2 * np.pi, 200_001)
    ring = np.column_stack([a * np.cos(t), b * np.sin(t)])
    for point, dist in zip(p[:60], d[:60], strict=True):
        k = int(np.argmin(np.hypot(*(ring - point[:2]).T)))
        fine = np.linspace(
            t[k - 1], t[(k + 1) % t.size] + (2 * np.pi if k + 1 == t.size else 0), 20_001
        )
        local = np.column_stack([a * np.cos(fine), b * np.sin(fine)])
        brute = np.min(np.hypot(*(local - point[:2]).T))  # sampled at ~5e-10 m: exact to ~1e-15
        assert abs(dist) <= brute + 1e-12
        assert abs(dist) >= brute - 1e-9
    inside = (p[:, 0] / a) ** 2 + (p[:, 1] / b) ** 2 < 1
    assert np.all((d < 0) == inside)


def test_ellipse_curvature_and_perimeter():
    body = EllipticCylinder(0.15, 0.10)
    np.testing.assert_allclose(
        body.curvature([[0.15, 0.0], [0.0, 0.10]]), [0.15 / 0.01, 0.10 / 0.0225]
    )
    h = ((0.15 - 0.10) / 0.25) ** 2  # Ramanujan II, accurate to ~1e-10 here
    ramanujan = np.pi * 0.25 * (1 + 3 * h / (10 + np.sqrt(4 - 3 * h)))
    assert body.girth(0.5)[0] == pytest.approx(ramanujan, rel=1e-9)


def test_cone_is_exact():
    body = Cone(0.12, 0.08, bottom=0.0, top=1.0)
    p = random_points(300, 0.1)
    d, q, n = body.query(p)
    zq = q[:, 2]
    np.testing.assert_allclose(np.hypot(q[:, 0], q[:, 1]), body.radius(zq), atol=1e-15)
    np.testing.assert_allclose(p - q, d[:, None] * n, atol=1e-12)
    slope_normal = np.array([1.0, 0.04]) / np.hypot(1.0, 0.04)
    np.testing.assert_allclose(n[:, 2], slope_normal[1], atol=1e-15)


# numpy's is 25x slower here and runs in make test-slow; test_numpy_and_igl_backends_agree keeps it
# in the fast suite
@pytest.mark.parametrize("backend", ["igl", pytest.param("numpy", marks=pytest.mark.slow)])
def test_mesh_cylinder_within_faceting_error(backend):
    sections, radius = 5000, 0.1
    mesh = trimesh.creation.cylinder(radius=radius, height=1.0, sections=sections)
    assert 19_000 <= len(mesh.faces) <= 21_000
    body = MeshBody(mesh.vertices, mesh.faces, backend=backend)
    p = random_points(2000, radius, z=(-0.3, 0.3))
    d, _, n = body.query(p)
    exact_d, _, exact_n = Cylinder(radius, -0.5, 0.5).query(p)
    sagitta = radius * (1 - np.cos(np.pi / sections))  # the polygon's largest gap to the circle
    assert np.max(np.abs(d - exact_d)) <= sagitta + 1e-12
    angle = np.arccos(np.clip(np.einsum("ij,ij->i", n, exact_n), -1, 1))
    far = np.abs(exact_d) > 1e-3  # the normal of a point off the surface is (p - q)/|p - q|
    assert np.max(angle[far]) <= 2 * np.pi / sections + np.max(sagitta / np.abs(exact_d[far]))


def test_numpy_and_igl_backends_agree():
    vertices, faces = torso_mesh(chart_size("S"), around=48, rings=30)
    p = RNG.normal(scale=0.15, size=(3000, 3)) + np.array([0, 0, 1.0])
    a = MeshBody(vertices, faces, backend="igl").query(p)
    b = MeshBody(vertices, faces, backend="numpy").query(p)
    np.testing.assert_allclose(a[0], b[0], atol=1e-12)
    np.testing.assert_allclose(a[1], b[1], atol=1e-12)


@pytest.mark.parametrize("size", ["S", "M", "L"])
def test_torso_matches_chart_and_is_watertight(size):
    chart = chart_size(size)
    vertices, faces = torso_mesh(chart)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    body = MeshBody(vertices, faces)
    for landmark in LANDMARKS:
        section, hull = body.girth(chart.height[landmark])
        assert section == pytest.approx(chart.girth[landmark], rel=5e-3)
        assert hull == pytest.approx(chart.girth[landmark], rel=5e-3)


@pytest.mark.parametrize(("around", "rings"), [(32, 30), (64, 60), (128, 120)])
def test_torso_mesh_is_mirror_symmetric_like_the_torso(around, rings):
    """The torso is left-right symmetric, and so is its mesh: the mirrored mesh (x -> -x) has
    the same triangles. Splitting every quad along the same diagonal made the mesh chiral (its
    creases ran in helices), and a frictionless garment on the coarse mesh turned about the body
    without end (docs/solvers.md)."""
    vertices, faces = torso_mesh(chart_size("M"), around, rings)
    mirrored = vertices * np.array([-1.0, 1.0, 1.0])

    def triangles(points):
        corners = np.round(points[faces], 9).reshape(len(faces), 3, 3)
        return {tuple(sorted(map(tuple, triangle))) for triangle in corners}

    assert triangles(mirrored) == triangles(vertices)


@pytest.mark.parametrize("rings", [30, 60, 120])
def test_torso_mesh_rings_are_even_and_meet_the_landmarks(rings):
    """``rings`` rings through every landmark height, no gap more than 15 % off the even one:
    rings added at the landmarks left slivers of 3 mm among 19 mm rings (32 x 30), where 1 mm
    of vertex noise made slopes of 0.3 on the girth lines themselves."""
    chart = chart_size("M")
    vertices, _ = torso_mesh(chart, 32, rings)
    heights = np.unique(vertices[:, 2])
    assert heights.size == rings
    for landmark in LANDMARKS:
        assert np.min(np.abs(heights - chart.height[landmark])) < 1e-12, landmark
    even = (chart.height["top"] - chart.height["bottom"]) / (rings - 1)
    np.testing.assert_allclose(np.diff(heights), even, rtol=0.15)


def test_units_and_up_axis_give_the_same_body(tmp_path):
    vertices, faces = torso_mesh(chart_size("M"), around=64, rings=40)

    metres = write_obj(tmp_path / "torso_m_zup.obj", vertices, faces)
    y_up_mm = np.column_stack([vertices[:, 0], vertices[:, 2], -vertices[:, 1]]) * 1000
    millimetres = write_obj(tmp_path / "torso_mm_yup.obj", y_up_mm, faces)
    a = MeshBody.load(metres)
    b = MeshBody.load(millimetres, units="mm", up="y")
    for z in np.linspace(0.8, 1.3, 7):
        np.testing.assert_allclose(a.girth(z), b.girth(z), rtol=1e-9)


def test_loop_around_picks_the_enclosing_loop():
    t = np.linspace(0, 2 * np.pi, 33)[:-1]

    def ring(cx):
        return np.column_stack([cx + 0.05 * np.cos(t), 0.05 * np.sin(t)])

    loops = [np.stack([r, np.roll(r, -1, axis=0)], axis=1) for r in (ring(-0.1), ring(0.1))]
    chosen = loop_around(loops, [0.1, 0.0])
    assert len(chosen) == 1 and chosen[0][:, 0, 0].mean() > 0
    with pytest.raises(InputError, match="encloses"):
        loop_around(loops, [0.0, 0.0])


def broken_box(kind, tmp_path):
    box = trimesh.creation.box(extents=[0.3, 0.2, 0.5])
    faces = box.faces.copy()
    if kind == "hole":
        faces = faces[1:]
    elif kind == "winding":
        faces[0] = faces[0][::-1]
    elif kind == "inverted":
        faces = faces[:, ::-1]
    path = tmp_path / f"{kind}.ply"
    trimesh.Trimesh(box.vertices, faces, process=False).export(path)
    return path


@pytest.mark.parametrize(
    ("kind", "message"),
    [("hole", "not watertight"), ("winding", "inconsistently wound"), ("inverted", "inside out")],
)
def test_broken_meshes_are_refused_and_repaired_on_request(tmp_path, kind, message):
    path = broken_box(kind, tmp_path)
    with pytest.raises(InputError, match=message):
        MeshBody.load(path)
    body = MeshBody.load(path, repair=True)
    assert body.report.repairs and body.report.watertight and body.report.volume > 0
