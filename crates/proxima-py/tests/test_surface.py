"""What comes with an answer: barycentrics, features, normals and gradients
(`return_*` options), against numpy oracles, trimesh and finite differences."""

import numpy as np
import pytest
import trimesh

import proxima
from conftest import load_shared
from oracles import f32, fan_triangles


def corner_points(mesh, answers):
    """The barycentric combination of each answer's corners, in float64."""
    v = mesh.vertices.astype(np.float64)
    return np.einsum("nk,nkd->nd", answers.barycentric, v[answers.corners])


def queries(mesh, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = mesh.bounds
    span = hi - lo
    near = mesh.sample_near_surface(n, sigma=0.02, seed=seed)
    box = (lo - 0.2 * span + rng.random((n, 3)) * 1.4 * span).astype(np.float32)
    return np.concatenate([near, box, mesh.vertices[: n // 4]])


@pytest.mark.parametrize("name", ["spot_quadrangulated.obj", "fandisk.obj", "teapot.obj"])
def test_barycentrics_reproduce_closest_points_and_match_trimesh(name):
    mesh = load_shared(name)
    points = queries(mesh, 2000, 1)
    a = mesh.closest_points(points, return_barycentric=True)
    closest, distance, face = a  # unpacks as the plain tuple
    diagonal = np.linalg.norm(np.subtract(*mesh.bounds))
    assert np.all(a.barycentric >= 0) and np.allclose(a.barycentric.sum(axis=1), 1.0, atol=1e-12)
    assert np.abs(corner_points(mesh, a) - closest).max() <= 1e-6 * diagonal
    # The corners are the face's fan triangle `triangle`, in the face's order.
    tris, src = fan_triangles(mesh.faces)
    assert np.array_equal(src[a.triangle], face)
    assert np.array_equal(tris[a.triangle], a.corners)
    # trimesh's barycentrics of the same points on the same triangles (its own algorithm).
    v = mesh.vertices.astype(np.float64)
    theirs = trimesh.triangles.points_to_barycentric(v[a.corners], corner_points(mesh, a))
    assert np.abs(theirs - a.barycentric).max() < 1e-6


def voronoi_feature(tri, p):
    """The feature of triangle ``tri`` (3, 3) closest to ``p`` by trying each
    vertex, open edge and the open face in float64: (code, local index, margin
    over the runner-up). Codes: 0 face, 1 edge k (corner k to k+1), 2 vertex k."""
    found = [(np.linalg.norm(tri[k] - p), 2, k) for k in range(3)]
    for k in range(3):
        a, b = tri[k], tri[(k + 1) % 3]
        s = np.dot(p - a, b - a) / np.dot(b - a, b - a)
        if 0 < s < 1:
            found.append((np.linalg.norm(a + s * (b - a) - p), 1, k))
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    q = p - n * np.dot(p - tri[0], n) / np.dot(n, n)
    if all(np.dot(np.cross(tri[(k + 1) % 3] - tri[k], q - tri[k]), n) > 0 for k in range(3)):
        found.append((np.linalg.norm(q - p), 0, 0))
    found.sort(key=lambda f: f[0])
    return found[0][1], found[0][2], found[1][0] - found[0][0]


def test_features_match_a_brute_force_voronoi_classification():
    # Triangles only (every side is a mesh edge), so features compare directly.
    mesh = proxima.noisy_icosphere(6, seed=3)
    points = queries(mesh, 800, 2)
    a = mesh.closest_points(points, return_barycentric=True, return_feature=True)
    v = mesh.vertices.astype(np.float64)
    clear = 0
    for i, p in enumerate(points.astype(np.float64)):
        code, k, margin = voronoi_feature(v[a.corners[i]], p)
        if margin < 1e-9:
            continue
        clear += 1
        assert a.feature[i] == code, (i, p, a.feature[i], code)
        c = a.corners[i]
        expected = {0: [-1, -1], 1: [c[k], c[(k + 1) % 3]], 2: [c[k], -1]}[code]
        assert a.feature_vertices[i].tolist() == list(expected)
    assert clear > 0.8 * len(points)
    # Queries right on vertices are at those vertices.
    on = mesh.closest_points(mesh.vertices[:50], return_feature=True)
    assert np.all(on.feature == 2) and np.array_equal(on.feature_vertices[:, 0], np.arange(50))


def test_polygon_diagonals_are_the_face_and_options_need_faces():
    square = proxima.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    a = square.closest_points([[0.5, 0.5, 1.0], [2.0, 0.5, 0.0], [2.0, 2.0, 1.0]], return_feature=True)
    assert a.feature.tolist() == [0, 1, 2]
    assert a.feature_vertices.tolist() == [[-1, -1], [1, 2], [2, -1]]
    with pytest.raises(ValueError, match="primitives"):
        square.closest_points([[0, 0, 0]], primitives="edges", return_barycentric=True)


def angle_weighted_normals(vertices, faces):
    """Vertex normals: face normals weighted by the face's angle at the vertex."""
    v = vertices.astype(np.float64)
    tris, _ = fan_triangles(faces)
    normals = np.zeros_like(v)
    n = np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    for k in range(3):
        e1 = v[tris[:, (k + 1) % 3]] - v[tris[:, k]]
        e2 = v[tris[:, (k + 2) % 3]] - v[tris[:, k]]
        cos = np.einsum("ij,ij->i", e1, e2) / np.linalg.norm(e1, axis=1) / np.linalg.norm(e2, axis=1)
        np.add.at(normals, tris[:, k], n * np.arccos(np.clip(cos, -1, 1))[:, None])
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


@pytest.mark.parametrize("name", ["spot_triangulated.obj", "rocker-arm.obj"])
def test_normals_match_numpy_and_trimesh(name):
    mesh = load_shared(name)
    expected = angle_weighted_normals(mesh.vertices, mesh.faces)
    assert np.abs(mesh.vertex_normals - expected).max() < 1e-5
    # trimesh weights its vertex normals by angle too (on its own unmerged copy).
    theirs = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False).vertex_normals
    assert np.abs(mesh.vertex_normals - theirs).max() < 1e-4
    points = queries(mesh, 500, 4)
    a = mesh.closest_points(points, return_barycentric=True, return_normal=True)
    interpolated = np.einsum("nk,nkd->nd", a.barycentric, expected[a.corners])
    interpolated /= np.linalg.norm(interpolated, axis=1, keepdims=True)
    assert np.abs(a.normal - interpolated).max() < 1e-5
    v = mesh.vertices.astype(np.float64)[a.corners]
    face_normal = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    face_normal /= np.linalg.norm(face_normal, axis=1, keepdims=True)
    assert np.abs(a.face_normal - face_normal).max() < 1e-9
    assert "normals" in mesh.built_structures()


def test_ray_attributes_locate_hits():
    mesh = load_shared("spot_quadrangulated.obj")
    rng = np.random.default_rng(5)
    n = 3000
    origins = np.zeros((n, 3)) + mesh.bounds.mean(axis=0)
    directions = rng.normal(size=(n, 3))
    a = mesh.cast_rays(origins, directions, return_barycentric=True, return_normal=True, return_feature=True)
    t, face = a
    hit = face >= 0
    assert hit.mean() > 0.9
    unit = directions / np.linalg.norm(directions, axis=1, keepdims=True)
    points = f32(origins) + t[:, None] * unit
    diagonal = np.linalg.norm(np.subtract(*mesh.bounds))
    assert np.abs(corner_points(mesh, a)[hit] - points[hit]).max() < 1e-5 * diagonal
    assert np.all(a.barycentric[hit] >= 0) and np.allclose(a.barycentric[hit].sum(axis=1), 1.0)
    # A miss: -1 and NaN.
    assert np.all(a.triangle[~hit] == -1) and np.all(np.isnan(a.normal[~hit]))
    # The interpolated normal lies within the hemisphere of the geometric one.
    assert np.all(np.einsum("ij,ij->i", a.normal[hit], a.face_normal[hit]) > 0)
    plain_t, plain_face = mesh.cast_rays(origins, directions)
    assert np.array_equal(plain_t, t) and np.array_equal(plain_face, face)


@pytest.mark.parametrize("sign", ["winding", "pseudonormal"])
def test_gradients_match_central_differences(sign):
    mesh = proxima.noisy_icosphere(8, seed=2)
    rng = np.random.default_rng(6)
    points = (rng.random((400, 3)) * 3.0 - 1.5).astype(np.float32)
    distance, gradient = mesh.signed_distance(points, sign=sign, return_gradient=True)
    assert np.array_equal(distance, mesh.signed_distance(points, sign=sign))
    assert np.allclose(np.linalg.norm(gradient, axis=1), 1.0, atol=1e-9)

    def central(h):
        out = np.empty_like(gradient)
        for axis in range(3):
            step = np.zeros(3)
            step[axis] = h
            up = mesh.signed_distance(points + step, sign=sign)
            down = mesh.signed_distance(points - step, sign=sign)
            out[:, axis] = (up - down) / (np.float32(points + step) - np.float32(points - step))[:, axis]
        return out

    coarse, fine = central(2e-3), central(5e-4)
    # Away from the surface and the medial axis (where the two step sizes disagree).
    smooth = (np.abs(distance) > 0.05) & (np.linalg.norm(coarse - fine, axis=1) < 2e-3)
    assert smooth.sum() > 300
    assert np.abs(coarse[smooth] - gradient[smooth]).max() < 2e-2


def test_gradients_on_the_surface_are_outward_normals():
    mesh = proxima.noisy_icosphere(6, seed=1)
    distance, gradient = mesh.signed_distance(mesh.vertices, return_gradient=True)
    assert np.all(distance == 0)
    assert np.abs(gradient - mesh.vertex_normals).max() < 1e-5


def test_answers_behave_as_a_named_result():
    mesh = proxima.noisy_icosphere(4)
    a = mesh.closest_points(np.zeros((2, 3)), return_normal=True)
    assert len(a) == 3 and a.keys() == ["closest", "distance", "index", "normal", "face_normal"]
    assert a["normal"] is not None and a.normal.shape == (2, 3)
    assert "normal(2, 3)" in repr(a)
    with pytest.raises(AttributeError, match="barycentric"):
        a.barycentric
    empty = mesh.closest_points(np.zeros((0, 3)), return_barycentric=True)
    assert empty.barycentric.shape == (0, 3) and empty.corners.shape == (0, 3)
    d, g = mesh.signed_distance(np.zeros((0, 3)), return_gradient=True)
    assert d.shape == (0,) and g.shape == (0, 3)


def obj_corner_uvs(path):
    """The texture coordinates of every face corner of an OBJ file (v/vt
    faces), read with numpy: (C, 2), and each face's corner count."""
    vt, corners, sizes = [], [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "vt":
            vt.append([float(parts[1]), float(parts[2])])
        elif parts[0] == "f":
            refs = [int(p.split("/")[1]) for p in parts[1:]]
            corners.extend(r - 1 if r > 0 else len(vt) + r for r in refs)
            sizes.append(len(refs))
    return np.asarray(vt, dtype=np.float32)[corners], np.asarray(sizes)


def fan_slots(sizes, face, triangle):
    """The face corners (C numbering) of fan triangle ``triangle`` of ``face``."""
    first = np.concatenate([[0], np.cumsum(sizes)])[face]
    first_triangle = np.concatenate([[0], np.cumsum(sizes - 2)])[face]
    i = triangle - first_triangle
    return np.stack([first, first + i + 1, first + i + 2], axis=1)


@pytest.mark.parametrize("name", ["spot_quadrangulated.obj", "spot_triangulated.obj"])
def test_uvs_interpolate_the_files_corner_values(name):
    mesh = load_shared(name)
    from conftest import data_path

    uvs, sizes = obj_corner_uvs(data_path(name))
    assert np.array_equal(mesh.corner_uvs, uvs)
    points = queries(mesh, 1000, 7)
    a = mesh.closest_points(points, return_barycentric=True, return_uv=True)
    slots = fan_slots(sizes, a.index, a.triangle)
    expected = np.einsum("nk,nkd->nd", a.barycentric, uvs.astype(np.float64)[slots])
    assert np.abs(a.uv - expected).max() < 1e-12
    # Rays: the same interpolation at the hits.
    rng = np.random.default_rng(8)
    origins = np.zeros((500, 3)) + mesh.bounds.mean(axis=0)
    r = mesh.cast_rays(origins, rng.normal(size=(500, 3)), return_barycentric=True, return_uv=True)
    hit = r.index >= 0
    slots = fan_slots(sizes, r.index[hit], r.triangle[hit])
    expected = np.einsum("nk,nkd->nd", r.barycentric[hit], uvs.astype(np.float64)[slots])
    assert np.abs(r.uv[hit] - expected).max() < 1e-12
    assert np.all(np.isnan(r.uv[~hit]))


def test_uvs_are_refused_on_meshes_without_them():
    mesh = proxima.noisy_icosphere(3)
    assert mesh.corner_uvs is None and mesh.corner_normals is None
    with pytest.raises(ValueError, match="return_uv"):
        mesh.closest_points(np.zeros((1, 3)), return_uv=True)
