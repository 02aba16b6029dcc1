"""Scenes of rigid instances against the same triangles merged into one
Mesh (placed in float64 by numpy), and float64 brute force for distances."""

import numpy as np
import pytest

import proxima
from oracles import triangle_distances


def random_pose(rng, spread=3.0):
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = rng.uniform(-spread, spread, 3)
    return pose


def placed(mesh, pose):
    v = np.asarray(mesh.vertices, dtype=np.float64)
    return v @ pose[:3, :3].T + pose[:3, 3]


@pytest.fixture(scope="module")
def world():
    rng = np.random.default_rng(4)
    meshes = [proxima.noisy_icosphere(5, seed=1), proxima.noisy_icosphere(3, seed=2)]
    instances = [(meshes[k % 2], random_pose(rng)) for k in range(12)]
    scene = proxima.Scene(instances)
    vertices, faces, owner = [], [], []
    offset = 0
    for k, (mesh, pose) in enumerate(instances):
        vertices.append(placed(mesh, pose))
        f = np.asarray(mesh.faces)
        faces.append(f + offset)
        owner += [(k, i) for i in range(len(f))]
        offset += len(mesh.vertices)
    vertices, faces = np.vstack(vertices), np.vstack(faces)
    return scene, instances, vertices, faces, np.array(owner)


def test_closest_points_equal_brute_force(world):
    scene, _, vertices, faces, owner = world
    points = np.random.default_rng(5).uniform(-4.5, 4.5, (300, 3))
    closest, distance, instance, face = scene.closest_points(points)
    expected = triangle_distances(points, vertices, faces)
    np.testing.assert_allclose(distance, expected.min(axis=1), rtol=1e-5, atol=1e-5)
    # The named face is at that distance, and the point on it.
    rows = np.arange(len(points))
    merged = np.array([np.flatnonzero((owner[:, 0] == i) & (owner[:, 1] == f))[0] for i, f in zip(instance, face)])
    np.testing.assert_allclose(expected[rows, merged], distance, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(closest - points, axis=1), distance, rtol=1e-5, atol=1e-5)


def test_k_nearest_equals_the_merged_mesh(world):
    scene, _, vertices, faces, owner = world
    merged = proxima.Mesh(vertices.astype(np.float32), faces)
    points = np.random.default_rng(8).uniform(-4, 4, (100, 3))
    distance, instance, face = scene.k_nearest(points, 5)
    merged_distance, _ = merged.k_nearest(points, 5)
    np.testing.assert_allclose(distance, merged_distance, rtol=1e-5, atol=1e-5)
    expected = triangle_distances(points, vertices, faces)
    rows = np.repeat(np.arange(len(points)), 5)
    named = np.array([np.flatnonzero((owner[:, 0] == i) & (owner[:, 1] == f))[0] for i, f in zip(instance.ravel(), face.ravel())])
    np.testing.assert_allclose(expected[rows, named], distance.ravel(), rtol=1e-5, atol=1e-5)
    small = proxima.Scene([(proxima.noisy_icosphere(1), None)])
    d, i, f = small.k_nearest([[0, 0, 0]], 25)
    assert np.isfinite(d[0, :20]).all() and np.isinf(d[0, 20:]).all() and (i[0, 20:] == -1).all()
    with pytest.raises(ValueError, match="k: 0 is less than 1"):
        scene.k_nearest(points, 0)
    with pytest.raises(ValueError, match="k"):
        scene.k_nearest(points, 2**40)


def test_rays_and_signs_equal_the_merged_mesh(world):
    scene, _, vertices, faces, owner = world
    merged = proxima.Mesh(vertices.astype(np.float32), faces)
    rng = np.random.default_rng(6)
    origins = rng.uniform(-8, 8, (500, 3))
    directions = rng.uniform(-4, 4, (500, 3)) - origins
    t, instance, face = scene.cast_rays(origins, directions)
    t_merged, face_merged = merged.cast_rays(origins, directions)
    np.testing.assert_allclose(t, t_merged, rtol=1e-5, atol=1e-5)
    hit = np.isfinite(t)
    assert hit.sum() > 150
    same = (owner[face_merged[hit], 0] == instance[hit]) & (owner[face_merged[hit], 1] == face[hit])
    assert same.mean() > 0.98  # the rest: ties on shared edges
    some_t, some_instance, _ = scene.cast_rays(origins, directions, any_hit=True)
    np.testing.assert_array_equal(np.isfinite(some_t), hit)
    points = rng.uniform(-4.5, 4.5, (400, 3))
    inside = merged.winding_number(points) > 0.5  # a union of closed spheres: w counts overlaps twice
    np.testing.assert_array_equal(scene.contains(points), inside)
    signed = scene.signed_distance(points)
    np.testing.assert_array_equal(signed < 0, inside)
    _, distance, _, _ = scene.closest_points(points)
    np.testing.assert_array_equal(np.abs(signed), distance)


