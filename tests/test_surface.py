"""The smooth surface fitted to a mesh: against the closed-form body it samples, and Laplace."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from cloth.bodies.mesh import MeshBody
from cloth.bodies.refine import auto_levels, phong_refine
from cloth.bodies.smoothmesh import SmoothMeshBody
from cloth.bodies.spline import SplineField
from cloth.bodies.surface import FitOptions, fit_surface
from cloth.cli import main
from cloth.files.surface import load_or_fit, read_surface
from tests.conftest import capped_cylinder, write_obj
from tests.test_relax import hoop_tension, pressure, solve, tube

R = 0.1
RNG = np.random.default_rng(7)


def smooth(vertices, faces, refine: int | None = None) -> SmoothMeshBody:
    fit = fit_surface(MeshBody(vertices, faces), FitOptions(refine=refine), progress=False)
    return SmoothMeshBody(MeshBody(vertices, faces), lambda: (fit, None))


def errors(body, points, distance, normal):
    """Largest distance error (m) and normal error (deg) of the body's query."""
    d, _, n = body.query(points)
    cosine = np.clip(np.einsum("ij,ij->i", n, normal), -1.0, 1.0)
    return float(np.abs(d - distance).max()), float(np.degrees(np.arccos(cosine)).max())


def test_spline_reproduces_a_linear_field_and_its_derivatives():
    """Cubic B-splines with the samples as coefficients reproduce linear fields exactly; the
    gradient and Hessian of a cubic field match finite differences."""
    h, origin = 0.01, np.array([-0.1, -0.2, 0.05])
    axes = [origin[a] + h * np.arange(n) for a, n in enumerate((21, 31, 17))]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    linear = SplineField(origin, h, 0.3 * x - 0.7 * y + 0.2 * z + 0.01)
    p = origin + RNG.uniform(2 * h, 14 * h, (200, 3))
    value, gradient, hessian = linear.evaluate(p)
    np.testing.assert_allclose(value, p @ [0.3, -0.7, 0.2] + 0.01, atol=1e-15)
    np.testing.assert_allclose(gradient, np.broadcast_to([0.3, -0.7, 0.2], p.shape), atol=1e-13)
    np.testing.assert_allclose(hessian, 0.0, atol=1e-10)
    field = SplineField(origin, h, np.sin(7 * x) * np.cos(5 * y) + z**3)
    value, gradient, hessian = field.evaluate(p)
    step = 1e-6
    for axis in range(3):
        e = np.zeros(3)
        e[axis] = step
        plus, grad_plus, _ = field.evaluate(p + e)
        minus, grad_minus, _ = field.evaluate(p - e)
        np.testing.assert_allclose((plus - minus) / (2 * step), gradient[:, axis], atol=1e-7)
        np.testing.assert_allclose(
            (grad_plus - grad_minus) / (2 * step), hessian[:, :, axis], atol=1e-5
        )
    assert np.all(field.within(p))
    assert not np.any(field.within(origin + np.array([[0.5 * h, 5 * h, 5 * h]])))


@pytest.mark.slow  # a minute; test_laplace_on_a_meshed_cylinder_within_one_percent stays fast
def test_sphere_and_cylinder_meshes_converge_to_the_closed_form():
    """Distance and normal errors against the body the mesh samples (docs/bodies.md). Fitted to
    the facets as they are (refine 0), they shrink with resolution: 1.5 mm / 1 deg on the
    coarsest, 0.1 mm / 0.1 deg on the finest. Refined along curved patches first (the default
    for clean coarse meshes), the coarse levels come within 0.25 mm / 0.6 deg, and no level is
    worse than unrefined."""
    u = RNG.normal(size=(1500, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    offset = RNG.uniform(-0.005, 0.005, 1500)
    angle = RNG.uniform(0, 2 * np.pi, 1500)
    radial = np.column_stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)])
    points = radial * (R + offset)[:, None] + np.outer(RNG.uniform(0.06, 0.14, 1500), [0, 0, 1])
    meshes = {
        "sphere": [trimesh.creation.icosphere(level, radius=R) for level in (2, 3, 4)],
        "cylinder": [trimesh.Trimesh(*capped_cylinder(R, 0.2, n)) for n in (32, 64, 128)],
    }
    probes = {"sphere": (u * (R + offset)[:, None], u), "cylinder": (points, radial)}
    for kind, levels in meshes.items():
        at, normal = probes[kind]
        flat, default = [], []
        for mesh in levels:
            v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
            body = smooth(v, f, refine=0)
            flat.append(errors(body, at, offset, normal))
            if auto_levels(v, f):
                default.append(errors(smooth(v, f), at, offset, normal))
            else:  # the same fit
                default.append(flat[-1])
        distance = [d for d, _ in flat]
        assert distance[0] > distance[1] > distance[2], (kind, flat)
        assert distance[0] < 1.5e-3 and distance[2] < 1e-4, (kind, flat)
        assert max(n for _, n in flat) < 1.0 and flat[2][1] < 0.1, (kind, flat)
        assert max(d for d, _ in default) < 0.25e-3 and max(n for _, n in default) < 0.6
        for (d_flat, n_flat), (d, n) in zip(flat, default, strict=True):
            assert d <= d_flat * 1.05 and n <= n_flat * 1.05, (kind, flat, default)
    # at the finest level the hoop curvature is 1/r within 2 % away from the caps
    feet = body.closest(points)
    k1, k2 = body.curvature(feet)
    np.testing.assert_allclose(k1, 1 / R, rtol=0.02)
    np.testing.assert_allclose(k2, 0.0, atol=0.02 / R)


