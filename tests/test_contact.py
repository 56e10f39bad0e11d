"""Mesh contact: the normal cone and Newton's plane constraints are exact."""

from __future__ import annotations

import numpy as np
from scipy.optimize import nnls

from cloth.bodies import MeshBody
from cloth.bodies.torso import chart_size, torso_mesh
from cloth.contact import polyhedral as contact
from cloth.solvers.newton import _plane_constraints


def test_cone_pair_is_the_nonnegative_least_squares_optimum():
    rng = np.random.default_rng(1)
    force = rng.normal(size=(400, 3))
    normals = rng.normal(size=(400, 2, 3))
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    lam = contact.cone_pair(force, normals)
    assert np.all(lam >= 0)
    for f, n, got in zip(force, normals, lam, strict=True):
        want, _ = nnls(n.T, -f)
        # same remainder |F + N lambda| (lambda itself is unique here: generic normals)
        np.testing.assert_allclose(f + n.T @ got, f + n.T @ want, atol=1e-12)


def test_plane_constraints_project_and_meet_the_targets():
    rng = np.random.default_rng(2)
    basis = rng.normal(size=(300, 4, 3))
    basis[:, 3] = 0.0  # an unused row
    basis[::3, 2] = basis[::3, 1]  # dependent rows: rank 2
    basis[1::3, 1:] = 0.0  # a single constraint
    target = rng.normal(size=(300, 4))
    target[:, 3] = 0.0
    target[::3, 2] = target[::3, 1]  # consistent with the dependent row
    projector, move = _plane_constraints(basis, target)
    for b, t, p, c in zip(basis, target, projector, move, strict=True):
        want = np.linalg.lstsq(b, t, rcond=None)[0]  # minimum-norm solution
        np.testing.assert_allclose(c, want, atol=1e-10)
        np.testing.assert_allclose(p @ p, p, atol=1e-12)  # a projector
        np.testing.assert_allclose(b @ p, 0.0, atol=1e-12)  # onto the free directions
        assert np.isclose(np.trace(p), 3 - np.linalg.matrix_rank(b))


def _tetrahedron() -> MeshBody:
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    return MeshBody(vertices, faces)


def test_frames_on_an_edge_pushed_by_both_faces_constrain_both_planes():
    body = _tetrahedron()
    point = np.array([[0.5, 0.0, 0.0]])  # on the edge between z = 0 and y = 0
    both = np.array([[0.0, 1.0, 1.0]])  # pushes into both faces (their outward normals -z, -y)
    normals, offsets, faces = contact.frames(body, point, both, np.zeros(1, bool))
    assert sorted(faces[0][faces[0] >= 0]) == [0, 1]
    np.testing.assert_allclose(np.abs(normals[0]).sum(axis=0), [0.0, 1.0, 1.0])  # -y and -z
    np.testing.assert_allclose(offsets, 0.0, atol=1e-15)
    assert np.allclose(contact.remainder(body, point, both), 0.0)
    one = np.array([[0.0, -1.0, 1.0]])  # into the bottom, away from the front: one plane
    _, _, faces = contact.frames(body, point, one, np.zeros(1, bool))
    assert list(faces[0]) == [0, -1, -1]
    np.testing.assert_allclose(contact.remainder(body, point, one), [[0.0, -1.0, 0.0]])


def test_remainder_on_the_torso_matches_nnls_at_every_feature():
    vertices, faces = torso_mesh(chart_size("S"), around=32, rings=20)
    body = MeshBody(vertices, faces)
    rng = np.random.default_rng(3)
    # points on faces, edges and vertices
    corners = vertices[faces[rng.integers(0, len(faces), 60)]]
    weights = rng.dirichlet(np.ones(3), 60)
    weights[20:40, 2] = 0.0
    weights[20:40] /= weights[20:40].sum(axis=1, keepdims=True)
    weights[40:] = np.eye(3)[rng.integers(0, 3, 20)]
    points = np.einsum("pc,pcd->pd", weights, corners)
    force = rng.normal(size=(60, 3))
    got = contact.remainder(body, points, force)
    face, _, code = contact.locate(body, points)
    topo = body.topology()
    for i in range(60):
        if code[i] == contact.FACE:
            ring = [face[i]]
        elif code[i] < contact.VERTEX_A:
            ring = list(topo["edge_faces"][face[i], code[i] - contact.EDGE_AB])
        else:
            ring = list(topo["vertex_faces"][faces[face[i], code[i] - contact.VERTEX_A]])
        n = topo["face_normal"][ring]
        lam, _ = nnls(n.T, -force[i])
        np.testing.assert_allclose(got[i], force[i] + n.T @ lam, atol=1e-10)
