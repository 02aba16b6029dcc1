"""Meshes that move: ``Mesh.update_vertices`` refits what is built, and
every query then answers as a new Mesh over the moved vertices (the oracle)
and, for closest points, as brute force over the triangles in float64."""

import numpy as np
import pytest

import proxima
from oracles import triangle_distances


def sphere(n=12):
    """A UV sphere of radius 1: (V, 3) vertices and triangles."""
    theta = np.linspace(0, np.pi, n + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    vertices = np.vstack([[0, 0, 1], ring, [0, 0, -1]]).astype(np.float32)
    m = 2 * n
    at = lambda i, j: 1 + i * m + j % m
    faces = [[0, at(0, j), at(0, j + 1)] for j in range(m)]
    for i in range(n - 2):
        for j in range(m):
            faces += [[at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]]
    last = len(vertices) - 1
    faces += [[at(n - 2, j), last, at(n - 2, j + 1)] for j in range(m)]
    return vertices, np.array(faces)


def swirl(vertices, turns):
    angle = turns * 2 * np.pi * (vertices[:, 2] + 1) / 2
    c, s = np.cos(angle), np.sin(angle)
    x, y = vertices[:, 0], vertices[:, 1]
    return np.stack([c * x - s * y, s * x + c * y, vertices[:, 2] * 1.3], -1).astype(np.float32)


def every_answer(mesh, points, origins, directions):
    closest = mesh.closest_points(points, return_barycentric=True, return_normal=True)
    signed = mesh.signed_distance(points, sign="pseudonormal")
    winding = mesh.winding_number(points) > 0.5
    rays = mesh.cast_rays(origins, directions)
    knn = mesh.k_nearest(points, 4, primitives="vertices")
    return closest, signed, winding, rays, knn


def assert_same(a, b):
    if isinstance(a, proxima.Answers):
        assert a.keys() == b.keys()
        for key in a.keys():
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    elif isinstance(a, (tuple, list)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            assert_same(x, y)
    elif a is None:
        assert b is None
    else:
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))


@pytest.mark.parametrize("turns", [0.01, 0.6])
def test_moved_mesh_answers_as_a_new_one(turns):
    vertices, faces = sphere()
    mesh = proxima.Mesh(vertices, faces)
    rng = np.random.default_rng(3)
    points = rng.uniform(-1.5, 1.5, (500, 3)).astype(np.float32)
    origins = rng.uniform(-3, 3, (300, 3)).astype(np.float32)
    directions = (-origins + rng.normal(0, 0.2, origins.shape)).astype(np.float32)
    every_answer(mesh, points, origins, directions)
    built = mesh.built_structures()
    moved = swirl(vertices, turns)
    updated = mesh.update_vertices(moved)
    assert [u[0] for u in updated] == built
    trees = {name: (rebuilt, ratio) for name, rebuilt, ratio in updated}
    # A small swirl refits; a large one wears the faces' tree past the ratio.
    assert trees["faces"][0] == (turns > 0.5), trees
    np.testing.assert_array_equal(mesh.vertices, moved)
    fresh = proxima.Mesh(moved, faces)
    assert_same(every_answer(mesh, points, origins, directions), every_answer(fresh, points, origins, directions))
    _, distance, face = mesh.closest_points(points)
    expected = triangle_distances(points, moved, faces).min(axis=1)
    np.testing.assert_allclose(distance, expected, rtol=1e-5, atol=1e-6)


def test_many_updates_in_a_row():
    vertices, faces = sphere(8)
    mesh = proxima.Mesh(vertices, faces)
    points = np.random.default_rng(5).uniform(-1.2, 1.2, (200, 3))
    mesh.closest_points(points)
    mesh.signed_distance(points)
    rng = np.random.default_rng(6)
    current = vertices.copy()
    for step in range(30):
        current = (current + rng.normal(0, 0.01, current.shape)).astype(np.float32)
        mesh.update_vertices(current)
    fresh = proxima.Mesh(current, faces)
    assert_same(mesh.closest_points(points), fresh.closest_points(points))
    assert_same(mesh.signed_distance(points), fresh.signed_distance(points))


def test_unbuilt_structures_stay_unbuilt_and_normals_follow():
    vertices, faces = sphere(6)
    mesh = proxima.Mesh(vertices, faces)
    assert mesh.update_vertices(vertices * 2) == []
    assert mesh.built_structures() == []
    np.testing.assert_allclose(mesh.vertex_normals, proxima.Mesh(vertices * 2, faces).vertex_normals)
    mesh.update_vertices(vertices * -1)  # mirrored: normals turn inward
    np.testing.assert_array_equal(mesh.vertex_normals, proxima.Mesh(vertices * -1, faces).vertex_normals)


@pytest.mark.parametrize(
    "bad, message",
    [
        (lambda v: v[:-1], "positions: 61 positions for 62 vertices"),
        (lambda v: v[:, :2], "positions"),
        (lambda v: np.where(np.arange(len(v))[:, None] == 5, np.nan, v), "positions"),
        (lambda v: np.where(np.arange(len(v))[:, None] == 7, np.inf, v), "positions"),
        (lambda v: v * 1e19, "positions: vertex 0 has a coordinate beyond"),
        (lambda v: "not an array", "positions"),
    ],
)
def test_bad_positions_change_nothing(bad, message):
    vertices, faces = sphere(6)
    assert len(vertices) == 62
    mesh = proxima.Mesh(vertices, faces)
    points = np.random.default_rng(1).uniform(-1, 1, (50, 3))
    before = mesh.closest_points(points)
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        mesh.update_vertices(bad(vertices))
    np.testing.assert_array_equal(mesh.vertices, vertices)
    assert_same(mesh.closest_points(points), before)