@pytest.mark.slow  # a fitted mesh surface relaxed (30 s; make test-slow)
def test_laplace_on_a_meshed_cylinder_within_one_percent(tmp_path):
    """64 segments, r = 0.1 m, reduction 0.2: p = T / r at every interior contact node within
    1 %, where the faceted contact puts the pressure on the facets' edges (a node on a flat
    facet carries none)."""
    path = write_obj(tmp_path / "cylinder64.obj", *capped_cylinder(R, 0.5, 64))
    for surface in ("smooth", "mesh"):
        state = tube({"mesh": str(path), "surface": surface}, 0.2, n=96, m=8)
        result = solve(state, iterations=100)
        assert result.converged, surface
        held, p = pressure(state, result)
        laplace = (hoop_tension(state, result) / R).ravel()
        interior = np.zeros((8, 96), bool)
        interior[1:-1] = True
        ratio = (p / laplace)[interior.ravel()]
        if surface == "smooth":
            assert np.all(held[interior.ravel()])
            np.testing.assert_allclose(ratio, 1.0, rtol=0.01)
        else:  # the faceted contact cannot: nodes on facets press nothing
            assert np.abs(ratio - 1).max() > 0.2


@pytest.mark.slow  # three fits (10 s; make test-slow)
def test_fit_is_cached_by_mesh_and_options_and_round_trips(tmp_path):
    vertices, faces = capped_cylinder(R, 0.3, 48)
    mesh = MeshBody(vertices, faces)
    fit, path = load_or_fit(mesh, FitOptions(), tmp_path / "s.nc")
    again = read_surface(path)
    assert again.key == fit.key and again.smoothing == fit.smoothing
    np.testing.assert_array_equal(again.field.coefficients, fit.field.coefficients)
    reused, same = load_or_fit(mesh, FitOptions(), tmp_path / "s.nc")
    assert same == path and reused.key == fit.key
    other, elsewhere = load_or_fit(mesh, FitOptions(smoothing=0.012), tmp_path / "s.nc")
    assert other.key != fit.key and elsewhere != path and other.smoothing == 0.012