def test_set_pose_answers_as_a_new_scene(world):
    _, instances, _, _, _ = world
    scene = proxima.Scene(instances)
    rng = np.random.default_rng(7)
    moved = list(instances)
    for _ in range(20):
        i = int(rng.integers(len(moved)))
        pose = random_pose(rng)
        scene.set_pose(i, pose)
        moved[i] = (moved[i][0], pose)
        np.testing.assert_allclose(scene.pose(i), pose)
    fresh = proxima.Scene(moved)
    points = rng.uniform(-4, 4, (200, 3))
    for a, b in zip(scene.closest_points(points), fresh.closest_points(points)):
        np.testing.assert_array_equal(a, b)
    assert len(scene) == len(instances)


def test_update_vertices_deforms_every_instance_of_the_mesh(world):
    _, instances, _, _, _ = world
    scene = proxima.Scene(instances)
    rng = np.random.default_rng(9)
    points = rng.uniform(-4, 4, (200, 3))
    rays_o = rng.uniform(-6, 6, (100, 3))
    rays_d = -rays_o + rng.normal(size=(100, 3))
    scene.closest_points(points)  # the structures built
    sphere = instances[0][0]
    rest = np.asarray(sphere.vertices).copy()
    faces = np.asarray(sphere.faces)

    def check(vertices):
        # Every instance of that mesh (the even ones) moved; a scene built
        # anew answers the same, and brute force agrees on the distances.
        moved = proxima.Mesh(vertices, faces)
        fresh = proxima.Scene([(moved if k % 2 == 0 else m, pose) for k, (m, pose) in enumerate(instances)])
        for a, b in zip(scene.closest_points(points), fresh.closest_points(points)):
            np.testing.assert_array_equal(a, b)
        for a, b in zip(scene.cast_rays(rays_o, rays_d), fresh.cast_rays(rays_o, rays_d)):
            np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(scene.signed_distance(points), fresh.signed_distance(points))
        _, distance, _, _ = scene.closest_points(points[:20])
        brute = np.full(20, np.inf)
        for k, (m, pose) in enumerate(instances):
            v = placed(moved, pose) if k % 2 == 0 else placed(m, pose)
            f = faces if k % 2 == 0 else np.asarray(m.faces)
            brute = np.minimum(brute, triangle_distances(points[:20], v, f).min(axis=1))
        np.testing.assert_allclose(distance, brute, atol=1e-5)

    first = (rest * 1.3 + rng.normal(scale=0.01, size=rest.shape)).astype(np.float32)
    assert scene.update_vertices(2, first) == []  # a copy of the scene's own
    np.testing.assert_array_equal(np.asarray(sphere.vertices), rest)  # yours unchanged
    check(first)
    second = (first + rng.normal(scale=0.02, size=rest.shape)).astype(np.float32)
    report = scene.update_vertices(4, second)
    assert "faces" in [name for name, _, _ in report]  # refit in place now
    check(second)
    # Refused: the scene unchanged.
    before = scene.closest_points(points)
    with pytest.raises(ValueError, match="index: 12 is out of range"):
        scene.update_vertices(12, second)
    with pytest.raises(ValueError, match="positions"):
        scene.update_vertices(0, second[:-1])
    bad = second.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="positions"):
        scene.update_vertices(0, bad)
    for a, b in zip(before, scene.closest_points(points)):
        np.testing.assert_array_equal(a, b)


def test_bad_input():
    sphere = proxima.noisy_icosphere(3)
    with pytest.raises(ValueError, match=r"instances\[0\]: expected a \(mesh, pose\) pair"):
        proxima.Scene([sphere])
    with pytest.raises(ValueError, match=r"instances\[1\]: the first item is not a proxima.Mesh"):
        proxima.Scene([(sphere, None), ("mesh", None)])
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match=r"instances\[0\]\[1\]"):
        proxima.Scene([(sphere, mirror)])
    with pytest.raises(ValueError, match=r"instances\[0\]\[1\]"):
        proxima.Scene([(sphere, np.eye(4) * 2)])
    points_only = proxima.Mesh(np.eye(3), np.zeros((0, 3), dtype=np.int64))
    with pytest.raises(ValueError, match="instances: instance 1: the mesh has no faces"):
        proxima.Scene([(sphere, None), (points_only, None)])
    scene = proxima.Scene([(sphere, None)])
    with pytest.raises(ValueError, match="index: 1 is out of range"):
        scene.set_pose(1, np.eye(4))
    with pytest.raises(ValueError, match="index: -1 is out of range"):
        scene.set_pose(-1, np.eye(4))
    with pytest.raises(ValueError, match="pose"):
        scene.set_pose(0, mirror)
    with pytest.raises(ValueError, match="sign"):
        scene.signed_distance([[0, 0, 0]], sign="parity")
    with pytest.raises(ValueError, match="points"):
        scene.closest_points([[np.nan, 0, 0]])
    with pytest.raises(ValueError, match=r"directions\[0\]: the direction is zero"):
        scene.cast_rays([[0, 0, 0]], [[0, 0, 0]])
    # A placed mesh cannot deform under the scene.
    with pytest.raises(ValueError, match="positions: the mesh is placed in a Scene"):
        sphere.update_vertices(np.asarray(sphere.vertices) * 2)
    empty = proxima.Scene([])
    _, distance, instance, _ = empty.closest_points([[0, 0, 0]])
    assert distance[0] == np.inf and instance[0] == -1