@pytest.mark.slow  # a fit of a noisy mesh (6 s; make test-slow)
def test_noise_is_smoothed_not_amplified():
    """1 mm of vertex noise on a 64-segment cylinder (vertices 10 mm apart): around a ring the
    fitted surface's radius varies by less than half the noise and sits within half of it of
    the clean radius (measured 0.26-0.43 mm and -0.18..+0.002 mm over three seeds)."""
    vertices, faces = capped_cylinder(R, 0.4, 64)
    noisy = vertices + RNG.normal(scale=1e-3, size=vertices.shape)
    body = smooth(noisy, faces)
    angle = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    ring = np.column_stack([R * np.cos(angle), R * np.sin(angle), np.full(400, 0.2)])
    feet = body.closest(ring)
    radius = np.hypot(feet[:, 0], feet[:, 1])
    assert radius.std() < 0.5e-3 and abs(radius.mean() - R) < 0.5e-3


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("nan.obj", "not finite"),
        ("fin.obj", "non-manifold"),
        ("empty.obj", "no triangles"),
        ("open.obj", "too large for the winding number"),
    ],
)
def test_bad_meshes_one_line_exit_2_no_output(tmp_path, capsys, name, expected):
    vertices, faces = capped_cylinder(R, 0.3, 24)
    if name == "nan.obj":
        vertices = vertices.copy()
        vertices[5] = np.nan
    elif name == "fin.obj":  # a third face on an edge
        vertices = np.vstack([vertices, [[0.5, 0.5, 0.5]]])
        faces = np.vstack([faces, [[faces[0][0], faces[0][1], len(vertices) - 1]]])
    elif name == "open.obj":  # the side without its caps: two holes as large as the girth
        faces = faces[: -2 * 24]
    path = tmp_path / name
    if name == "empty.obj":
        path.write_text("")
    else:
        write_obj(path, vertices, faces)
    out = tmp_path / "surface.nc"
    assert main(["body", "fit", str(path), "-o", str(out)]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(err) == 1 and expected in err[0], err
    assert not out.exists()


def test_body_fit_writes_its_output_when_the_cache_already_holds_the_fit(tmp_path):
    """The pipeline's body_surface rule asks for its file: a fit read from the cache (another
    run fitted the same mesh) is written there too, the same surface."""
    vertices, faces = capped_cylinder(R, 0.3, 24)
    path = tmp_path / "cyl.obj"
    write_obj(path, vertices, faces)
    first, second = tmp_path / "a.nc", tmp_path / "b.nc"
    assert main(["body", "fit", str(path), "-o", str(first)]) == 0
    assert main(["body", "fit", str(path), "-o", str(second)]) == 0
    assert second.is_file() and read_surface(second).key == read_surface(first).key


@pytest.mark.slow  # a fit and its figure (5 s; make test-slow)
def test_body_check_reports_the_deviation_and_draws_the_curvature(tmp_path, capsys):
    path = write_obj(tmp_path / "cyl.obj", *capped_cylinder(R, 0.3, 48))
    figure = tmp_path / "curvature.png"
    assert main(["body", "check", str(path), "--levels", "2", "--curvature", str(figure)]) == 0
    text = capsys.readouterr().out
    assert "vertices from the smooth surface: max" in text and "RMS" in text
    assert figure.stat().st_size > 10_000


@pytest.mark.parametrize("kind", ["cylinder", "sphere"])
def test_phong_refinement_puts_new_points_on_the_curved_body(kind):
    """Split twice along Phong patches (alpha 1/2), a coarse mesh's new points lie close to the
    body it samples: the largest radius error is under an eighth of the flat facets' (measured:
    0.7 % on a 32-segment cylinder, where alpha 1/2 is exact to second order; 9.5 % on an
    icosphere of subdivision 1, curved both ways), and the mesh stays closed and outward."""
    if kind == "cylinder":
        vertices, faces = capped_cylinder(R, 0.4, 32)
    else:
        sphere = trimesh.creation.icosphere(subdivisions=1, radius=R)
        vertices, faces = sphere.vertices, sphere.faces
    refined, triangles = phong_refine(vertices, faces, 2)
    mesh = trimesh.Trimesh(refined, triangles, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    if kind == "cylinder":  # the side, away from the rims (features: kept flat)
        side = (refined[:, 2] > 0.05) & (refined[:, 2] < 0.35)
        radius = np.hypot(refined[side, 0], refined[side, 1])
        flat_radius = np.hypot(*trimesh.remesh.subdivide(vertices, faces)[0][:, :2].T)
    else:
        radius = np.linalg.norm(refined, axis=1)
        flat_radius = np.linalg.norm(
            trimesh.remesh.subdivide(*trimesh.remesh.subdivide(vertices, faces))[0], axis=1
        )
    flat_error = np.abs(flat_radius - R).max()
    assert flat_error > 1e-4  # the facets' own error is real
    assert np.abs(radius - R).max() < 0.125 * flat_error


def test_only_clean_coarse_meshes_are_refined():
    """Refinement assumes the vertices lie on a smooth surface: a clean 32-segment cylinder
    (facets 20 mm wide) is split twice; with 1 mm of vertex noise it is not; a fine one
    (256 segments, 2.5 mm) needs none."""
    vertices, faces = capped_cylinder(R, 0.4, 32)
    assert auto_levels(vertices, faces) == 2
    noisy = vertices + RNG.normal(scale=1e-3, size=vertices.shape)
    assert auto_levels(noisy, faces) == 0
    assert auto_levels(*capped_cylinder(R, 0.4, 256)) == 0
